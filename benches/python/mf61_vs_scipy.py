#!/usr/bin/env python3
"""Benchmark: tire-gap's diagnosis against an independent, complete Magic Formula 6.1 fit made
with scipy, on the same rows and the same cross-validation folds: held-out RMS of Fx and Fy for
scipy's MF 6.1, tire-gap's own MF 6.1 reference, the verdict's model, the 1987 baseline and the
per-sweep floor, the ratio verdict / scipy MF 6.1 (the acceptance asks for at most 1.3), and the
wall time of each side.

Usage (from the repository root, after `cargo build --release` and scripts/python-env.sh):
    .venv/bin/python benches/python/mf61_vs_scipy.py [INPUTS ...] [--folds 5] [--seed 1]
        [--stability-draws N] [--json OUT.json] [--rows 56000] [--keep]
        [--one-fit] [--max-fit-rows 25000]

The speed comparison: `--one-fit --max-fit-rows 0` times one scipy MF 6.1 fit of every row of
the programme per channel (stages a-d below, no folds) against the whole diagnosis of the same
file, and prints the ratio diagnosis / one fit.

INPUTS are files or directories, as `tire-gap diagnose` takes them. Without any, a synthetic
programme shaped like a TTC drive/brake/combined programme is generated (`tire-gap synth --seed 3
--effects combined_slip,inflation_pressure`: combined-slip sweeps at several loads, cambers and
pressures; --rows rows). `tire-gap prepare` writes the rows the diagnosis fits and scores, with
the fold that holds each test block out; `tire-gap diagnose --json` (timed as a child process,
wall clock) gives its held-out RMS per channel.

The scipy side is MF 6.1 written here in numpy from the published equations (Pacejka, Tire and
Vehicle Dynamics, 3rd ed., section 4.3.2; MF-Tyre 6.1.2): Fx0 and Fy0 with their load, camber and
pressure terms, the combined-slip weights Gxa and Gyk and the kappa-induced side force SVyk; all
scaling factors 1, no turn slip, no low-speed terms; alpha* = tan(alpha), gamma* = sin(gamma), E
capped at 1. The equations are checked at start (weights 1 at zero combined slip, stiffnesses by
central differences, peak and cap). Fz0 and p0 are the median load and pressure of the rows
fitted. Only the terms the programme identifies are free, the others neutral (combined weights 1,
no SVyk): load terms when the median loads of the test blocks that sweep the channel's own slip
spread (10th to 90th percentile) at least 400 N, camber terms when their cambers spread at least
1 deg, pressure terms when their pressures spread at least 20 kPa, combined-slip terms when at
least 5 % of the rows are combined (those that also depend on load or camber, when the blocks of
the combined rows spread so). This is decided once, from the test conditions of all rows (the
test plan, not the forces), and holds for every fold's fit.

The fit goes in stages, as an engineer fits by hand: (a) the core terms on the pure-slip rows
(|kappa| < 0.01 for Fy, |alpha| < 0.5 deg for Fx; all rows if fewer than 500) from the data's
peak (99th percentile of |F| / Fz) and three stiffness starts, the best kept; (b) every
identified pure-slip term on the pure-slip rows; (c) the combined-slip terms alone on all rows,
from typical values; (d) every identified term on all rows. Each stage is one
scipy.optimize.least_squares call set up as scipy's documentation recommends for badly scaled
problems: the trust-region reflective method with the Jacobian's column norms as parameter scales
(`method="trf", x_scale="jac"`), 2-point Jacobian, no bounds. Each stage stops when a step lowers
the cost by less than 1e-6 of it, or after 200 steps: with scipy's default (1e-8, up to 100 steps
per term) the stages crawl for thousands of steps along the flat valleys of weakly identified
combined-slip terms (the combined-slip sweeps of a programme hold only a few slip angles), changing
the RMS by a fraction of a percent. The stages run once per fold on its training rows, the fold
scored on the rows it holds out (the held-out RMS is over all rows), and once on all rows (in
sample). A stage fitting more than 25,000 rows fits an evenly spaced sample of 25,000 of them,
as tire-gap's fits do. The scipy time is the fits' alone (all folds and the all-rows fit; data
loading left out).
"""

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.optimize import least_squares

REPO = Path(__file__).resolve().parents[2]
TIRE_GAP = REPO / "target" / "release" / "tire-gap"

# The built-in synthetic programme: a drive/brake/combined programme at several loads, cambers
# and pressures, with the combined-slip and inflation-pressure effects on the base tire.
SYNTH_SEED, SYNTH_EFFECTS = 3, "combined_slip,inflation_pressure"

