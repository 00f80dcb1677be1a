#!/usr/bin/env python3
"""Step steer of a single-track (bicycle) vehicle with two instances of the tire FMU, one per
axle (each stands for one tire; the axle force is twice its Fy), run two ways:

- Model Exchange: the tires' relaxation states join the vehicle's states (lateral velocity v,
  yaw rate r) in one ODE, integrated by scipy's solve_ivp; the forces answer the current slip
  angles, with no delay.
- Co-simulation at communication steps H: the master sets the slip angles at t_k, steps the
  tires, and holds their forces over [t_k, t_k + H] while it integrates the vehicle (RK4):
  the forces answer the slip angles of the step before.

Vehicle: mass 1300 kg, yaw inertia 2000 kg m^2, CG 1.1 m behind the front axle and 1.5 m
ahead of the rear one, 20 m/s; steering 1 deg (road wheel) from t = 0.2 s, ramped over 0.05 s.
Tires: the FMU's built-in 1987 coefficients, with a relaxation length of 0.5 m on Fy (and
Mz) from a parameter file. Aligning moments are not fed into the yaw balance.

Usage (from the repository root, after `cargo xtask fmu` and scripts/python-env.sh):
    .venv/bin/python demo/single_track.py [--fmu PATH] [--out DIR]
PATH is either archive: target/fmu/Pacejka87Tire.fmu (FMI 2.0, the default) or
target/fmu/Pacejka87Tire-fmi3.fmu (FMI 3.0).
Writes <out>/single_track.png and prints the steady state against linear single-track theory.
"""

import argparse
import ctypes
import json
import math
import sys
import tempfile
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
DEFAULT_FMU = REPO / "target" / "fmu" / "Pacejka87Tire.fmu"
sys.path.insert(0, str(REPO / "tests" / "python"))

G = 9.81  # m/s^2
MASS = 1300.0  # kg
YAW_INERTIA = 2000.0  # kg m^2
A = 1.1  # CG to front axle [m]
B = 1.5  # CG to rear axle [m]
SPEED = 20.0  # m/s
STEER = math.radians(1.0)  # road-wheel angle [rad]
STEER_START, STEER_RAMP = 0.2, 0.05  # s
RELAXATION_LENGTH = 0.5  # m
STOP = 3.0  # s
# Static load per tire [N]: half the axle load.
FZ_FRONT = MASS * G * B / (A + B) / 2.0
FZ_REAR = MASS * G * A / (A + B) / 2.0


def steer(t):
    return STEER * float(np.clip((t - STEER_START) / STEER_RAMP, 0.0, 1.0))


def slip_angles(v, r, t):
    """Front and rear slip angles [rad] (paper axes: positive alpha, positive Fy, to the left)."""
    return steer(t) - math.atan2(v + A * r, SPEED), -math.atan2(v - B * r, SPEED)


def vehicle_rates(v, r, fy_front, fy_rear, t):
    """(dv/dt, dr/dt) from one tire's Fy per axle (the axle has two)."""
    front, rear = 2.0 * fy_front * math.cos(steer(t)), 2.0 * fy_rear
    return (front + rear) / MASS - SPEED * r, (A * front - B * rear) / YAW_INERTIA


def parameter_file(directory):
    import magic_formula as mf

    params = mf.paper_table()
    params["extensions"] = {
        "nominal": {"pressure_kPa": 220.0, "speed_mps": SPEED, "temperature_degC": 40.0},
        "Fy": {"relaxation_length": {"sigma_m": RELAXATION_LENGTH}},
        "Mz": {"relaxation_length": {"sigma_m": RELAXATION_LENGTH}},
    }
    path = Path(directory) / "single_track_tire.json"
    path.write_text(json.dumps(params))
    return str(path)


class Tire:
    """One FMU instance, as Model Exchange or co-simulation, addressed by variable names; the
    FMI 2.0 or the FMI 3.0 archive (the calls that differ are the methods below)."""

    def __init__(self, fmu_path, unzipdir, md, name, interface, params_file, fz):
        self.fmi3 = md.fmiVersion.startswith("3")
        if self.fmi3:
            from fmpy.fmi3 import FMU3Model as Model, FMU3Slave as Slave
        else:
            from fmpy.fmi2 import FMU2Model as Model, FMU2Slave as Slave

        cls, ident = (Model, md.modelExchange) if interface == "me" else (Slave, md.coSimulation)
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        token = md.instantiationToken if self.fmi3 else md.guid
        self.fmu = cls(guid=token, unzipDirectory=unzipdir, modelIdentifier=ident.modelIdentifier,
                       instanceName=name)
        self.fmu.instantiate()
        if not self.fmi3:
            self.fmu.setupExperiment(startTime=0.0)
        self.fmu.setString([self.vr["parameterFile"]], [params_file])
        self.set_real([self.vr["Fz"], self.vr["vx"], self.vr["alpha"]], [fz, SPEED, 0.0])
        if self.fmi3:
            self.fmu.enterInitializationMode(startTime=0.0)
        else:
            self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()
        self.fy_vr = [self.vr["Fy"]]
        if interface == "me":
            if self.fmi3:
                self.fmu.updateDiscreteStates()
            else:
                self.fmu.newDiscreteStates()
            self.fmu.enterContinuousTimeMode()

    def set_real(self, vrs, values):
        (self.fmu.setFloat64 if self.fmi3 else self.fmu.setReal)(vrs, values)

    def get_real(self, vrs):
        return (self.fmu.getFloat64 if self.fmi3 else self.fmu.getReal)(vrs)

    def get_derivatives(self, buf, n):
        if self.fmi3:
            self.fmu.getContinuousStateDerivatives(buf, n)
        else:
            self.fmu.getDerivatives(buf, n)

    def cornering_stiffness(self):
        """dFy/dalpha [N/rad] in steady state (the relaxation state moved with alpha) at the
        current inputs, from one directional derivative of the FMU."""
        known = [self.vr["alpha"], self.vr["lag_Fy"]]
        return self.fmu.getDirectionalDerivative(self.fy_vr, known, [1.0, 1.0])[0]

    def free(self):
        self.fmu.terminate()
        self.fmu.freeInstance()


