#!/usr/bin/env bash
# CPU per budget-exhausted triangle on N threads against one thread
# (issue 37): one triangle over 10^6 periods of the 256 x 1024 chain
# texture at level 12 (16.7 M micro-triangles), baked with
# `--work-budget 1048576` (the budget runs out) and with the default budget
# (it runs out too, after 67 M work units), on 1 thread and on every core.
# The split walk's subtrees share the triangle's budget; the bytes are the
# same on every thread count (`cmp` below). CPU seconds are user + system
# from /usr/bin/time, the best of ROUNDS rounds per column, the columns
# alternating in every round.
# Usage: docs/results/bake_budget_threads.sh [ROUNDS] > docs/results/bake_budget_threads.txt
set -euo pipefail
rounds=${1:-3}
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
cargo build --release --quiet -p micromap-index-cli
mi="$root/target/release/micromap-index"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo '{"triangles":[[[0,0],[1000000,0],[0,1000000]]]}' >"$work/big.json"
cores=$(nproc)
echo "# docs/results/bake_budget_threads.sh $rounds, commit $(git rev-parse --short HEAD)$(git diff --quiet || echo -dirty) ($(date -u +%F\ %H:%M) UTC)"
echo "# $(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //'), $cores cores, load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
# bake BUDGET THREADS -> "cpu_seconds wall_seconds work_units speculative_units"
bake() {
  local out="$work/o-$1-$2"
  rm -rf "$out"
  local budget=()
  [ "$1" = default ] || budget=(--work-budget "$1")
  /usr/bin/time -f '%U %S %e' -o "$work/time" "$mi" bake --texture assets/crytek-sponza/chain.png \
    --triangles "$work/big.json" --level 12 --no-preview --quiet --threads "$2" "${budget[@]}" \
    --out "$out" >/dev/null
  python3 - "$work/time" "$out/summary.json" <<'PY'
import json, sys
user, system, wall = map(float, open(sys.argv[1]).read().split())
s = json.load(open(sys.argv[2]))
assert s["status"]["work_budget_exceeded"] == 1, s["status"]
print(f'{user + system:.2f} {wall:.2f} {s["work_units"]} {s["speculative_work_units"]}')
PY
}
printf '%-9s %7s %10s %10s %10s %12s %12s %9s\n' budget threads cpu_s wall_s \
  work_units speculative cpu/1-thread same_bytes
for budget in 1048576 default; do
  declare -A best=() wall=() units=() spec=()
  for _ in $(seq "$rounds"); do
    for threads in 1 "$cores"; do
      read -r c w u p < <(bake "$budget" "$threads")
      if [ -z "${best[$threads]:-}" ] || python3 -c "import sys; sys.exit(not $c < ${best[$threads]})"; then
        best[$threads]=$c wall[$threads]=$w
      fi
      units[$threads]=$u spec[$threads]=$p
    done
  done
  same=yes
  for f in "$work/o-$budget-1"/*.bin; do
    cmp -s "$f" "$work/o-$budget-$cores/$(basename "$f")" || same=no
  done
  for threads in 1 "$cores"; do
    ratio=$(python3 -c "print(f'{${best[$threads]} / max(${best[1]}, 0.01):.2f}')")
    printf '%-9s %7s %10s %10s %10s %12s %12s %9s\n' "$budget" "$threads" "${best[$threads]}" \
      "${wall[$threads]}" "${units[$threads]}" "${spec[$threads]}" "$ratio" "$same"
  done
  unset best wall units spec
done
