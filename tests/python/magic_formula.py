"""An independent Python implementation of the 1987 Magic Formula (Bakker, Nyborg, Pacejka,
SAE 870421), written from the paper's formulas and tables read with the errata in docs/errata.md.

It is the tests' oracle: test_formula_reference.py checks it against every row of
tests/data/mf87_reference.csv before the FMU is compared with it.

Inside the formula: Fz in kN, alpha and gamma in degrees, slip sigma in percent (= 100 kappa).
`tire_forces` is the SI entry point with the FMU's input clamping and sign conventions.
"""

import copy
import math

import numpy as np

# Tables 1 and 2 of the paper with the errata applied (Fy a1..a8 without the stray -4.04).
PAPER_TABLE = {
    "source": "SAE 870421 Tables 1 and 2 with the errata in docs/errata.md (tests/python/magic_formula.py)",
    "Fy": {
        "C": 1.30,
        "a1": -22.1, "a2": 1011.0, "a3": 1078.0, "a4": 1.82, "a5": 0.208,
        "a6": 0.000, "a7": -0.354, "a8": 0.707,
        "a9": 0.028, "a10": 0.000, "a11": 14.8, "a12": 0.022, "a13": 0.000,
    },
    "Mz": {
        "C": 2.40,
        "a1": -2.72, "a2": -2.28, "a3": -1.86, "a4": -2.73, "a5": 0.110,
        "a6": -0.070, "a7": 0.643, "a8": -4.04,
        "a9": 0.015, "a10": -0.066, "a11": 0.945, "a12": 0.030, "a13": 0.070,
    },
    "Fx": {
        "C": 1.65,
        "a1": -21.3, "a2": 1144.0, "a3": 49.6, "a4": 226.0, "a5": 0.069,
        "a6": -0.006, "a7": 0.056, "a8": 0.486,
    },
    # Validity range of the model (the FMU's Fz_max and gamma_max start values).
    "limits": {"fz_max_N": 10000.0, "gamma_max_deg": 10.0},
}


def paper_table():
    """A fresh, mutable copy of the paper's parameter set (parameter-file schema)."""
    return copy.deepcopy(PAPER_TABLE)


def _magic(x, B, C, D, E):
    """y = D sin(C atan(B phi)), phi = (1 - E) x + (E / B) atan(B x)."""
    phi = (1.0 - E) * x + (E / B) * np.arctan(B * x)
    return D * np.sin(C * np.arctan(B * phi))


def fy_paper(p, fz_kn, alpha_deg, gamma_deg):
    """Lateral force [N]; stiffness BCD = a3 sin(a4 atan(a5 Fz))."""
    c = p["Fy"]
    D = c["a1"] * fz_kn**2 + c["a2"] * fz_kn
    BCD = c["a3"] * np.sin(c["a4"] * np.arctan(c["a5"] * fz_kn))
    return _lateral(c, fz_kn, alpha_deg, gamma_deg, D, BCD)


def mz_paper(p, fz_kn, alpha_deg, gamma_deg):
    """Aligning moment [N.m]; BCD = (a3 Fz^2 + a4 Fz) / e^(a5 Fz) (erratum 2: a5, not a3)."""
    c = p["Mz"]
    D = c["a1"] * fz_kn**2 + c["a2"] * fz_kn
    BCD = (c["a3"] * fz_kn**2 + c["a4"] * fz_kn) / np.exp(c["a5"] * fz_kn)
    return _lateral(c, fz_kn, alpha_deg, gamma_deg, D, BCD)


def _lateral(c, fz_kn, alpha_deg, gamma_deg, D, BCD):
    """Fy or Mz with the camber terms of erratum 3."""
    B = BCD / (c["C"] * D)
    E = c["a6"] * fz_kn**2 + c["a7"] * fz_kn + c["a8"]
    g = np.abs(gamma_deg)
    Sh = c["a9"] * gamma_deg
    Sv = (c["a10"] * fz_kn**2 + c["a11"] * fz_kn) * gamma_deg
    B = B * (1.0 - c["a12"] * g)  # B + dB
    E = E / (1.0 - c["a13"] * g)  # E + dE
    return _magic(alpha_deg + Sh, B, c["C"], D, E) + Sv


