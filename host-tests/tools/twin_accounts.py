"""The twin's count accounts as a host checks them (shared by twin_check.py and
kernel_check.py)."""


def lost_unconfirmed(got, got_n, summary):
    """The subset of the twin's unconfirmed reports (the last before each disconnect, which
    USB/IP cannot confirm) that the host lost, if the host's sum is the twin's `sent` minus
    exactly that subset (and its report count, unless `got_n` is None: evdev merges none but
    counts frames, not reports); None if no subset explains it."""
    unconfirmed = summary.get("unconfirmed", [])
    for mask in range(1 << len(unconfirmed)):
        lost = [u for k, u in enumerate(unconfirmed) if mask >> k & 1]
        want = [summary["sent"][i] - sum(u[i] for u in lost) for i in (0, 1)]
        if want == got and (got_n is None or summary["reports"] - len(lost) == got_n):
            return lost
    return None
