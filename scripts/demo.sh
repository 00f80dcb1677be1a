#!/usr/bin/env bash
# The main job on the built-in defaults: build the FMU, run a cornering-and-braking
# co-simulation with fmpy, print a table and write out/demo.png.
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo"
scripts/setup.sh
cargo xtask fmu
.venv/bin/python demo/cosim_demo.py --fmu target/fmu/Pacejka87Tire.fmu --out out
