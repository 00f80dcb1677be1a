"""The FMI Compliance Checker (fmuCheck, built from third_party/fmuchecker into
target/third_party/fmuchecker, once per source change): an importer written by neither the
Reference-FMUs nor fmpy. It checks modelDescription.xml (-k xml) and simulates the FMU as
co-simulation (-k cs) and as Model Exchange with its own explicit Euler (-k me).

Each run must end with 0 warnings and errors from the FMU and 0 warnings and 0 errors from
the checker (the last lines of its log; at log level 4 it logs info and worse and counts
warnings and errors). The FMU is unpacked with -z, which makes the checker instantiate it
with logging on.

Timing. The checker reads the inputs from a CSV file, interpolated linearly in time. In
co-simulation, at each communication point t it sets the inputs of t, calls
fmi2DoStep(t, H) and records every variable at t + H, so a recorded row holds the inputs of
the step before it (row 0: after initialization, the inputs of t = 0). In Model Exchange it
records each step at the time of its inputs. Either way each recorded row's outputs belong
to the inputs recorded with it, which is what the oracle is given.
"""

import csv
import math
import re
import subprocess

import numpy as np
import pytest

import magic_formula as mf
from conftest import third_party_tool
from fmu_helpers import OUTPUTS

H = 0.01  # Euler step (ME) and communication step (CS) [s]
STOP = 2.0  # [s]
# All seven inputs, each over a part of its valid range (modelDescription.xml: Fz <= Fz_max =
# 10 kN, |alpha| <= 90 deg, |kappa| <= 1, |gamma| <= gamma_max = 10 deg; vx, p and T_tread act
# only through a parameter file's extensions, and have none here). Different periods, so
# the combinations vary.
SWEEP = {
    "Fz": lambda t: 5000.0 + 4000.0 * math.sin(math.pi * t / 2.0),  # 1 .. 9 kN
    "alpha": lambda t: math.radians(15.0) * math.sin(math.pi * t),
    "kappa": lambda t: 0.4 * math.sin(1.5 * math.pi * t),
    "gamma": lambda t: math.radians(8.0) * math.sin(0.5 * math.pi * t + 1.0),
    "vx": lambda t: 20.0 + 10.0 * math.sin(math.pi * t),
    "p": lambda t: 2.2e5 + 3.0e4 * math.sin(math.pi * t),
    "T_tread": lambda t: 320.0 + 20.0 * math.sin(math.pi * t),
}
INPUT_ROWS = 201  # time 0 .. STOP every H
SUMMARY = re.compile(
    r"FMU check summary:\s*FMU reported:\s*(\d+) warning\(s\) and error\(s\)\s*"
    r"Checker reported:\s*(\d+) Warning\(s\)\s*(\d+) Error\(s\)\s*\Z"
)


@pytest.fixture(scope="session")
def fmucheck():
    """fmuCheck.linux64 built from third_party/fmuchecker (reused while unchanged)."""
    return third_party_tool("fmuchecker")


@pytest.fixture(scope="module")
def input_csv(tmp_path_factory):
    """(path, {name: column}) of the checker's input file."""
    time = np.linspace(0.0, STOP, INPUT_ROWS)
    columns = {"time": time, **{n: np.array([f(t) for t in time]) for n, f in SWEEP.items()}}
    path = tmp_path_factory.mktemp("fmucheck") / "inputs.csv"
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(columns)
        for k in range(INPUT_ROWS):
            w.writerow([repr(float(c[k])) for c in columns.values()])
    return path, columns


def run_fmucheck(fmucheck, fmu_path, workdir, kind, input_path):
    """Runs the checker (kind: xml, cs or me); returns (log text, result rows as a dict of
    columns, or None for xml). Fails unless it exits with 0 and every count in its summary
    is 0."""
    log, out, unzip = workdir / f"{kind}.log", workdir / f"{kind}.csv", workdir / f"{kind}_fmu"
    unzip.mkdir()
    cmd = [str(fmucheck), "-k", kind, "-h", repr(H), "-s", repr(STOP), "-l", "4", "-f",
           "-i", str(input_path), "-o", str(out), "-e", str(log), "-z", str(unzip), fmu_path]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    text = log.read_text() if log.is_file() else ""
    assert p.returncode == 0, f"fmuCheck -k {kind}: exit status {p.returncode}\n{p.stderr}\n{text[-3000:]}"
    m = SUMMARY.search(text)
    assert m, f"fmuCheck -k {kind}: no summary at the end of its log:\n{text[-3000:]}"
    fmu, warnings, errors = map(int, m.groups())
    assert (fmu, warnings, errors) == (0, 0, 0), (
        f"fmuCheck -k {kind}: the FMU reported {fmu} warning(s) and error(s), the checker "
        f"{warnings} warning(s) and {errors} error(s):\n{text[-3000:]}"
    )
    if kind == "xml":
        return text, None
    with open(out, newline="") as f:
        header, *rows = list(csv.reader(f))
    # Every column but the String parameter is numeric.
    numeric = [i for i, name in enumerate(header) if name != "parameterFile"]
    data = np.array([[float(r[i]) for i in numeric] for r in rows])
    return text, {header[i]: data[:, j] for j, i in enumerate(numeric)}


def test_checker_accepts_the_model_description(fmucheck, fmu_path, input_csv, tmp_path):
    log, _ = run_fmucheck(fmucheck, fmu_path, tmp_path, "xml", input_csv[0])
    # It did read the model: the variable counts of modelDescription.xml.
    assert "7 inputs\n3 outputs\n" in log, log[-2000:]


@pytest.mark.parametrize("kind", ["cs", "me"])
def test_checker_simulation_is_clean_and_matches_the_formula(fmucheck, fmu_path, input_csv, tmp_path, kind):
    path, signals = input_csv
    _, result = run_fmucheck(fmucheck, fmu_path, tmp_path, kind, path)
    t = result["time"]
    np.testing.assert_allclose(t, np.arange(INPUT_ROWS) * H, rtol=0, atol=1e-12)
    for name in OUTPUTS:
        assert np.isfinite(result[name]).all(), f"{kind}: {name} not finite"
    # The inputs the FMU had: the sweep at the row's time (ME) or one step before it (CS).
    t_set = t if kind == "me" else np.concatenate(([0.0], t[:-1]))
    for name in SWEEP:
        want = np.interp(t_set, signals["time"], signals[name])
        np.testing.assert_allclose(result[name], want, rtol=1e-12, atol=1e-15, err_msg=f"{kind}: input {name}")
    # The outputs are the formula's at those inputs, row by row.
    expected = mf.tire_forces(result["Fz"], result["alpha"], result["kappa"], result["gamma"])
    where = [f"{kind} t={x:g} s" for x in t]
    for name, want in zip(OUTPUTS, expected):
        mf.assert_close(name, result[name], want, context=where)
    # The sweep reached the forces of a loaded, slipping tire (|Fx| and |Fy| of several kN).
    assert np.abs(result["Fx"]).max() > 5000.0 and np.abs(result["Fy"]).max() > 5000.0
