"""fmpy.validate_fmu and fmpy.simulate_fmu sweeps against the tests' formula and the CSV.

How outputs line up with inputs (see fmu_helpers.applied_inputs): fmpy sets the inputs at
t_k, calls fmi2DoStep(t_k, h) and records at t_{k+1}, so row k >= 1 holds the outputs for
the inputs of t_{k-1}; row 0 those of t_0, computed in initialization. The sweeps put one
input value on every communication point (linear between them, never an input event) and
hold the last value one extra step: the simulation ends when the last value's outputs
are recorded. The recorded inputs are checked
to be the applied ones, which confirms this reading of fmpy's loop.
"""

import fmpy
import numpy as np
import pytest
from fmpy.validation import validate_fmu

import magic_formula as mf
from fmu_helpers import INPUTS, LOG, OUTPUTS, applied_inputs, input_signals

H = 0.01  # communication step [s]


def test_validate_fmu_finds_no_problems(fmu_path):
    assert validate_fmu(fmu_path) == []


def test_start_values_are_the_paper_table(model_description):
    """The coefficient parameters start at the paper's table (with the errata)."""
    starts = {v.name: v.start for v in model_description.modelVariables}
    for channel in ("Fy", "Mz", "Fx"):
        for coef, value in mf.PAPER_TABLE[channel].items():
            assert float(starts[f"{channel}_{coef}"]) == value, f"{channel}_{coef}"
    assert float(starts["Fz_max"]) == mf.PAPER_TABLE["limits"]["fz_max_N"]
    assert float(starts["gamma_max"]) == pytest.approx(np.radians(10.0), rel=1e-15)


def simulate_sweep(fmu_path, **columns):
    """Simulate one input value per communication point; returns (result, applied inputs).

    `columns` maps each input name to a sequence (all the same length) or a constant.
    """
    n = max(np.size(v) for v in columns.values())
    cols = {k: np.broadcast_to(np.asarray(v, float), (n,)) for k, v in columns.items()}
    cols = {k: np.append(v, v[-1]) for k, v in cols.items()}  # hold the last value a step
    signals = input_signals(np.arange(n + 1) * H, **cols)
    first = len(LOG.records)
    result = fmpy.simulate_fmu(
        fmu_path,
        start_time=0.0,
        stop_time=signals["time"][-1],
        output_interval=H,
        input=signals,
        output=list(INPUTS + OUTPUTS),
        debug_logging=True,
    )
    assert len(result) == n + 1  # rows t_0 .. t_n: row k >= 1 shows value k - 1
    assert np.allclose(result["time"], signals["time"], rtol=0, atol=1e-12)
    # Every sweep stays inside the validity range: nothing to warn about. (The capture
    # sees this instance: with debug logging its instantiation is logged.)
    logged = LOG.records[first:]
    assert any(r[0] == "Pacejka87Tire" for r in logged)
    assert [r for r in logged if r[1] >= 1] == []
    applied = applied_inputs(result, signals)
    for name in INPUTS:  # the FMU reports the inputs that were set
        np.testing.assert_allclose(result[name], applied[name], rtol=1e-15, atol=0)
    return result, applied


def assert_matches_formula(result, applied, where):
    """Every recorded row against magic_formula.tire_forces at the applied inputs."""
    expected = mf.tire_forces(applied["Fz"], applied["alpha"], applied["kappa"], applied["gamma"])
    for name, exp in zip(OUTPUTS, expected):
        mf.assert_close(name, result[name], exp, context=where)


def describe(applied):
    return [
        f"Fz={f:g} N alpha={np.degrees(a):.4g} deg kappa={k:.4g} gamma={np.degrees(g):.4g} deg"
        for f, a, k, g in zip(applied["Fz"], applied["alpha"], applied["kappa"], applied["gamma"])
    ]


def csv_hits(result, applied, rows, columns, outputs):
    """Pairs (recorded, reference) for rows whose applied inputs are a CSV row's inputs.

    `columns` maps CSV input columns to the applied values in the CSV's units.
    """
    found = {o: ([], []) for o in outputs}
    for k in range(len(result)):
        mask = np.ones(len(rows), bool)
        for col, values in columns.items():
            mask &= np.isclose(rows[col], values[k], rtol=0, atol=1e-9)
        if mask.any():
            row = rows[np.flatnonzero(mask)[0]]
            for out, col in outputs.items():
                found[out][0].append(result[out][k])
                found[out][1].append(row[col])
    return found


