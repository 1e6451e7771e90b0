#!/usr/bin/env bash
# Mutation testing of the proof tiers: applies each mutant of
# crates/lab/mutants/mutants.txt to the work tree, one at a time, runs the
# proof tiers and reports the mutants that survive (exit 1 if any does,
# except those the list marks "(equivalent)": they cannot be killed, and
# docs/verification.md 10.7 says why).
#
#   bash crates/lab/mutants/run.sh            # every mutant (~20 min on 2 cores)
#   bash crates/lab/mutants/run.sh --subset   # the default CI subset (below)
#   bash crates/lab/mutants/run.sh 2 3        # mutants 2 and 3 (1-based)
#
# The full run is behind the project's exhaustive switch (`cargo test
# --release --all-features -- --ignored` runs crates/lab/tests/mutants.rs);
# .ci/run runs the subset: the issue's three mutants of the reference (the
# 64-bit prefix XOR limited to 16 bits, the hypotenuse move on >, the move
# switched off at levels >= 20), the over-pruning search, and three of the
# entry points' (the narrow kernel's fold on <=, cell_dyadic's diagonal
# on the diagonal itself at levels >= 21, which survived every test before
# section 10.12, and index_unchecked's last step by version 1), the SIMD
# lanes' scale one ulp high (outside the modelled source: only the run
# intrinsics catch it) and the rationals' diagonal on > (the token check
# against rationals.py's model).
#
# The proof tiers: `micromap-lab prove --all-levels` itself (the product,
# the kernel's integer halves and spec::cell_dyadic, section 10.12), then
# the all-levels proof and its certification and
# derivations (the lab's prove_all_levels unit tests: the search,
# `Machine::new`'s symbolic derivation of the reference, the certification
# against every face of levels 0..=8 and the committed listing), the
# transducers against the real functions on faces (tests/prove_all_levels.rs)
# and the face-by-face enumeration at small levels (tests/prove.rs). The
# first tier that fails kills the mutant.
# Needs the mutated files unchanged from git; restores them on exit. Pure
# bash and git (no other tool), so it runs on a bare CI machine.
set -uo pipefail
cd "$(dirname "$0")/../../.."
list=crates/lab/mutants/mutants.txt
subset=(1 2 3 11 14 18 23 36 37)
tiers() {
    cargo run -q --release -p micromap-index-lab --bin micromap-lab -- prove --all-levels >/dev/null 2>&1 \
        && cargo test -q -p micromap-index-lab --lib prove_all_levels >/dev/null 2>&1 \
        && cargo test -q -p micromap-index-lab --test prove_all_levels >/dev/null 2>&1 \
        && cargo test -q -p micromap-index-lab --test prove >/dev/null 2>&1
}
mapfile -t mutants < <(grep -v '^#' "$list" | grep -v '^$')
if [ "${1:-}" = --subset ]; then
    selected=("${subset[@]}")
else
    selected=("$@")
fi
[ ${#selected[@]} -gt 0 ] || selected=($(seq 1 ${#mutants[@]}))
current=""
restore() { [ -n "$current" ] && git checkout -q -- "$current"; current=""; }
trap restore EXIT
trap 'restore; exit 130' INT TERM
survivors=0
equivalent=0
started=$SECONDS
for i in "${selected[@]}"; do
    line=${mutants[$((i - 1))]}
    IFS='|' read -r file from to what <<<"${line//\\|/$'\x01'}"
    from=${from//$'\x01'/|}; to=${to//$'\x01'/|}
    if ! git diff --quiet -- "$file"; then
        echo "mutant $i: $file has local changes; not run" >&2; survivors=$((survivors + 1)); continue
    fi
    # Replace the first occurrence of the literal text (quoted: no
    # patterns, no & in the replacement); $(<...) drops the final newline.
    text=$(<"$file")
    if [[ "$text" != *"$from"* ]]; then
        echo "mutant $i: text not found in $file" >&2; survivors=$((survivors + 1)); continue
    fi
    current=$file
    printf '%s\n' "${text/"$from"/"$to"}" >"$file"
    mutant_started=$SECONDS
    # A mutant that does not compile proves nothing about the tiers.
    if ! cargo build -q --release -p micromap-index-lab --bin micromap-lab >/dev/null 2>&1; then
        echo "mutant $i DOES NOT BUILD: $what ($file)"
        survivors=$((survivors + 1))
    elif tiers; then
        if [[ "$what" == "(equivalent)"* ]]; then
            echo "mutant $i survived, as documented: $what ($file, $((SECONDS - mutant_started)) s)"
            equivalent=$((equivalent + 1))
        else
            echo "mutant $i SURVIVED: $what ($file, $((SECONDS - mutant_started)) s)"
            survivors=$((survivors + 1))
        fi
    else
        echo "mutant $i killed: $what ($((SECONDS - mutant_started)) s)"
    fi
    restore
done
echo "$survivors of ${#selected[@]} mutants survived unexpectedly ($equivalent equivalent, documented), $((SECONDS - started)) s"
[ "$survivors" -eq 0 ]
