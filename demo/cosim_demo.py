#!/usr/bin/env python3
"""Co-simulation demo of the Pacejka87Tire FMU with fmpy, on its built-in coefficients.

1. A 4 s manoeuvre: cornering (slip angle sine to +-8 deg at 4 kN with lateral load
   transfer), then braking (slip ratio ramp to -30 % with -2 deg camber and longitudinal
   load transfer). A table of it goes to stdout.
2. The tire's characteristic curves at 2, 4, 6 and 8 kN, each from one simulation with
   swept inputs: Fy and Mz against slip angle, Fx against slip ratio.
Both go into one figure, <out>/demo.png.

Usage (from the repository root, after `cargo xtask fmu` and scripts/python-env.sh):
    .venv/bin/python demo/cosim_demo.py [--fmu PATH] [--out DIR]
Exit status: 0 done, 2 FMU missing.
"""

import argparse
import sys
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
DEFAULT_FMU = REPO / "target" / "fmu" / "Pacejka87Tire.fmu"
INPUTS = ("Fz", "alpha", "kappa", "gamma")
OUTPUTS = ("Fx", "Fy", "Mz")
STEP = 0.01  # communication step [s]


def simulate(fmu, time, **inputs):
    """Runs the FMU with inputs sampled on `time` (linear in between).

    Returns fmpy's result with inputs and outputs per row. fmpy sets the inputs at t_k and
    records after fmi2DoStep(t_k, h), so each row's recorded inputs are the ones its outputs
    were computed from (the outputs lag the input signal by one communication step).
    """
    import fmpy

    # Every input of the FMU gets a signal; those the demo does not drive (vx, p, T_tread act
    # only through a parameter file's extensions) are held at their start value.
    held = {
        v.name: float(v.start)
        for v in fmpy.read_model_description(str(fmu)).modelVariables
        if v.causality == "input" and v.name not in inputs
    }
    names = list(inputs) + list(held)
    signals = np.zeros(len(time), dtype=[("time", float)] + [(n, float) for n in names])
    signals["time"] = time
    for name, value in {**inputs, **held}.items():
        signals[name] = value
    return fmpy.simulate_fmu(
        str(fmu),
        start_time=float(time[0]),
        stop_time=float(time[-1]),
        output_interval=STEP,
        input=signals,
        output=list(INPUTS + OUTPUTS),
    )


def manoeuvre(fmu):
    """Cornering 0..2 s, braking 2..4 s (one input value per communication point)."""
    t = np.round(np.arange(0.0, 4.0 + STEP / 2, STEP), 10)
    cornering = t < 2.0
    alpha = np.where(cornering, np.radians(8.0) * np.sin(np.pi * t), 0.0)
    braking = np.clip((t - 2.2) / 1.3, 0.0, 1.0)  # slip ratio ramp 2.2..3.5 s, then held
    kappa = -0.3 * braking + 0.0  # + 0.0: no "-0.0" in the table
    gamma = np.where(t >= 2.0, np.radians(-2.0) * np.clip((t - 2.0) / 0.2, 0.0, 1.0), 0.0)
    # Load transfer: the wheel gains load on the outside of the turn and when braking.
    fz = 4000.0 + 1200.0 * alpha / np.radians(8.0) + 1500.0 * braking
    return simulate(fmu, t, Fz=fz, alpha=alpha, kappa=kappa, gamma=gamma)


def curves(fmu, fz):
    """One simulation at load `fz`: slip angle -15..15 deg and slip ratio -0.5..0.5 together
    (Fx depends on kappa only, Fy and Mz on alpha and gamma)."""
    n = 301
    t = np.arange(n + 1) * STEP
    sweep = np.append(np.linspace(-1.0, 1.0, n), 1.0)  # last value held one step
    return simulate(fmu, t, Fz=fz, alpha=np.radians(15.0) * sweep, kappa=0.5 * sweep, gamma=0.0)


