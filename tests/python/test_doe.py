"""The design-of-experiments demo (demo/doe.py) on a local Dask cluster of 2 workers: the
physics of its results table (an understeering car's steady yaw-rate gain against linear
single-track theory, and below it at the friction limit), failed runs as rows, the figure."""

import csv
import json
import math
import subprocess
import sys
from collections import defaultdict

import magic_formula as mf
from conftest import REPO

DOE = REPO / "demo" / "doe.py"
sys.path.insert(0, str(REPO / "demo"))
import doe  # noqa: E402

SPEEDS = (10.0, 20.0, 30.0)
STEERS = (0.5, 1.0, 2.0, 4.0)


def test_doe_batch_physics_failed_rows_and_plot(fmu_path, tmp_path):
    missing = tmp_path / "missing.json"
    rejected = tmp_path / "rejected.json"  # Fy's C outside its bounds [0.1, 5]: the FMU refuses it
    params = mf.paper_table()
    params["Fy"]["C"] = 50.0
    rejected.write_text(json.dumps(params))
    fit = doe.DEFAULT_PARAMS
    done = subprocess.run(
        [sys.executable, str(DOE), "--fmu", fmu_path, "--out", str(tmp_path), "--workers", "2",
         "--speeds", ",".join(map(str, SPEEDS)), "--steers", ",".join(map(str, STEERS)),
         "--params", str(fit), str(missing), str(rejected)],
        capture_output=True, text=True, timeout=300)
    assert done.returncode == 1, done.stdout + done.stderr  # 1: some runs failed
    with open(tmp_path / "doe_results.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert sorted(int(r["run"]) for r in rows) == list(range(4 * len(SPEEDS) * len(STEERS)))
    by_params = defaultdict(list)
    for r in rows:
        by_params[r["params"]].append(r)
    assert set(by_params) == {doe.BUILT_IN, fit.stem, "missing", "rejected"}

    # The failing runs are rows with their reason; every other run finished.
    for r in by_params["missing"]:
        assert r["status"] == "failed" and "missing.json" in r["error"], r
    for r in by_params["rejected"]:
        assert r["status"] == "failed" and "parameterFile" in r["error"] and "rejected.json" in r["error"], r
    good = by_params[doe.BUILT_IN] + by_params[fit.stem]
    assert all(r["status"] in ("ok", "unsteady") for r in good), [r for r in good if r["status"] == "failed"]

    ok = [{k: (v if k in ("params", "status", "worker", "error") else float(v)) for k, v in r.items()}
          for r in good if r["status"] == "ok"]
    assert len(ok) >= 18, len(ok)
    assert len({r["worker"] for r in rows if r["worker"]}) == 2, "both workers ran"

    # The built-in tires' axle cornering stiffness is BCD at the axle's static load, twice
    # (two tires), per rad, as computed by hand from the paper's coefficients.
    for r in ok:
        if r["params"] == doe.BUILT_IN:
            for c, fz in ((r["c_front_N_per_rad"], doe.FZ_FRONT), (r["c_rear_N_per_rad"], doe.FZ_REAR)):
                bcd = 1078.0 * math.sin(1.82 * math.atan(0.208 * fz / 1000.0)) * 180.0 / math.pi
                assert math.isclose(c, 2.0 * bcd, rel_tol=1e-5), (c, 2.0 * bcd)

    for r in ok:
        # Steady state: a_y = V r, and the normalised gain r L / (V delta) is the yaw-rate gain
        # r / delta times L / V.
        r_rad = math.radians(r["yaw_rate_degps"])
        assert math.isclose(r["ay_mps2"], r["speed_mps"] * r_rad, rel_tol=doe.SETTLED), r
        assert math.isclose(r["gain_norm"], r["yaw_gain_per_s"] * doe.L / r["speed_mps"], rel_tol=1e-5)
        # An understeering car: K = (m / L)(b / C_f - a / C_r) > 0, and the normalised gain
        # below 1 (neutral steer).
        k = doe.MASS / doe.L * (doe.B / r["c_front_N_per_rad"] - doe.A / r["c_rear_N_per_rad"])
        assert k > 0 and math.isclose(r["understeer_deg_per_g"], math.degrees(k * doe.G), rel_tol=1e-5)
        assert r["gain_norm"] < 1.0, r
        # Linear single-track theory, r / delta = V / (L (1 + K V^2 / L)), holds within 0.5 % up
        # to 2.5 m/s^2 (slip angles below 1 deg; the tires' curvature there shifts the gain by
        # up to 0.3 % for the fitted set, 0.1 % for the built-in one).
        linear = 1.0 / (1.0 + k * r["speed_mps"] ** 2 / doe.L)
        assert math.isclose(r["gain_norm_linear"], linear, rel_tol=1e-5)
        if r["ay_mps2"] <= 2.5:
            assert abs(r["gain_norm"] / linear - 1.0) <= 0.005, r

    def gains(params, **fixed):
        """(level, gain_norm, a_y) of the ok runs of a parameter set at one speed or steer."""
        (name, value), = fixed.items()
        other = "steer_deg" if name == "speed_mps" else "speed_mps"
        return sorted((r[other], r["gain_norm"], r["ay_mps2"]) for r in ok
                      if r["params"] == params and r[name] == value)

    falls_with_steer = 0
    for params in (doe.BUILT_IN, fit.stem):
        # The normalised gain falls with speed at every steer amplitude.
        for steer in STEERS:
            g = [gain for _, gain, _ in gains(params, steer_deg=steer)]
            assert all(b < a for a, b in zip(g, g[1:])), (params, steer, g)
        # At a high lateral acceleration it falls with the steer amplitude (the tires
        # saturate, the front ones first) and lies well below the linear theory's.
        for speed in SPEEDS:
            g = gains(params, speed_mps=speed)
            for (_, g_low, _), (_, g_high, ay_high) in zip(g, g[1:]):
                if ay_high >= 5.0:
                    assert g_high < 0.99 * g_low, (params, speed, g)
                    falls_with_steer += 1
    assert falls_with_steer >= 2
    assert max(1.0 - r["gain_norm"] / r["gain_norm_linear"] for r in ok) > 0.05

    png = tmp_path / "doe_response.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10_000
    assert "built-in" in done.stdout and "batch: 48 runs" in done.stdout, done.stdout


def test_doe_chunks_and_latin_hypercube(fmu_path, tmp_path):
    """Several runs per task, a Latin hypercube design, the built-in tires only: the same
    responses as the same runs one per task."""
    args = [sys.executable, str(DOE), "--fmu", fmu_path, "--workers", "2", "--params", "--runs", "7"]
    for chunk in ("1", "3"):
        done = subprocess.run([*args, "--chunk", chunk, "--out", str(tmp_path / chunk)],
                              capture_output=True, text=True, timeout=300)
        assert done.returncode == 0, done.stdout + done.stderr
    tables = []
    for chunk in ("1", "3"):
        with open(tmp_path / chunk / "doe_results.csv", newline="") as fh:
            tables.append({r["run"]: r for r in csv.DictReader(fh)})
    assert sorted(tables[0]) == sorted(tables[1]) == [str(k) for k in range(7)]
    for run, row in tables[0].items():
        assert row["params"] == doe.BUILT_IN and row["status"] != "failed", row
        for key in ("speed_mps", "steer_deg", "yaw_rate_degps", "ay_mps2", "status"):
            assert row[key] == tables[1][run][key], (key, row, tables[1][run])


def test_levels_and_latin_hypercube():
    assert doe.parse_levels("10:30:5") == [10.0, 15.0, 20.0, 25.0, 30.0]
    assert doe.parse_levels("0.5,1,2") == [0.5, 1.0, 2.0]
    design = doe.make_design([10.0, 30.0], [0.5, 4.0], [(doe.BUILT_IN, None), ("b", "b.json")], runs=8)
    assert [r["run"] for r in design] == list(range(16))
    for label in (doe.BUILT_IN, "b"):
        mine = [r for r in design if r["params"] == label]
        # One point in each eighth of either range.
        assert sorted(int((r["speed_mps"] - 10.0) / 20.0 * 8) for r in mine) == list(range(8))
        assert sorted(int((r["steer_deg"] - 0.5) / 3.5 * 8) for r in mine) == list(range(8))


def test_doe_without_fmu_says_so_and_exits_2(tmp_path):
    done = subprocess.run([sys.executable, str(DOE), "--fmu", str(tmp_path / "missing.fmu")],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 2 and "FMU not found" in done.stderr
