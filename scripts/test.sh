#!/usr/bin/env bash
# Every test: formatting and lints, the Rust tests (model against the reference values, the
# C ABI with hostile call sequences), then the packaged FMU with fmpy and libcosim.
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo"
scripts/setup.sh
cargo fmt --all --check
cargo clippy --workspace --all-targets -- -D warnings
cargo test --workspace
cargo xtask fmu
.venv/bin/pytest tests/python
