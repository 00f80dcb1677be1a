#!/usr/bin/env python3
"""Design of experiments on Dask: step steers of a single-track (bicycle) vehicle whose two
axles each run an instance of the tire FMU, over a grid of speed x steer amplitude x tire
parameter set, mapped over a dask.distributed cluster.

Vehicle (the one of demo/single_track.py): mass 1300 kg, yaw inertia 2000 kg m^2, CG 1.1 m
behind the front axle and 1.5 m ahead of the rear one, static loads, no load transfer; each
axle is two tires, so its force is twice one FMU instance's Fy. Manoeuvre: the road-wheel
steer angle ramps to its amplitude over 0.1 s and is held until the vehicle is steady (from
1.5 s on, checked every 0.1 s: over the last 0.5 s the yaw rate within 0.1 % of its mean and
the lateral acceleration within 0.1 % of speed x yaw rate), at most 10 s; the steady values
are the means over those last 0.5 s. Co-simulation with fmpy's FMU2Slave at a 5 ms
communication step: the master sets the slip angles, steps the tires and integrates the
vehicle with the forces held (RK4, two substeps).

Each run instantiates its own two FMU instances and frees them; a Dask task holds one run, or
--chunk of them. The FMU and the parameter files travel to the workers inside a Dask worker
plugin, once per worker: the plugin extracts the FMU into the worker's local directory, so
workers need no shared file system.

Usage (from the repository root, after `cargo xtask fmu` and scripts/python-env.sh):
    .venv/bin/python demo/doe.py                      # 9 speeds x 8 steers x 2 tires, 2 workers
    .venv/bin/python demo/doe.py --speeds 10:30:9 --steers 0.5,1,2,4 --params a.json b.json
    .venv/bin/python demo/doe.py --runs 200           # Latin hypercube, 200 runs per tire
    .venv/bin/python demo/doe.py --scheduler tcp://host:8786 --chunk 10
Levels are a comma list (10,20,30) or start:stop:count (10:30:5). Writes <out>/doe_results.csv
(one row per run, in the order the runs finish) and <out>/doe_response.png, and prints a
summary. A run that fails (the FMU refuses its parameter file, a worker dies, ...) is a row
with status "failed" and the reason in "error"; one not steady after 10 s (at the friction
limit) is "unsteady", with the reason in "error". Exit status: 0 no run failed, 1 some runs failed,
2 FMU missing or bad arguments.
"""

import argparse
import contextlib
import csv
import io
import math
import shutil
import sys
import tempfile
import time
import uuid
from pathlib import Path

from distributed import WorkerPlugin

REPO = Path(__file__).resolve().parents[1]
DEFAULT_FMU = REPO / "target" / "fmu" / "Pacejka87Tire.fmu"
# A parameter set shipped in the repository besides the built-in coefficients: tire-gap's fit
# of a perturbed 1987 tire with a relaxation length of 0.9 m and a tread-temperature effect
# (nominal 56 degC; the FMU's T_tread input stays at its start value, 25 degC).
DEFAULT_PARAMS = (REPO / "crates" / "mf87" / "tests" / "data" / "fits"
                  / "mf87_perturbed_relaxation_temperature.json")
BUILT_IN = "built-in"  # the label of the FMU's own coefficients (no parameter file)

G = 9.81  # m/s^2
MASS = 1300.0  # kg
YAW_INERTIA = 2000.0  # kg m^2
A = 1.1  # CG to front axle [m]
B = 1.5  # CG to rear axle [m]
L = A + B  # wheelbase [m]
FZ_FRONT = MASS * G * B / L / 2.0  # static load per tire [N]
FZ_REAR = MASS * G * A / L / 2.0
RAMP = 0.1  # s, steer ramp from t = 0
MIN_HOLD, MAX_HOLD = 1.5, 10.0  # s, the simulation stops once steady, between these times
CHECK_EVERY = 0.1  # s, how often it checks
WINDOW = 0.5  # s, the steady values are means over the last WINDOW
SETTLED = 0.001  # steady: yaw rate and a_y - V r within this fraction over the window
STEP = 0.005  # communication step [s]
SUBSTEPS = 2  # RK4 steps of the vehicle per communication step

