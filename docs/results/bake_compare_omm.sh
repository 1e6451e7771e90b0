#!/usr/bin/env bash
# Side by side: micromap-index (the CLI, 1 thread and default threads),
# meshoptimizer 1.3 (other-bake meshopt-cpp) and NVIDIA's OMM SDK CPU baker
# (other-bake omm-sdk, your own build: crates/other-bakers/README.md) on the
# committed Poly Haven fern and on the Crytek Sponza grid (both textures),
# linear, clamp-to-edge, cutoff 0.5, opaque above, every triangle at the same
# level. Per case and level, ROUNDS rounds, each running every baker once in
# a rotating order (so all see the same machine load): known fraction, bake
# time (best over the rounds: the CLI's bake_seconds, other-bake's timed
# bake call), the whole process's wall time and peak RSS (/usr/bin/time);
# then `micromap-index verify-bake` under our model on each baker's output
# (contradictions), and whether the multi-threaded outputs are byte-identical
# to the one-thread ones. Writes the tables to OUT.
#
# Usage (from anywhere):
#   docs/results/bake_compare_omm.sh /path/to/libomm-lib.so   (or OMM_SDK_LIB=...)
#   docs/results/bake_compare_omm.sh --no-omm                 (without the SDK)
# Environment: ROUNDS (default 5; level 8 and above run (ROUNDS+1)/2),
#   LEVELS (default "4 6 8"), CASES (default "fern thorn-grid chain-grid"),
#   VERIFY_ARGS (extra verify-bake flags, e.g. "--model exact"),
#   OUT (default docs/results/bake_compare_omm.txt).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
lib=${1:-${OMM_SDK_LIB:-}}
if [ -z "$lib" ]; then
  echo "usage: $0 /path/to/libomm-lib.so | --no-omm   (or set OMM_SDK_LIB)" >&2
  exit 2
fi
if [ "$lib" = --no-omm ]; then
  lib=""
elif [ ! -f "$lib" ]; then
  echo "$0: $lib: no such file (your build of the OMM SDK's libomm-lib.so)" >&2
  exit 2
else
  lib=$(cd "$(dirname "$lib")" && pwd)/$(basename "$lib")
fi
rounds=${ROUNDS:-5}
levels=${LEVELS:-"4 6 8"}
cases=${CASES:-"fern thorn-grid chain-grid"}
verify_args=${VERIFY_ARGS:-}
out_file=${OUT:-$root/docs/results/bake_compare_omm.txt}
command -v /usr/bin/time >/dev/null || { echo "$0: needs /usr/bin/time (GNU time)" >&2; exit 2; }

cd "$root"
cargo build --release --quiet -p micromap-index-cli
(cd crates/other-bakers && CARGO_TARGET_DIR="$PWD/target" cargo build --release --quiet)
mi="$root/target/release/micromap-index"
ob="$root/crates/other-bakers/target/release/other-bake"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The fern's 6,232 UV triangles in TRIS.json form, from its glTF (the four
# meshes in order; f32 values written exactly).
python3 - assets/polyhaven-fern02/fern_02.gltf >"$work/fern.tris.json" <<'PY'
import json, os, struct, sys
path = sys.argv[1]
g = json.load(open(path))
bufs = [open(os.path.join(os.path.dirname(path), b["uri"]), "rb").read() for b in g["buffers"]]
def accessor(i):
    a = g["accessors"][i]
    view = g["bufferViews"][a["bufferView"]]
    n = {"SCALAR": 1, "VEC2": 2, "VEC3": 3}[a["type"]]
    fmt = {5126: "f", 5125: "I", 5123: "H", 5121: "B"}[a["componentType"]]
    stride = view.get("byteStride", struct.calcsize(fmt) * n)
    start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    data = bufs[view["buffer"]]
    return [struct.unpack_from("<" + fmt * n, data, start + k * stride) for k in range(a["count"])]
tris = []
for mesh in g["meshes"]:
    for p in mesh["primitives"]:
        uv = accessor(p["attributes"]["TEXCOORD_0"])
        idx = [i[0] for i in accessor(p["indices"])] if "indices" in p else list(range(len(uv)))
        tris += [[list(uv[idx[t + k]]) for k in range(3)] for t in range(0, len(idx), 3)]
print('{"triangles": [\n' + ",\n".join("  " + json.dumps(t) for t in tris) + "\n]}")
PY

case_inputs() { # case -> "texture triangles"
  case $1 in
    fern) echo "assets/polyhaven-fern02/textures/fern_02_diff_1k.png $work/fern.tris.json" ;;
    thorn-grid) echo "assets/crytek-sponza/sponza_thorn.png assets/crytek-sponza/grid.tris.json" ;;
    chain-grid) echo "assets/crytek-sponza/chain.png assets/crytek-sponza/grid.tris.json" ;;
    *) echo "$0: unknown case $1" >&2; exit 2 ;;
  esac
}
bakers="ours-1t ours-mt meshopt"
[ -n "$lib" ] && bakers="$bakers omm-1t omm-mt"
sampler=(--filter linear --address clamp-to-edge)
runs="$work/runs.tsv"
: >"$runs"

