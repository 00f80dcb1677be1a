#!/usr/bin/env bash
# The main job on the built-in defaults: build the FMU, run a cornering-and-braking
# co-simulation with fmpy, print a table and write out/demo.png. Installs only what that needs
# (libclang-dev if missing, .venv with demo/requirements.txt) and builds the linux64 binary
# alone, against this machine's glibc (`cargo xtask fmu --host`); scripts/test.sh builds the
# full FMU. Idempotent: a second run installs nothing and rebuilds nothing.
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo"
scripts/setup.sh --demo
# The Python packages install (mostly waiting on the network) while cargo compiles.
scripts/python-env.sh --demo >/dev/null &
python_env=$!
build=0
cargo xtask fmu --host || build=$?
wait "$python_env"
[ "$build" -eq 0 ] || exit "$build"
.venv/bin/python demo/cosim_demo.py --fmu target/fmu/Pacejka87Tire.fmu --out out