# Pure-slip rows: the other slip near zero (|kappa| < 1 % for Fy, |alpha| < 0.5 deg for Fx);
# stages (a) and (b) fit all rows when fewer than MIN_PURE_ROWS are pure.
PURE_KAPPA, PURE_ALPHA_DEG, MIN_PURE_ROWS = 0.01, 0.5, 500
# Combined rows: |kappa| >= 0.02 (for Fy), |alpha| >= 1 deg (for Fx); the combined-slip terms
# are free when at least COMBINED_SHARE of the rows fitted are combined.
COMBINED_KAPPA, COMBINED_ALPHA_DEG, COMBINED_SHARE = 0.02, 1.0, 0.05
# Spreads (10th to 90th percentile of the test blocks' medians) that identify the load, camber
# and pressure terms; only the blocks that sweep the channel's own slip count (95th percentile
# of |kappa| at least SWEEP_KAPPA for Fx, of |alpha| at least SWEEP_ALPHA_DEG for Fy).
SWEEP_KAPPA, SWEEP_ALPHA_DEG = 0.02, 1.0
SPREADS = {"load": ("fz_N", 400.0), "camber": ("gamma_deg", 1.0), "pressure": ("p_kPa", 20.0)}
# Largest number of rows one stage fits (an evenly spaced sample above it), as tire-gap's fits.
MAX_FIT_ROWS = 25_000
# Starts of stage (a): cornering / slip stiffness per unit load (1/rad, 1/unit slip).
STIFFNESS_STARTS = (10.0, 20.0, 40.0)
# Stopping rule of each stage: a step lowering the cost by less than FTOL of it, or MAX_STEPS
# steps (scipy's nfev, Jacobian evaluations aside).
FTOL, MAX_STEPS = 1e-6, 200
# Keeps B = K / (C D) and the camber shift (.) / Kya finite (the equations' epsilons).
EPS = 1e-6

# Each MF 6.1 coefficient: (its value when not free, its start when free, the conditions it
# needs). "core" is always identified; a term is free when all its conditions are identified.
# Combined weights are neutral (1) with rBx1 = rBy1 = 0 and SVyk is zero with rVy1 = 0; their
# starts are typical values, away from the points where the weights' gradients vanish.
TERMS = {
    "Fx": {
        "pCx1": (1.65, 1.65, {"core"}),
        "pDx1": (1.0, 1.0, {"core"}),
        "pDx2": (0.0, 0.0, {"load"}),
        "pDx3": (0.0, 0.0, {"camber"}),
        "pEx1": (0.0, 0.0, {"core"}),
        "pEx2": (0.0, 0.0, {"load"}),
        "pEx3": (0.0, 0.0, {"load"}),
        "pEx4": (0.0, 0.0, {"core"}),
        "pKx1": (20.0, 20.0, {"core"}),
        "pKx2": (0.0, 0.0, {"load"}),
        "pKx3": (0.0, 0.0, {"load"}),
        "pHx1": (0.0, 0.0, {"core"}),
        "pHx2": (0.0, 0.0, {"load"}),
        "pVx1": (0.0, 0.0, {"core"}),
        "pVx2": (0.0, 0.0, {"load"}),
        "ppx1": (0.0, 0.0, {"pressure"}),
        "ppx2": (0.0, 0.0, {"pressure"}),
        "ppx3": (0.0, 0.0, {"pressure"}),
        "ppx4": (0.0, 0.0, {"pressure"}),
        "rBx1": (0.0, 10.0, {"combined"}),
        "rBx2": (10.0, 10.0, {"combined"}),
        "rBx3": (0.0, 0.0, {"combined", "camber"}),
        "rCx1": (1.0, 1.0, {"combined"}),
        "rEx1": (0.0, 0.0, {"combined"}),
        "rEx2": (0.0, 0.0, {"combined", "load"}),
        "rHx1": (0.0, 0.0, {"combined"}),
    },
    "Fy": {
        "pCy1": (1.3, 1.3, {"core"}),
        "pDy1": (1.0, 1.0, {"core"}),
        "pDy2": (0.0, 0.0, {"load"}),
        "pDy3": (0.0, 0.0, {"camber"}),
        "pEy1": (0.0, 0.0, {"core"}),
        "pEy2": (0.0, 0.0, {"load"}),
        "pEy3": (0.0, 0.0, {"core"}),
        "pEy4": (0.0, 0.0, {"camber"}),
        "pEy5": (0.0, 0.0, {"camber"}),
        "pKy1": (20.0, 20.0, {"core"}),
        "pKy2": (2.0, 2.0, {"load"}),
        "pKy3": (0.0, 0.0, {"camber"}),
        "pKy4": (2.0, 2.0, {"load"}),
        "pKy5": (0.0, 0.0, {"camber"}),
        "pKy6": (0.0, 0.0, {"camber"}),
        "pKy7": (0.0, 0.0, {"camber", "load"}),
        "pHy1": (0.0, 0.0, {"core"}),
        "pHy2": (0.0, 0.0, {"load"}),
        "pVy1": (0.0, 0.0, {"core"}),
        "pVy2": (0.0, 0.0, {"load"}),
        "pVy3": (0.0, 0.0, {"camber"}),
        "pVy4": (0.0, 0.0, {"camber", "load"}),
        "ppy1": (0.0, 0.0, {"pressure"}),
        "ppy2": (0.0, 0.0, {"pressure", "load"}),
        "ppy3": (0.0, 0.0, {"pressure"}),
        "ppy4": (0.0, 0.0, {"pressure"}),
        "ppy5": (0.0, 0.0, {"pressure", "camber"}),
        "rBy1": (0.0, 10.0, {"combined"}),
        "rBy2": (10.0, 10.0, {"combined"}),
        "rBy3": (0.0, 0.0, {"combined"}),
        "rBy4": (0.0, 0.0, {"combined", "camber"}),
        "rCy1": (1.0, 1.0, {"combined"}),
        "rEy1": (0.0, 0.0, {"combined"}),
        "rEy2": (0.0, 0.0, {"combined", "load"}),
        "rHy1": (0.0, 0.0, {"combined"}),
        "rHy2": (0.0, 0.0, {"combined", "load"}),
        "rVy1": (0.0, 0.0, {"combined"}),
        "rVy2": (0.0, 0.0, {"combined", "load"}),
        "rVy3": (0.0, 0.0, {"combined", "camber"}),
        "rVy4": (10.0, 10.0, {"combined"}),
        "rVy5": (1.9, 1.9, {"combined"}),
        "rVy6": (10.0, 10.0, {"combined"}),
    },
}
# Per channel: the measured force's column, the peak and stiffness terms stage (a) starts from.
CHANNELS = {"Fx": ("fx_N", "pDx1", "pKx1"), "Fy": ("fy_N", "pDy1", "pKy1")}


