"""The twin's count accounts as a host checks them (shared by twin_check.py and
kernel_check.py)."""


def lost_unconfirmed(got, got_n, summary):
    """The subset of the twin's unconfirmed reports (the last before each disconnect, which
    USB/IP cannot confirm) that the host lost, if the host's sum is the twin's `sent` with
    each unconfirmed report either taken out (counted sent, lost by the host: `usbip detach`
    may drop a RET_SUBMIT still in the socket) or put in (counted discarded, taken by the
    host: the bus reset reached the app in the same poll as the packet's completion, which
    usb-device then never reports, so the app counted it lost with the endpoint's buffer),
    or left as it is; and the report count likewise, unless `got_n` is None (evdev merges
    none but counts frames, not reports). None if no such assignment explains it; the
    reports put in are given negated ((-x, -y): the host has them, the twin's sent does not)."""
    unconfirmed = summary.get("unconfirmed", [])
    for code in range(3 ** len(unconfirmed)):
        # Each report's fate: 0 as counted, 1 counted sent but lost, 2 counted discarded but taken.
        fate = [(code // 3 ** k) % 3 for k in range(len(unconfirmed))]
        lost = [u for u, f in zip(unconfirmed, fate) if f == 1]
        taken = [u for u, f in zip(unconfirmed, fate) if f == 2]
        want = [summary["sent"][i] - sum(u[i] for u in lost) + sum(u[i] for u in taken)
                for i in (0, 1)]
        n = summary["reports"] - len(lost) + len(taken)
        if want == got and (got_n is None or n == got_n):
            return lost + [[-u[0], -u[1]] for u in taken]
    return None