def print_table(result, rows=11):
    header = ("t [s]", "Fz [N]", "alpha [deg]", "kappa [%]", "gamma [deg]", "Fx [N]", "Fy [N]", "Mz [N.m]")
    print("  ".join(f"{h:>11}" for h in header))
    for k in np.linspace(0, len(result) - 1, rows).round().astype(int):
        r = result[k]
        cells = (
            f"{r['time']:.2f}",
            f"{r['Fz']:.0f}",
            f"{np.degrees(r['alpha']):.2f}",
            f"{100.0 * r['kappa']:.1f}",
            f"{np.degrees(r['gamma']):.2f}",
            f"{r['Fx']:.1f}",
            f"{r['Fy']:.1f}",
            f"{r['Mz']:.2f}",
        )
        print("  ".join(f"{c:>11}" for c in cells))


def plot(man, sweeps, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(15, 11), layout="constrained")
    grid = fig.add_gridspec(3, 3, height_ratios=(1.2, 0.8, 1.0))
    fy_ax, mz_ax, fx_ax = (fig.add_subplot(grid[0, i]) for i in range(3))
    for fz, r in sweeps.items():
        label = f"Fz = {fz / 1000:g} kN"
        fy_ax.plot(np.degrees(r["alpha"][1:]), r["Fy"][1:], label=label)
        mz_ax.plot(np.degrees(r["alpha"][1:]), r["Mz"][1:], label=label)
        fx_ax.plot(100.0 * r["kappa"][1:], r["Fx"][1:], label=label)
    for ax, title, xlabel, ylabel in (
        (fy_ax, "Lateral force", "slip angle alpha [deg]", "Fy [N]"),
        (mz_ax, "Aligning moment", "slip angle alpha [deg]", "Mz [N.m]"),
        (fx_ax, "Longitudinal force", "slip ratio kappa [%]", "Fx [N]"),
    ):
        ax.set(title=title + " (paper's axes, gamma = 0)", xlabel=xlabel, ylabel=ylabel)
        ax.grid(True, alpha=0.4)
        ax.axhline(0.0, color="k", lw=0.6)
        ax.legend(fontsize="small")

    t = man["time"]
    ins = fig.add_subplot(grid[1, :])
    ins.plot(t, np.degrees(man["alpha"]), label="alpha [deg]")
    ins.plot(t, 100.0 * man["kappa"], label="kappa [%]")
    ins.plot(t, np.degrees(man["gamma"]), label="gamma [deg]")
    ins.set(title="Manoeuvre: cornering, then braking with camber", ylabel="alpha, gamma [deg]; kappa [%]")
    load = ins.twinx()
    load.plot(t, man["Fz"] / 1000.0, "k--", label="Fz [kN]")
    load.set_ylabel("Fz [kN]")
    lines = ins.get_lines() + load.get_lines()
    ins.legend(lines, [ln.get_label() for ln in lines], loc="lower left", fontsize="small", ncols=4)
    ins.grid(True, alpha=0.4)

    outs = fig.add_subplot(grid[2, :], sharex=ins)
    outs.plot(t, man["Fx"], label="Fx [N]")
    outs.plot(t, man["Fy"], label="Fy [N]")
    outs.set(xlabel="time [s]", ylabel="Fx, Fy [N]")
    moment = outs.twinx()
    moment.plot(t, man["Mz"], "C3", label="Mz [N.m]")
    moment.set_ylabel("Mz [N.m]")
    lines = outs.get_lines() + moment.get_lines()
    outs.legend(lines, [ln.get_label() for ln in lines], loc="lower left", fontsize="small", ncols=3)
    outs.grid(True, alpha=0.4)

    fig.suptitle("Pacejka87Tire FMU (1987 Magic Formula) co-simulated with fmpy")
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--fmu", type=Path, default=DEFAULT_FMU, help=f"the FMU (default: {DEFAULT_FMU})")
    parser.add_argument("--out", type=Path, default=REPO / "out", help="output folder (default: <repo>/out)")
    args = parser.parse_args(argv)

    if not args.fmu.is_file():
        print(f"cosim_demo: FMU not found: {args.fmu}\n  build it with `cargo xtask fmu`, or pass --fmu PATH",
              file=sys.stderr)
        return 2
    args.out.mkdir(parents=True, exist_ok=True)

    man = manoeuvre(args.fmu)
    print("Manoeuvre (paper's sign convention; outputs belong to the inputs on their row):")
    print_table(man)
    sweeps = {fz: curves(args.fmu, fz) for fz in (2000.0, 4000.0, 6000.0, 8000.0)}
    png = args.out / "demo.png"
    plot(man, sweeps, png)
    print(f"figure: {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
