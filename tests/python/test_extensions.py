"""Extensions from a parameter file (the format `tire-gap --params` writes) in the packaged FMU,
against an independent computation of their forms (docs/parameters.md, "Extensions").

The oracle reaches the forms another way than the FMU: a peak scale s_d of D = a1 Fz^2 + a2 Fz
is a1 and a2 times s_d, a stiffness scale s_k of BCD is a3 (Fy) or a3 and a4 (Mz, Fx) times
s_k, so magic_formula.tire_forces with scaled coefficients gives the scaled curve; the ply-steer
shift is a shifted slip angle, the slip-ratio shift a shifted slip ratio; the relaxation lag is
the closed-form step response.
"""

import json
import math

import fmpy
import numpy as np

import magic_formula as mf
from fmu_helpers import LOG, Tire

NOMINAL = {"pressure_kPa": 220.0, "speed_mps": 15.0, "temperature_degC": 40.0}
H = 0.01  # communication step [s]

# One parameter file with an extension of every kind except relaxation.
EXTENSIONS = {
    "Fy": {
        "combined_slip": {"B": 8.0, "C": 1.1},
        "inflation_pressure": {"k": 0.3, "d": -0.12},
    },
    "Mz": {
        "temperature": {"w": 0.25, "Topt_degC": 6.0, "k": 0.15},
        "ply_steer_conicity": {"Sh_deg": 0.3, "Sv": 1.5},
    },
    "Fx": {
        "speed_dependence": {"v": -0.06},
        "rolling_resistance": {"q1": 0.012, "q2": 0.004},
        "slip_ratio_shift": {"Sh": 0.008, "Sh_per_kN": 0.0015},
    },
}


def parameter_file(tmp_path, extensions):
    params = mf.paper_table()
    params["extensions"] = {"nominal": NOMINAL, **extensions}
    path = tmp_path / "fitted.json"
    path.write_text(json.dumps(params))
    return str(path)


def scaled(params, channel, s_k, s_d):
    """`params` with channel's peak D scaled by s_d and stiffness BCD by s_k."""
    c = params[channel]
    c["a1"] *= s_d
    c["a2"] *= s_d
    for a in ("a3",) if channel == "Fy" else ("a3", "a4"):
        c[a] *= s_k


def expected(fz, alpha, kappa, gamma, vx, p_pa, t_k):
    """(Fx, Fy, Mz) with EXTENSIONS, computed from the forms through scaled coefficients."""
    p_kpa, t_c = p_pa / 1000.0, t_k - 273.15
    p0, v0, t0 = NOMINAL["pressure_kPa"], NOMINAL["speed_mps"], NOMINAL["temperature_degC"]
    params = mf.paper_table()
    fy_ext, mz_ext, fx_ext = EXTENSIONS["Fy"], EXTENSIONS["Mz"], EXTENSIONS["Fx"]

    ip = fy_ext["inflation_pressure"]
    dp = (p_kpa - p0) / p0
    scaled(params, "Fy", 1 + ip["k"] * dp, 1 + ip["d"] * dp)

    tp = mz_ext["temperature"]
    q = ((t_c - t0 - tp["Topt_degC"]) / 50.0) ** 2
    scaled(params, "Mz", 1 + tp["k"] * (t_c - t0) / 50.0, 1 - tp["w"] * q / (1 + q))

    speed = abs(vx)
    scaled(params, "Fx", 1.0, 1 + fx_ext["speed_dependence"]["v"] * (speed - v0) / v0)

    srs = fx_ext["slip_ratio_shift"]
    shift = srs["Sh"] + srs["Sh_per_kN"] * fz / 1000.0
    fx, _, _ = mf.tire_forces(fz, alpha, kappa + shift, gamma, params=params)
    _, fy, _ = mf.tire_forces(fz, alpha, kappa, gamma, params=params)
    ply = mz_ext["ply_steer_conicity"]
    _, _, mz = mf.tire_forces(fz, alpha + math.radians(ply["Sh_deg"]), kappa, gamma, params=params)
    mz = mz + ply["Sv"]

    cs = fy_ext["combined_slip"]
    fy = fy * math.cos(cs["C"] * math.atan(cs["B"] * kappa))
    rr = fx_ext["rolling_resistance"]
    fx = fx - (rr["q1"] + rr["q2"] * speed / v0) * fz
    return fx, fy, mz


