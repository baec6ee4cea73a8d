"""CI check: what `cargo lab hid` says the device sends, decoded by an independent HID parser
(hid-tools, the Linux kernel HID maintainers' tool). For each case: the descriptor is one
Mouse application with buttons 1-3, X, Y and a wheel; every report has the descriptor's size;
the decoded X and Y sum to the requested motion exactly; every report shows the requested
buttons held. Run from the repository root with hid-tools installed; needs `cargo`.
"""
import json
import subprocess
import sys

from hidtools.hid import ReportDescriptor

CASES = [  # dx, dy, buttons
    (300, -100, 1),
    (5, -3, 2),
    (0, 0, 5),
    (-127, 127, 0),
    (-1_000_000, 999_999, 7),
]


def lab_hid(dx, dy, buttons):
    out = subprocess.run(
        ["cargo", "lab", "hid", "--dx", str(dx), "--dy", str(dy), "--buttons", str(buttons), "--json"],
        check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def fail(msg):
    sys.exit(f"check_hid: {msg}")


def main():
    for dx, dy, held in CASES:
        wire = lab_hid(dx, dy, held)
        rd = ReportDescriptor.from_bytes(bytes.fromhex(wire["descriptor_hex"]))
        reports = list(rd.input_reports.values())
        if len(reports) != 1 or reports[0].application_name != "Mouse":
            fail(f"descriptor is not a single Mouse application: {[r.application_name for r in reports]}")
        rep = reports[0]
        names = [f.usage_name for f in rep.fields]
        for want in ("B1", "B2", "B3", "X", "Y", "Wheel"):
            if want not in names:
                fail(f"descriptor lacks {want}: {names}")
        sums = {"X": 0, "Y": 0, "Wheel": 0}
        for hexrep in wire["reports_hex"]:
            data = list(bytes.fromhex(hexrep))
            if len(data) != rep.size:
                fail(f"report {hexrep} is {len(data)} bytes, the descriptor says {rep.size}")
            values = {f.usage_name: f.get_values(data)[0] for f in rep.fields}
            for axis in sums:
                sums[axis] += values[axis]
            got = values["B1"] | values["B2"] << 1 | values["B3"] << 2
            if got != held:
                fail(f"({dx}, {dy}, {held}): report {hexrep} decodes buttons {got}")
        if (sums["X"], sums["Y"], sums["Wheel"]) != (dx, dy, 0):
            fail(f"({dx}, {dy}, {held}): reports sum to {sums}")
        if held and not wire["reports_hex"]:
            fail(f"({dx}, {dy}, {held}): buttons held but no report sent")
        print(f"hid ok: dx {dx:>9} dy {dy:>9} buttons {held}: {len(wire['reports_hex']):>5} reports "
              f"decode to X {sums['X']}, Y {sums['Y']}, buttons held in each")


if __name__ == "__main__":
    main()