def column(rows, name):
    """Column `name` of `rows` as floats; zeros when `tire-gap prepare` left it out."""
    return rows[name].to_numpy(float) if name in rows else np.zeros(len(rows))


def conditions(rows, nominal):
    """The model's inputs for `rows` (a DataFrame) at nominal load and pressure `nominal`
    (Fz0 [N], p0 [kPa] or None): Fz, dfz, dpi, kappa, alpha* = tan(alpha), gamma [rad] and
    gamma* = sin(gamma)."""
    fz0, p0 = nominal
    fz = column(rows, "fz_N")
    gamma = np.radians(column(rows, "gamma_deg"))
    return {
        "fz": fz,
        "dfz": (fz - fz0) / fz0,
        "dpi": (column(rows, "p_kPa") - p0) / p0 if p0 is not None else np.zeros(len(rows)),
        "kappa": column(rows, "kappa"),
        "alpha": np.tan(np.radians(column(rows, "alpha_deg"))),
        "gamma": gamma,
        "gamma_star": np.sin(gamma),
    }


def magic(B, C, D, E, x):
    """The Magic Formula sine curve D sin(C atan(B x - E (B x - atan(B x))))."""
    return D * np.sin(C * np.arctan(B * x - E * (B * x - np.arctan(B * x))))


def combined_weight(B, C, E, x, shift):
    """The MF 6.1 combined-slip weight cos(C atan(B s - E (B s - atan(B s)))) at s = x + shift,
    divided by its value at s = shift (1 where x = 0)."""

    def cosine(s):
        return np.cos(C * np.arctan(B * s - E * (B * s - np.arctan(B * s))))

    return cosine(x + shift) / cosine(shift)


def fx_pure(p, c):
    """Pure longitudinal force Fx0 [N]."""
    fz, dfz, dpi = c["fz"], c["dfz"], c["dpi"]
    kappa_x = c["kappa"] + p["pHx1"] + p["pHx2"] * dfz
    C = p["pCx1"]
    mu = (p["pDx1"] + p["pDx2"] * dfz) * (1 + p["ppx3"] * dpi + p["ppx4"] * dpi**2) * (1 - p["pDx3"] * c["gamma"] ** 2)
    D = mu * fz
    E = (p["pEx1"] + p["pEx2"] * dfz + p["pEx3"] * dfz**2) * (1 - p["pEx4"] * np.sign(kappa_x))
    K = fz * (p["pKx1"] + p["pKx2"] * dfz) * np.exp(p["pKx3"] * dfz) * (1 + p["ppx1"] * dpi + p["ppx2"] * dpi**2)
    B = K / (C * D + EPS)
    return magic(B, C, D, np.minimum(E, 1.0), kappa_x) + fz * (p["pVx1"] + p["pVx2"] * dfz)