def test_every_extension_form_matches_the_independent_computation(tmp_path, unzipdir, model_description):
    path = parameter_file(tmp_path, EXTENSIONS)
    tire = Tire(unzipdir, model_description, "extensions-forms")
    try:
        tire.initialize(parameterFile=path)
        loaded = [m for _, _, m in tire.messages() if "extensions loaded" in m]
        assert len(loaded) == 1 and "Fx: speed_dependence (v = -0.06)" in loaded[0], loaded
        cases = [
            # Fz [N], alpha [rad], kappa, gamma [rad], vx [m/s], p [Pa], T_tread [K]
            (4000.0, math.radians(4.0), 0.05, math.radians(1.0), 15.0, 220e3, 313.15),
            (3000.0, math.radians(-6.0), -0.08, math.radians(-2.0), 25.0, 260e3, 353.15),
            (5500.0, math.radians(1.5), 0.12, 0.0, -8.0, 190e3, 290.15),
            (2000.0, math.radians(10.0), -0.02, math.radians(3.0), 40.0, 240e3, 333.15),
        ]
        for fz, alpha, kappa, gamma, vx, p, t in cases:
            out = tire.step(H, Fz=fz, alpha=alpha, kappa=kappa, gamma=gamma, vx=vx, p=p, T_tread=t)
            exp = expected(fz, alpha, kappa, gamma, vx, p, t)
            plain = mf.tire_forces(fz, alpha, kappa, gamma)
            for name, got, want, base in zip(("Fx", "Fy", "Mz"), out, exp, plain):
                mf.assert_close(name, got, want, rel=1e-9, context=[(fz, alpha, kappa, vx, p, t)])
                assert abs(got - base) > 1e-3 * max(abs(base), 1.0), f"{name}: extension has no effect"
        assert [m for s, _, m in tire.messages(min_status=1)] == []
    finally:
        tire.free()


def test_relaxation_length_gives_the_first_order_step_response(tmp_path, fmu_path):
    """simulate_fmu with a slip-angle step: Fy follows alpha (1 - exp(-x / sigma)), x = vx t."""
    sigma, vx, alpha = 0.5, 10.0, math.radians(3.0)
    path = parameter_file(tmp_path, {"Fy": {"relaxation_length": {"sigma_m": sigma}}})
    n = 60
    signals = np.zeros(3, dtype=[("time", float), ("alpha", float)])
    signals["time"] = [0.0, H, n * H]
    signals["alpha"] = [0.0, alpha, alpha]  # 0 in initialization, the step from t = H on
    first = len(LOG.records)
    result = fmpy.simulate_fmu(
        fmu_path,
        start_time=0.0,
        stop_time=n * H,
        output_interval=H,
        start_values={"parameterFile": path, "vx": vx},
        input=signals,
        output=["alpha", "Fy", "Mz"],
        debug_logging=True,
    )
    logged = [r[3] for r in LOG.records[first:]]
    assert any("extensions loaded: Fy: relaxation_length (sigma_m = 0.5)" in m for m in logged)
    # Row k >= 1 holds the outputs after the step from t_{k-1}; alpha acts from row 2 on, so
    # row k has travelled vx (k - 1) H with the step applied.
    k = np.arange(len(result))
    x = vx * H * np.maximum(k - 1, 0)
    lagged = alpha * (1.0 - np.exp(-x / sigma))
    _, fy, _ = mf.tire_forces(4000.0, lagged, 0.0, 0.0)
    mf.assert_close("Fy", result["Fy"], fy, rel=1e-9)
    assert 0 < result["Fy"][2] < 0.5 * result["Fy"][-1]
    # Mz has no relaxation length: it follows the step at once.
    _, _, mz = mf.tire_forces(4000.0, np.where(k >= 2, alpha, 0.0), 0.0, 0.0)
    mf.assert_close("Mz", result["Mz"], mz)