COLUMNS = (
    "run", "params", "speed_mps", "steer_deg", "status", "hold_s", "yaw_rate_degps", "yaw_gain_per_s",
    "ay_mps2", "gain_norm", "gain_norm_linear", "understeer_deg_per_g", "alpha_front_deg",
    "alpha_rear_deg", "rise_90_s", "overshoot_pct", "c_front_N_per_rad", "c_rear_N_per_rad",
    "run_s", "run_cpu_s", "worker", "error",
)


# --- one run: the vehicle and its two tires -------------------------------------------------

def simulate(unzipdir, md, params_file, speed, steer_deg, name="doe"):
    """One step steer; returns the responses (a dict of COLUMNS' response fields).

    unzipdir: the extracted FMU; md: its model description; params_file: a path or None
    (the built-in coefficients). Raises on any FMU error, with the FMU's messages."""
    from fmpy.fmi2 import FMU2Slave

    vr = {v.name: v.valueReference for v in md.modelVariables}
    delta = math.radians(steer_deg)
    tires, log = [], io.StringIO()
    try:
        # fmpy prints the FMU's messages (errors even with logging off): keep them for the row.
        with contextlib.redirect_stdout(log):
            for axle, fz in (("front", FZ_FRONT), ("rear", FZ_REAR)):
                fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir,
                                modelIdentifier=md.coSimulation.modelIdentifier,
                                instanceName=f"{name}-{axle}")
                fmu.instantiate()
                tires.append(fmu)
                fmu.setupExperiment(startTime=0.0)
                if params_file is not None:
                    fmu.setString([vr["parameterFile"]], [str(params_file)])
                fmu.setReal([vr["Fz"], vr["vx"], vr["alpha"]], [fz, speed, 0.0])
                fmu.enterInitializationMode()
                fmu.exitInitializationMode()
            # Axle cornering stiffness [N/rad] at zero slip, in steady state (the relaxation
            # state moved with alpha): one directional derivative per tire, two tires per axle.
            c_front, c_rear = (2.0 * f.getDirectionalDerivative([vr["Fy"]], [vr["alpha"], vr["lag_Fy"]],
                                                                [1.0, 1.0])[0] for f in tires)
            t_hist, r_hist, ay_hist, af_hist, ar_hist = _step_steer(tires, vr, speed, delta)
    except Exception as e:
        messages = " | ".join(line.strip() for line in log.getvalue().splitlines() if line.strip())
        raise RuntimeError(f"{type(e).__name__}: {e}" + (f" FMU: {messages}" if messages else "")) from None
    finally:
        for fmu in tires:
            with contextlib.suppress(Exception):
                fmu.terminate()
            with contextlib.suppress(Exception):
                fmu.freeInstance()

    n = int(round(WINDOW / STEP))
    r_ss = sum(r_hist[-n:]) / n
    ay = sum(ay_hist[-n:]) / n
    k_us = MASS / L * (B / c_front - A / c_rear)  # understeer gradient [rad / (m/s^2)]
    target = 0.9 * r_ss
    rise = next((t for t, r in zip(t_hist, r_hist) if r >= target), math.nan) if r_ss > 0 else math.nan
    unsteady = _unsteady(r_hist, ay_hist, speed, n)
    return {
        "status": "unsteady" if unsteady else "ok",
        "hold_s": t_hist[-1],
        "yaw_rate_degps": math.degrees(r_ss),
        "yaw_gain_per_s": r_ss / delta,
        "ay_mps2": ay,
        "gain_norm": r_ss * L / (speed * delta),
        "gain_norm_linear": 1.0 / (1.0 + k_us * speed**2 / L),
        "understeer_deg_per_g": math.degrees(k_us * G),
        "alpha_front_deg": math.degrees(sum(af_hist[-n:]) / n),
        "alpha_rear_deg": math.degrees(sum(ar_hist[-n:]) / n),
        "rise_90_s": rise,
        "overshoot_pct": 100.0 * (max(r_hist) / r_ss - 1.0) if r_ss > 0 else math.nan,
        "c_front_N_per_rad": c_front,
        "c_rear_N_per_rad": c_rear,
        "error": unsteady or "",
    }


