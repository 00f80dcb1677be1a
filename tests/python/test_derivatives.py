"""fmi2GetDirectionalDerivative through fmpy against central differences of the independent
formula of magic_formula.py (not the FMU's own code), at random points of the valid range."""

import numpy as np
import pytest

import magic_formula as mf
from fmu_helpers import Tire

INPUTS = ("Fz", "alpha", "kappa", "gamma")
OUTPUTS = ("Fx", "Fy", "Mz")
# Central-difference steps (N, rad, 1, rad).
STEPS = (1e-2, 1e-7, 1e-7, 1e-7)


@pytest.fixture
def tire(unzipdir, model_description):
    t = Tire(unzipdir, model_description, "derivatives")
    yield t
    t.free()


@pytest.mark.parametrize("iso", [False, True])
def test_directional_derivatives_match_the_independent_formula(tire, iso):
    tire.initialize(isoSignConvention=iso)
    rng = np.random.default_rng(7)
    unknown = [tire.vr(n) for n in OUTPUTS]
    known = [tire.vr(n) for n in INPUTS]
    worst = 0.0
    for _ in range(200):
        x = [rng.uniform(300.0, 7500.0), rng.uniform(-1.4, 1.4), rng.uniform(-0.9, 0.9),
             rng.uniform(-0.08, 0.08)]
        tire.step(**dict(zip(INPUTS, x)))
        for k, h in enumerate(STEPS):
            seed = [0.0] * 4
            seed[k] = 1.0
            d = tire.fmu.getDirectionalDerivative(unknown, known, seed)
            up, down = list(x), list(x)
            up[k] += h
            down[k] -= h
            fd = (np.array(mf.tire_forces(*up, iso=iso)) - np.array(mf.tire_forces(*down, iso=iso))) / (2 * h)
            err = np.abs(np.array(d) - fd) / np.maximum(np.abs(fd), 10.0)
            worst = max(worst, err.max())
            assert err.max() < 1e-5, f"d{OUTPUTS}/d{INPUTS[k]} at {x}: {d} vs {fd}"
    # A combined seed is the same combination of the columns.
    seed = [0.3, -1.0, 2.0, 0.5]
    combined = tire.fmu.getDirectionalDerivative(unknown, known, seed)
    columns = [tire.fmu.getDirectionalDerivative(unknown, known, list(np.eye(4)[k])) for k in range(4)]
    expected = sum(s * np.array(c) for s, c in zip(seed, columns))
    assert np.allclose(combined, expected, rtol=1e-12, atol=1e-9)
