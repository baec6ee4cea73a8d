"""CI check of the firmware ELF: flash and static RAM within budget, and the vector table
binds the DMA and USB interrupts to their RTIC handlers (not to DefaultHandler).

Usage: check_elf.py ELF LLVM_BIN_DIR
Budgets: flash (.vector_table + .text + .rodata + .data) <= 64 KiB, static RAM
(.data + .bss + .uninit) <= 16 KiB (issue 11): the code stays in sectors 0-3 and 4 (the
first 128 KiB holds it with room), the 128 KiB sectors stay free for settings.
"""
import re
import subprocess
import sys

FLASH_BUDGET = 64 * 1024
RAM_BUDGET = 16 * 1024
# STM32F411 IRQ numbers (RM0383 table 38): DMA2 stream 0 = 56, OTG_FS = 67.
IRQS = {"DMA2_STREAM0": 56, "OTG_FS": 67}


def run(tool, *args):
    return subprocess.run([f"{sys.argv[2]}/{tool}", *args], check=True, capture_output=True,
                          text=True).stdout


def main():
    elf = sys.argv[1]
    sizes = {}
    for line in run("llvm-size", "-A", elf).splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[0].startswith("."):
            sizes[parts[0]] = int(parts[1])
    flash = sum(sizes.get(s, 0) for s in (".vector_table", ".text", ".rodata", ".data"))
    ram = sum(sizes.get(s, 0) for s in (".data", ".bss", ".uninit"))
    print(f"flash {flash} bytes ({flash / 1024:.1f} KiB, budget 64 KiB); "
          f"static RAM {ram} bytes ({ram / 1024:.1f} KiB, budget 16 KiB)")
    ok = flash <= FLASH_BUDGET and ram <= RAM_BUDGET

    symbols = {}
    for line in run("llvm-nm", elf).splitlines():
        parts = line.split()
        if len(parts) == 3:
            symbols[parts[2]] = int(parts[0], 16)
    dump = run("llvm-objdump", "-s", "-j", ".vector_table", elf)
    words = []
    for line in dump.splitlines():
        m = re.match(r"^ ([0-9a-f]{7,8}) ((?:[0-9a-f]{8} ?){1,4})", line)
        if m:
            for w in m.group(2).split():
                words.append(int.from_bytes(bytes.fromhex(w), "little"))
    default = symbols["DefaultHandler"]
    for name, irq in IRQS.items():
        entry = words[16 + irq] & ~1  # clear the Thumb bit
        bound = entry == symbols.get(name) and entry != default
        print(f"vector {16 + irq} ({name}): {entry:#010x} -> "
              f"{'bound to ' + name if bound else 'NOT bound'}")
        ok = ok and bound
    if not ok:
        sys.exit("check_elf: budget exceeded or an interrupt is not bound")


if __name__ == "__main__":
    main()
