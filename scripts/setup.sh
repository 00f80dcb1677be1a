#!/usr/bin/env bash
# One-time machine set-up, idempotent: libclang for bindgen (fmi-sys), the cross tools for the
# FMU's win64 binary and Wine to test it, valgrind for the fuzz test, and the Python environment
# for the tests, the demo and the linux64 build (.venv: fmpy, cargo-zigbuild, ...).
#     scripts/setup.sh           # everything (test.sh)
#     scripts/setup.sh --demo    # the system part of the demo (demo.sh): /dev/null and
#                                # libclang; demo.sh installs its Python packages itself
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
case "${1:-}" in
    "") demo= ;;
    --demo) demo=1 ;;
    *) echo "setup: unknown argument '$1' (none, or --demo)" >&2; exit 2 ;;
esac

# /dev/null must be the null device. On some machines it is a plain file: build scripts then
# write their probe errors into it and cargo feeds that text to rustc as source, which fails.
if [ ! -c /dev/null ]; then
    if [ "$(id -u)" -eq 0 ]; then
        echo "setup: /dev/null is not a character device; recreating it" >&2
        rm -f /dev/null
        mknod -m 666 /dev/null c 1 3
    else
        echo "setup: /dev/null is not a character device; as root: rm /dev/null && mknod -m 666 /dev/null c 1 3" >&2
        exit 1
    fi
fi

# libclang itself (libclang.so or libclang-NN.so), not libclang-cpp, which a fresh machine has.
have_libclang() {
    [ -n "${LIBCLANG_PATH:-}" ] && return 0
    local pattern
    for pattern in '/usr/lib/llvm-*/lib/libclang.so*' '/usr/lib/*/libclang.so*' '/usr/lib/*/libclang-[0-9]*.so*'; do
        compgen -G "$pattern" >/dev/null && return 0
    done
    return 1
}

can_install() { [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null 2>&1; }
updated=
apt_install() {
    [ -n "$updated" ] || { apt-get update -qq >&2; updated=1; }
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >&2
}

if ! have_libclang; then
    if can_install; then
        echo "setup: installing libclang-dev (bindgen needs it)" >&2
        apt_install libclang-dev
    else
        echo "setup: libclang is missing; install it (Debian: sudo apt-get install libclang-dev)" >&2
        exit 1
    fi
fi

[ -z "$demo" ] || exit 0

# The win64 DLL: Debian's Rust with the standard library's source (built for the Windows
# target with -Zbuild-std; the default toolchain stays as it is), mingw-w64 to link, Wine to
# test. Without them `cargo xtask fmu` packages linux64 only and says so.
cross_packages=(rustc-web cargo-web rust-web-src gcc-mingw-w64-x86-64 wine wine64)
if command -v dpkg >/dev/null 2>&1; then
    missing=()
    for p in "${cross_packages[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
    if [ "${#missing[@]}" -gt 0 ]; then
        if can_install; then
            echo "setup: installing ${missing[*]} (the win64 binary and its tests)" >&2
            apt_install "${missing[@]}"
        else
            echo "setup: the win64 binary needs (as root) apt-get install ${missing[*]}" >&2
        fi
    fi
fi

# valgrind: the fuzz test runs part of its sequences under memcheck (leaks, memory errors).
# Without it that part is skipped, except in CI (CI set), where it fails.
if ! command -v valgrind >/dev/null 2>&1; then
    if can_install; then
        echo "setup: installing valgrind (the fuzz test's memcheck run)" >&2
        apt_install valgrind
    else
        echo "setup: the fuzz test's memcheck run needs valgrind (Debian: sudo apt-get install valgrind)" >&2
    fi
fi

"$repo/scripts/python-env.sh" >/dev/null