def test_slip_angle_sweep_at_4kN(fmu_path, reference_rows):
    alpha_deg = np.linspace(-15.0, 15.0, 121)  # 0.25 deg apart: hits every CSV slip angle
    result, applied = simulate_sweep(fmu_path, Fz=4000.0, alpha=np.radians(alpha_deg), kappa=0.0, gamma=0.0)
    assert_matches_formula(result, applied, describe(applied))
    hits = csv_hits(
        result,
        applied,
        reference_rows,
        {"fz_N": applied["Fz"], "alpha_deg": np.degrees(applied["alpha"]), "gamma_deg": np.degrees(applied["gamma"])},
        {"Fy": "fy_N", "Mz": "mz_Nm"},
    )
    assert len(hits["Fy"][0]) >= 13 + 1  # 13 CSV slip angles, the first twice (rows 0 and 1)
    for name, (got, want) in hits.items():
        mf.assert_close(name, got, want)
    # The sweep is the curve's shape, not noise: odd in alpha, saturating near 15 deg.
    fy = result["Fy"][1:]  # the sweep's 121 values, once each
    assert fy[0] < -3000.0 < 3000.0 < fy[-1]
    np.testing.assert_allclose(fy, -fy[::-1], rtol=1e-12, atol=1e-9)


@pytest.mark.parametrize("fz", [2000.0, 4000.0, 6000.0, 8000.0])
def test_braking_ramp(fmu_path, reference_rows, fz):
    kappa = -np.arange(101) * 0.5 / 100.0  # 0 .. -0.5 in 0.5 % steps
    result, applied = simulate_sweep(fmu_path, Fz=fz, alpha=0.0, kappa=kappa, gamma=0.0)
    assert_matches_formula(result, applied, describe(applied))
    hits = csv_hits(
        result, applied, reference_rows,
        {"fz_N": applied["Fz"], "kappa_pct": 100.0 * applied["kappa"]},
        {"Fx": "fx_N"},
    )
    assert len(hits["Fx"][0]) >= 7  # 0, -0.5, -1, -5, -10, -20, -50 %
    mf.assert_close("Fx", *hits["Fx"])
    assert result["Fx"].min() < -0.8 * fz  # a braking force of the order of mu Fz


@pytest.mark.parametrize("gamma_deg", [-4.0, 4.0])
def test_slip_angle_sweep_with_camber(fmu_path, reference_rows, gamma_deg):
    alpha_deg = np.linspace(-15.0, 15.0, 121)
    result, applied = simulate_sweep(
        fmu_path, Fz=4000.0, alpha=np.radians(alpha_deg), kappa=0.0, gamma=np.radians(gamma_deg)
    )
    assert_matches_formula(result, applied, describe(applied))
    hits = csv_hits(
        result, applied, reference_rows,
        {"fz_N": applied["Fz"], "alpha_deg": np.degrees(applied["alpha"]), "gamma_deg": np.degrees(applied["gamma"])},
        {"Fy": "fy_N", "Mz": "mz_Nm"},
    )
    assert len(hits["Fy"][0]) >= 13
    for name, (got, want) in hits.items():
        mf.assert_close(name, got, want)


def test_camber_ramp(fmu_path, reference_rows):
    gamma_deg = np.linspace(-4.0, 4.0, 17)  # 0.5 deg apart
    result, applied = simulate_sweep(
        fmu_path, Fz=6000.0, alpha=np.radians(5.0), kappa=0.0, gamma=np.radians(gamma_deg)
    )
    assert_matches_formula(result, applied, describe(applied))
    hits = csv_hits(
        result, applied, reference_rows,
        {"fz_N": applied["Fz"], "alpha_deg": np.degrees(applied["alpha"]), "gamma_deg": np.degrees(applied["gamma"])},
        {"Fy": "fy_N", "Mz": "mz_Nm"},
    )
    assert len(hits["Fy"][0]) >= 5  # gamma -4, -2, 0, 2, 4
    for name, (got, want) in hits.items():
        mf.assert_close(name, got, want)
    # Camber thrust: in the paper's axes, gamma > 0 adds lateral force.
    assert np.all(np.diff(result["Fy"][1:]) >= 0.0)