def fx_combined(p, c):
    """Longitudinal force Fx = Gxa Fx0 [N]."""
    B = (p["rBx1"] + p["rBx3"] * c["gamma_star"] ** 2) * np.cos(np.arctan(p["rBx2"] * c["kappa"]))
    E = np.minimum(p["rEx1"] + p["rEx2"] * c["dfz"], 1.0)
    return combined_weight(B, p["rCx1"], E, c["alpha"], p["rHx1"]) * fx_pure(p, c)


def fy_pure(p, c):
    """Pure lateral force Fy0 [N] and the friction coefficient mu_y (MF 6.1's shift
    SHy = pHy1 + pHy2 dfz + (Kyg0 gamma* - SVyg) / Kya)."""
    fz, dfz, dpi, gs = c["fz"], c["dfz"], c["dpi"], c["gamma_star"]
    fz0 = fz / (1 + dfz)
    Kya = (
        p["pKy1"] * fz0 * (1 + p["ppy1"] * dpi) * (1 - p["pKy3"] * np.abs(gs))
        * np.sin(p["pKy4"] * np.arctan(fz / ((p["pKy2"] + p["pKy5"] * gs**2) * (1 + p["ppy2"] * dpi) * fz0)))
    )
    SVyg = fz * (p["pVy3"] + p["pVy4"] * dfz) * gs
    SVy = fz * (p["pVy1"] + p["pVy2"] * dfz) + SVyg
    Kyg0 = fz * (p["pKy6"] + p["pKy7"] * dfz) * (1 + p["ppy5"] * dpi)
    SHy = p["pHy1"] + p["pHy2"] * dfz + (Kyg0 * gs - SVyg) / (Kya + EPS)
    alpha_y = c["alpha"] + SHy
    C = p["pCy1"]
    mu = (p["pDy1"] + p["pDy2"] * dfz) * (1 + p["ppy3"] * dpi + p["ppy4"] * dpi**2) * (1 - p["pDy3"] * gs**2)
    D = mu * fz
    E = (p["pEy1"] + p["pEy2"] * dfz) * (1 + p["pEy5"] * gs**2 - (p["pEy3"] + p["pEy4"] * gs) * np.sign(alpha_y))
    B = Kya / (C * D + EPS)
    return magic(B, C, D, np.minimum(E, 1.0), alpha_y) + SVy, mu


def fy_combined(p, c):
    """Lateral force Fy = Gyk Fy0 + SVyk [N]."""
    fy0, mu = fy_pure(p, c)
    kappa, alpha, dfz, gs = c["kappa"], c["alpha"], c["dfz"], c["gamma_star"]
    B = (p["rBy1"] + p["rBy4"] * gs**2) * np.cos(np.arctan(p["rBy2"] * (alpha - p["rBy3"])))
    E = np.minimum(p["rEy1"] + p["rEy2"] * dfz, 1.0)
    weight = combined_weight(B, p["rCy1"], E, kappa, p["rHy1"] + p["rHy2"] * dfz)
    DVyk = mu * c["fz"] * (p["rVy1"] + p["rVy2"] * dfz + p["rVy3"] * gs) * np.cos(np.arctan(p["rVy4"] * alpha))
    SVyk = DVyk * np.sin(p["rVy5"] * np.arctan(p["rVy6"] * kappa))
    return weight * fy0 + SVyk


MODELS = {"Fx": fx_combined, "Fy": fy_combined}


