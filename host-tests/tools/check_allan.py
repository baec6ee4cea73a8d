"""CI check: `cargo lab allan` agrees with allantools' oadev (data_type="freq",
taus="octave") on the real MPU-6050 recording at every tau to 1e-6 relative.
Run from the repository root with allantools installed; needs `cargo`."""
import json
import subprocess
import sys

import allantools
import numpy as np

FILE = "host-tests/data/mpu6050-static-100hz.csv"
SCALE = 9.80665 / 16384  # +-2 g range: 16384 LSB per g
COLUMNS = ["ax", "ay", "az"]

out = subprocess.run(["cargo", "lab", "allan", FILE, "--columns", ",".join(COLUMNS),
                      "--scale", repr(SCALE), "--json"], check=True, capture_output=True,
                     text=True).stdout
ours = json.loads(out)["axes"]

lines = open(FILE).read().splitlines()
header = lines.index("ax,ay,az,gx,gy,gz")
data = np.array([[float(v) for v in l.split(",")] for l in lines[header + 1:] if l.strip()])
worst = 0.0
for k, name in enumerate(COLUMNS):
    y = data[:, k] * SCALE
    taus, adev, _, _ = allantools.oadev(y, rate=100.0, data_type="freq", taus="octave")
    mine = ours[name]
    if len(taus) != len(mine["taus_s"]):
        sys.exit(f"{name}: {len(mine['taus_s'])} taus, allantools has {len(taus)}")
    for t, a, t2, a2 in zip(taus, adev, mine["taus_s"], mine["adev_m_s2"]):
        rel = abs(a2 / a - 1.0)
        worst = max(worst, rel)
        if abs(t2 / t - 1.0) > 1e-12 or rel > 1e-6:
            sys.exit(f"{name} tau {t}: ours {a2!r}, allantools {a!r} (rel {rel:.2e})")
    print(f"allan ok: {name}: {len(taus)} taus, {taus[0]} .. {taus[-1]} s")
print(f"worst relative difference from allantools: {worst:.2e}")
