#!/usr/bin/env bash
# Where the device's sample path spends its instructions: `bash firmware/tools/profile.sh [OUT]`.
#
# Builds `firmware/src/bin/profile.rs` (the speed harness's device_3khz kernel alone), runs it
# in QEMU with one log line per executed instruction (-singlestep -d exec,nochain), counts
# each address from the profile's start mark on, and attributes the counts with addr2line
# (inlined frames included). Writes OUT/report.txt (default target/profile): instructions per
# sample triple by function, by source line, and by inline chain. Four to five minutes on 2
# cores (the log is 1.6 M lines of the path after ~140 M of calibration and settings
# derivation, streamed, never stored). Needs qemu-system-arm and binutils-arm-none-eabi
# (Debian packages). A relative OUT is taken from the directory the script is run in.
# The totals are instructions, as `cargo lab speed` counts them, plus the desk's own code
# (the kernel's prepare, reported apart); the speed harness's figure is the one to quote.
set -euo pipefail
here=$(pwd)
cd "$(dirname "$0")/../.."
out=${1:-target/profile}
case "$out" in /*) ;; *) [ -n "${1:-}" ] && out="$here/$out" ;; esac
mkdir -p "$out"
for tool in qemu-system-arm arm-none-eabi-addr2line arm-none-eabi-nm; do
  command -v "$tool" >/dev/null || {
    echo "$tool not found: apt-get install qemu-system-arm binutils-arm-none-eabi" >&2
    exit 2
  }
done
cargo build -q -p firmware --bin profile --target thumbv7em-none-eabihf --release
elf=target/thumbv7em-none-eabihf/release/profile
mark=$(arm-none-eabi-nm -C "$elf" | awk '/ profile::mark$/ {print $1}')
[ -n "$mark" ] || { echo "no profile::mark symbol in $elf" >&2; exit 1; }
# The exec log goes to stderr; QEMU's stdout (the checksum line) is kept apart.
set +e
timeout 1200 qemu-system-arm -machine netduinoplus2 -cpu cortex-m4 -nographic -monitor none \
  -serial none -semihosting-config enable=on,target=native -singlestep -d exec,nochain \
  -kernel "$elf" 2>&1 >"$out/stdout.txt" |
  awk -F'/' -v m="$mark" '!on { if ($2 != m) next; on = 1 } { n[$2]++ } END { for (p in n) print p, n[p] }' \
    >"$out/counts.txt"
status=("${PIPESTATUS[@]}")
set -e
if [ "${status[0]}" -ne 0 ] || [ "${status[1]}" -ne 0 ] || ! grep -q '^checksum ' "$out/stdout.txt"; then
  echo "the profile run did not finish (qemu exit ${status[0]}, 124 is the 20-minute timeout; awk exit ${status[1]}); its output:" >&2
  cat "$out/stdout.txt" >&2
  exit 1
fi
awk '{print "0x" $1}' "$out/counts.txt" | arm-none-eabi-addr2line -e "$elf" -f -C -i -a >"$out/addr2line.txt"
python3 firmware/tools/profile_report.py "$out" 3072 >"$out/report.txt"
head -n 40 "$out/report.txt"
echo "(whole report: $out/report.txt)"