def check_equations():
    """Sanity checks of the equations above (exits if one fails): at zero combined slip the
    weights are 1 and SVyk is 0; by central differences, dFx0/dkappa at kappa = 0 and Fz = Fz0
    is pKx1 Fz0, dFy0/dalpha is pKy1 Fz0 sin(pKy4 atan(1/pKy2)) and dFy0/dgamma* at alpha = 0 is
    the camber stiffness Kyg0 = pKy6 Fz0; the peak of Fx0 is pDx1 Fz0; E is capped at 1."""
    fz0, h = 4000.0, 1e-6
    p = {ch: {k: start for k, (_, start, _) in terms.items()} for ch, terms in TERMS.items()}
    p["Fx"].update(pEx1=0.3, pEx2=0.4, pDx3=2.0, pKx3=0.2, rBx3=3.0, rEx1=0.2, rHx1=0.01)
    p["Fy"].update(pEy1=-0.5, pKy2=1.7, pKy4=1.6, pKy6=0.8, pVy3=0.2, pHy1=0.0, pVy1=0.0)
    p["Fy"].update(rBy3=0.02, rHy1=0.01, rVy1=0.05, rVy3=0.3, rVy4=20.0)

    def at(kappa, alpha, gamma=0.0, fz=fz0):
        n = np.broadcast(kappa, alpha, gamma).shape or (1,)
        rows = pd.DataFrame(
            {"fz_N": np.full(n, fz), "kappa": np.broadcast_to(kappa, n), "gamma_deg": np.broadcast_to(gamma, n),
             "alpha_deg": np.degrees(np.arctan(np.broadcast_to(alpha, n)))}
        )
        return conditions(rows, (fz0, None))

    slips = np.linspace(-0.3, 0.3, 61)
    pure_fy, _ = fy_pure(p["Fy"], at(0.0, slips, 2.0, 5500.0))
    checks = {
        "Gxa = 1 at alpha = 0": (fx_combined(p["Fx"], at(slips, 0.0, 2.0, 5500.0)), fx_pure(p["Fx"], at(slips, 0.0, 2.0, 5500.0))),
        "Gyk = 1, SVyk = 0 at kappa = 0": (fy_combined(p["Fy"], at(0.0, slips, 2.0, 5500.0)), pure_fy),
        "dFx0/dkappa = pKx1 Fz0": (
            (fx_pure(p["Fx"], at(h, 0.0)) - fx_pure(p["Fx"], at(-h, 0.0))) / (2 * h), p["Fx"]["pKx1"] * fz0,
        ),
        "dFy0/dalpha = pKy1 Fz0 sin(pKy4 atan(1/pKy2))": (
            (fy_pure(p["Fy"], at(0.0, h))[0] - fy_pure(p["Fy"], at(0.0, -h))[0]) / (2 * h),
            p["Fy"]["pKy1"] * fz0 * np.sin(p["Fy"]["pKy4"] * np.arctan(1 / p["Fy"]["pKy2"])),
        ),
        "dFy0/dgamma* = pKy6 Fz0": (
            (fy_pure(p["Fy"], at(0.0, 0.0, np.degrees(h)))[0] - fy_pure(p["Fy"], at(0.0, 0.0, -np.degrees(h)))[0])
            / (2 * np.sin(h)),
            p["Fy"]["pKy6"] * fz0,
        ),
        "max Fx0 = pDx1 Fz0": (fx_pure(p["Fx"], at(np.linspace(0, 1, 200_001), 0.0)).max(), p["Fx"]["pDx1"] * fz0),
        "E capped at 1": (
            fx_pure({**p["Fx"], "pEx1": 5.0}, at(slips, 0.0)), fx_pure({**p["Fx"], "pEx1": 1.0}, at(slips, 0.0)),
        ),
    }
    for name, (value, expected) in checks.items():
        if not np.allclose(value, expected, rtol=1e-5, atol=1e-6):
            sys.exit(f"MF 6.1 equation check failed: {name}: {np.ravel(value)[:3]} != {np.ravel(expected)[:3]}")


# Rows a stage fits at most (`--max-fit-rows`; 0: all).
fit_rows_limit = MAX_FIT_ROWS


def evenly_spaced(index):
    """`index` (row positions), or an evenly spaced sample of `fit_rows_limit` of them when
    longer."""
    limit = fit_rows_limit
    if not limit or len(index) <= limit:
        return index
    return index[np.round(np.linspace(0, len(index) - 1, limit)).astype(int)]


def identified(rows, channel):
    """The conditions `rows` identify for `channel`: "core", and "load", "camber" and
    "pressure" when the medians of the test blocks that sweep the channel's own slip spread
    enough."""
    slip, reach = ("kappa", SWEEP_KAPPA) if channel == "Fx" else ("alpha_deg", SWEEP_ALPHA_DEG)
    sweeps = pd.Series(np.abs(column(rows, slip)), index=rows.index).groupby(rows["run"]).quantile(0.95) >= reach
    blocks = rows[rows["run"].map(sweeps)].groupby("run").median()
    found = {"core"}
    for condition, (name, spread) in SPREADS.items():
        if name in blocks and len(blocks) and np.ptp(np.percentile(blocks[name], [10, 90])) >= spread:
            found.add(condition)
    return found


def slip_rows(rows, channel):
    """Positions of the pure-slip rows and of the combined-slip rows of `channel` in `rows`."""
    if channel == "Fx":
        other = np.abs(column(rows, "alpha_deg"))
        return np.flatnonzero(other < PURE_ALPHA_DEG), np.flatnonzero(other >= COMBINED_ALPHA_DEG)
    other = np.abs(column(rows, "kappa"))
    return np.flatnonzero(other < PURE_KAPPA), np.flatnonzero(other >= COMBINED_KAPPA)


