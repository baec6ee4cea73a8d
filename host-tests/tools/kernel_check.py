"""CI: the Linux kernel's own USB and HID drivers as the twin's host.

Debian's stock kernel boots under qemu-system-x86_64 (software emulation) from an initramfs
built here, from Debian packages only: the kernel's modules (their dependencies read from the
modules themselves with kmod's `modinfo`), busybox-static, and the `usbip` userland and this
build's `lab`, each with the shared libraries `ldd` finds for it. The guest attaches the
running `lab twin` over QEMU's user network (the host is 10.0.2.2), and the check judges, from
what the guest's kernel reports:

- enumeration: the device and both interfaces bound by usbhid; no error or warning about the
  device in the kernel log (vhci_hcd's own lines are reported, not judged);
- the mouse: hid-input's capabilities equal what the report descriptor (read back from sysfs)
  declares; the evdev REL sums equal the twin's count total exactly (usbmon's record too,
  when its text reader kept every report: under load it drops events); every KEY press and
  release (the twin's operator presses KEY three times) arrives once, in order; the whole
  guest paused 300 ms (QEMU stopped: its USB host polls nothing) loses nothing;
- a bus reset mid-scene (`usbip detach`, `attach`) with KEY held: re-enumerated, the held
  button re-sent, every count sent, discarded or owed as the twin's accounts say;
- the configuration interface: its hidraw node, and `lab device info`, `config set`, `config
  get`, `save` and `record --seconds 3` run inside the guest on that node through the hidapi
  backend a board uses on Linux; the recording equals the scene's codes, a refused setting
  changes nothing.

On a failure it prints the kernel log's lines about the device and the usbmon trace of the
enumeration. Every process it starts is ended by its own id; the USB/IP port is chosen free.

Usage: kernel_check.py LAB_BINARY WORK_DIR   (exit status 1 on any failed check)
Needs root or sudo for apt (qemu-system-x86 and kmod on the host; the guest's packages are
only downloaded and unpacked into WORK_DIR).
"""
import base64
import gzip
import json
import lzma
import os
import queue
import re
import shutil
import signal
import socket
import struct
import subprocess
import sys
import threading
import time

from twin_accounts import lost_unconfirmed

GUEST_PACKAGES = ["busybox-static", "usbip"]
MODULES = ["usbmon", "vhci-hcd", "usbhid", "hid-generic", "evdev", "virtio_net", "virtio_pci"]
SCENE_S = 25
BOOT_TIMEOUT_S = 90
COMMAND_TIMEOUT_S = 60
EV_SYN, EV_KEY, EV_REL, EV_MSC = 0, 1, 2, 4
BTN_LEFT = 0x110
REL_NAMES = {0: "X", 1: "Y", 6: "HWHEEL", 8: "WHEEL", 11: "WHEEL_HI_RES", 12: "HWHEEL_HI_RES"}

failures = []
diagnostics = {}


def say(msg):
    print(f"kernel_check: {msg}", flush=True)


def check(ok, what):
    say(("ok: " if ok else "FAIL: ") + what)
    if not ok:
        failures.append(what)


def run(*args, **kw):
    return subprocess.run(args, check=True, capture_output=True, text=True, **kw).stdout


def as_root(*args):
    prefix = [] if os.geteuid() == 0 else ["sudo"]
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    subprocess.run(prefix + list(args), check=True, env=env, stdout=subprocess.DEVNULL)


# --- the guest's parts, from Debian packages -------------------------------------------


def host_tools():
    missing = [pkg for cmd, pkg in [("qemu-system-x86_64", "qemu-system-x86"), ("modinfo", "kmod")]
               if shutil.which(cmd) is None and not os.path.exists(f"/sbin/{cmd}")]
    if missing:
        as_root("apt-get", "update", "-qq")
        as_root("apt-get", "install", "-y", "-qq", *missing)


def kernel_package():
    out = run("apt-cache", "depends", "linux-image-amd64")
    m = re.search(r"Depends: (linux-image-[0-9][^\s]*-amd64)", out)
    if not m:
        sys.exit(f"kernel_check: no kernel named by `apt-cache depends linux-image-amd64`:\n{out}")
    return m.group(1)


