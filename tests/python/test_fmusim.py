"""A third, independent co-simulation master: fmusim, the Modelica Association's reference FMU
importer (C, built from third_party/fmusim into target/third_party/fmusim, once per source
change). It validates modelDescription.xml against the FMI 2.0 schema when it loads the FMU.

Timing. fmusim reads the inputs from a CSV file and, at each communication point t, sets
them, calls fmi2DoStep(t, H) and records the outputs at t + H; the first row (t = 0) is
recorded after initialization with the inputs of t = 0. It interpolates Real continuous
inputs linearly between time stamps, and a repeated time stamp is a jump: at that instant
it uses the later row. So the input file holds reference row k over [k H, (k + 1) H)
(rows `k H, v_k` and `(k + 1) H, v_k`), and recorded row k + 1 shows the outputs of
reference row k. H is a power of two: fmusim compares the time stamps with its grid
`start + n H` exactly, and in binary these agree to the bit.
"""

import csv
import re
import subprocess

import numpy as np
import pytest

import magic_formula as mf
from conftest import third_party_tool
from fmu_helpers import INPUTS, OUTPUTS

H = 0.125  # communication step [s]
BAD_LOG_LINE = ("[Warning]", "[Discard]", "[Error]", "[Fatal]")


@pytest.fixture(scope="session")
def fmusim():
    """fmusim built from third_party/fmusim (reused while its source is unchanged)."""
    return third_party_tool("fmusim")


@pytest.fixture(params=["fmi2", "fmi3"])
def fmu_any(request, fmu_path, fmu3_path):
    """(the FMI version, the path) of each of the two archives: fmusim runs both standards."""
    return request.param, fmu_path if request.param == "fmi2" else fmu3_path


@pytest.fixture(scope="module")
def reference_inputs(reference_rows, tmp_path_factory):
    """(path of the input CSV, the reference rows' inputs in SI units)."""
    r = reference_rows
    si = {
        "Fz": r["fz_N"],
        "alpha": np.radians(r["alpha_deg"]),
        "kappa": r["kappa_pct"] / 100.0,
        "gamma": np.radians(r["gamma_deg"]),
    }
    path = tmp_path_factory.mktemp("fmusim") / "inputs.csv"
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(("time",) + INPUTS)
        for k in range(len(r)):
            values = [repr(float(si[n][k])) for n in INPUTS]
            w.writerow([repr(k * H)] + values)  # row k from k H ...
            w.writerow([repr((k + 1) * H)] + values)  # ... held until (k + 1) H
    return path, si


def run_fmusim(fmusim, fmu_path, workdir, name, *options, interface="cs"):
    """Runs the FMU in fmusim (co-simulation, or Model Exchange with interface="me");
    returns (recorded columns, stdout).

    Fails unless fmusim exits with 0 (it returns the worst FMI status) and writes nothing to
    stderr, where schema validation errors go, and unless the FMU logged nothing above OK.
    """
    out = workdir / f"{name}.csv"
    cmd = [str(fmusim), "--interface-type", interface, "--logging-on", *map(str, options),
           "--output-file", str(out), fmu_path]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and p.stderr == "", (
        f"fmusim {name}: exit status {p.returncode}\nstderr:\n{p.stderr}\nstdout (end):\n{p.stdout[-3000:]}"
    )
    bad = [line for line in p.stdout.splitlines() if line.startswith(BAD_LOG_LINE)]
    assert bad == [], f"fmusim {name}: the FMU logged problems:\n" + "\n".join(bad[:10])
    with open(out, newline="") as f:
        header, *rows = list(csv.reader(f))
    data = np.array(rows, dtype=float)
    return {col: data[:, i] for i, col in enumerate(header)}, p.stdout


def sweep(fmusim, fmu_path, reference_inputs, workdir, name, *options, steps=None):
    """The reference rows' input file through fmusim, from communication point steps[0] to
    steps[1] (default: all of them); returns what run_fmusim returns."""
    path, si = reference_inputs
    start, stop = steps or (0, len(si["Fz"]))
    return run_fmusim(
        fmusim, fmu_path, workdir, name, "--input-file", path,
        "--start-time", start * H, "--stop-time", stop * H, "--output-interval", H, *options,
    )


def calls(stdout):
    """(function, arguments, status) of every FMI call fmusim logged."""
    return re.findall(r"^(fmi[23]\w+)\((.*)\) -> (\w+)$", stdout, re.M)


def test_fmusim_reproduces_every_reference_row(fmusim, fmu_any, reference_inputs, reference_rows, tmp_path):
    _, fmu_path = fmu_any
    _, si = reference_inputs
    n = len(reference_rows)
    record = [a for v in INPUTS + OUTPUTS for a in ("--output-variable", v)]
    result, _ = sweep(fmusim, fmu_path, reference_inputs, tmp_path, "all_rows", *record)
    np.testing.assert_array_equal(result["time"], np.arange(n + 1) * H)
    # Recorded row j shows reference row behind[j]: row 0 from initialization, then one step late.
    behind = np.concatenate(([0], np.arange(n)))
    for name in INPUTS:  # the inputs fmusim had set are exactly the reference row's
        np.testing.assert_allclose(result[name], si[name][behind], rtol=1e-15, atol=0, err_msg=name)
    r = reference_rows[behind]
    where = [
        f"t={t:g} s, reference row {k}: Fz={row['fz_N']:g} N alpha={row['alpha_deg']:g} deg "
        f"gamma={row['gamma_deg']:g} deg kappa={row['kappa_pct']:g} %"
        for t, k, row in zip(result["time"], behind, r)
    ]
    for name, col in zip(OUTPUTS, ("fx_N", "fy_N", "mz_Nm")):
        mf.assert_close(name, result[name], r[col], context=where)


