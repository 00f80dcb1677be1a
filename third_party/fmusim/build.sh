#!/usr/bin/env bash
# Builds fmusim, the Modelica Association's reference FMU importer (Reference-FMUs v0.0.39,
# commit c8d4e6d, the last release with the C fmusim; BSD-2-Clause, see LICENSE), from the
# tarball next to this script against Debian 12's libraries. The tests run it
# (tests/python/test_fmusim.py).
#
# usage: build.sh [CACHEDIR]    (default CACHEDIR: <repo>/target/third_party/fmusim)
# The binary goes to CACHEDIR/<key>/fmusim, <key> the SHA-256 of the tarball and this script,
# so a changed source or recipe builds anew and an unchanged one is reused. The last line on
# stdout is the binary's path; progress and errors go to stderr. As root it installs the
# Debian packages it needs when they are missing.
#
# Two local changes to upstream: SUN_COMM_NULL is defined for Debian's SUNDIALS 6.4 (upstream
# expects 7), and fmusim/FMIUtil.c passes &state, not state, to fmi2FreeFMUstate /
# fmi3FreeFMUState (upstream bug: --final-fmu-state-file crashed any FMU).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)
tarball="$here/reference-fmus-v0.0.39-fmusim-src.tar.gz"
cache=${1:-"$repo/target/third_party/fmusim"}
key=$(cat "$tarball" "${BASH_SOURCE[0]}" | sha256sum | cut -c1-16)
out="$cache/$key"
if [ -x "$out/fmusim" ]; then echo "$out/fmusim"; exit 0; fi

can_install() { [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null 2>&1; }
pkgs="gcc libc6-dev libsundials-dev libminizip-dev zlib1g-dev libxml2-dev"
missing=$(for p in $pkgs; do dpkg -s "$p" >/dev/null 2>&1 || echo "$p"; done | xargs)
if [ -n "$missing" ]; then
    if can_install; then
        echo "fmusim: installing $missing" >&2
        apt-get update -qq >&2
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $missing >&2
    else
        echo "fmusim: needs (as root) apt-get install $missing" >&2
        exit 1
    fi
fi

# Build in a fresh directory and move it into place whole: an interrupted or concurrent
# build never leaves a half-built binary under the key.
mkdir -p "$cache"
work=$(mktemp -d "$cache/.build-XXXXXX")
trap 'rm -rf "$work"' EXIT
tar xzf "$tarball" -C "$work"
mkdir "$work/obj" "$work/bin"
(
    cd "$work"
    sed -i 's/FreeFMUstate(S, FMUState)/FreeFMUstate(S, \&FMUState)/; s/FreeFMUState(S, FMUState)/FreeFMUState(S, \&FMUState)/' fmusim/FMIUtil.c
    grep -q 'FreeFMUstate(S, &FMUState)' fmusim/FMIUtil.c || { echo "fmusim: the FMIUtil.c patch did not apply" >&2; exit 1; }
    objs=()
    for s in src/FMI.c src/FMI1.c src/FMI2.c src/FMI3.c src/structured_variable_name.yy.c \
             src/structured_variable_name.tab.c fmusim/*.c; do
        o="obj/$(basename "${s%.c}").o"
        gcc -O2 -std=gnu11 -w -c "$s" -o "$o" -Ifmusim -Iinclude -I/usr/include/libxml2 \
            -I/usr/include/minizip '-DFMUSIM_VERSION="v0.0.39-c8d4e6d"' -DSUN_COMM_NULL=NULL
        objs+=("$o")
    done
    gcc -o bin/fmusim "${objs[@]}" -lxml2 -lminizip -lz -lsundials_cvode -lsundials_nvecserial \
        -lsundials_sunmatrixdense -lsundials_sunlinsoldense -ldl -lm
)
# rename(2) is atomic; if a concurrent build got there first, its binary is kept.
mv -T "$work/bin" "$out" 2>/dev/null || [ -x "$out/fmusim" ] ||
    { echo "fmusim: $out exists without fmusim; remove it and run again" >&2; exit 1; }
echo "fmusim: built $out/fmusim" >&2
echo "$out/fmusim"