def open_fmu(fmu_path):
    from fmpy import extract, read_model_description

    return read_model_description(fmu_path), extract(fmu_path)


def simulate_me(fmu_path, params_file, t_eval):
    """Model Exchange: (t, yaw rate, lateral acceleration) and the front cornering stiffness."""
    from scipy.integrate import solve_ivp

    md, unzipdir = open_fmu(fmu_path)
    tires = [Tire(fmu_path, unzipdir, md, f"me-{k}", "me", params_file, fz)
             for k, fz in enumerate((FZ_FRONT, FZ_REAR))]
    stiffness = [t.cornering_stiffness() for t in tires]  # at alpha = 0
    n = 3  # states per tire
    buf = (ctypes.c_double * n)()

    def forces(t, y):
        alphas = slip_angles(y[0], y[1], t)
        out, lag_rates = [], []
        for k, (tire, alpha) in enumerate(zip(tires, alphas)):
            fmu = tire.fmu
            fmu.setTime(t)
            tire.set_real([tire.vr["alpha"]], [alpha])
            buf[:] = y[2 + n * k: 2 + n * (k + 1)]
            fmu.setContinuousStates(buf, n)
            out.append(tire.get_real(tire.fy_vr)[0])
            tire.get_derivatives(buf, n)
            lag_rates.extend(buf)
        return out, lag_rates

    def rhs(t, y):
        (fy_f, fy_r), lag_rates = forces(t, y)
        return [*vehicle_rates(y[0], y[1], fy_f, fy_r, t), *lag_rates]

    y0 = [0.0, 0.0]
    for tire in tires:
        tire.fmu.getContinuousStates(buf, n)
        y0.extend(buf)
    sol = solve_ivp(rhs, (0.0, STOP), y0, t_eval=t_eval, rtol=1e-8, atol=1e-10, max_step=0.01)
    ay = []
    for t, y in zip(sol.t, sol.y.T):
        (fy_f, fy_r), _ = forces(t, y)
        ay.append(vehicle_rates(y[0], y[1], fy_f, fy_r, t)[0] + SPEED * y[1])
    for tire in tires:
        tire.free()
    return sol.t, sol.y[1], np.array(ay), stiffness


def simulate_cs(fmu_path, params_file, h):
    """Co-simulation with communication step h: (t, yaw rate, lateral acceleration)."""
    md, unzipdir = open_fmu(fmu_path)
    tires = [Tire(fmu_path, unzipdir, md, f"cs-{k}-{h}", "cs", params_file, fz)
             for k, fz in enumerate((FZ_FRONT, FZ_REAR))]
    steps = int(round(STOP / h))
    v = r = 0.0
    ts, rs, ays = [0.0], [0.0], [0.0]
    for k in range(steps):
        t = k * h
        fy = []
        for tire, alpha in zip(tires, slip_angles(v, r, t)):
            tire.set_real([tire.vr["alpha"]], [alpha])
            tire.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
            fy.append(tire.get_real(tire.fy_vr)[0])
        # RK4 of the vehicle over [t, t + h] with the tire forces held.
        sub = 4
        dt = h / sub
        for j in range(sub):
            tj = t + j * dt
            f = lambda tt, vv, rr: vehicle_rates(vv, rr, fy[0], fy[1], tt)
            k1 = f(tj, v, r)
            k2 = f(tj + dt / 2, v + dt / 2 * k1[0], r + dt / 2 * k1[1])
            k3 = f(tj + dt / 2, v + dt / 2 * k2[0], r + dt / 2 * k2[1])
            k4 = f(tj + dt, v + dt * k3[0], r + dt * k3[1])
            v += dt / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            r += dt / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        ts.append(t + h)
        rs.append(r)
        ays.append(vehicle_rates(v, r, fy[0], fy[1], t + h)[0] + SPEED * r)
    for tire in tires:
        tire.free()
    return np.array(ts), np.array(rs), np.array(ays)


