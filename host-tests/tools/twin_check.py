"""CI check of the device twin with a third-party USB host: PyPI `usbip` (a user-space USB/IP
host) enumerates `cargo lab twin`, fetches the report descriptor and parses it with
hid-tools, reads reports until the scene ends, and checks that their decoded sum equals the
device's own count total exactly; it pauses 300 ms mid-scene (nothing may be lost), and
disconnects and reconnects while KEY is held (a bus reset: the button must be re-sent).

Usage: twin_check.py LAB_BINARY [--seconds S]   (exit status 1 on any failed check)
"""
import json
import socket
import subprocess
import sys
import time

from twin_accounts import lost_unconfirmed

import usbip
from usbip.classes.host import hid as usbip_hid
from usbip.classes.host.hid import HIDDriver
from usbip.transport import USBIP
from hidtools.hid import ReportDescriptor

VID_PID = (0x1209, 0x0001)
TIMEOUT_S = 30.0  # a URB may stay pending (NAK) through a long rest


def fail(msg):
    print(f"twin_check: FAIL: {msg}", file=sys.stderr)
    sys.exit(1)


class Transport(USBIP):
    """The library's transport with a socket timeout (it sets none of its own)."""

    def connect(self):
        sock = super().connect()
        sock.settimeout(TIMEOUT_S)
        return sock


def wait_for_server(transport, deadline):
    while time.monotonic() < deadline:
        try:
            return usbip.host.list_devices(transport)
        except OSError:
            time.sleep(0.1)
    fail("the twin did not listen on 127.0.0.1:3240")


def mouse_driver(handle):
    """The HID driver on the mouse interface (the first HID interface): PyPI usbip's
    HIDDriver takes the last one, which is the configuration interface."""
    drv = HIDDriver(handle)
    info = {"iface": None, "in_ep": 0x81, "out_ep": None, "in_mps": 64, "report_desc_len": 0}
    current = None
    for desc in usbip_hid.iter_descriptors(usbip_hid.fetch_config(handle)):
        if desc[1] == usbip_hid.DT_INTERFACE and len(desc) >= 9:
            current = desc[2] if desc[5] == 0x03 else None
            if current is not None and info["iface"] is None:
                info["iface"] = current
        elif current is not None and current == info["iface"]:
            if desc[1] == usbip_hid.HID_DT_HID and len(desc) >= 9:
                info["report_desc_len"] = desc[7] | (desc[8] << 8)
            elif desc[1] == usbip_hid.DT_ENDPOINT and len(desc) >= 7 and desc[2] & 0x80:
                info["in_ep"], info["in_mps"] = desc[2], desc[4] | (desc[5] << 8)
    if info["iface"] != 0:
        fail(f"the mouse is not interface 0: {info}")
    drv._discovered = info
    return drv


def decoder(rdesc_bytes):
    """The parsed descriptor's fields for buttons and X, Y (hid-tools, not our own parser)."""
    rd = ReportDescriptor.from_bytes(list(rdesc_bytes))
    report = rd.get(0, 4)
    if report is None or report.size != 4:
        fail(f"report descriptor does not describe one 4-byte input report: {rd.input_reports}")
    names = set()
    for f in report.fields:
        names.update(f.get_usage_name(i) or f.usage_name for i in range(f.count))
    if not {"X", "Y"} <= names:
        fail(f"descriptor fields {sorted(names)} lack X and Y")

    def decode(data):
        values = {"buttons": 0}
        for f in report.fields:
            if f.is_const:
                continue
            for i, v in enumerate(f.get_values(list(data))):
                name = f.get_usage_name(i) or f.usage_name
                if name in ("X", "Y", "Wheel"):
                    values[name] = v
                elif f.usage_page_name == "Button":
                    values["buttons"] |= (v & 1) << i
        return values

    return decode