def unpack(work, packages):
    debs, root = os.path.join(work, "debs"), os.path.join(work, "root")
    os.makedirs(debs, exist_ok=True)
    have = os.listdir(debs)
    want = [p for p in packages if not any(f.startswith(p.replace(":", "%3a") + "_") for f in have)]
    if want:
        try:
            subprocess.run(["apt-get", "download", *want], cwd=debs, check=True,
                           capture_output=True, text=True)
        except subprocess.CalledProcessError:
            as_root("apt-get", "update", "-qq")
            subprocess.run(["apt-get", "download", *want], cwd=debs, check=True,
                           capture_output=True, text=True)
    shutil.rmtree(root, ignore_errors=True)
    for f in sorted(os.listdir(debs)):
        run("dpkg", "-x", os.path.join(debs, f), root)
    return root


def modinfo():
    return shutil.which("modinfo") or "/sbin/modinfo"


def module_order(root, release):
    """The modules to load and everything they depend on, dependencies first, as
    `modinfo -F depends` reads them from each module."""
    tree = os.path.join(root, "lib/modules", release)
    files = {}
    for d, _, names in os.walk(tree):
        for n in names:
            if n.endswith(".ko"):
                files[n[:-3].replace("-", "_")] = os.path.join(d, n)
    order, seen = [], set()

    def visit(name):
        key = name.replace("-", "_")
        if key in seen:
            return
        seen.add(key)
        if key not in files:
            sys.exit(f"kernel_check: module {name} is not in {tree} (built in, or renamed?)")
        deps = run(modinfo(), "-F", "depends", files[key]).strip()
        for dep in filter(None, deps.split(",")):
            visit(dep)
        order.append((key, files[key]))

    for m in MODULES:
        visit(m)
    return order


def shared_libraries(binary, extra_dirs):
    """The files `ldd` resolves for `binary` (with the unpacked packages' library folders
    searched too), the loader included."""
    env = dict(os.environ, LD_LIBRARY_PATH=":".join(extra_dirs))
    out = run("ldd", binary, env=env)
    libs = []
    for line in out.splitlines():
        if "not found" in line:
            sys.exit(f"kernel_check: {binary} needs a library ldd cannot find: {line.strip()}")
        m = re.search(r"(/\S+)", line.split("=>")[-1])
        if m:
            libs.append(m.group(1))
    return libs


def vmlinux(bzimage, out):
    """The uncompressed kernel inside the bzImage (its xz payload), which QEMU boots through
    its PVH entry without spending seconds of emulated time unpacking it."""
    if os.path.exists(out):
        return out
    data = open(bzimage, "rb").read()
    start = data.find(b"\xfd7zXZ\x00")
    if start < 0:
        return bzimage
    elf = lzma.LZMADecompressor(format=lzma.FORMAT_XZ).decompress(data[start:])
    if not elf.startswith(b"\x7fELF"):
        return bzimage
    with open(out, "wb") as f:
        f.write(elf)
    return out


class Cpio:
    """An uncompressed newc archive (the kernel unpacks it without a decompressor)."""

    def __init__(self):
        self.parts, self.ino = [], 1

    def entry(self, name, mode, data=b"", rdev=(0, 0)):
        name_b = name.lstrip("/").encode() + b"\0"
        fields = [self.ino, mode, 0, 0, 1, 0, len(data), 0, 0, rdev[0], rdev[1], len(name_b), 0]
        self.ino += 1
        head = b"070701" + b"".join(b"%08X" % v for v in fields)
        pad = lambda n: b"\0" * (-n % 4)
        self.parts += [head, name_b, pad(len(head) + len(name_b)), data, pad(len(data))]

    def dirs(self, path):
        parts = path.strip("/").split("/")
        for i in range(1, len(parts)):
            d = "/".join(parts[:i])
            if d not in getattr(self, "made", set()):
                self.made = getattr(self, "made", set()) | {d}
                self.entry(d, 0o040755)

    def file(self, path, data, mode=0o100755):
        self.dirs(path)
        self.entry(path, mode, data)

    def link(self, path, target):
        self.dirs(path)
        self.entry(path, 0o120777, target.encode())

    def bytes(self):
        self.entry("TRAILER!!!", 0)
        return b"".join(self.parts)