def free_terms(channel, found, found_combined):
    """The terms of `channel` whose conditions are identified: `found` for the pure-slip terms,
    `found_combined` (what the combined rows identify, with "combined" when enough rows are
    combined) for the combined-slip terms."""
    return [k for k, (_, _, needs) in TERMS[channel].items() if needs <= (found_combined if "combined" in needs else found)]


def fit_stage(channel, params, free, c, measured):
    """One least_squares fit (trf, x_scale="jac", 2-point Jacobian) of the terms `free` of
    `params`, the others held; returns the fitted parameters and scipy's result."""
    model = MODELS[channel]

    def residuals(x):
        return model({**params, **dict(zip(free, x))}, c) - measured

    x0 = np.array([params[k] for k in free])
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        result = least_squares(residuals, x0, method="trf", x_scale="jac", ftol=FTOL, max_nfev=MAX_STEPS)
    return {**params, **dict(zip(free, result.x))}, result


def identified_terms(channel, rows):
    """The terms the programme identifies for `channel`, decided once on all its rows from
    the test conditions alone (not the forces) and used by every fold's fit: the terms stage
    (b) frees on the pure-slip rows, and those stage (d) frees on all rows."""
    pure, combined = slip_rows(rows, channel)
    found_combined = set()
    if len(combined) >= COMBINED_SHARE * len(rows):
        found_combined = identified(rows.iloc[combined], channel) | {"combined"}
    pure_rows = rows.iloc[pure] if len(pure) >= MIN_PURE_ROWS else rows
    return (
        free_terms(channel, identified(pure_rows, channel), set()),
        free_terms(channel, identified(rows, channel), found_combined),
    )


def fit_channel(channel, rows, pure_terms, free):
    """The staged MF 6.1 fit of `channel` on `rows`, stage (b) freeing `pure_terms` and stage
    (d) `free`: returns (parameters, nominal (Fz0, p0), a log of the stages)."""
    force, peak_term, stiffness_term = CHANNELS[channel]
    terms = TERMS[channel]
    nominal = (float(rows["fz_N"].median()), float(rows["p_kPa"].median()) if "p_kPa" in rows else None)
    c_all = conditions(rows, nominal)
    y_all = rows[force].to_numpy(float)
    pure, _ = slip_rows(rows, channel)
    if len(pure) < MIN_PURE_ROWS:
        pure = np.arange(len(rows))
    log = []

    def stage(name, params, free, index):
        sample = evenly_spaced(index)
        c = {k: v[sample] for k, v in c_all.items()}
        fitted, result = fit_stage(channel, params, free, c, y_all[sample])
        log.append({
            "stage": name, "rows": len(index), "rows_fitted": len(sample), "free": len(free),
            "rms": float(np.sqrt(np.mean(result.fun**2))), "nfev": int(result.nfev), "status": int(result.status),
        })
        return fitted, result.cost

    # (a) core terms on the pure-slip rows, from the data's peak and several stiffnesses.
    neutral = {k: value for k, (value, _, _) in terms.items()}
    core = [k for k, (_, _, needs) in terms.items() if needs == {"core"}]
    peak = float(np.percentile(np.abs(y_all[pure]) / c_all["fz"][pure], 99))
    # Fy's stiffness at Fz0 is pKy1 Fz0 sin(pKy4 atan(1/pKy2)): start pKy1 so that it is the start.
    per_stiffness = 1.0 if channel == "Fx" else np.sin(neutral["pKy4"] * np.arctan(1 / neutral["pKy2"]))
    best, best_cost = None, np.inf
    for stiffness in STIFFNESS_STARTS:
        start = {**neutral, peak_term: peak, stiffness_term: stiffness / per_stiffness}
        fitted, cost = stage(f"a (stiffness {stiffness:g})", start, core, pure)
        if cost < best_cost:
            best, best_cost = fitted, cost
    # (b) every identified pure-slip term on the pure-slip rows.
    params, _ = stage("b", best, pure_terms, pure)
    everything = np.arange(len(rows))
    # (c) the combined-slip terms alone on all rows, from their typical starts.
    combined_terms = [k for k in free if "combined" in terms[k][2]]
    if combined_terms:
        params, _ = stage("c", {**params, **{k: terms[k][1] for k in combined_terms}}, combined_terms, everything)
    # (d) every identified term on all rows.
    params, _ = stage("d", params, free, everything)
    return params, nominal, log


def rms(residuals):
    """Root mean square of `residuals`."""
    return float(np.sqrt(np.mean(np.square(residuals))))


