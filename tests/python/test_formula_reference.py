"""The tests' own Magic Formula (magic_formula.py) against the independent reference CSV.

Everything else compares the FMU with magic_formula.py, so it must first be shown right.
"""

import math

import numpy as np

import magic_formula as mf


def test_reproduces_every_reference_row(reference_rows):
    r = reference_rows
    fx, fy, mz = mf.paper_units(mf.PAPER_TABLE, r["fz_N"], r["alpha_deg"], r["gamma_deg"], r["kappa_pct"])
    where = [
        f"Fz={a} N alpha={b} deg gamma={c} deg kappa={d} %"
        for a, b, c, d in zip(r["fz_N"], r["alpha_deg"], r["gamma_deg"], r["kappa_pct"])
    ]
    mf.assert_close("Fx", fx, r["fx_N"], context=where)
    mf.assert_close("Fy", fy, r["fy_N"], context=where)
    mf.assert_close("Mz", mz, r["mz_Nm"], context=where)


def test_si_entry_point_matches_paper_units(reference_rows):
    r = reference_rows
    fx, fy, mz = mf.tire_forces(
        r["fz_N"], np.radians(r["alpha_deg"]), r["kappa_pct"] / 100.0, np.radians(r["gamma_deg"])
    )
    mf.assert_close("Fx", fx, r["fx_N"])
    mf.assert_close("Fy", fy, r["fy_N"])
    mf.assert_close("Mz", mz, r["mz_Nm"])


def test_errata_worked_examples():
    # docs/errata.md, at 4 kN: Fy(5 deg, 0) = 3389.600985 N, Mz(5 deg, 2 deg) = -29.02908832 N.m,
    # Fx(10 %) = 4234.444513 N.
    fx, fy, mz = mf.paper_units(mf.PAPER_TABLE, 4000.0, 5.0, 2.0, 10.0)
    _, fy0, _ = mf.paper_units(mf.PAPER_TABLE, 4000.0, 5.0, 0.0, 0.0)
    assert math.isclose(fy0, 3389.600985, rel_tol=1e-9)
    assert math.isclose(mz, -29.02908832, rel_tol=1e-9)
    assert math.isclose(fx, 4234.444513, rel_tol=1e-9)


def test_cornering_stiffness_is_bcd():
    # dFy/dalpha at alpha = 0, gamma = 0 is BCD = a3 sin(a4 atan(a5 Fz)) [N/deg].
    h = 1e-5
    _, fp, _ = mf.paper_units(mf.PAPER_TABLE, 4000.0, h, 0.0, 0.0)
    _, fm, _ = mf.paper_units(mf.PAPER_TABLE, 4000.0, -h, 0.0, 0.0)
    bcd = 1078.0 * math.sin(1.82 * math.atan(0.208 * 4.0))
    assert math.isclose((fp - fm) / (2 * h), bcd, rel_tol=1e-7)


def test_clamping_and_iso_of_the_si_entry_point():
    base = mf.tire_forces(4000.0, math.pi / 2, 1.0, math.radians(10.0))
    beyond = mf.tire_forces(4000.0, 2.0, 1.7, math.radians(15.0))
    assert base == beyond
    assert mf.tire_forces(25e3, 0.1, 0.1, 0.0) == mf.tire_forces(10e3, 0.1, 0.1, 0.0)
    paper = mf.tire_forces(4000.0, 0.05, 0.08, 0.03)
    iso = mf.tire_forces(4000.0, 0.05, 0.08, 0.03, iso=True)
    assert iso == (paper[0], -paper[1], -paper[2])
    assert mf.tire_forces(0.0, 0.1, 0.1, 0.1) == (0.0, 0.0, 0.0)
