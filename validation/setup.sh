#!/usr/bin/env bash
# Sets up the Mitsuba 3 side of the validation, idempotently:
#   - LLVM 19 (libllvm19), which Dr.Jit's llvm_ad_* variants load at run time (the Python
#     integrator validation/mitsuba/whitted.py and the fast variants need it);
#   - validation/.venv, a Python virtual environment with the pinned validation/requirements.txt.
# Prints the DRJIT_LIBLLVM_PATH to export. Run from anywhere:  validation/setup.sh
# Needs python3 (3.11 or later: the scripts read TOML with tomllib) and, for LLVM, apt-get.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
venv="$here/.venv"

find_libllvm() {
    local candidate
    for candidate in \
        "${DRJIT_LIBLLVM_PATH:-}" \
        "/usr/lib/$(uname -m)-linux-gnu/libLLVM-19.so" \
        /usr/lib/llvm-19/lib/libLLVM-19.so \
        /usr/lib/llvm-19/lib/libLLVM.so.19.1; do
        if [ -n "$candidate" ] && [ -e "$candidate" ]; then
            echo "$candidate"
            return 0
        fi
    done
    return 1
}

if ! libllvm="$(find_libllvm)"; then
    echo "setup: installing libllvm19 (LLVM 19 for Dr.Jit's llvm_ad_* variants)"
    sudo=""
    if [ "$(id -u)" -ne 0 ]; then
        sudo="sudo"
    fi
    if ! command -v apt-get >/dev/null; then
        echo "setup: no apt-get; install LLVM 19 and set DRJIT_LIBLLVM_PATH to its libLLVM" >&2
        exit 1
    fi
    $sudo apt-get update
    $sudo apt-get install -y libllvm19
    libllvm="$(find_libllvm)" || { echo "setup: libLLVM-19 not found after installing libllvm19" >&2; exit 1; }
fi

python="${PYTHON:-python3}"
if ! "$python" -c 'import sys; sys.exit(sys.version_info < (3, 11))'; then
    echo "setup: $python is older than 3.11 (tomllib); set PYTHON to a newer interpreter" >&2
    exit 1
fi
if [ ! -x "$venv/bin/python" ]; then
    echo "setup: creating $venv"
    "$python" -m venv "$venv"
fi
# pip leaves satisfied pins alone, so a second run costs only the check.
"$venv/bin/pip" install --quiet --disable-pip-version-check -r "$here/requirements.txt"

DRJIT_LIBLLVM_PATH="$libllvm" "$venv/bin/python" - <<'EOF'
import mitsuba as mi
mi.set_variant("llvm_ad_spectral")
print(f"setup: mitsuba {mi.__version__}, variant {mi.variant()} works")
EOF

echo "setup: done. Before running the scripts in validation/mitsuba/:"
echo "  export DRJIT_LIBLLVM_PATH=$libllvm"