def fx_paper(p, fz_kn, sigma_pct):
    """Longitudinal force [N]; no camber terms."""
    c = p["Fx"]
    D = c["a1"] * fz_kn**2 + c["a2"] * fz_kn
    BCD = (c["a3"] * fz_kn**2 + c["a4"] * fz_kn) / np.exp(c["a5"] * fz_kn)
    B = BCD / (c["C"] * D)
    E = c["a6"] * fz_kn**2 + c["a7"] * fz_kn + c["a8"]
    return _magic(sigma_pct, B, c["C"], D, E)


def paper_units(p, fz_n, alpha_deg, gamma_deg, sigma_pct):
    """(Fx, Fy, Mz) for inputs in the CSV's units (N, deg, deg, percent), paper's signs.

    Fz <= 0 is a lifted wheel: all zero. Works on scalars and numpy arrays alike.
    """
    fz_n, alpha_deg, gamma_deg, sigma_pct = np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (fz_n, alpha_deg, gamma_deg, sigma_pct))
    )
    loaded = fz_n > 0.0
    fz_kn = np.where(loaded, fz_n, 1.0) / 1000.0  # any load > 0 keeps the 0/0 out
    with np.errstate(invalid="ignore", divide="ignore"):
        fx = fx_paper(p, fz_kn, sigma_pct)
        fy = fy_paper(p, fz_kn, alpha_deg, gamma_deg)
        mz = mz_paper(p, fz_kn, alpha_deg, gamma_deg)
    return tuple(np.where(loaded, v, 0.0) for v in (fx, fy, mz))


def tire_forces(fz, alpha, kappa, gamma, *, iso=False, params=None):
    """(Fx, Fy, Mz) in N, N, N.m for SI inputs (N, rad, 1, rad), as the FMU defines them.

    Inputs outside the validity range are clamped first (modelDescription.xml):
    Fz <= Fz_max, |alpha| <= 90 deg, |kappa| <= 1, |gamma| <= gamma_max.
    iso=True: ISO 8855 axes, Fy and Mz change sign, Fx, alpha and gamma do not.
    """
    p = PAPER_TABLE if params is None else params
    lim = p["limits"]
    fz = np.minimum(np.asarray(fz, dtype=float), lim["fz_max_N"])
    alpha = np.clip(alpha, -math.pi / 2, math.pi / 2)
    kappa = np.clip(kappa, -1.0, 1.0)
    g_max = math.radians(lim["gamma_max_deg"])
    gamma = np.clip(gamma, -g_max, g_max)
    fx, fy, mz = paper_units(p, fz, np.degrees(alpha), np.degrees(gamma), 100.0 * kappa)
    if iso:
        fy, mz = -fy, -mz
    return fx, fy, mz


def close(actual, expected, floor, rel=1e-8):
    """Elementwise |actual - expected| <= rel * max(|expected|, floor)."""
    actual, expected = np.asarray(actual, float), np.asarray(expected, float)
    return np.abs(actual - expected) <= rel * np.maximum(np.abs(expected), floor)


# Floors of the relative comparison: 1 N for forces, 0.01 N.m for the moment.
FLOORS = {"Fx": 1.0, "Fy": 1.0, "Mz": 0.01}


def assert_close(name, actual, expected, rel=1e-8, context=None):
    """Assert `actual` matches `expected` for output `name` (Fx, Fy or Mz) at 1e-8 relative."""
    actual = np.atleast_1d(np.asarray(actual, float))
    expected = np.atleast_1d(np.asarray(expected, float))
    ok = close(actual, expected, FLOORS[name], rel) & np.isfinite(actual)
    if not ok.all():
        bad = np.flatnonzero(~ok)
        lines = [
            f"  [{i}] {name} = {float(actual[i])!r}, expected {float(expected[i])!r}"
            + (f" at {context[i]}" if context is not None else "")
            for i in bad[:10]
        ]
        raise AssertionError(
            f"{len(bad)} of {ok.size} {name} values off by more than {rel:g} relative "
            f"(floor {FLOORS[name]}):\n" + "\n".join(lines)
        )
