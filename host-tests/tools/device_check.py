"""CI: every `cargo lab device` command, as a user runs it, against the twin.

Usage: device_check.py LAB_BINARY WORK_DIR

Starts `lab twin` (a resting hand, its flash in WORK_DIR/flash.bin), then: info; config get;
config set of several keys; a refused value (the error names the key, exit 1, nothing
changed); an unknown key (exit 2); save; record 2 s (the file reads back through
`lab allan`); recalibrate. Restarts the twin with the flash kept: the saved settings are
there; defaults; another restart: the defaults are stored. Exits non-zero on any mismatch.
"""
import atexit
import json
import os
import subprocess
import sys
import time

LAB, WORK = sys.argv[1], sys.argv[2]
ADDR = "127.0.0.1:3240"
FLASH = os.path.join(WORK, "flash.bin")


def lab(*args, expect=0):
    r = subprocess.run([LAB, *args], capture_output=True, text=True, timeout=60)
    if r.returncode != expect:
        sys.exit(f"lab {' '.join(args)}: exit {r.returncode}, wanted {expect}\n"
                 f"{r.stdout}{r.stderr}")
    return r


def device(*args, expect=0):
    return lab("device", "--twin", ADDR, *args, expect=expect)


def config():
    return json.loads(device("--json", "config", "get").stdout)


running = []


def stop_all():
    """Every twin this check started, ended by its own id (also when a check fails)."""
    for p in running:
        if p.poll() is None:
            p.terminate()
            p.wait(timeout=10)


atexit.register(stop_all)


def twin(seconds):
    p = subprocess.Popen([LAB, "twin", "--scene", "rest", "--seconds", str(seconds),
                          "--flash", FLASH, "--addr", ADDR],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    running.append(p)
    time.sleep(0.5)
    return p


def stop(p):
    p.terminate()
    p.wait(timeout=10)


def check(cond, what):
    if not cond:
        sys.exit(f"device check: {what}")
    print(f"ok: {what}")


os.makedirs(WORK, exist_ok=True)
if os.path.exists(FLASH):
    os.remove(FLASH)

t = twin(60)
info = json.loads(device("--json", "info").stdout)
check(info["profile"].startswith("defaults") and info["fs_hz"] == 3000,
      f"a fresh twin runs the defaults: {info['profile']}, {info['fs_hz']} Hz")
before = config()
check(before["counts_per_inch"] == 800 and before["lowpass_fc_hz"] is None,
      "config get lists every key (counts_per_inch 800, lowpass off)")
device("config", "set", "counts_per_inch=1600", "lowpass_fc_hz=80", "x_sign=-1",
       "drift.hold_s=0.02", "scheme=trapezoid", "calibration_s=0.5", "fs_hz=4000")
changed = config()
check(changed["counts_per_inch"] == 1600 and changed["lowpass_fc_hz"] == 80
      and changed["x_sign"] == -1 and changed["scheme"] == "trapezoid"
      and changed["fs_hz"] == 4000,
      "config set applies seven keys as a whole")
r = device("config", "set", "counts_per_inch=3200", "adc_bits=1", expect=2)
check("adc_bits" in r.stderr, f"a value that does not validate is named: {r.stderr.strip()}")
check(config() == changed, "and nothing changed (counts_per_inch is still 1600)")
r = device("config", "set", "fs_hz=7000", expect=2)
check("fs_hz" in r.stderr, f"a rate the trigger cannot make is named: {r.stderr.strip()}")
r = device("config", "set", "cpi=3", expect=2)
check("unknown key" in r.stderr, "an unknown key is a bad argument (exit 2)")
device("save")
check(json.loads(device("--json", "info").stdout)["profile"] == "stored", "save")
rec = os.path.join(WORK, "recording.csv")
out = json.loads(device("--json", "record", "--seconds", "2", "--out", rec).stdout)
check(out["samples"] == 8000 and out["lost"] == 0 and out["fs_hz"] == 4000,
      f"record: {out['samples']} samples at {out['fs_hz']} Hz, {out['lost']} lost")
# The recording carries the device's profile: allan takes x,y,z and the scale from it.
a = lab("allan", rec, "--out", os.path.join(WORK, "allan"))
check("8000 samples at 4000 Hz" in a.stdout and "x: N_v" in a.stdout,
      "the recording reads back through lab allan, columns and scale from its profile")
r = device("recalibrate")
check(r.stdout.startswith("recalibrated in "), f"recalibrate waits: {r.stdout.splitlines()[0]}")
stop(t)

t = twin(10)
check(config() == changed, "a restarted twin runs the saved settings")
device("defaults")
check(config() == before, "defaults run")
stop(t)
t = twin(10)
check(config() == before and
      json.loads(device("--json", "info").stdout)["profile"] == "stored",
      "and are kept")
stop(t)
print("device check: every command works against the twin")