# One bake: baker case level round -> a line of runs.tsv
# (case level baker round bake_s wall_s rss_kb known_fraction dir).
bake() {
  local baker=$1 case=$2 level=$3 round=$4 texture triangles dir
  read -r texture triangles <<<"$(case_inputs "$case")"
  dir="$work/$case-L$level/$baker"
  rm -rf "$dir"
  local time=(/usr/bin/time -f "%e %M" -o "$work/time")
  case $baker in
    ours-*)
      local threads=()
      [ "$baker" = ours-1t ] && threads=(--threads 1)
      "${time[@]}" "$mi" bake --texture "$texture" --triangles "$triangles" --out "$dir" \
        --level "$level" "${sampler[@]}" --opaque-above "${threads[@]}" --no-preview --quiet >/dev/null
      ;;
    meshopt)
      "${time[@]}" "$ob" --baker meshopt-cpp --texture "$texture" --triangles "$triangles" \
        --level "$level" --format 4 --out "$dir" 2>/dev/null
      ;;
    omm-*)
      local threads=1
      [ "$baker" = omm-mt ] && threads=$(nproc)
      OMM_SDK_LIB="$lib" OTHER_BAKE_THREADS=$threads "${time[@]}" "$ob" --baker omm-sdk \
        --texture "$texture" --triangles "$triangles" --level "$level" --format 4 "${sampler[@]}" \
        --out "$dir" 2>/dev/null
      ;;
  esac
  python3 - "$dir/summary.json" "$work/time" "$case" "$level" "$baker" "$round" "$dir" >>"$runs" <<'PY'
import json, sys
summary, timefile, case, level, baker, rnd, d = sys.argv[1:]
s = json.load(open(summary))
wall, rss = open(timefile).read().split()[-2:]
if "bake_seconds" in s:  # micromap-index bake
    seconds, known = s["bake_seconds"], s["known_fraction"]
else:  # other-bake
    m = s["micro_triangle_states"]
    seconds = s["timing"]["best_seconds"]
    known = (m["transparent"] + m["opaque"]) / sum(m.values())
print(case, level, baker, rnd, seconds, wall, rss, known, d, sep="\t")
PY
}

# verify-bake under our model: baker case level -> a line of verify.tsv
# (case level baker exit contradictions known_checked model).
verify() {
  local baker=$1 case=$2 level=$3 texture triangles dir rc=0
  read -r texture triangles <<<"$(case_inputs "$case")"
  dir="$work/$case-L$level/$baker"
  # shellcheck disable=SC2086 # VERIFY_ARGS is a list of flags
  "$mi" verify-bake --texture "$texture" --triangles "$triangles" --micromaps "$dir" --no-usage \
    "${sampler[@]}" --opaque-above --quiet --json --max-report 1 $verify_args \
    >"$work/verify.json" 2>"$work/verify.err" || rc=$?
  python3 - "$work/verify.json" "$work/verify.err" "$case" "$level" "$baker" "$rc" >>"$work/verify.tsv" <<'PY'
import json, sys
path, err, case, level, baker, rc = sys.argv[1:]
try:
    v = json.load(open(path))
    print(case, level, baker, rc, v["contradictions"], v["known_micro_triangles"], v["model"], sep="\t")
except (ValueError, KeyError):
    print(case, level, baker, rc, "error: " + open(err).read().strip().replace("\t", " "), "", "", sep="\t")
PY
}

