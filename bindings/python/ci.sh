#!/usr/bin/env bash
# The Python package's CI tier (.ci/run calls it; runs alone too):
# 1. a build venv with pinned maturin, ziglang and auditwheel from PyPI;
#    the crate's rustfmt and clippy;
# 2. the wheel users get: abi3 (CPython 3.9+), manylinux2014, built by
#    `maturin build --zig` and checked by `auditwheel show`;
# 3. a fresh venv holding only that wheel and the test dependencies
#    (numpy, pytest, ray), pytest run from outside the source tree;
# 4. the `pip install ./bindings/python` path (PEP 517, maturin backend).
# Prints SKIPPED (and exits 0) only when pip cannot reach the package index.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
work=$root/target/python-ci
BUILD_PINS=(maturin==1.7.4 ziglang==0.13.0 auditwheel==6.8.2 numpy==2.0.2)
TEST_PINS=(numpy==2.0.2 pytest==8.3.3 ray==2.60.0)
export PIP_DISABLE_PIP_VERSION_CHECK=1

python=${PYTHON:-python3}
if ! command -v "$python" >/dev/null 2>&1; then
    # A fresh Debian 12 without the pyenv CPython: Debian's.
    apt-get update -qq && apt-get install -y -qq python3 python3-venv >/dev/null
    python=python3
fi
"$python" --version
rm -rf "$work/venv" "$work/test-venv" "$work/wheels" "$work/run"
mkdir -p "$work"
venv() {
    if ! "$python" -m venv "$1" 2>/dev/null; then
        # Debian's python3 ships venv without ensurepip.
        apt-get update -qq && apt-get install -y -qq python3-venv >/dev/null
        "$python" -m venv "$1"
    fi
}
# pip install into venv $1 the pins that follow; an unreachable index is
# the only skip, any other pip failure fails.
install_pins() {
    local py=$1
    shift
    if ! "$py" -m pip install --quiet "$@"; then
        if ! "$py" -m pip download --quiet --no-deps -d "$work/probe" pytest==8.3.3 >/dev/null 2>&1; then
            echo "SKIPPED: pip cannot reach the package index, so the Python package was not built or tested"
            exit 0
        fi
        echo "pip could reach the index but could not install $*" >&2
        exit 1
    fi
}
venv "$work/venv"
py=$work/venv/bin/python
install_pins "$py" "${BUILD_PINS[@]}"
export PYO3_PYTHON=$py
# The venv first: maturin finds zig there, and pip's PEP 517 build without
# isolation runs its maturin.
export PATH=$work/venv/bin:$PATH

echo "-- rustfmt and clippy (the crate is its own workspace)"
cargo fmt --manifest-path bindings/python/Cargo.toml --check
cargo clippy --quiet --manifest-path bindings/python/Cargo.toml --all-targets -- -D warnings

echo "-- maturin build --zig: one abi3 manylinux2014 wheel for CPython 3.9+"
"$work/venv/bin/maturin" build --quiet --release --zig --compatibility manylinux2014 \
    -m bindings/python/Cargo.toml --interpreter "$py" -o "$work/wheels"
wheel=$(ls "$work"/wheels/micromap_index-*.whl)
case "$wheel" in
    *-cp39-abi3-manylinux_2_17_*.manylinux2014_*.whl) ;;
    *) echo "not an abi3 cp39 manylinux2014 wheel: $wheel" >&2; exit 1 ;;
esac
# auditwheel reads the symbol versions the extension needs: the tag must
# be one PyPI accepts and pip installs on glibc 2.17 and later.
shown=$("$work/venv/bin/auditwheel" show "$wheel")
echo "$shown"
if ! tr -s ' \n' ' ' <<<"$shown" | grep -q 'consistent with the following platform tag: "manylinux_2_17_'; then
    echo "auditwheel: the wheel is not manylinux_2_17 (manylinux2014) compatible" >&2
    exit 1
fi

echo "-- a fresh venv with only the wheel and ${TEST_PINS[*]}"
venv "$work/test-venv"
test_py=$work/test-venv/bin/python
install_pins "$test_py" "${TEST_PINS[@]}"
"$test_py" -m pip install --quiet --no-index --no-deps "$wheel"

echo "-- pytest (bindings/python/tests) in that venv, the CLI's bytes from target/release"
cargo build --quiet --release -p micromap-index-cli --bin micromap-index
mkdir -p "$work/run"
# From outside the source tree: the installed wheel is what is imported.
(cd "$work/run" && MICROMAP_INDEX_CLI=$root/target/release/micromap-index \
    "$test_py" -m pytest -q -p no:cacheprovider --rootdir "$root/bindings/python" \
    "$root/bindings/python/tests")

echo "-- pip install ./bindings/python (maturin as the PEP 517 backend)"
"$py" -m pip install --quiet --no-build-isolation --no-deps ./bindings/python
(cd "$work" && "$py" -c "import micromap_index as m; assert m.index(0.28, 0.4, 3) == 23; print('micromap_index', m.__version__, 'from', m.__file__)")
