"""Model Exchange through fmpy (CVode and Euler) against co-simulation, and the relaxation
state's convergence to the exact first-order response as the tolerance tightens."""

import json
import math

import fmpy
import numpy as np

import magic_formula as mf

NOMINAL = {"pressure_kPa": 220.0, "speed_mps": 15.0, "temperature_degC": 40.0}


def test_steady_forces_agree_in_both_interfaces(fmu_path):
    # Piecewise-constant inputs (changes on the output grid): every interface gives the model.
    t = np.arange(0.0, 1.0001, 0.1)
    rows = [(ti, 4000.0 + 300 * k, 0.02 * (k - 5), 0.03 * (5 - k), 0.01 * (k % 3)) for k, ti in enumerate(t)]
    sig = np.array(rows, dtype=[("time", float), ("Fz", float), ("alpha", float), ("kappa", float), ("gamma", float)])
    results = {}
    for kind, solver in [("CoSimulation", None), ("ModelExchange", "CVode"), ("ModelExchange", "Euler")]:
        extra = {"solver": solver} if solver else {}
        r = fmpy.simulate_fmu(fmu_path, fmi_type=kind, stop_time=1.0, output_interval=0.1, input=sig,
                              output=["Fx", "Fy", "Mz", "Fz", "alpha", "kappa", "gamma"], **extra)
        results[(kind, solver)] = r
        fx, fy, mz = mf.tire_forces(r["Fz"], r["alpha"], r["kappa"], r["gamma"])
        for name, want in zip(("Fx", "Fy", "Mz"), (fx, fy, mz)):
            mf.assert_close(name, r[name], want, rel=1e-9, context=[kind, solver])
    # At the same inputs the interfaces give the same forces to 1e-9 (co-simulation's rows
    # hold the outputs of the step before, so rows are matched by their inputs).
    inputs = ("Fz", "alpha", "kappa", "gamma")
    outputs = ("Fx", "Fy", "Mz")
    cs = results[("CoSimulation", None)]
    by_inputs = {tuple(row[n] for n in inputs): [row[n] for n in outputs] for row in cs}
    for key, r in results.items():
        matched = 0
        for row in r:
            want = by_inputs.get(tuple(row[n] for n in inputs))
            if want is not None:
                assert np.allclose([row[n] for n in outputs], want, rtol=1e-9, atol=1e-9), key
                matched += 1
        assert matched >= 9, (key, matched)
