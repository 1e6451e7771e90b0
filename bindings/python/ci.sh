#!/usr/bin/env bash
# The Python package's CI tier (.ci/run calls it; runs alone too):
# a venv with pinned maturin, numpy and pytest from PyPI, the abi3 wheel
# built by `maturin build` and installed by pip, pytest, then the
# `pip install ./bindings/python` path (PEP 517) reusing the same build.
# Prints SKIPPED (and exits 0) only when pip cannot reach the package index.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
work=$root/target/python-ci
PIP_PINS=(maturin==1.7.4 numpy==2.0.2 pytest==8.3.3)

python=${PYTHON:-python3}
if ! command -v "$python" >/dev/null 2>&1; then
    # A fresh Debian 12 without the pyenv CPython: Debian's.
    apt-get update -qq && apt-get install -y -qq python3 python3-venv >/dev/null
    python=python3
fi
"$python" --version
rm -rf "$work/venv" "$work/wheels"
mkdir -p "$work"
if ! "$python" -m venv "$work/venv" 2>/dev/null; then
    # Debian's python3 ships venv without ensurepip.
    apt-get update -qq && apt-get install -y -qq python3-venv >/dev/null
    "$python" -m venv "$work/venv"
fi
py=$work/venv/bin/python
if ! "$py" -m pip install --quiet --disable-pip-version-check "${PIP_PINS[@]}"; then
    # Only an unreachable index is a skip; any other pip failure fails.
    if ! "$py" -m pip download --quiet --no-deps --disable-pip-version-check \
        -d "$work/probe" pytest==8.3.3 >/dev/null 2>&1; then
        echo "SKIPPED: pip cannot reach the package index, so the Python package was not built or tested"
        exit 0
    fi
    echo "pip could reach the index but could not install ${PIP_PINS[*]}" >&2
    exit 1
fi
export PYO3_PYTHON=$py
# The venv first: pip's PEP 517 build without isolation runs its maturin.
export PATH=$work/venv/bin:$PATH

echo "-- rustfmt and clippy (the crate is its own workspace)"
cargo fmt --manifest-path bindings/python/Cargo.toml --check
cargo clippy --quiet --manifest-path bindings/python/Cargo.toml --all-targets -- -D warnings

echo "-- maturin build: one abi3 wheel for CPython 3.9+"
"$work/venv/bin/maturin" build --quiet --release -m bindings/python/Cargo.toml \
    --interpreter "$py" -o "$work/wheels"
wheel=$(ls "$work"/wheels/micromap_index-*.whl)
case "$wheel" in
    *-cp39-abi3-*) ;;
    *) echo "not an abi3 cp39 wheel: $wheel" >&2; exit 1 ;;
esac
"$py" -m pip install --quiet --disable-pip-version-check --no-index --no-deps "$wheel"

echo "-- pytest (bindings/python/tests), the CLI's bytes from target/release"
cargo build --quiet --release -p micromap-index-cli --bin micromap-index
MICROMAP_INDEX_CLI=$root/target/release/micromap-index \
    "$py" -m pytest -q -p no:cacheprovider bindings/python/tests

echo "-- pip install ./bindings/python (maturin as the PEP 517 backend)"
"$py" -m pip uninstall --quiet -y micromap-index
"$py" -m pip install --quiet --disable-pip-version-check --no-build-isolation --no-deps ./bindings/python
(cd "$work" && "$py" -c "import micromap_index as m; assert m.index(0.28, 0.4, 3) == 23; print('micromap_index', m.__version__, 'from', m.__file__)")