def _unsteady(r_hist, ay_hist, speed, n):
    """Why the last n samples are not a steady state, or None: steady is the yaw rate within
    SETTLED of its mean, and the mean lateral acceleration within SETTLED of speed x yaw rate
    (the sideslip no longer drifts)."""
    r_win = r_hist[-n:]
    r_mean, ay_mean = sum(r_win) / n, sum(ay_hist[-n:]) / n
    if not r_mean:
        return "no yaw rate"
    spread = (max(r_win) - min(r_win)) / abs(r_mean)
    drift = abs(ay_mean - speed * r_mean) / abs(ay_mean) if ay_mean else math.inf
    if spread > SETTLED:
        return f"yaw rate moves {100 * spread:.2f} % in the last {WINDOW:g} s"
    if drift > SETTLED:
        return f"a_y differs from V r by {100 * drift:.2f} % in the last {WINDOW:g} s"
    return None


def _step_steer(tires, vr, speed, delta):
    """Co-simulation of the step steer, from MIN_HOLD s on until steady or MAX_HOLD s;
    histories at the communication points."""
    front, rear = tires
    alpha_vr, fy_vr = [vr["alpha"]], [vr["Fy"]]
    mass, inertia = MASS, YAW_INERTIA

    def steer(t):
        return delta * min(max(t / RAMP, 0.0), 1.0)

    def rates(t, v, r, fy_f, fy_r):
        f = 2.0 * fy_f * math.cos(steer(t))
        return (f + 2.0 * fy_r) / mass - speed * r, (A * f - B * 2.0 * fy_r) / inertia

    v = r = 0.0
    n, check = int(round(WINDOW / STEP)), int(round(CHECK_EVERY / STEP))
    first, last = int(round(MIN_HOLD / STEP)), int(round(MAX_HOLD / STEP))
    dt = STEP / SUBSTEPS
    ts, rs, ays, afs, ars = [], [], [], [], []
    for k in range(last):
        t = k * STEP
        a_f = steer(t) - math.atan2(v + A * r, speed)
        a_r = -math.atan2(v - B * r, speed)
        front.setReal(alpha_vr, [a_f])
        front.doStep(currentCommunicationPoint=t, communicationStepSize=STEP)
        rear.setReal(alpha_vr, [a_r])
        rear.doStep(currentCommunicationPoint=t, communicationStepSize=STEP)
        fy_f, fy_r = front.getReal(fy_vr)[0], rear.getReal(fy_vr)[0]
        for j in range(SUBSTEPS):
            tj = t + j * dt
            k1 = rates(tj, v, r, fy_f, fy_r)
            k2 = rates(tj + dt / 2, v + dt / 2 * k1[0], r + dt / 2 * k1[1], fy_f, fy_r)
            k3 = rates(tj + dt / 2, v + dt / 2 * k2[0], r + dt / 2 * k2[1], fy_f, fy_r)
            k4 = rates(tj + dt, v + dt * k3[0], r + dt * k3[1], fy_f, fy_r)
            v += dt / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            r += dt / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        ts.append(t + STEP)
        rs.append(r)
        ays.append(rates(t + STEP, v, r, fy_f, fy_r)[0] + speed * r)
        afs.append(a_f)
        ars.append(a_r)
        if k + 1 >= first and (k + 1 - first) % check == 0 and _unsteady(rs, ays, speed, n) is None:
            break
    return ts, rs, ays, afs, ars


# --- the Dask side ---------------------------------------------------------------------------

