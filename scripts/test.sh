#!/usr/bin/env bash
# Every test: formatting and lints, the Rust tests (model against the reference values, the
# C ABI with hostile call sequences and a seeded call-sequence fuzzer, part under valgrind),
# the same FMU tests compiled for Windows under Wine, then the packaged FMU (both binaries)
# with fmpy, libcosim, fmusim, the FMI Compliance Checker and a Windows harness (fmusim and
# the checker are built from third_party/, see docs/testing.md).
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo"
scripts/setup.sh
cargo fmt --all --check
cargo clippy --workspace --all-targets -- -D warnings
# tire-gap without its synthetic-data generator (the cargo feature synth) builds too.
cargo clippy -p tire-gap --no-default-features --all-targets -- -D warnings
# The API docs build without a warning (broken or private intra-doc links).
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps
cargo test --workspace
cargo xtask fmu
cargo xtask test-win64
.venv/bin/pytest tests/python