uptime_before=$(uptime)
start=$(date +%s)
: >"$work/verify.tsv"
: >"$work/same.tsv"
for case in $cases; do
  for level in $levels; do
    n=$rounds
    [ "$level" -ge 8 ] && n=$(( (rounds + 1) / 2 ))
    read -ra order <<<"$bakers"
    for ((r = 0; r < n; r++)); do
      for ((k = 0; k < ${#order[@]}; k++)); do
        b=${order[$(( (k + r) % ${#order[@]} ))]}
        bake "$b" "$case" "$level" "$r"
      done
    done
    echo "baked $case L$level ($n rounds), $(( $(date +%s) - start )) s" >&2
    for b in ours-1t meshopt ${lib:+omm-1t}; do
      verify "$b" "$case" "$level"
    done
    for pair in ours-1t:ours-mt ${lib:+omm-1t:omm-mt}; do
      a=${pair%:*}; m=${pair#*:}; same=yes
      for f in micromap-data.bin micromap-triangles.bin micromap-indices.bin; do
        cmp -s "$work/$case-L$level/$a/$f" "$work/$case-L$level/$m/$f" || same=no
      done
      printf '%s\t%s\t%s\t%s\n' "$case" "$level" "$m" "$same" >>"$work/same.tsv"
    done
    echo "verified $case L$level, $(( $(date +%s) - start )) s" >&2
  done
done
elapsed=$(( $(date +%s) - start ))

{
  echo "# docs/results/bake_compare_omm.sh: micromap-index vs meshoptimizer 1.3 vs NVIDIA OMM SDK CPU baker"
  echo "# commit: $(git -C "$root" describe --always --dirty) ($(git -C "$root" log -1 --format=%cd --date=short))"
  echo "# machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), $(nproc) cores online ($(grep -c ^processor /proc/cpuinfo) logical CPUs), $(awk '/MemTotal/ {printf "%.0f GiB", $2 / 1048576}' /proc/meminfo)"
  echo "# load before: ${uptime_before#*load average: }; after: $(uptime | sed 's/.*load average: //'); script run ${elapsed} s"
  if [ -n "$lib" ]; then
    echo "# omm-sdk: $(OMM_SDK_LIB="$lib" "$ob" --list | sed -n 's/^omm-sdk loads: //p')"
  else
    echo "# omm-sdk: not run (--no-omm)"
  fi
  echo "# settings: linear, clamp-to-edge, cutoff 0.5, opaque iff alpha > 0.5 (meshoptimizer: its fixed rule, README), 4-state, every triangle at level L"
  echo "# ours: micromap-index bake --level L --filter linear --address clamp-to-edge --opaque-above [--threads 1]"
  echo "# meshopt: other-bake --baker meshopt-cpp; omm: OMM_SDK_LIB=... [OTHER_BAKE_THREADS=$(nproc)] other-bake --baker omm-sdk"
  echo "# verify: micromap-index verify-bake --no-usage --filter linear --address clamp-to-edge --opaque-above $verify_args"
  echo "#   (contradictions as verify-bake counts them: a special-index triangle counts as one micro-triangle)"
  echo "# times: bake = the baker's own timed bake (CLI: summary bake_seconds; other-bake: the bake call, OMM texture creation included),"
  echo "#   best over the rounds; wall = the whole process (reading, writing), best; peak RSS = the largest over the rounds"
  echo
  python3 - "$runs" "$work/verify.tsv" "$work/same.tsv" <<'PY'
import collections, sys
runs = collections.defaultdict(list)
for line in open(sys.argv[1]):
    case, level, baker, rnd, sec, wall, rss, known, _ = line.rstrip("\n").split("\t")
    runs[(case, int(level), baker)].append((float(sec), float(wall), int(rss), float(known)))
verify = {}
for line in open(sys.argv[2]):
    case, level, baker, rc, contra, known, model = line.rstrip("\n").split("\t")
    verify[(case, int(level), baker)] = (rc, contra, known, model)
same = {}
for line in open(sys.argv[3]):
    case, level, baker, s = line.split()
    same[(case, int(level), baker)] = s
names = {"ours-1t": "micromap-index, 1 thread", "ours-mt": "micromap-index, default threads",
         "meshopt": "meshoptimizer 1.3", "omm-1t": "OMM SDK, 1 thread", "omm-mt": "OMM SDK, OpenMP threads"}
order = ["ours-1t", "ours-mt", "meshopt", "omm-1t", "omm-mt"]
cases = list(dict.fromkeys(k[0] for k in runs))
for case in cases:
    for level in sorted({k[1] for k in runs if k[0] == case}):
        base = min(r[0] for r in runs[(case, level, "ours-1t")])
        n = len(runs[(case, level, "ours-1t")])
        print(f"## {case}, level {level} ({n} rounds)")
        print("| baker | known fraction | bake s (best) | vs ours 1 thread | wall s (best) | peak RSS MB | contradictions / known checked (verify-bake) |")
        print("|---|---|---|---|---|---|---|")
        for b in order:
            rs = runs.get((case, level, b))
            if not rs:
                continue
            sec = min(r[0] for r in rs)
            wall = min(r[1] for r in rs)
            rss = max(r[2] for r in rs) / 1024
            known = {round(r[3], 12) for r in rs}
            known_text = f"{rs[0][3]:.4f}" + ("" if len(known) == 1 else " (differs between rounds!)")
            if (case, level, b) in verify:
                rc, contra, checked, model = verify[(case, level, b)]
                check = f"{contra} / {checked} ({model}, exit {rc})" if checked else f"{contra} (exit {rc})"
            else:
                s = same.get((case, level, b))
                check = "same bytes as 1 thread" if s == "yes" else "DIFFERENT bytes from 1 thread"
            print(f"| {names[b]} | {known_text} | {sec:.4f} | {sec / base:.1f}x | {wall:.2f} | {rss:.0f} | {check} |")
        print()
print("## every round: case level baker round bake_s wall_s peak_rss_kb")
for (case, level, b), rs in runs.items():
    cells = "  ".join(f"{r[0]:.4f}/{r[1]:.2f}/{r[2]}" for r in rs)
    print(f"{case} L{level} {b}: {cells}")
PY
} >"$out_file"
echo "wrote $out_file (${elapsed} s)" >&2