class FmuOnWorker(WorkerPlugin):
    """Worker plugin: brings the FMU and the parameter files to each worker once (they are
    pickled with the plugin), extracts the FMU into the worker's local directory at set-up and
    removes it at teardown. Tasks find it by name in the worker's plugins."""

    def __init__(self, name, fmu_bytes, params):
        self.name = name
        self.fmu_bytes = fmu_bytes
        self.params = params  # label -> (file name, JSON text, or None when the client could not read it)
        self.dir = self.unzipdir = self.md = None
        self.param_paths = {}

    def setup(self, worker=None):
        from fmpy import extract, read_model_description

        base = worker.local_directory if worker is not None else None
        self.dir = Path(tempfile.mkdtemp(prefix="pacejka87-doe-", dir=base))
        fmu = self.dir / "Pacejka87Tire.fmu"
        fmu.write_bytes(self.fmu_bytes)
        self.unzipdir = extract(str(fmu), unzipdir=str(self.dir / "fmu"))
        self.md = read_model_description(str(fmu))
        for k, (label, (file_name, text)) in enumerate(self.params.items()):
            if text is not None:
                path = self.dir / f"params-{k}" / file_name  # the FMU's messages name the file
                path.parent.mkdir()
                path.write_text(text, encoding="utf-8")
                self.param_paths[label] = path

    def teardown(self, worker=None):
        if self.dir is not None:
            shutil.rmtree(self.dir, ignore_errors=True)


def run_task(runs, plugin_name):
    """DOE runs on a worker, one after the other, each with its own FMU instances; never
    raises: a failure is a row with status 'failed'."""
    from distributed import get_worker

    worker = get_worker()
    plugin = worker.plugins[plugin_name]
    rows = []
    for run in runs:
        wall, cpu = time.perf_counter(), time.process_time()
        row = {key: run[key] for key in ("run", "params", "speed_mps", "steer_deg")}
        row["worker"] = worker.address
        try:
            if run["params"] != BUILT_IN and run["params"] not in plugin.param_paths:
                raise FileNotFoundError(f"parameter file not readable on the client: {run['params_path']}")
            row.update(simulate(plugin.unzipdir, plugin.md, plugin.param_paths.get(run["params"]),
                                run["speed_mps"], run["steer_deg"], name=f"doe-{run['run']}"))
        except Exception as e:
            error = str(e) if isinstance(e, RuntimeError) else f"{type(e).__name__}: {e}"
            row.update(status="failed", error=error)
        row["run_s"] = time.perf_counter() - wall
        row["run_cpu_s"] = time.process_time() - cpu
        rows.append(row)
    return rows


def noop(i):
    return i


def _cpu_time():
    return time.process_time()


def parse_levels(text):
    """'10,20,30' -> [10, 20, 30]; '10:30:5' -> 5 levels from 10 to 30."""
    if ":" in text:
        start, stop, count = text.split(":")
        start, stop, count = float(start), float(stop), int(count)
        if count < 1:
            raise ValueError(f"count must be at least 1: {text}")
        return [start] if count == 1 else [start + (stop - start) * k / (count - 1) for k in range(count)]
    return [float(x) for x in text.split(",") if x.strip()]


def params_label(path, taken):
    label = Path(path).stem
    while label in taken:
        label += "'"
    return label


def make_design(speeds, steers, param_sets, runs=None, seed=0):
    """The runs: the full factorial speed x steer x parameter set, or with `runs`, a Latin
    hypercube of that many (speed, steer) points over the levels' ranges, the same points for
    each parameter set."""
    design = []
    for label, path in param_sets:
        if runs is None:
            points = [(v, d) for v in speeds for d in steers]
        else:
            import numpy as np

            rng = np.random.default_rng(seed)
            u = [(rng.permutation(runs) + rng.random(runs)) / runs for _ in range(2)]
            v0, v1, d0, d1 = min(speeds), max(speeds), min(steers), max(steers)
            points = [(v0 + (v1 - v0) * a, d0 + (d1 - d0) * b) for a, b in zip(*u)]
        design += [{"params": label, "params_path": path, "speed_mps": float(v), "steer_deg": float(d)}
                   for v, d in points]
    for k, run in enumerate(design):
        run["run"] = k
    return design