INIT = r"""#!/bin/sh
export PATH=/bin:/sbin:/usr/bin:/usr/sbin
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t devtmpfs devtmpfs /dev
mount -t debugfs debugfs /sys/kernel/debug
mkdir -p /tmp /var/run
exec 0</dev/console 1>/dev/console 2>&1
stty -echo
for m in $(cat /modules.order); do insmod /lib/modules/$m.ko || echo "@@INSMOD-FAILED $m"; done
ip link set lo up
ip link set eth0 up
ip addr add 10.0.2.15/24 dev eth0
ip route add default via 10.0.2.2
# The mouse interface's event node, once hid-input made it (10 s at most).
node() {
  i=0
  while [ $i -lt 100 ]; do
    for e in /sys/bus/usb/devices/1-1:1.0/0003:*/input/input*/event*; do
      [ -e "$e" ] && { echo /dev/input/${e##*/}; return 0; }
    done
    sleep 0.1; i=$((i + 1))
  done
  return 1
}
# Attach the twin on port $1 and read its mouse's events into /tmp/ev$2.bin.
attach() {
  usbip --tcp-port $1 attach -r 10.0.2.2 -b 1-1 || return 1
  ev=$(node) || return 2
  cat $ev > /tmp/ev$2.bin &
  echo "@@EVENT $ev"
}
# A file as gzip + base64 between markers.
send() { echo "@@FILE $1"; gzip -c $1 | base64; echo "@@END"; }
echo "@@READY"
while IFS= read -r line; do
  eval "$line"
  echo "@@DONE $?"
done
poweroff -f
"""


def initramfs(root, release, lab, out):
    c = Cpio()
    c.entry("dev", 0o040755)
    c.made = {"dev"}
    c.entry("dev/console", 0o020600, rdev=(5, 1))
    for d in ["proc", "sys", "tmp", "var", "root", "bin", "sbin", "usr", "usr/bin", "usr/sbin"]:
        if d not in c.made:
            c.made.add(d)
            c.entry(d, 0o040755)
    busybox = os.path.join(root, "bin/busybox")
    c.file("bin/busybox", open(busybox, "rb").read())
    for applet in run(busybox, "--list").split():
        if applet != "busybox":
            c.link(f"bin/{applet}", "busybox")
    c.file("init", INIT.encode())
    order = module_order(root, release)
    for name, path in order:
        c.file(f"lib/modules/{name}.ko", open(path, "rb").read(), 0o100644)
    c.file("modules.order", "\n".join(n for n, _ in order).encode() + b"\n", 0o100644)
    lib_dirs = [os.path.join(root, d) for d in ["lib/x86_64-linux-gnu", "usr/lib/x86_64-linux-gnu"]]
    usbip = os.path.join(root, "usr/sbin/usbip")
    c.file("usr/sbin/usbip", open(usbip, "rb").read())
    c.file("bin/lab", open(lab, "rb").read())
    libs = sorted(set(shared_libraries(usbip, lib_dirs) + shared_libraries(lab, lib_dirs)))
    for lib in libs:
        c.file(lib, open(os.path.realpath(lib), "rb").read())
    with open(out, "wb") as f:
        f.write(c.bytes())
    return [n for n, _ in order], libs


# --- the guest ---------------------------------------------------------------------------


