#!/bin/sh
# Builds the C driver with the implementation under test and checks it.
# Usage: reference/drivers/c/build.sh [IMPLEMENTATION.c]   (from the repository root)
set -eu
here=$(dirname "$0")
impl=${1:-$here/implementation.c}
out=${OUT_DIR:-${TMPDIR:-/tmp}}
cc -O2 -std=c99 -Wall -Wextra -ffp-contract=off -fno-fast-math \
   "$here/driver.c" "$impl" -o "$out/micromap-driver"
"$out/micromap-driver" reference/vectors/spec-f32.json > "$out/answers.jsonl"
echo "wrote $out/answers.jsonl; check it with:"
echo "  micromap-index check --vectors reference/vectors/spec-f32.json --answers $out/answers.jsonl"