def run_batch(client, design, fmu_path, param_sets, csv_path, chunk=1, progress=True):
    """Maps the design over the cluster, `chunk` runs per task; writes each row to csv_path
    as its task finishes."""
    from distributed import as_completed

    texts = {}
    for label, path in param_sets:
        if path is None:
            continue
        try:
            texts[label] = (Path(path).name, Path(path).read_text(encoding="utf-8"))
        except OSError:
            texts[label] = (Path(path).name, None)
    name = f"pacejka87-doe-{uuid.uuid4().hex[:12]}"
    client.register_plugin(FmuOnWorker(name, Path(fmu_path).read_bytes(), texts), name=name)
    chunks = [design[k:k + chunk] for k in range(0, len(design), chunk)]
    rows = []
    try:
        futures = client.map(run_task, chunks, plugin_name=name,
                             key=[f"{name}-runs-{c[0]['run']}-{c[-1]['run']}" for c in chunks])
        by_key = {f.key: c for f, c in zip(futures, chunks)}
        start = time.perf_counter()
        every = max(1, len(design) // 20)
        width = len(str(len(design)))
        with open(csv_path, "w", newline="") as fh:
            writer = csv.DictWriter(fh, fieldnames=COLUMNS, restval="")
            writer.writeheader()
            for future in as_completed(futures):
                try:
                    # Waits if the result was lost with its worker and is being computed again.
                    new_rows = future.result()
                except Exception as exc:  # the task itself died (e.g. KilledWorker): still rows
                    new_rows = [{key: run[key] for key in ("run", "params", "speed_mps", "steer_deg")}
                                | {"status": "failed", "error": f"{type(exc).__name__}: {exc}"}
                                for run in by_key[future.key]]
                future.release()
                for row in new_rows:
                    rows.append(row)
                    writer.writerow({k: _fmt(row.get(k, "")) for k in COLUMNS})
                    done = len(rows)
                    if progress and (done % every == 0 or done == len(design) or row["status"] == "failed"):
                        note = f"  {row['status']}: {row['error']}" if row["status"] != "ok" else ""
                        print(f"[{done:>{width}}/{len(design)}] {time.perf_counter() - start:6.1f} s  "
                              f"{row['params']} {row['speed_mps']:g} m/s {row['steer_deg']:g} deg{note}",
                              flush=True)
                fh.flush()
    finally:
        with contextlib.suppress(Exception):
            client.unregister_worker_plugin(name)
    return rows


def probe_overhead(client, n):
    """Wall time of n no-op tasks through map and as_completed, as the batch uses them."""
    from distributed import as_completed

    start = time.perf_counter()
    futures = client.map(noop, range(n), key=[f"noop-{uuid.uuid4().hex}" for _ in range(n)])
    for future in as_completed(futures):
        future.release()
    return time.perf_counter() - start


def _fmt(value):
    return f"{value:.10g}" if isinstance(value, float) else value


# --- outputs ---------------------------------------------------------------------------------

def plot(rows, labels, path):
    """Filled contours of the steady yaw-rate gain over speed x steer amplitude, one panel per
    parameter set, with lines of steady lateral acceleration; runs not ok marked x."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    ok = [r for r in rows if r["status"] == "ok"]
    gains = [r["yaw_gain_per_s"] for r in ok]
    levels = np.linspace(min(gains), max(gains), 15) if len(gains) > 1 and max(gains) > min(gains) else None
    fig, axes = plt.subplots(1, len(labels), figsize=(4.6 * len(labels) + 1.2, 4.8), squeeze=False,
                             sharex=True, sharey=True, layout="constrained")
    filled = None
    for ax, label in zip(axes[0], labels):
        mine = [r for r in ok if r["params"] == label]
        bad = [r for r in rows if r["params"] == label and r["status"] != "ok"]
        x = np.array([r["speed_mps"] for r in mine])
        y = np.array([r["steer_deg"] for r in mine])
        if len(mine) >= 3 and np.ptp(x) > 0 and np.ptp(y) > 0:
            filled = ax.tricontourf(x, y, [r["yaw_gain_per_s"] for r in mine], levels=levels, cmap="viridis")
            lines = ax.tricontour(x, y, [r["ay_mps2"] for r in mine], levels=[1, 2, 4, 6, 8],
                                  colors="white", linewidths=0.8)
            ax.clabel(lines, fmt="%g m/s²", fontsize=7)
            k_us = mine[0]["understeer_deg_per_g"]
            ax.set_title(f"{label}\nundersteer gradient {k_us:.2f} deg/g (linear)", fontsize=9)
        else:
            ax.set_title(f"{label}\n{len(mine)} runs ok", fontsize=9)
        ax.plot(x, y, ".", color="k", ms=2)
        for status, color in (("unsteady", "tab:orange"), ("failed", "tab:red")):
            mark = [r for r in bad if r["status"] == status]
            if mark:
                ax.plot([r["speed_mps"] for r in mark], [r["steer_deg"] for r in mark], "x", color=color,
                        label=f"{len(mark)} {status}")
        if bad:
            ax.legend(loc="upper right", fontsize=8)
        ax.set_xlabel("speed [m/s]")
        ax.set_ylabel("steer amplitude (road wheel) [deg]")
    if filled is not None:
        fig.colorbar(filled, ax=axes[0].tolist(), format="%.1f", label="steady yaw-rate gain r/δ [1/s]")
    fig.suptitle("Step steer, single-track vehicle on two Pacejka87Tire FMUs: steady yaw-rate gain "
                 "(white: lateral acceleration)", fontsize=10)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def summary(rows, labels):
    """One line per parameter set."""
    lines = [f"{'params':<40} {'runs':>5} {'ok':>5} {'not ok':>6} {'K deg/g':>8} "
             f"{'gain_norm':>13} {'max ay':>7} {'run ms':>8}"]
    for label in labels:
        mine = [r for r in rows if r["params"] == label]
        ok = [r for r in mine if r["status"] == "ok"]
        if ok:
            g = [r["gain_norm"] for r in ok]
            ks = [r["understeer_deg_per_g"] for r in ok]  # varies with speed only if the tire's does
            k = f"{ks[0]:8.3f}" if max(ks) - min(ks) < 5e-4 else f"{min(ks):.2f}..{max(ks):.2f}"
            span = f"{min(g):.3f}..{max(g):.3f}"
            ay = f"{max(r['ay_mps2'] for r in ok):7.2f}"
        else:
            k, span, ay = f"{'-':>8}", "-", f"{'-':>7}"
        timed = [r["run_s"] for r in mine if "run_s" in r]  # not the runs of a killed task
        ms = sum(timed) / max(1, len(timed)) * 1000
        lines.append(f"{label[:40]:<40} {len(mine):>5} {len(ok):>5} {len(mine) - len(ok):>6} {k} "
                     f"{span:>13} {ay} {ms:8.1f}")
    return "\n".join(lines)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--speeds", default="10:30:9", help="speed levels [m/s] (default 10:30:9)")
    p.add_argument("--steers", default="0.5:4:8",
                   help="road-wheel steer amplitudes [deg] (default 0.5:4:8)")
    p.add_argument("--params", nargs="*", metavar="FILE",
                   help="tire parameter files (JSON) besides the built-in coefficients (default: "
                        "the fit in crates/mf87/tests/data/fits; none with a bare --params)")
    p.add_argument("--runs", type=int, help="Latin hypercube of this many runs per parameter set over "
                                            "the speed and steer ranges, instead of the full grid")
    p.add_argument("--seed", type=int, default=0, help="seed of the Latin hypercube")
    p.add_argument("--chunk", type=int, default=1, help="runs per Dask task (default 1)")
    p.add_argument("--workers", type=int, default=2, help="local cluster size (default 2)")
    p.add_argument("--scheduler", help="address of a running scheduler, e.g. tcp://host:8786")
    p.add_argument("--out", default="out", help="output directory (default out)")
    p.add_argument("--fmu", default=str(DEFAULT_FMU))
    p.add_argument("--probe", action="store_true",
                   help="also time as many no-op tasks (the cluster's overhead per task)")
    args = p.parse_args(argv)
    if not Path(args.fmu).is_file():
        print(f"FMU not found: {args.fmu} (build it with `cargo xtask fmu`)", file=sys.stderr)
        return 2
    try:
        speeds, steers = parse_levels(args.speeds), parse_levels(args.steers)
        if not speeds or not steers or min(speeds) <= 0 or min(steers) <= 0:
            raise ValueError("speeds and steer amplitudes must be positive")
        if args.runs is not None and args.runs < 1:
            raise ValueError("--runs must be at least 1")
        if args.chunk < 1 or args.workers < 1:
            raise ValueError("--chunk and --workers must be at least 1")
    except ValueError as e:
        print(f"bad arguments: {e}", file=sys.stderr)
        return 2
    files = [str(DEFAULT_PARAMS)] if args.params is None else args.params
    param_sets = [(BUILT_IN, None)]
    for f in files:
        param_sets.append((params_label(f, [label for label, _ in param_sets]), str(Path(f).resolve())))
    labels = [label for label, _ in param_sets]
    design = make_design(speeds, steers, param_sets, args.runs, args.seed)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    from distributed import Client, LocalCluster

    t0 = time.perf_counter()
    if args.scheduler:
        cluster, client = None, Client(args.scheduler, direct_to_workers=True)
    else:
        # No dashboard; the scheduler's HTTP routes (health, metrics) on any free port.
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                               dashboard_address=None, scheduler_kwargs={"dashboard_address": ":0"})
        client = Client(cluster, direct_to_workers=True)
    try:
        n_workers = len(client.scheduler_info(n_workers=-1)["workers"])
        t_up = time.perf_counter() - t0
        print(f"{len(design)} runs on {n_workers} workers "
              f"({args.scheduler or 'local cluster'}, up in {t_up:.1f} s)", flush=True)
        # CPU time of the scheduler's process and of this one around the batch and the probe.
        cpu0, t1 = (client.run_on_scheduler(_cpu_time), time.process_time()), time.perf_counter()
        rows = run_batch(client, design, args.fmu, param_sets, out / "doe_results.csv", args.chunk)
        t_batch = time.perf_counter() - t1
        cpu_batch = (client.run_on_scheduler(_cpu_time) - cpu0[0], time.process_time() - cpu0[1])
        if args.probe:
            cpu0 = (client.run_on_scheduler(_cpu_time), time.process_time())
            t_probe = probe_overhead(client, len(design))
            cpu_probe = (client.run_on_scheduler(_cpu_time) - cpu0[0], time.process_time() - cpu0[1])
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    plot(rows, labels, out / "doe_response.png")
    print(summary(rows, labels))
    runs_s = [r["run_s"] for r in rows if "run_s" in r]
    cpu = [r["run_cpu_s"] for r in rows if "run_cpu_s" in r]
    print(f"batch: {len(rows)} runs in {t_batch:.2f} s wall on {n_workers} workers, {args.chunk} per task "
          f"({t_batch / len(rows) * 1000:.2f} ms per run); each run on its worker: "
          f"{sum(runs_s) / max(1, len(runs_s)) * 1000:.1f} ms wall, "
          f"{sum(cpu) / max(1, len(cpu)) * 1000:.1f} ms CPU")

    def central(cpu, n, what):
        # A local cluster's scheduler runs in this process, with the client.
        if args.scheduler:
            return (f"scheduler {cpu[0] / n * 1000:.2f} ms CPU, client {cpu[1] / n * 1000:.2f} ms CPU "
                    f"per {what}")
        return f"scheduler and client (one process) {cpu[1] / n * 1000:.2f} ms CPU per {what}"

    print(f"batch: {central(cpu_batch, len(rows), 'run')}")
    if args.probe:
        print(f"no-op probe: {len(design)} tasks in {t_probe:.2f} s ({t_probe / len(design) * 1000:.2f} ms "
              f"per task); {central(cpu_probe, len(design), 'task')}")
    print(f"wrote {out / 'doe_results.csv'} and {out / 'doe_response.png'} "
          f"({time.perf_counter() - t0:.1f} s from cluster start)")
    return 1 if any(r["status"] == "failed" for r in rows) else 0


if __name__ != "__main__":
    # Imported (e.g. by the tests): ship this module's functions and plugin to the workers by
    # value, as when it runs as a script, so workers need not import it.
    import cloudpickle

    cloudpickle.register_pickle_by_value(sys.modules[__name__])

if __name__ == "__main__":
    sys.exit(main())
