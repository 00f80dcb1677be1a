#!/usr/bin/env bash
# Builds fmuCheck, the FMI Compliance Checker (modelica-tools/FMUComplianceChecker at commit
# c704b98, release 2.0.4 code; BSD-3-Clause, see LICENSE) on FMI Library (FMIL) 2.0.3 (bundled
# in the tarball under FMIL/ with its expat, minizip and zlib; BSD-3-Clause, see
# LICENSE-FMIL.md), from the tarball next to this script. The tests run it
# (tests/python/test_compliance_checker.py).
#
# usage: build.sh [CACHEDIR]    (default CACHEDIR: <repo>/target/third_party/fmuchecker)
# The binary goes to CACHEDIR/<key>/fmuCheck.linux64, <key> the SHA-256 of the tarball and
# this script, so a changed source or recipe builds anew and an unchanged one is reused. The
# last line on stdout is the binary's path; progress and errors go to stderr (the build's own
# output to CACHEDIR/<key>.log). As root it installs cmake, make and gcc when missing.
#
# Local changes to upstream: FMIL comes from the bundled copy instead of a git clone, FMIL's
# own tests are not built, and -fcommon lets gcc 10+ link it.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)
tarball="$here/fmuchecker-c704b98-fmil-2.0.3-src.tar.gz"
cache=${1:-"$repo/target/third_party/fmuchecker"}
key=$(cat "$tarball" "${BASH_SOURCE[0]}" | sha256sum | cut -c1-16)
out="$cache/$key"
if [ -x "$out/fmuCheck.linux64" ]; then echo "$out/fmuCheck.linux64"; exit 0; fi

can_install() { [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null 2>&1; }
missing=$(for t in cmake:cmake make:make gcc:gcc; do
    command -v "${t%%:*}" >/dev/null 2>&1 || echo "${t#*:}"; done | xargs)
if [ -n "$missing" ]; then
    if can_install; then
        echo "fmuchecker: installing $missing" >&2
        apt-get update -qq >&2
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $missing >&2
    else
        echo "fmuchecker: needs (as root) apt-get install $missing" >&2
        exit 1
    fi
fi

# Build in a fresh directory and move the result into place whole: an interrupted or
# concurrent build never leaves a half-built binary under the key.
mkdir -p "$cache"
work=$(mktemp -d "$cache/.build-XXXXXX")
trap 'rm -rf "$work"' EXIT
log="$cache/$key.log"
echo "fmuchecker: building (about a minute on 2 cores; log $log)" >&2
tar xzf "$tarball" -C "$work"
mkdir "$work/build" "$work/bin"
(
    cd "$work/build"
    cmake -DFMUCHK_INSTALL_PREFIX="$work/install" -DCMAKE_C_FLAGS=-fcommon \
        -DCMAKE_BUILD_TYPE=Release "$work/fmuchecker-c704b98"
    make -j"$(nproc)" install
) >"$log" 2>&1 || { tail -30 "$log" >&2; echo "fmuchecker: build failed (log $log)" >&2; exit 1; }
bin=$(find "$work/install" -name fmuCheck.linux64 -type f | head -1)
[ -n "$bin" ] || { echo "fmuchecker: no fmuCheck.linux64 in the install tree (log $log)" >&2; exit 1; }
cp "$bin" "$work/bin/fmuCheck.linux64"
# rename(2) is atomic; if a concurrent build got there first, its binary is kept.
mv -T "$work/bin" "$out" 2>/dev/null || [ -x "$out/fmuCheck.linux64" ] ||
    { echo "fmuchecker: $out exists without fmuCheck.linux64; remove it and run again" >&2; exit 1; }
echo "fmuchecker: built $out/fmuCheck.linux64" >&2
echo "$out/fmuCheck.linux64"
