#!/usr/bin/env bash
# The main job on the built-in defaults: build the FMU, run a cornering-and-braking
# co-simulation with fmpy, print a table and write out/demo.png. Installs only what that needs
# (libclang-dev if missing, .venv with demo/requirements.txt) and builds the linux64 binary
# alone, against this machine's glibc (`cargo xtask fmu --host`); scripts/test.sh builds the
# full FMU.
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo"
scripts/setup.sh --demo
cargo xtask fmu --host
.venv/bin/python demo/cosim_demo.py --fmu target/fmu/Pacejka87Tire.fmu --out out