class Guest:
    """QEMU with the guest's console on a pipe: commands in, lines out."""

    def __init__(self, kernel, initrd, qmp_path, log_path):
        self.qmp_path = qmp_path
        self.log = open(log_path, "w")
        self.proc = subprocess.Popen(
            ["qemu-system-x86_64", "-accel", "tcg", "-m", "512", "-smp", "1",
             "-display", "none", "-monitor", "none", "-serial", "stdio", "-no-reboot",
             "-kernel", kernel, "-initrd", initrd,
             "-append", "console=ttyS0 quiet loglevel=1 panic=-1",
             "-netdev", "user,id=n0", "-device", "virtio-net-pci,netdev=n0,romfile=",
             "-qmp", f"unix:{qmp_path},server=on,wait=off"],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        self.lines = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        for raw in self.proc.stdout:
            line = raw.decode(errors="replace").rstrip("\r\n")
            self.log.write(line + "\n")
            self.log.flush()
            self.lines.put(line)
        self.lines.put(None)

    def wait_for(self, prefix, timeout):
        deadline = time.monotonic() + timeout
        seen = []
        while True:
            try:
                line = self.lines.get(timeout=max(0.0, deadline - time.monotonic()))
            except queue.Empty:
                raise TimeoutError(f"no {prefix!r} from the guest in {timeout} s")
            if line is None:
                raise RuntimeError(f"the guest stopped before {prefix!r}")
            if line.startswith(prefix):
                return line, seen
            seen.append(line)

    def sh(self, command, timeout=COMMAND_TIMEOUT_S):
        """Runs `command` in the guest's shell: its exit status and output lines."""
        self.proc.stdin.write(command.encode() + b"\n")
        self.proc.stdin.flush()
        done, out = self.wait_for("@@DONE ", timeout)
        return int(done.split()[1]), out

    def file(self, path):
        rc, out = self.sh(f"send {path}")
        if rc != 0 or "@@FILE " + path not in out:
            return None
        body = out[out.index("@@FILE " + path) + 1:out.index("@@END")]
        return gzip.decompress(base64.b64decode("".join(body)))

    def qmp(self, *commands):
        s = socket.socket(socket.AF_UNIX)
        s.connect(self.qmp_path)
        f = s.makefile("rw")
        f.readline()
        for cmd in ("qmp_capabilities",) + commands:
            f.write(json.dumps({"execute": cmd}) + "\n")
            f.flush()
            f.readline()
        s.close()

    def stop(self):
        if self.proc.poll() is None:
            self.proc.kill()
        self.proc.wait()
        self.log.close()


def operator(twin, *lines, gap_s=0.0):
    """Lines for the twin's operator on its standard input (`press`, `release`), `gap_s`
    apart."""
    for line in lines:
        twin.stdin.write(line + "\n")
        twin.stdin.flush()
        time.sleep(gap_s)


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


# --- what the kernel reports, judged ----------------------------------------------------


def events(blob):
    """evdev `struct input_event` records (24 bytes on x86_64): (type, code, value)."""
    n = len(blob) // 24
    return [struct.unpack_from("<qqHHi", blob, 24 * i)[2:] for i in range(n)]


def declared(descriptor):
    """What a report descriptor declares, as hid-input maps it: button numbers and relative
    axes (Generic Desktop X, Y, Wheel; Consumer AC Pan), constants skipped."""
    i, page, usages, umin, umax = 0, 0, [], None, None
    buttons, axes = set(), set()
    while i < len(descriptor):
        prefix = descriptor[i]
        size = [0, 1, 2, 4][prefix & 3]
        value = int.from_bytes(descriptor[i + 1:i + 1 + size], "little")
        kind, tag = (prefix >> 2) & 3, prefix >> 4
        i += 1 + size
        if kind == 1 and tag == 0:
            page = value
        elif kind == 2 and tag == 0:
            usages.append(value if size == 4 else (page << 16) | value)
        elif kind == 2 and tag == 1:
            umin = value
        elif kind == 2 and tag == 2:
            umax = value
        elif kind == 0:
            if tag == 8 and not value & 1:  # Input, data
                found = list(usages)
                if umin is not None and umax is not None:
                    found += [(page << 16) | u for u in range(umin, umax + 1)]
                for u in found:
                    if u >> 16 == 0x09:
                        buttons.add(u & 0xFFFF)
                    elif value & 4 and u >> 16 == 0x01:
                        axes.add({0x30: "X", 0x31: "Y", 0x38: "WHEEL"}.get(u & 0xFFFF, hex(u)))
                    elif value & 4 and u == 0x000C0238:
                        axes.add("HWHEEL")
            usages, umin, umax = [], None, None
    # hid-input adds the high-resolution wheel events beside each wheel (Linux 5.0 and on).
    axes |= {a + "_HI_RES" for a in axes if a in ("WHEEL", "HWHEEL")}
    return buttons, axes


def bitmap(text):
    """A sysfs capability bitmap (hex words, most significant first) as a set of bits."""
    bits, words = set(), text.split()
    for k, w in enumerate(reversed(words)):
        v = int(w, 16)
        bits |= {64 * k + b for b in range(64) if v >> b & 1}
    return bits


def device_lines(dmesg):
    """The kernel log's lines about the device (raw `<level>` prefix kept)."""
    pat = re.compile(r"usb 1-1|1-1:1\.|1209:0001|usbhid|vhci_hcd: ")
    return [l for l in dmesg if pat.search(l)]


def mouse_reports(usbmon):
    """The mouse reports the USB core completed (usbmon's text lines `C Ii:BUS:DEV:1 0:...`
    on endpoint 1, any address), as `(x, y)`: the report's bytes 1 and 2, signed, as the
    descriptor checked above lays them out (buttons, X, Y, wheel: a byte each)."""
    out = []
    for line in usbmon.splitlines():
        p = line.split()
        if len(p) > 6 and p[2] == "C" and re.fullmatch(r"Ii:\d+:\d+:1", p[3]) \
                and p[4].startswith("0:") and p[6] == "=":
            data = bytes.fromhex("".join(p[7:]))
            if len(data) >= 3:
                out.append((int.from_bytes(data[1:2], "little", signed=True),
                            int.from_bytes(data[2:3], "little", signed=True)))
    return out


def parsed(lines):
    """A command's JSON output, or {} if it printed none."""
    try:
        return json.loads("\n".join(lines))
    except ValueError:
        return {}


def codes(csv_text):
    rows = []
    for line in csv_text.splitlines():
        parts = line.split(",")
        if len(parts) == 4 and parts[0].isdigit():
            rows.append(tuple(int(p) for p in parts[1:]))
    return rows


class Stopped(Exception):
    """SIGTERM or SIGINT: the check stops, ending what it started."""


def on_signal(signum, _frame):
    raise Stopped(f"stopped by signal {signum}")


def main():
    # A CI cancel, `kill` or `timeout` sends SIGTERM: end QEMU and the twin as on any failure.
    signal.signal(signal.SIGTERM, on_signal)
    signal.signal(signal.SIGINT, on_signal)
    lab, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    os.makedirs(work, exist_ok=True)
    t_start = time.monotonic()
    host_tools()
    kpkg = kernel_package()
    release = kpkg[len("linux-image-"):]
    root = unpack(work, [kpkg] + GUEST_PACKAGES)
    kernel = vmlinux(os.path.join(root, "boot", f"vmlinuz-{release}"), os.path.join(work, "vmlinux"))
    initrd = os.path.join(work, "initramfs.cpio")
    mods, libs = initramfs(root, release, lab, initrd)
    say(f"guest: {kpkg}, {len(mods)} modules ({', '.join(mods)}), busybox, usbip and lab "
        f"with {len(libs)} shared libraries; {os.path.getsize(initrd) >> 20} MiB initramfs, "
        f"built in {time.monotonic() - t_start:.0f} s")

    scene = os.path.join(work, "scene.csv")
    run(lab, "simulate", "--scene", "adxl335-stroke", "--seconds", str(SCENE_S), "--csv", scene)
    flash = os.path.join(work, "flash.bin")
    if os.path.exists(flash):
        os.remove(flash)
    port = free_port()
    twin = subprocess.Popen(
        [lab, "twin", "--replay", scene, "--addr", f"127.0.0.1:{port}", "--json",
         "--wait-host", "120", "--flash", flash],
        stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    qmp_path = os.path.join(work, f"qmp-{os.getpid()}.sock")
    guest = Guest(kernel, initrd, qmp_path, os.path.join(work, "console.log"))
    try:
        t_boot = time.monotonic()
        _, early = guest.wait_for("@@READY", BOOT_TIMEOUT_S)
        check(not any("@@INSMOD-FAILED" in l for l in early), "every module loaded")
        rc, out = guest.sh("uname -r; cat /sys/kernel/debug/usb/usbmon/0u > /tmp/usbmon.txt &")
        check(out[:1] == [release], f"the guest runs {out[:1]}")
        rc, out = guest.sh(f"attach {port} 1")
        t_attach = time.monotonic()
        check(rc == 0, f"usbip attached the twin and hid-input made {out[-1:]} "
              f"({t_attach - t_boot:.1f} s from QEMU's start)")
        if rc != 0:
            raise RuntimeError("not attached")
        # What the kernel made of it, while it is attached.
        rc, bound = guest.sh("ls /sys/bus/usb/drivers/usbhid/")
        caps = {}
        mouse = "/sys/bus/usb/devices/1-1:1.0/0003:*"
        for name in ["ev", "key", "rel"]:
            rc, out = guest.sh(f"cat {mouse}/input/input*/capabilities/{name}")
            caps[name] = bitmap(" ".join(out))
        guest.sh(f"cat {mouse}/report_descriptor > /tmp/rdesc")
        rdesc = guest.file("/tmp/rdesc")

        # KEY pressed and released three times by the twin's operator.
        for _ in range(3):
            operator(twin, "press", gap_s=0.15)
            operator(twin, "release", gap_s=0.25)
        # The host stops for 300 ms: QEMU paused, its USB host polls nothing.
        guest.qmp("stop")
        time.sleep(0.3)
        guest.qmp("cont")
        say("the guest paused 300 ms mid-scene")

        # A bus reset with KEY held, mid-stroke: re-enumerated, the button must come again
        # and every count be sent, discarded or owed (usbhid drops the reports of its first
        # 50 ms after opening the device: the mouse's opening, imu_app::opening, waits it out).
        operator(twin, "press", gap_s=0.3)
        rc, out = guest.sh(f"usbip detach -p 00 && sleep 0.3 && attach {port} 2")
        check(rc == 0, f"detached and attached again: {out[-1:]}")
        time.sleep(0.3)
        operator(twin, "release")

        # The configuration interface on its hidraw node, through hidapi, in the guest.
        rc, out = guest.sh("ls /sys/bus/usb/devices/1-1:1.1/0003:*/hidraw/")
        check(rc == 0 and any(l.startswith("hidraw") for l in out),
              f"the configuration interface has a hidraw node: {out}")
        rc, out = guest.sh("lab device --json info")
        info = parsed(out) if rc == 0 else {}
        check("fs_hz" in info, f"lab device info in the guest: firmware {info.get('firmware')}, "
              f"{info.get('fs_hz')} Hz, profile {info.get('profile')!r}")
        rc_set, out = guest.sh("lab device config set counts_per_inch=800")
        rc_get, after = guest.sh("lab device --json config get")
        after = parsed(after)
        check(rc_set == 0 and after.get("counts_per_inch") == 800,
              f"config set counts_per_inch=800, read back by config get: "
              f"{after.get('counts_per_inch')}")
        rc_bad, out = guest.sh("lab device config set fs_hz=7")
        rc_get, again = guest.sh("lab device --json config get")
        check(rc_bad != 0 and parsed(again) == after,
              f"a refused setting (fs_hz=7, exit {rc_bad}: {out[-1:]}) changes nothing")
        rc, out = guest.sh("lab device save")
        check(rc == 0, f"save: {out[-1:]}")
        rc, out = guest.sh("lab device record --seconds 3 --out /tmp/rec.csv 2>/tmp/rec.err")
        check(rc == 0, f"record --seconds 3: {out[-1:]}")
        recording = guest.file("/tmp/rec.csv")

        out_text, _ = twin.communicate(timeout=SCENE_S + 60)
        summary = json.loads(out_text.strip().splitlines()[-1])
        time.sleep(0.5)
        rc, dmesg = guest.sh("dmesg -r")
        ev1, ev2 = guest.file("/tmp/ev1.bin"), guest.file("/tmp/ev2.bin")
        usbmon = (guest.file("/tmp/usbmon.txt") or b"").decode(errors="replace")
        diagnostics["usbmon"] = usbmon
    except (OSError, RuntimeError, TimeoutError, ValueError, subprocess.TimeoutExpired,
            Stopped) as e:
        say(f"FAIL: {e}")
        say("the guest's console, last 40 lines:")
        for l in open(os.path.join(work, "console.log")).read().splitlines()[-40:]:
            print("  " + l)
        sys.exit(1)
    finally:
        if twin.poll() is None:
            twin.kill()
            twin.wait()
        guest.stop()
        if os.path.exists(qmp_path):
            os.remove(qmp_path)

    for name, blob in [("ev1.bin", ev1), ("ev2.bin", ev2), ("recording.csv", recording),
                       ("usbmon.txt", usbmon.encode()), ("dmesg.txt", "\n".join(dmesg).encode())]:
        with open(os.path.join(work, name), "wb") as f:
            f.write(blob or b"")
    # Enumeration.
    lines = device_lines(dmesg)
    diagnostics["dmesg"] = lines
    check(any("idVendor=1209, idProduct=0001" in l for l in lines), "enumerated as 1209:0001")
    bound = " ".join(bound).split()
    check("1-1:1.0" in bound and "1-1:1.1" in bound,
          f"usbhid bound both interfaces: {[b for b in bound if b.startswith('1-1')]}")
    judged = [l for l in lines if re.match(r"<[0-4]>", l) and "vhci" not in l]
    vhci = [l for l in lines if re.match(r"<[0-4]>", l) and "vhci" in l]
    check(not judged, f"no error or warning about the device in the kernel log: {judged}")
    say(f"vhci_hcd's own warnings (reported, not judged): {vhci}")

    # The mouse.
    buttons, axes = declared(rdesc or b"")
    want_keys = {BTN_LEFT + b - 1 for b in buttons}
    got_axes = {REL_NAMES.get(b, str(b)) for b in caps["rel"]}
    check(caps["ev"] == {EV_SYN, EV_KEY, EV_REL, EV_MSC} and caps["key"] == want_keys
          and got_axes == axes,
          f"hid-input's capabilities equal the descriptor's: buttons {sorted(buttons)}, "
          f"axes {sorted(axes)} (kernel: keys {sorted(caps['key'])}, rel {sorted(got_axes)})")
    files = [events(ev1 or b""), events(ev2 or b"")]
    rel = [sum(v for t, c, v in evs if t == EV_REL and c == axis) for axis in (0, 1)
           for evs in [sum(files, [])]]
    frames = sum(1 for t, c, v in sum(files, []) if t == EV_SYN and c == 0)
    clicks = [[v for t, c, v in evs if t == EV_KEY and c == BTN_LEFT] for evs in files]
    say(f"evdev: REL sums {rel} in {frames} frames; the twin sent {summary['sent']} in "
        f"{summary['reports']} reports (discarded {summary['discarded']}, owed "
        f"{summary['undelivered']}, in flight {summary['in_flight']})")
    lost = lost_unconfirmed(rel, None, summary)
    check(lost is not None,
          f"the evdev REL sums equal the twin's count total exactly, less the unconfirmed "
          f"reports its detach dropped (unconfirmed {summary['unconfirmed']}, dropped {lost})")
    # usbmon's text reader drops events when it falls behind (it says nothing of it): its
    # record is judged only when it holds every report.
    mon = mouse_reports(usbmon)
    mon_sum = [sum(x for x, _ in mon), sum(y for _, y in mon)]
    if lost is not None and len(mon) == summary["reports"] - len(lost):
        check(mon_sum == rel, f"usbmon: the USB core completed {len(mon)} mouse reports "
              f"summing to {mon_sum}, the same")
    else:
        say(f"usbmon's reader kept {len(mon)} of the mouse reports (summing to {mon_sum}): "
            f"incomplete under load, not judged")
    check(summary["accounted"], "every count the twin produced is sent, discarded or owed")
    check(summary["sent"] != [0, 0], "the cursor moved")
    # Before the reset: three clicks, then the held press, released by the input core when
    # the device went away; after it: the held button re-sent, then its release.
    check(clicks[0] == [1, 0, 1, 0, 1, 0, 1, 0] and clicks[1] == [1, 0],
          f"every KEY press and release once, in order, the held one re-sent: {clicks}")

    # The configuration interface's recording against the scene.
    want = codes(open(scene).read())
    got = codes((recording or b"").decode())
    start = next((k for k in range(len(want) - len(got) + 1)
                  if got and want[k:k + 50] == got[:50]), None)
    check(len(got) >= 3 * 3000 * 0.9 and start is not None and want[start:start + len(got)] == got,
          f"the 3 s recording ({len(got)} samples) equals the scene's codes from sample {start}")

    say(f"kernel {release}; boot to attach {t_attach - t_boot:.1f} s; the whole check "
        f"{time.monotonic() - t_start:.0f} s")
    say("kernel log lines about the device:")
    for l in lines:
        print("  " + l)
    if failures:
        say("usbmon trace of the enumeration (first 80 lines):")
        for l in usbmon.splitlines()[:80]:
            print("  " + l)
        sys.exit(f"kernel_check: {len(failures)} check(s) failed")


if __name__ == "__main__":
    try:
        main()
    except Stopped as stopped:
        sys.exit(f"kernel_check: {stopped}")
