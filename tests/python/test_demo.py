"""The README's main job: the co-simulation demo runs cleanly and writes its figure."""

import subprocess
import sys

from conftest import REPO

DEMO = REPO / "demo" / "cosim_demo.py"


def run_demo(*args):
    return subprocess.run([sys.executable, str(DEMO), *args], capture_output=True, text=True, timeout=300)


def test_demo_runs_without_warnings_and_writes_png(fmu_path, tmp_path):
    done = run_demo("--fmu", fmu_path, "--out", str(tmp_path))
    assert done.returncode == 0, done.stderr
    # fmpy warns for every FMU input the signal leaves out; the demo drives or holds them all.
    assert "Warning" not in done.stdout + done.stderr, done.stdout + done.stderr
    png = tmp_path / "demo.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert png.stat().st_size > 10_000
    # Braking at -30 % slip ratio: the last row of the table carries a braking force.
    last = done.stdout.strip().splitlines()[-2].split()
    kappa_pct, fx = float(last[3]), float(last[5])
    assert kappa_pct == -30.0 and fx < -1000.0, last


def test_demo_without_fmu_says_so_and_exits_2(tmp_path):
    done = run_demo("--fmu", str(tmp_path / "missing.fmu"), "--out", str(tmp_path))
    assert done.returncode == 2
    assert "FMU not found" in done.stderr and "missing.fmu" in done.stderr