def scipy_side(rows, one_fit=False):
    """The scipy MF 6.1 fits per channel present in `rows`: held-out RMS over the folds (not
    with `one_fit`), the all-rows (in-sample) fit, the seconds spent fitting, and the seconds
    of the all-rows fits alone (one MF 6.1 fit of the programme)."""
    results, start, one_fit_seconds = {}, time.perf_counter(), 0.0
    for channel, (force, _, _) in CHANNELS.items():
        if force not in rows:
            continue
        data = rows[np.isfinite(rows[force])].reset_index(drop=True)
        folds, heldout = data["fold"].to_numpy(), np.empty(len(data))
        pure_terms, free = identified_terms(channel, data)
        fold_logs = []
        for fold in [] if one_fit else np.unique(folds):
            train, test = data[folds != fold], data[folds == fold]
            params, nominal, log = fit_channel(channel, train, pure_terms, free)
            residuals = MODELS[channel](params, conditions(test, nominal)) - test[force].to_numpy(float)
            heldout[folds == fold] = residuals
            fold_logs.append({"fold": int(fold), "heldout_rms": rms(residuals), "stages": log})
        started = time.perf_counter()
        params, nominal, log = fit_channel(channel, data, pure_terms, free)
        one_fit_seconds += time.perf_counter() - started
        in_sample = MODELS[channel](params, conditions(data, nominal)) - data[force].to_numpy(float)
        results[channel] = {
            "rows": len(data),
            "heldout_rms": None if one_fit else rms(heldout),
            "in_sample_rms": rms(in_sample),
            "nominal_load_n": nominal[0],
            "nominal_pressure_kpa": nominal[1],
            "free": free,
            "fitted": {k: float(params[k]) for k in free},
            "sampled": any(s["rows_fitted"] < s["rows"] for f in [*fold_logs, {"stages": log}] for s in f["stages"]),
            "stages": {"all rows": log, "folds": fold_logs},
        }
    return results, time.perf_counter() - start, one_fit_seconds


def run(cmd):
    """Runs `cmd` as a child process; returns (wall seconds, stdout); exits if it fails."""
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    if proc.returncode != 0:
        sys.exit(f"{' '.join(map(str, cmd))} failed:\n{proc.stderr}")
    return elapsed, proc.stdout


def tire_gap_side(ceiling):
    """Per channel of tire-gap's `ceiling`: the baseline, verdict, MF 6.1 reference and floor."""
    side = {}
    for entry in ceiling:
        reference, floor = entry.get("reference"), entry.get("floor")
        side[entry["channel"]] = {
            "baseline_rms": entry["baseline_rms"],
            "verdict_rms": entry["verdict_rms"],
            "reference": None if reference is None else {
                k: reference[k] for k in ("heldout_rms", "in_sample_rms", "fitted", "not_identified")
            },
            "floor_rms": None if floor is None else floor["rms"],
        }
    return side


def compare(scipy, gap):
    """Per channel present on either side: the scipy fit, tire-gap's numbers, and the ratio of
    the verdict's held-out RMS to scipy MF 6.1's."""
    channels = {}
    for name in CHANNELS:
        if name not in scipy and name not in gap:
            continue
        if name not in gap:
            sys.exit(f"tire-gap's diagnosis has no {name} channel but the prepared rows do")
        fit = scipy.get(name)
        channels[name] = {
            "scipy": fit,
            "tire_gap": gap[name],
            "verdict_over_scipy": gap[name]["verdict_rms"] / fit["heldout_rms"]
            if fit and fit["heldout_rms"]
            else None,
        }
    return channels


def cell(value, width, digits=1):
    """`value` right-aligned in `width` characters, or n/a."""
    return f"{value:>{width}.{digits}f}" if value is not None else f"{'n/a':>{width}}"