def test_fmusim_fmi_call_sequence_is_all_ok(fmusim, fmu_any, reference_inputs, tmp_path):
    version, fmu_path = fmu_any
    n = len(reference_inputs[1]["Fz"])
    _, log = sweep(fmusim, fmu_path, reference_inputs, tmp_path, "calls", "--log-fmi-calls")
    logged = calls(log)
    not_ok = [c for c in logged if c[2] != "OK"]
    assert not_ok == [], f"FMI calls that did not return OK: {not_ok[:10]}"
    names = [c[0] for c in logged]
    if version == "fmi2":
        assert names[:3] == ["fmi2Instantiate", "fmi2SetupExperiment", "fmi2EnterInitializationMode"]
    else:
        assert names[0] == "fmi3InstantiateCoSimulation"
        assert names.index("fmi3EnterInitializationMode") < names.index("fmi3ExitInitializationMode")
    assert names[-2:] == [f"{version}Terminate", f"{version}FreeInstance"]
    assert names.count(f"{version}ExitInitializationMode") == 1
    steps = re.findall(rf"^{version}DoStep\(currentCommunicationPoint=(\S+), communicationStepSize=(\S+),", log, re.M)
    np.testing.assert_array_equal(np.array(steps, float), [(k * H, H) for k in range(n)])


def test_fmusim_restored_state_continues_the_run(fmusim, fmu_any, reference_inputs, tmp_path):
    version, fmu_path = fmu_any
    n = len(reference_inputs[1]["Fz"])
    m = n // 2  # save after step m, restore, run the rest
    state = tmp_path / "state.bin"
    whole, _ = sweep(fmusim, fmu_path, reference_inputs, tmp_path, "whole")
    assert whole["Fy"][m] != 0.0  # the saved outputs are not the ones before any input
    first, _ = sweep(fmusim, fmu_path, reference_inputs, tmp_path, "first",
                     "--final-fmu-state-file", state, steps=(0, m))
    assert state.stat().st_size > 0
    rest, log = sweep(fmusim, fmu_path, reference_inputs, tmp_path, "rest",
                      "--initial-fmu-state-file", state, "--log-fmi-calls", steps=(m, n))
    # The restored instance is not initialized again: it deserializes and sets the state, and
    # its first row (t = m H, before any input is set) is the saved run's last.
    names = [c[0] for c in calls(log)]
    if version == "fmi2":
        expected = ["fmi2Instantiate", "fmi2DeSerializeFMUstate", "fmi2SetFMUstate", "fmi2FreeFMUstate"]
    else:
        expected = ["fmi3InstantiateCoSimulation", "fmi3DeserializeFMUState", "fmi3SetFMUState",
                    "fmi3FreeFMUState"]
    assert names[:4] == expected
    assert "fmi2SetupExperiment" not in names and f"{version}EnterInitializationMode" not in names
    for name in ("time",) + OUTPUTS:
        np.testing.assert_array_equal(first[name], whole[name][: m + 1], err_msg=f"{name}, saved run")
        np.testing.assert_array_equal(rest[name], whole[name][m:], err_msg=f"{name}, restored run")


@pytest.mark.parametrize("solver", ["euler", "cvode"])
def test_fmusim_model_exchange_reproduces_the_reference_rows(fmusim, fmu_any, reference_inputs, reference_rows,
                                                             tmp_path, solver):
    """Model Exchange in fmusim, with both of its solvers: at every output time the forces are
    the reference row's whose inputs fmusim had set then (no step of delay)."""
    _, fmu_path = fmu_any
    path, si = reference_inputs
    n = len(reference_rows)
    record = [a for v in INPUTS + OUTPUTS for a in ("--output-variable", v)]
    result, stdout = run_fmusim(
        fmusim, fmu_path, tmp_path, f"me_{solver}", "--input-file", path, "--start-time", 0.0,
        "--stop-time", n * H, "--output-interval", H, "--solver", solver, "--log-fmi-calls", *record,
        interface="me",
    )
    assert all(status == "OK" for _, _, status in calls(stdout))
    assert len(result["time"]) > n / 2
    # Each recorded row is the model at the inputs recorded with it; those are reference rows.
    ref = {tuple(float(si[k][j]) for k in INPUTS): j for j in range(n)}
    matched = 0
    for i in range(len(result["time"])):
        j = ref.get(tuple(float(result[k][i]) for k in INPUTS))
        if j is None:
            continue
        matched += 1
        for name, col, floor in (("Fx", "fx_N", 1.0), ("Fy", "fy_N", 1.0), ("Mz", "mz_Nm", 0.01)):
            want = reference_rows[col][j]
            assert abs(result[name][i] - want) <= 1e-8 * max(abs(want), floor), (name, i, j)
    assert matched > n / 2, matched