def linear_steady_yaw_rate(c_front, c_rear):
    """Linear single-track theory: r = u delta / (L + K u^2), understeer gradient
    K = (m / L) (b / C_f - a / C_r), C the axle cornering stiffnesses [N/rad]."""
    length = A + B
    k_us = MASS / length * (B / c_front - A / c_rear)
    return SPEED * STEER / (length + k_us * SPEED**2), k_us


def run(fmu_path, out_dir, steps=(0.005, 0.04)):
    with tempfile.TemporaryDirectory() as tmp:
        params_file = parameter_file(tmp)
        t_eval = np.linspace(0.0, STOP, 601)
        t_me, r_me, ay_me, stiffness = simulate_me(fmu_path, params_file, t_eval)
        cs = {h: simulate_cs(fmu_path, params_file, h) for h in steps}
    c_front, c_rear = 2.0 * stiffness[0], 2.0 * stiffness[1]
    r_linear, k_us = linear_steady_yaw_rate(c_front, c_rear)
    result = {"me": (t_me, r_me, ay_me), "cs": cs, "r_linear": r_linear, "k_us": k_us,
              "c_front": c_front, "c_rear": c_rear}
    if out_dir is not None:
        plot(result, Path(out_dir) / "single_track.png")
    return result


def rise_time(t, r, fraction=0.5):
    """When the yaw rate first reaches `fraction` of its final value [s] (linear in between)."""
    target = fraction * r[-1]
    k = int(np.argmax(r >= target))
    return t[k - 1] + (target - r[k - 1]) * (t[k] - t[k - 1]) / (r[k] - r[k - 1])


def deviation(me, tc, rc):
    """The largest |yaw rate| difference of a co-simulation run from Model Exchange [rad/s],
    at the co-simulation's communication points."""
    t, r, _ = me
    return float(np.max(np.abs(rc - np.interp(tc, t, r))))


def plot(result, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_r, ax_a) = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    t, r, ay = result["me"]
    t90 = rise_time(t, r)
    label = f"Model Exchange (no delay), 50 % yaw rate at {t90 - STEER_START:.3f} s"
    ax_r.plot(t, np.degrees(r), "k", lw=2.5, label=label)
    ax_a.plot(t, ay, "k", lw=2.5, label="Model Exchange")
    for (h, (tc, rc, ac)), color in zip(result["cs"].items(), ("tab:blue", "tab:red")):
        label = (f"co-simulation, H = {h * 1000:g} ms: up to "
                 f"{math.degrees(deviation(result['me'], tc, rc)):.2f} deg/s off")
        ax_r.plot(tc, np.degrees(rc), ".-", color=color, lw=1.2, ms=4, label=label)
        ax_a.plot(tc, ac, ".-", color=color, lw=1.2, ms=4, label=f"co-simulation, H = {h * 1000:g} ms")
    ax_r.axhline(math.degrees(result["r_linear"]), color="gray", ls="--",
                 label=f"linear theory, K = {result['k_us'] * 1000:.2f} mrad/(m/s^2)")
    ax_r.set_ylabel("yaw rate [deg/s]")
    ax_a.set_ylabel("lateral acceleration [m/s^2]")
    ax_a.set_xlabel("time [s]")
    ax_r.set_title(f"Step steer {math.degrees(STEER):g} deg at {SPEED:g} m/s, single-track vehicle, "
                   "two Pacejka87Tire FMUs (relaxation length 0.5 m)")
    for ax in (ax_r, ax_a):
        ax.grid(alpha=0.3)
        ax.legend(loc="lower right", fontsize=8)
        ax.set_xlim(0.0, 1.5)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--fmu", default=str(DEFAULT_FMU))
    p.add_argument("--out", default="out")
    args = p.parse_args()
    if not Path(args.fmu).is_file():
        print(f"FMU not found: {args.fmu} (build it with `cargo xtask fmu`)", file=sys.stderr)
        return 2
    res = run(args.fmu, args.out)
    t, r, _ = res["me"]
    print(f"axle cornering stiffnesses (FMU directional derivatives): front {res['c_front']:.0f} N/rad, "
          f"rear {res['c_rear']:.0f} N/rad; understeer gradient {res['k_us'] * 1000:.3f} mrad/(m/s^2)")
    print(f"steady yaw rate: Model Exchange {math.degrees(r[-1]):.4f} deg/s, "
          f"linear theory {math.degrees(res['r_linear']):.4f} deg/s")
    t90 = rise_time(t, r)
    print(f"Model Exchange: 50 % of the steady yaw rate {t90 - STEER_START:.3f} s after the steer")
    for h, (tc, rc, _) in res["cs"].items():
        print(f"co-simulation H = {h * 1000:g} ms: steady yaw rate {math.degrees(rc[-1]):.4f} deg/s, "
              f"50 % {1000 * (rise_time(tc, rc) - t90):+.1f} ms later than Model Exchange, "
              f"up to {math.degrees(deviation(res['me'], tc, rc)):.3f} deg/s off it")
    return 0


if __name__ == "__main__":
    sys.exit(main())
