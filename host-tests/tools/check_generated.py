"""CI check: the committed generated data is what its generators produce.

- host-tests/data/reference_truth.csv == reference_truth.py's output, byte for byte;
- the C3, C2, C1 arrays in host-tests/src/oracle/reference.rs == ar1_series.py's values;
- core/tests/data/drift_settings.csv == drift_settings_truth.py's output, byte for byte.
Run from the repository root with mpmath and sympy installed.
"""
import pathlib
import re
import subprocess
import sys

root = pathlib.Path(__file__).resolve().parents[2]
tools = root / "host-tests" / "tools"


def run(script):
    return subprocess.run([sys.executable, str(tools / script)], check=True,
                          capture_output=True, text=True).stdout


def arrays(text):
    out = {}
    for name in ("C3", "C2", "C1"):
        body = re.search(rf"const {name}: \[f64; \d+\] = \[(.*?)\];", text, re.S).group(1)
        out[name] = [float(m) for m in re.findall(r"^\s*(-?[0-9.eE+-]+),", body, re.M)]
    return out


truth = (root / "host-tests" / "data" / "reference_truth.csv").read_text()
if run("reference_truth.py") != truth:
    sys.exit("reference_truth.csv differs from reference_truth.py's output")
want = arrays(run("ar1_series.py"))
got = arrays((root / "host-tests" / "src" / "oracle" / "reference.rs").read_text())
if want != got:
    sys.exit(f"series coefficients in reference.rs differ from ar1_series.py: {want} vs {got}")
drift = (root / "core" / "tests" / "data" / "drift_settings.csv").read_text()
if run("drift_settings_truth.py") != drift:
    sys.exit("drift_settings.csv differs from drift_settings_truth.py's output")
print("generated data: reference_truth.csv, the C3/C2/C1 series and drift_settings.csv match "
      "their generators")
