"""CI check of the firmware ELF: the flash layout, flash and static RAM within budget, and
the vector table binds the DMA and USB interrupts and Stop mode's three wake-up lines
(KEY, USB resume, the RTC's probe timer) to their RTIC handlers (not to DefaultHandler).

Usage: check_elf.py ELF LLVM_BIN_DIR
Layout (memory.x, firmware/src/board.rs): the vector table alone in sector 0, nothing in
sectors 1 and 2 (0x08004000..0x0800C000, the profile store: code there would be erased by
a save), the code from sector 3 (0x0800C000) on.
Budgets: flash (.vector_table + .text + .rodata + .data) <= 256 KiB, static RAM
(.data + .bss + .uninit) <= 24 KiB. Tripwires against growth, not the part's limits (512 KiB
and 128 KiB): issue 14 (the configuration interface, the store, the raw stream) took the
image from 62.9 to 88.8 KiB and the RAM from 13.7 to 17.1 KiB; issue 15 built the core at
opt-level 3, the code its speed figures measure (91.4 -> 110.8 KiB); issue 22's drift
control (its decisions, their derivation from the settings in f64, at opt-level 3) took it to
184.8 KiB, so the flash tripwire moved from 128 to 256 KiB (the code may use sectors 3 to 7,
464 KiB).
The tracker (the RTIC resource holding `imu_core::Tracker`) <= 8 KiB: issue 22's target.
"""
import re
import subprocess
import sys

FLASH_BUDGET = 256 * 1024
RAM_BUDGET = 24 * 1024
TRACKER_BUDGET = 8 * 1024
TRACKER_SYMBOL = "__rtic_internal_shared_resource_tracker"
FLASH_ORIGIN = 0x0800_0000
STORE = (0x0800_4000, 0x0800_C000)
# STM32F411 IRQ numbers (RM0383 table 38): DMA2 stream 0 = 56, OTG_FS = 67; Stop mode's
# wake-up lines: RTC wake-up (EXTI 22) = 3, EXTI 0 (KEY) = 6, OTG_FS_WKUP (EXTI 18) = 42.
IRQS = {"DMA2_STREAM0": 56, "OTG_FS": 67, "RTC_WKUP": 3, "EXTI0": 6, "OTG_FS_WKUP": 42}


def run(tool, *args):
    return subprocess.run([f"{sys.argv[2]}/{tool}", *args], check=True, capture_output=True,
                          text=True).stdout


def main():
    elf = sys.argv[1]
    sizes, addrs = {}, {}
    for line in run("llvm-size", "-A", elf).splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[0].startswith("."):
            sizes[parts[0]] = int(parts[1])
            addrs[parts[0]] = int(parts[2])
    layout_ok = addrs.get(".vector_table") == FLASH_ORIGIN and addrs.get(".text") == STORE[1]
    for name, size in sizes.items():
        start = addrs[name]
        if size and start < STORE[1] and start + size > STORE[0]:
            print(f"{name} at {start:#010x} overlaps the profile store")
            layout_ok = False
    print(f"layout: vector table at {addrs.get('.vector_table', 0):#010x}, code at "
          f"{addrs.get('.text', 0):#010x}, store {STORE[0]:#010x}..{STORE[1]:#010x} "
          f"{'free' if layout_ok else 'NOT as memory.x says'}")
    flash = sum(sizes.get(s, 0) for s in (".vector_table", ".text", ".rodata", ".data"))
    ram = sum(sizes.get(s, 0) for s in (".data", ".bss", ".uninit"))
    print(f"flash {flash} bytes ({flash / 1024:.1f} KiB, budget {FLASH_BUDGET // 1024} KiB); "
          f"static RAM {ram} bytes ({ram / 1024:.1f} KiB, budget {RAM_BUDGET // 1024} KiB)")
    ok = layout_ok and flash <= FLASH_BUDGET and ram <= RAM_BUDGET

    tracker = [int(p[1], 16) for p in (line.split() for line in
               run("llvm-nm", "--print-size", "-C", elf).splitlines())
               if len(p) == 4 and TRACKER_SYMBOL in p[3]]
    print(f"tracker: {tracker[0] if tracker else 'NOT FOUND'} bytes of RAM "
          f"(budget {TRACKER_BUDGET} bytes)")
    ok = ok and len(tracker) == 1 and tracker[0] <= TRACKER_BUDGET

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
        sys.exit("check_elf: layout wrong, budget exceeded or an interrupt is not bound")


if __name__ == "__main__":
    main()
