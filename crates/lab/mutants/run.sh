#!/usr/bin/env bash
# Mutation testing of the proof tiers: applies each mutant of
# crates/lab/mutants/mutants.txt to a clean tree, one at a time, runs the
# proof tiers and reports the mutants that survive (exit 1 if any does).
#
#   bash crates/lab/mutants/run.sh            # every mutant
#   bash crates/lab/mutants/run.sh 2 3        # mutants 2 and 3 (1-based)
#
# The proof tiers: the all-levels proof and its certification and
# derivations (the lab's prove_all_levels unit tests: the search,
# `Machine::new`'s symbolic derivation of the reference, the certification
# against every face of levels 0..=8 and the committed listing), the
# transducers against the real functions on faces (tests/prove_all_levels.rs)
# and the face-by-face enumeration at small levels (tests/prove.rs).
# Needs a clean work tree for the mutated files; restores them on exit.
set -uo pipefail
cd "$(dirname "$0")/../../.."
list=crates/lab/mutants/mutants.txt
tiers() {
    cargo test -q -p micromap-index-lab --lib prove_all_levels >/dev/null 2>&1 \
        && cargo test -q -p micromap-index-lab --test prove_all_levels >/dev/null 2>&1 \
        && cargo test -q -p micromap-index-lab --test prove >/dev/null 2>&1
}
mapfile -t mutants < <(grep -v '^#' "$list" | grep -v '^$')
selected=("$@")
[ ${#selected[@]} -gt 0 ] || selected=($(seq 1 ${#mutants[@]}))
current=""
restore() { [ -n "$current" ] && git checkout -q -- "$current"; current=""; }
trap restore EXIT INT TERM
survivors=0
for i in "${selected[@]}"; do
    line=${mutants[$((i - 1))]}
    IFS='|' read -r file from to what <<<"$(printf '%s' "$line" | sed 's/\\|/\x01/g')"
    from=${from//$'\x01'/|}; to=${to//$'\x01'/|}
    if ! git diff --quiet -- "$file"; then
        echo "mutant $i: $file has local changes; skipped" >&2; survivors=$((survivors + 1)); continue
    fi
    current=$file
    FROM="$from" TO="$to" python3 - "$file" <<'PY' || { echo "mutant $i: text not found in $file" >&2; restore; survivors=$((survivors + 1)); continue; }
import os, sys
path = sys.argv[1]
text = open(path).read()
old, new = os.environ["FROM"], os.environ["TO"]
if old not in text:
    sys.exit(1)
open(path, "w").write(text.replace(old, new, 1))
PY
    if tiers; then
        echo "mutant $i SURVIVED: $what ($file)"
        survivors=$((survivors + 1))
    else
        echo "mutant $i killed: $what"
    fi
    restore
done
echo "$survivors of ${#selected[@]} mutants survived"
[ "$survivors" -eq 0 ]