def print_table(summary):
    """The side-by-side table on stdout."""
    print(
        f"{summary['rows']} rows in {summary['blocks']} test blocks, {summary['folds']} folds (seed"
        f" {summary['seed']}); verdict: {', '.join(summary['verdict']) or '(none)'}"
    )
    print("held-out RMS [N]:")
    header = ["scipy MF 6.1", "tire-gap 6.1", "verdict", "1987 model", "floor", "verdict/scipy"]
    print(f"{'channel':<8}" + "".join(f"{h:>14}" for h in header))
    for name, ch in summary["channels"].items():
        fit, gap = ch["scipy"] or {}, ch["tire_gap"]
        reference = gap["reference"] or {}
        values = [fit.get("heldout_rms"), reference.get("heldout_rms"), gap["verdict_rms"], gap["baseline_rms"]]
        values.append(gap["floor_rms"])
        print(f"{name:<8}" + "".join(cell(v, 14) for v in values) + cell(ch["verdict_over_scipy"], 14, 2))
    print("in-sample RMS [N] of the MF 6.1 fits on all rows (terms free):")
    for name, ch in summary["channels"].items():
        fit, reference = ch["scipy"] or {}, ch["tire_gap"]["reference"] or {}
        print(
            f"{name:<8} scipy {cell(fit.get('in_sample_rms'), 0)} ({len(fit.get('free', []))}),"
            f" tire-gap {cell(reference.get('in_sample_rms'), 0)} ({len(reference.get('fitted', {}))})"
        )
    print(
        f"time: tire-gap diagnose {summary['tire_gap_seconds']:.1f} s (wall clock); scipy MF 6.1 fits"
        f" ({'all rows' if summary['one_fit'] else 'all folds and all rows'}) {summary['scipy_seconds']:.1f} s,"
        f" of which one fit of all rows {summary['scipy_one_fit_seconds']:.1f} s;"
        f" ratio diagnosis / one scipy fit {summary['diagnosis_over_one_fit']:.2f}"
    )
    if summary["sampled"]:
        limit = summary["max_fit_rows"]
        print(f"fits on more than {limit:,} rows fitted an evenly spaced sample of {limit:,}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("inputs", nargs="*", help="files or directories, as for `tire-gap diagnose`")
    parser.add_argument("--folds", type=int, default=5)
    parser.add_argument("--seed", type=int, default=1, help="seed of the split of blocks into folds")
    parser.add_argument("--stability-draws", type=int, help="passed to `tire-gap diagnose` (default: its own)")
    parser.add_argument("--json", type=Path, help="also write every number to this JSON file")
    parser.add_argument("--rows", type=int, default=56_000, help="rows of the synthetic programme (no inputs)")
    parser.add_argument("--tire-gap", type=Path, default=TIRE_GAP, help="the tire-gap binary")
    parser.add_argument("--keep", action="store_true", help="keep the temporary directory")
    parser.add_argument(
        "--one-fit",
        action="store_true",
        help="scipy fits all rows once per channel, no folds: the speed comparison (diagnosis / one fit)",
    )
    parser.add_argument(
        "--max-fit-rows",
        type=int,
        default=MAX_FIT_ROWS,
        help=f"rows a scipy stage fits at most, an evenly spaced sample beyond (0: all; default {MAX_FIT_ROWS})",
    )
    args = parser.parse_args()
    global fit_rows_limit
    fit_rows_limit = args.max_fit_rows
    if not args.tire_gap.is_file():
        sys.exit(f"{args.tire_gap} is missing: run `cargo build --release` first")
    check_equations()
    tmp = Path(tempfile.mkdtemp(prefix="mf61_vs_scipy_"))
    try:
        inputs = [str(Path(i).resolve()) for i in args.inputs]
        if not inputs:
            synth = ["synth", "--seed", str(SYNTH_SEED), "--rows", str(args.rows), "--effects", SYNTH_EFFECTS]
            run([args.tire_gap, *synth, "--out", tmp / "synthetic.csv"])
            inputs = [str(tmp / "synthetic.csv")]
        split = ["--folds", str(args.folds), "--seed", str(args.seed)]
        run([args.tire_gap, "prepare", *inputs, "--out", tmp / "rows.csv", *split])
        diagnose = [args.tire_gap, "diagnose", *inputs, "--json", *split]
        if args.stability_draws is not None:
            diagnose += ["--stability-draws", str(args.stability_draws)]
        t_gap, out = run(diagnose)
        report = json.loads(out)
        rows = pd.read_csv(tmp / "rows.csv")
        scipy, t_scipy, t_one_fit = scipy_side(rows, args.one_fit)
    finally:
        if args.keep:
            print(f"temporary files kept in {tmp}", file=sys.stderr)
        else:
            shutil.rmtree(tmp)
    summary = {
        "inputs": args.inputs or [f"tire-gap {' '.join(synth)}"],
        "rows": len(rows),
        "blocks": int(rows["run"].nunique()),
        "folds": args.folds,
        "seed": args.seed,
        "stability_draws": args.stability_draws,
        "verdict": report["verdict"],
        "tire_gap_seconds": t_gap,
        "scipy_seconds": t_scipy,
        "scipy_one_fit_seconds": t_one_fit,
        "diagnosis_over_one_fit": t_gap / t_one_fit,
        "one_fit": args.one_fit,
        "max_fit_rows": fit_rows_limit,
        "sampled": any(fit["sampled"] for fit in scipy.values()),
        "channels": compare(scipy, tire_gap_side(report["ceiling"])),
    }
    print_table(summary)
    if args.json:
        args.json.write_text(json.dumps(summary, indent=1) + "\n")


if __name__ == "__main__":
    main()