def read_until_closed(drv, decode, on_report):
    """Reads interrupt IN reports until the device closes the connection."""
    while True:
        try:
            data = drv.read_report()
        except (OSError, usbip.core.USBError, ConnectionError):
            return
        if not data:
            return
        if on_report(decode(data)) is False:
            return


def main():
    lab = sys.argv[1]
    seconds = sys.argv[sys.argv.index("--seconds") + 1] if "--seconds" in sys.argv else "14"
    twin = subprocess.Popen(
        [lab, "twin", "--scene", "desk", "--seconds", seconds, "--json", "--wait-host", "60"],
        stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    transport = Transport("127.0.0.1", 3240)
    try:
        devices = wait_for_server(transport, time.monotonic() + 30)
        listed = [(d["busid"], d["idVendor"], d["idProduct"]) for d in devices]
        if ("1-1", *VID_PID) not in listed:
            fail(f"device list {listed} lacks 1-1 {VID_PID[0]:04x}:{VID_PID[1]:04x}")

        drv = mouse_driver(usbip.open(*VID_PID, busid="1-1", transport=transport))
        h = drv.handle
        dd = h.device_descriptor
        rdesc = drv.report_descriptor()
        decode = decoder(rdesc)
        # The HID class requests as usbd-hid implements them: SET_IDLE accepted, GET_IDLE
        # stalled (a STALL must come back as one, not as silence).
        drv.set_idle(0)
        try:
            drv.get_idle()
            fail("GET_IDLE answered; usbd-hid 0.10 stalls it")
        except usbip.Stall:
            pass
        if drv.get_protocol() != 1:
            fail("GET_PROTOCOL is not report protocol")
        print(f"twin_check: enumerated {dd}, report descriptor {len(rdesc)} bytes parsed by hid-tools")
        # The configuration interface (interface 1): a vendor usage page, one 64-byte input
        # and one 64-byte output report, as hid-tools reads its descriptor.
        cdesc = h.control(0x81, 0x06, 0x2200, 1, 256)
        crd = ReportDescriptor.from_bytes(list(cdesc))
        cin = crd.get(0, 64)
        if not cdesc.startswith(bytes([0x06, 0x00, 0xFF])) or cin is None or cin.size != 64:
            fail(f"configuration interface descriptor {cdesc.hex()}: not vendor 0xFF00 with a 64-byte input report")
        if [r.size for r in crd.output_reports.values()] != [64]:
            fail(f"configuration interface: output reports {crd.output_reports}, wanted one of 64 bytes")
        print(f"twin_check: configuration interface descriptor {len(cdesc)} bytes parsed by hid-tools "
              f"(vendor page, 64-byte input and output reports)")

        total = {"x": 0, "y": 0, "n": 0}
        stamps = []
        state = {"paused": False, "t0": time.monotonic(), "limit_s": 5.0}

        def add(v):
            total["x"] += v.get("X", 0)
            total["y"] += v.get("Y", 0)
            total["n"] += 1
            return v

        def count(v):
            add(v)
            stamps.append(time.monotonic())
            # Pause the host once, mid-scene, while the mouse moves.
            if not state["paused"] and total["n"] >= 40:
                state["paused"] = True
                time.sleep(0.3)
            # Then stop reading to test the reset with KEY held.
            return time.monotonic() - state["t0"] < state["limit_s"]

        read_until_closed(drv, decode, count)
        if not state["paused"]:
            fail(f"only {total['n']} reports in the first 5 s: the mouse did not move")

        # KEY held, then a disconnect and reconnect (a bus reset): the button comes again.
        twin.stdin.write("press\n")
        twin.stdin.flush()
        while True:
            if add(decode(drv.read_report())).get("buttons", 0) & 1:
                break
        drv.close()
        drv = mouse_driver(usbip.open(*VID_PID, busid="1-1", transport=transport))
        v = add(decode(drv.read_report()))
        if not v.get("buttons", 0) & 1:
            fail(f"after the reset the first report {v} does not carry the held button")
        twin.stdin.write("release\n")
        twin.stdin.flush()
        print("twin_check: held button re-sent after a disconnect and reconnect")

        # Suspend (USB/IP has none: the twin's operator suspends its bus) with remote wake-up
        # allowed, then KEY pressed: the device must signal a wake-up, the twin resumes the
        # bus as a host would, and tracking goes on.
        drv.handle.control(0x00, 0x03, 0x0001, 0, b"")  # SET_FEATURE DEVICE_REMOTE_WAKEUP
        twin.stdin.write("suspend\n")
        twin.stdin.flush()
        time.sleep(0.4)
        twin.stdin.write("press\n")
        twin.stdin.flush()
        time.sleep(0.2)
        twin.stdin.write("release\n")
        twin.stdin.flush()
        # Suspended again, untouched: the scene's next stroke must wake the host.
        time.sleep(0.3)
        twin.stdin.write("suspend\n")
        twin.stdin.flush()

        state["limit_s"] = float("inf")
        read_until_closed(drv, decode, count)
        out, _ = twin.communicate(timeout=TIMEOUT_S)
    finally:
        if twin.poll() is None:
            twin.kill()
    if twin.returncode != 0:
        fail(f"the twin exited with {twin.returncode}")
    s = json.loads(out.strip().splitlines()[-1])
    got = [total["x"], total["y"]]
    print(f"twin_check: host decoded {total['n']} reports summing to {got}; "
          f"the device sent {s['reports']} reports summing to {s['sent']}")
    lost = lost_unconfirmed(got, total["n"], s)
    if lost is None:
        fail(f"the host's sum differs from the device's (unconfirmed at disconnects: {s['unconfirmed']})")
    print(f"twin_check: unconfirmed at the disconnect: {s['unconfirmed']}, of which the host lost {lost} "
          "(negated: counted discarded by the device, taken by the host)")
    if not s["accounted"]:
        fail(f"the device's counts do not add up: {s}")
    if s["sent"] == [0, 0]:
        fail("no motion was delivered")
    # The suspend: a wake-up within 100 ms of its cause (motion seen by the probe, or KEY),
    # no sampling restart while suspended, resumed afterwards.
    print(f"twin_check: suspended at {s['suspends_ms']} ms, causes {s['causes']}, "
          f"wake-ups {s['wakes_ms']}, resumed at {s['resumes_ms']}")
    if len(s["suspends_ms"]) != 2 or len(s["wakes_ms"]) != 2 or len(s["causes"]) != 2:
        fail("each of the two suspends did not end in one remote wake-up")
    if [kind for _, kind in s["causes"]] != ["key", "motion"]:
        fail(f"wake-ups caused by {s['causes']}, wanted KEY then motion")
    latencies = [w - c for w, (c, _) in zip(s["wakes_ms"], s["causes"])]
    if not all(0 <= d <= 100 for d in latencies):
        fail(f"remote wake-ups {latencies} ms after their causes (at most 100)")
    if s["restarts_suspended"]:
        fail(f"{s['restarts_suspended']} sampling restarts while suspended (no ADC data)")
    if len(s["resumes_ms"]) != 2 or s["resumes_ms"][-1] < s["suspends_ms"][-1]:
        fail("not resumed after each suspend")
    print(f"twin_check: remote wake-ups {latencies} ms after KEY and after motion; "
          "no restart while suspended")
    window = [b - a for a, b in zip(stamps, stamps[1:]) if b - a < 0.1]
    rate = len(window) / sum(window) if window else 0.0
    print(f"twin_check: report rate while moving {rate:.0f} per s (device peak "
          f"{s['peak_report_rate_hz']} per s); {s['urbs']} URBs, {s['stalls']} stalls, "
          f"{s['imports']} imports, {s['late_ticks']} late ticks")
    print("twin_check: ok")


if __name__ == "__main__":
    main()
