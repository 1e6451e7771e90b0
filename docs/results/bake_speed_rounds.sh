#!/usr/bin/env bash
# Bake speed, micromap-index against meshoptimizer's C++ baker, alternating
# the two in each round so that both see the same machine load: for each
# texture and level, ROUNDS rounds of `other-bake --repeat REPEAT` (best of
# REPEAT whole bakes, one thread) per baker, then per-round ratios
# (micromap-index time / meshoptimizer time) and a summary line.
# Usage (from anywhere): docs/results/bake_speed_rounds.sh [ROUNDS] [REPEAT]
# Needs the other-bakers crate built (crates/other-bakers/README.md).
set -euo pipefail
cd "$(dirname "$0")/../../crates/other-bakers"
rounds=${1:-6}
repeat=${2:-20}
export CARGO_TARGET_DIR="$PWD/target"
cargo build --release --quiet
bin="$CARGO_TARGET_DIR/release/other-bake"
assets=../../assets/crytek-sponza
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
grep -m1 "model name" /proc/cpuinfo
grep -m1 "cpu family" /proc/cpuinfo
uptime
best() { # baker texture level -> best seconds
  "$bin" --baker "$1" --texture "$assets/$2.png" --triangles "$assets/grid.tris.json" \
    --level "$3" --format 4 --repeat "$repeat" --out "$out/$1" >/dev/null
  python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["timing"]["best_seconds"])' "$out/$1/summary.json"
}
for texture in sponza_thorn chain; do
  for level in 4 6 8; do
    n=$rounds
    [ "$level" = 8 ] && n=$(( (rounds + 1) / 2 ))
    ratios=()
    mins=(1e9 1e9)
    for ((r = 0; r < n; r++)); do
      m=$(best meshopt-cpp "$texture" "$level")
      o=$(best micromap-index "$texture" "$level")
      ratio=$(python3 -c "print(f'{$o / $m:.2f}')")
      ratios+=("$ratio")
      mins=($(python3 -c "print(min(${mins[0]}, $m), min(${mins[1]}, $o))"))
      printf '%s L%s round %d: meshopt-cpp %.3f ms, micromap-index %.3f ms (%s)\n' \
        "$texture" "$level" "$r" "$(python3 -c "print($m * 1e3)")" "$(python3 -c "print($o * 1e3)")" "$ratio"
    done
    python3 - "$texture" "$level" "${mins[@]}" "${ratios[@]}" <<'PY'
import statistics, sys
texture, level, m, o, *ratios = sys.argv[1:]
m, o = float(m), float(o)
r = sorted(float(x) for x in ratios)
faster = sum(x < 1 for x in r)
print(f"# {texture} L{level} ({len(r)} rounds): fastest meshopt-cpp {m*1e3:.3f} ms, "
      f"fastest micromap-index {o*1e3:.3f} ms, ratio {o/m:.2f}; per round {r[0]:.2f}-{r[-1]:.2f}, "
      f"median {statistics.median(r):.2f}; micromap-index faster in {faster} of {len(r)}")
PY
  done
done
uptime
