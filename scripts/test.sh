#!/usr/bin/env bash
# Every test: formatting and lints, the Rust tests (model against the reference values, the
# C ABI with hostile call sequences and a seeded call-sequence fuzzer, part under valgrind),
# the same FMU tests compiled for Windows under Wine, then the packaged FMU (both binaries)
# with fmpy, libcosim, fmusim, the FMI Compliance Checker and a Windows harness (fmusim and
# the checker are built from third_party/, see docs/testing.md).
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo"
# Every build here starts from scratch on a CI machine: incremental state only costs time.
export CARGO_INCREMENTAL=0
# Each step's wall time, to stderr, so that the slow ones show in the CI log.
step() {
    local start=$SECONDS
    "$@"
    echo "test.sh: $((SECONDS - start)) s: $*" >&2
}
step scripts/setup.sh
step cargo fmt --all --check
step cargo clippy --workspace --all-targets -- -D warnings
# tire-gap without its synthetic-data generator (the cargo feature synth) builds too.
step cargo clippy -p tire-gap --no-default-features --all-targets -- -D warnings
# The API docs build without a warning (broken or private intra-doc links).
RUSTDOCFLAGS="-D warnings" step cargo doc --workspace --no-deps
# The tests run on the machine that builds them: built for x86-64-v3 (AVX2 and FMA) where the
# processor has it, the diagnosis suite runs about a third faster with the same numbers (Rust
# never fuses a multiply and an add on its own: a diagnosis's report is the same, number for
# number). Not for `native`: on a processor with AVX-512 that code stops valgrind (the fuzz
# test's memcheck run) at its first AVX-512 instruction.
x86_64_v3() {
    [ "$(uname -m)" = x86_64 ] || return 1
    local flag
    for flag in avx avx2 bmi1 bmi2 f16c fma abm movbe xsave; do
        grep -qw "$flag" /proc/cpuinfo || return 1
    done
}
cpu=
if x86_64_v3; then cpu="-C target-cpu=x86-64-v3"; fi
RUSTFLAGS="${RUSTFLAGS:-} $cpu" step cargo test --workspace
step cargo xtask fmu
step cargo xtask test-win64
step .venv/bin/pytest tests/python
echo "test.sh: all passed in $SECONDS s" >&2
