#!/usr/bin/env bash
# One-time machine set-up, idempotent: libclang for bindgen (fmi-sys) and the Python
# environment for the tests and the demo (.venv). Called by demo.sh and test.sh.
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

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

if ! have_libclang; then
    if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null 2>&1; then
        echo "setup: installing libclang-dev (bindgen needs it)" >&2
        apt-get update -qq >&2
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libclang-dev >&2
    else
        echo "setup: libclang is missing; install it (Debian: sudo apt-get install libclang-dev)" >&2
        exit 1
    fi
fi

"$repo/scripts/python-env.sh" >/dev/null
