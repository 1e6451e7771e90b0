#!/usr/bin/env bash
# Runs BIN (micromap-index) and LAB (micromap-lab) on a fixed list of
# command lines, mostly error paths, and writes each one's stdout, stderr
# and exit code under OUTDIR (run it with two builds and `diff -r` the two
# folders: issue 32 checked its moves this way). Run from the repository
# root: the messages name the paths as given. Usage: cli_messages.sh BIN LAB OUTDIR
set -uo pipefail
bin=$1; lab=$2; out=$3; rm -rf "$out"; mkdir -p "$out"
A=assets/crytek-sponza
# One scratch path for every run: messages name it.
T=${TMPDIR:-/tmp}/micromap-cli-messages; rm -rf "$T"; mkdir -p "$T"
printf '{"triangles": [[[0, 0], [1, 0], [0, 1]]]}' > "$T/one.json"
n=0
case_() { # case_ PROGRAM ARGS...
  local program=$1; shift; n=$((n + 1))
  local name; name=$(printf '%03d' $n)
  "$program" "$@" >"$out/$name.stdout" 2>"$out/$name.stderr" </dev/null
  local rc=$? label=bin
  [ "$program" = "$lab" ] && label=lab
  echo "$rc $label $*" >"$out/$name.cmd"
}
tex=(--texture $A/chain.png --triangles "$T/one.json")
for b in "$bin"; do
  case_ $b
  case_ $b help
  case_ $b nope
  case_ $b help nope
  case_ $b help bake extra
  for c in eval locate check tree bake verify-bake render prove vectors; do case_ $b help $c; case_ $b $c --help; done
  case_ $b prove
  case_ $b bake
  case_ $b bake --out "$T/x"
  case_ $b bake "${tex[@]}"
  case_ $b bake "${tex[@]}" --out "$T/x" --bogus
  case_ $b bake "${tex[@]}" --out "$T/x" --force=1
  case_ $b bake "${tex[@]}" --out "$T/x" --level
  case_ $b bake "${tex[@]}" --out "$T/x" --level 13
  case_ $b bake "${tex[@]}" --out "$T/x" --level +3
  case_ $b bake "${tex[@]}" --out "$T/x" --level ""
  case_ $b bake "${tex[@]}" --out "$T/x" --level 1 --level 2
  case_ $b bake "${tex[@]}" --out "$T/x" --max-level 99
  case_ $b bake "${tex[@]}" --out "$T/x" --max-level x
  case_ $b bake "${tex[@]}" --out "$T/x" --budget 9 --level 3
  case_ $b bake "${tex[@]}" --out "$T/x" --budget lots
  case_ $b bake "${tex[@]}" --out "$T/x" --format 3
  case_ $b bake "${tex[@]}" --out "$T/x" --unknown-as maybe
  case_ $b bake "${tex[@]}" --out "$T/x" --filter cubic
  case_ $b bake "${tex[@]}" --out "$T/x" --address wrap
  case_ $b bake "${tex[@]}" --out "$T/x" --address-u wrap
  case_ $b bake "${tex[@]}" --out "$T/x" --address-v ""
  case_ $b bake "${tex[@]}" --out "$T/x" --border x
  case_ $b bake "${tex[@]}" --out "$T/x" --border inf
  case_ $b bake "${tex[@]}" --out "$T/x" --cutoff 2
  case_ $b bake "${tex[@]}" --out "$T/x" --cutoff nan
  case_ $b bake "${tex[@]}" --out "$T/x" --model fast
  case_ $b bake "${tex[@]}" --out "$T/x" --mips some
  case_ $b bake "${tex[@]}" --out "$T/x" --mips -1
  case_ $b bake "${tex[@]}" --out "$T/x" --index-width 64
  case_ $b bake "${tex[@]}" --out "$T/x" --max-bytes -5
  case_ $b bake "${tex[@]}" --out "$T/x" --max-bytes 10 --level 4
  case_ $b bake "${tex[@]}" --out "$T/x" --work-budget lots
  case_ $b bake "${tex[@]}" --out "$T/x" --bake-work-budget -1
  case_ $b bake "${tex[@]}" --out "$T/x" --threads 0
  case_ $b bake "${tex[@]}" --out "$T/x" --threads +2
  case_ $b bake "${tex[@]}" --out "$T/x" --gltf-out a.gltf
  case_ $b bake --gltf $A/cards.gltf --out "$T/x" --gltf-out a/b.gltf
  case_ $b bake --gltf $A/cards.gltf --out "$T/x" --gltf-out summary.json
  case_ $b bake --gltf $A/cards.gltf --out "$T/x" --gltf-out x.gltf --filter linear
  case_ $b bake --gltf $A/cards.gltf --out "$T/x" --gltf-out x.gltf --opaque-above
  case_ $b bake --gltf $A/cards.gltf "${tex[@]}" --out "$T/x"
  case_ $b bake --gltf $A/missing.gltf --out "$T/x"
  case_ $b bake --gltf $A/chain.png --out "$T/x"
  case_ $b bake --texture $A/missing.png --triangles "$T/one.json" --out "$T/x"
  case_ $b bake --texture "$T/one.json" --triangles "$T/one.json" --out "$T/x"
  case_ $b bake --texture $A/chain.png --triangles $A/chain.png --out "$T/x"
  case_ $b bake --texture $A/chain.png --triangles "$T" --out "$T/x"
  case_ $b bake "${tex[@]}" --out "$T/one.json"
  case_ $b bake "${tex[@]}" --out ""
  case_ $b verify-bake
  case_ $b verify-bake "${tex[@]}"
  case_ $b verify-bake --micromaps "$T"
  case_ $b verify-bake "${tex[@]}" --micromaps "$T/none"
  case_ $b verify-bake "${tex[@]}" --micromaps "$T" --max-report x
  case_ $b verify-bake "${tex[@]}" --micromaps "$T" --max-checks x
  case_ $b verify-bake "${tex[@]}" --micromaps "$T" --model fast
  case_ $b verify-bake "${tex[@]}" --micromaps "$T" --address wrap
  case_ $b verify-bake --gltf $A/cards.gltf --filter linear
  case_ $b verify-bake --gltf $A/cards.gltf --micromaps "$T"
  case_ $b verify-bake --gltf $A/cards.gltf --no-usage
  case_ $b verify-bake --gltf $A/cards.gltf
  case_ $b verify-bake --gltf $A/missing.gltf
  case_ $b render
  case_ $b render "${tex[@]}"
  case_ $b render "${tex[@]}" --out "$T/r" --size 0x1
  case_ $b render "${tex[@]}" --out "$T/r" --size big
  case_ $b render "${tex[@]}" --out "$T/r" --methods bogus
  case_ $b render "${tex[@]}" --out "$T/r" --tracer gpu
  case_ $b render "${tex[@]}" --out "$T/r" --frames 0
  case_ $b render "${tex[@]}" --out "$T/r" --fault x
  case_ $b render "${tex[@]}" --out "$T/r" --max-report x
  case_ $b render "${tex[@]}" --out "$T/r" --level 13
  case_ $b render "${tex[@]}" --out "$T/r" --format 3
  case_ $b render "${tex[@]}" --out "$T/r" --model fast
  case_ $b render "${tex[@]}" --out "$T/r" --micromaps "$T" --level 3
  case_ $b render "${tex[@]}" --out "$T/r" --micromaps "$T" --format 2
  case_ $b render "${tex[@]}" --out "$T/r" --address wrap
  case_ $b eval --variant nope
  case_ $b locate --level 33
  case_ $b locate --level 3 --index x
  case_ $b check
  case_ $b check --vectors "$T/none"
  case_ $b tree
  case_ $b tree encode --format 3
  case_ $b tree lookup
done
case_ "$lab"
case_ "$lab" help
case_ "$lab" nope
case_ "$lab" help prove
case_ "$lab" help vectors
case_ "$lab" prove --level 33
case_ "$lab" prove --levels 3..3
case_ "$lab" prove --sample 0
case_ "$lab" vectors
case_ "$lab" vectors --out ""
case_ "$lab" vectors --answers-from nope --vectors "$T/none"
rm -rf "$T"
echo "$n command lines"
