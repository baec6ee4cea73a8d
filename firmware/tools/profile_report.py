"""Attributes QEMU's per-address instruction counts to functions, lines and inline chains.

Usage: profile_report.py DIR TRIPLES, with DIR/counts.txt ("<hex address> <count>" lines)
and DIR/addr2line.txt (arm-none-eabi-addr2line -f -C -i -a on those addresses). Prints
instructions per sample triple: by innermost function, by innermost source line, and by
the chain of the four innermost inlined frames. Called by firmware/tools/profile.sh.
"""

import collections
import re
import sys


def frames(path):
    """{address: [(function, file:line), ...]} innermost first, from addr2line -f -i -a."""
    out, addr, chain = {}, None, []
    lines = open(path, encoding="utf-8").read().splitlines()
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("0x"):
            if addr is not None:
                out[addr] = chain
            addr, chain = int(line, 16), []
            i += 1
        else:
            chain.append((line, lines[i + 1] if i + 1 < len(lines) else "?"))
            i += 2
    if addr is not None:
        out[addr] = chain
    return out


def short_fn(name):
    return re.sub(r"::h[0-9a-f]{16}$", "", name)


def short_loc(loc):
    loc = re.sub(r" \(discriminator \d+\)", "", loc)
    loc = re.sub(r".*/rustc/[0-9a-f]+/", "", loc)
    loc = re.sub(r".*/registry/src/[^/]+/", "", loc)
    return re.sub(r"^/.*?/(core|app|firmware)/src/", r"\1/src/", loc)


def main():
    folder, triples = sys.argv[1], int(sys.argv[2])
    counts = {}
    for line in open(f"{folder}/counts.txt", encoding="utf-8"):
        address, n = line.split()
        counts[int(address, 16)] = int(n)
    where = frames(f"{folder}/addr2line.txt")
    by_fn, by_line, by_chain = (collections.Counter() for _ in range(3))
    prepare = 0
    for address, n in counts.items():
        chain = where.get(address) or [("?", "?")]
        fn, loc = short_fn(chain[0][0]), short_loc(chain[0][1])
        by_fn[fn] += n
        by_line[loc] += n
        by_chain[" <- ".join(f"{short_fn(f).split('::')[-1]}@{short_loc(l)}" for f, l in chain[:4])] += n
        if any("prepare" in f or "DevicePath::desk" in f for f, _ in chain):
            prepare += n
    total = sum(counts.values())
    print(f"{total / triples:.1f} instructions per sample triple in all ({triples} triples), "
          f"of which the desk's prepare {prepare / triples:.1f} (not timed by cargo lab speed): "
          f"{(total - prepare) / triples:.1f} to compare with its device_3khz row")
    print("(a 'function' is the innermost frame, inlined or not: `<u128>::overflowing_mul` is "
          "128-bit arithmetic inlined where the chains below say)")
    for title, table, rows in (("function", by_fn, 40), ("source line", by_line, 60),
                               ("inline chain", by_chain, 60)):
        print(f"\nby {title} (instructions per triple)")
        for key, n in table.most_common(rows):
            print(f"{n / triples:8.1f}  {key}")


if __name__ == "__main__":
    main()
