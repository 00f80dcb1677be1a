#!/usr/bin/env bash
# Creates or updates the project's Python environment and prints its interpreter.
#
# Usage (run it, don't source it):
#     scripts/python-env.sh                 # -> last line of stdout: /abs/path/.venv/bin/python
#     scripts/python-env.sh --demo          # only what the demo needs: demo/requirements.txt,
#                                           # the complete list, installed with --no-deps
#     PY=$(scripts/python-env.sh | tail -n 1)
#     .venv/bin/pytest tests/python
#
# - Creates <repo>/.venv with `python3 -m venv` when it is missing or its interpreter no
#   longer runs (PYTHON=/path/to/python3.11 picks another base interpreter).
# - Installs tests/python/requirements.txt (which includes demo/requirements.txt), or with
#   --demo demo/requirements.txt alone, only when those files changed since the last
#   successful install: their SHA-256 is kept in .venv/.requirements-full.sha256 and
#   .venv/.requirements-demo.sha256 (a full install also satisfies --demo).
# - The full set-up then installs the package tire_gap from crates/tire-gap-py (maturin
#   compiles it with cargo, which rebuilds only what changed).
# - Progress goes to stderr; stdout carries only the interpreter's path. Needs no TTY,
#   works as root, and stops with a non-zero status on the first error.
set -euo pipefail

repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
venv="$repo/.venv"
demo_requirements="$repo/demo/requirements.txt"
full_requirements="$repo/tests/python/requirements.txt"
demo_stamp="$venv/.requirements-demo.sha256"
full_stamp="$venv/.requirements-full.sha256"
base_python=${PYTHON:-python3}

log() { printf 'python-env: %s\n' "$*" >&2; }
die() { log "error: $*"; exit 1; }

case "${1:-}" in
    "") requirements=$full_requirements stamp=$full_stamp pip_options=() ;;
    --demo) requirements=$demo_requirements stamp=$demo_stamp pip_options=(--no-deps) ;;
    *) die "unknown argument '$1' (none, or --demo)" ;;
esac
for f in "$demo_requirements" "$full_requirements"; do
    [ -f "$f" ] || die "missing $f"
done
command -v "$base_python" >/dev/null 2>&1 || die "no '$base_python' on PATH (set PYTHON=...)"
"$base_python" -c 'import sys; sys.exit(sys.version_info < (3, 11))' \
    || die "$base_python is $("$base_python" -V 2>&1); Python >= 3.11 is needed"

# A venv whose interpreter is gone (the base Python moved or was removed) is rebuilt.
if [ -d "$venv" ] && ! "$venv/bin/python" -c 'pass' >/dev/null 2>&1; then
    log "rebuilding $venv: its interpreter does not run"
    rm -rf "$venv"
fi
if [ ! -x "$venv/bin/python" ]; then
    log "creating $venv with $("$base_python" -V 2>&1)"
    "$base_python" -m venv "$venv"
fi

# The demo's pins are part of the full set, so the full stamp covers both files.
demo_sum=$(sha256sum "$demo_requirements" | cut -d' ' -f1)
full_sum=$(cat "$demo_requirements" "$full_requirements" | sha256sum | cut -d' ' -f1)
if [ "$stamp" = "$full_stamp" ]; then want=$full_sum; else want=$demo_sum; fi
have=$(cat "$stamp" 2>/dev/null || true)
if [ "$want" != "$have" ]; then
    log "installing ${requirements#"$repo"/} into $venv"
    rm -f "$stamp"
    PIP_DISABLE_PIP_VERSION_CHECK=1 PIP_NO_INPUT=1 PIP_ROOT_USER_ACTION=ignore \
        "$venv/bin/python" -m pip install --quiet "${pip_options[@]}" --requirement "$requirements" >&2
    echo "$want" >"$stamp"
    [ "$stamp" = "$demo_stamp" ] || echo "$demo_sum" >"$demo_stamp"
    log "done"
fi

if [ "$stamp" = "$full_stamp" ]; then
    log "installing the package tire_gap (crates/tire-gap-py) into $venv"
    # maturin, from the requirements, is found on PATH.
    PATH="$venv/bin:$PATH" PIP_DISABLE_PIP_VERSION_CHECK=1 PIP_NO_INPUT=1 PIP_ROOT_USER_ACTION=ignore \
        "$venv/bin/python" -m pip install --quiet --no-deps --no-build-isolation \
        "$repo/crates/tire-gap-py" >&2
fi

echo "$venv/bin/python"
