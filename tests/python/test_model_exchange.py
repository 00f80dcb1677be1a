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


def test_relaxation_state_converges_to_the_exact_response(tmp_path, fmu_path):
    """With a relaxation length, Model Exchange (CVode) converges to the exact first-order
    response, which is what co-simulation's step computes, as the tolerance tightens."""
    sigma, vx, t0, alpha = 0.5, 10.0, 0.1, math.radians(3.0)
    params = mf.paper_table()
    params["extensions"] = {"nominal": NOMINAL, "Fy": {"relaxation_length": {"sigma_m": sigma}}}
    path = tmp_path / "relaxation.json"
    path.write_text(json.dumps(params))
    sig = np.array([(0.0, 0.0), (t0, 0.0), (t0, alpha), (1.0, alpha)], dtype=[("time", float), ("alpha", float)])
    errors = []
    for tol in (1e-4, 1e-6, 1e-8):
        r = fmpy.simulate_fmu(fmu_path, fmi_type="ModelExchange", solver="CVode", relative_tolerance=tol,
                              stop_time=1.0, output_interval=0.01, input=sig,
                              start_values={"parameterFile": str(path), "vx": vx}, output=["Fy", "lag_Fy"])
        t = r["time"]
        exact = np.where(t > t0, alpha * (1.0 - np.exp(-vx * (t - t0) / sigma)), 0.0)
        errors.append(np.max(np.abs(r["lag_Fy"] - exact)))
        # Fy is the formula at the lagged slip angle.
        _, fy, _ = mf.tire_forces(4000.0, r["lag_Fy"], 0.0, 0.0)
        mf.assert_close("Fy", r["Fy"], fy, rel=1e-9)
    assert errors[0] > errors[1] > errors[2], errors
    assert errors[2] < 1e-7, errors


def test_directional_derivatives_of_the_state_derivatives(tmp_path, unzipdir, model_description):
    """der(lag_Fy) = |vx| (alpha - lag_Fy) / sigma: its partials by hand, and dFy/dlag_Fy as
    the central difference of the independent formula."""
    from fmpy.fmi2 import FMU2Model

    sigma, vx, alpha, lag = 0.4, 12.0, 0.05, 0.02
    params = mf.paper_table()
    params["extensions"] = {"nominal": NOMINAL, "Fy": {"relaxation_length": {"sigma_m": sigma}}}
    path = tmp_path / "relaxation.json"
    path.write_text(json.dumps(params))
    vr = {v.name: v.valueReference for v in model_description.modelVariables}
    fmu = FMU2Model(guid=model_description.guid, unzipDirectory=unzipdir,
                    modelIdentifier=model_description.modelExchange.modelIdentifier, instanceName="me-derivatives")
    fmu.instantiate()
    try:
        fmu.setupExperiment(startTime=0.0)
        fmu.setString([vr["parameterFile"]], [str(path)])
        fmu.setReal([vr["vx"], vr["alpha"]], [vx, alpha])
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        fmu.newDiscreteStates()
        fmu.enterContinuousTimeMode()
        import ctypes

        states = (ctypes.c_double * 3)(0.0, lag, lag)
        fmu.setContinuousStates(states, 3)
        der = [vr["der(lag_Fy)"]]
        d = lambda known: fmu.getDirectionalDerivative(der, [vr[known]], [1.0])[0]
        assert math.isclose(d("lag_Fy"), -vx / sigma, rel_tol=1e-12)
        assert math.isclose(d("alpha"), vx / sigma, rel_tol=1e-12)
        assert math.isclose(d("vx"), (alpha - lag) / sigma, rel_tol=1e-12)
        assert d("kappa") == 0.0 and d("lag_Mz") == 0.0
        # Fy reads the lagged slip angle, not alpha.
        dfy = lambda known: fmu.getDirectionalDerivative([vr["Fy"]], [vr[known]], [1.0])[0]
        h = 1e-7
        fd = (mf.tire_forces(4000.0, lag + h, 0.0, 0.0)[1] - mf.tire_forces(4000.0, lag - h, 0.0, 0.0)[1]) / (2 * h)
        assert math.isclose(dfy("lag_Fy"), fd, rel_tol=1e-6)
        assert dfy("alpha") == 0.0
        # Standing still the states do not move, and their rates are finite zeros.
        fmu.setReal([vr["vx"]], [0.0])
        rates = (ctypes.c_double * 3)()
        fmu.getDerivatives(rates, 3)
        assert list(rates) == [0.0, 0.0, 0.0]
        assert d("alpha") == 0.0 and d("lag_Fy") == 0.0
    finally:
        fmu.terminate()
        fmu.freeInstance()
