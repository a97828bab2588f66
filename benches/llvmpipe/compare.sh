#!/usr/bin/env bash
# Phosphor against Mesa's llvmpipe on the standard scene S1: for each round, mesh and mode,
# times `phosphor bench` and llvmpipe (run.sh) one after the other, alternating which goes
# first (Phosphor draws a copy of assets/scenes/s1.toml naming the mesh, so both draw S1's
# camera, lights, material and normals; `--mesh` alone would frame a three-quarter view), then prints the median over the rounds of each side's median frame time and the ratio
# phosphor / llvmpipe (under 1: Phosphor is faster). See README.md beside this file.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)

usage() {
  cat <<EOF
usage: benches/llvmpipe/compare.sh [options]

  --mesh FILE.obj     mesh drawn in S1 by both (repeatable; default assets/meshes/bunny.obj)
  --modes "M ..."     modes (default "flat gouraud phong"; llvmpipe also has fill)
  --size WxH          image size (default 1920x1080)
  --threads N         threads for both, N >= 1 (default 2)
  --rounds R          interleaved rounds (default 5)
  --frames N          timed frames per measurement, both sides (default 20)
  --cull              skip back faces: llvmpipe --cull, phosphor bench --cull auto
  --phosphor PATH     the binary (default \$CARGO_TARGET_DIR or target, then release/phosphor)
  --log FILE          keep every measurement line here (default: a temporary file, removed)
EOF
}

meshes=()
modes="flat gouraud phong"
size=1920x1080
threads=2
rounds=5
frames=20
cull=0
phosphor="${CARGO_TARGET_DIR:-$repo/target}/release/phosphor"
log=""

fail() { echo "error: $*" >&2; exit "${2:-1}"; }
need_value() { [ $# -ge 2 ] || { usage >&2; fail "$1 needs a value" 2; }; }
whole() { [[ $2 =~ ^[0-9]+$ ]] && [ "$2" -ge 1 ] || fail "$1: expected a whole number >= 1, got \`$2'" 2; }

while [ $# -gt 0 ]; do
  case $1 in
    --mesh) need_value "$@"; meshes+=("$2"); shift 2 ;;
    --modes) need_value "$@"; modes=$2; shift 2 ;;
    --size) need_value "$@"; size=$2; shift 2 ;;
    --threads) need_value "$@"; whole "$1" "$2"; threads=$2; shift 2 ;;
    --rounds) need_value "$@"; whole "$1" "$2"; rounds=$2; shift 2 ;;
    --frames) need_value "$@"; whole "$1" "$2"; frames=$2; shift 2 ;;
    --cull) cull=1; shift ;;
    --phosphor) need_value "$@"; phosphor=$2; shift 2 ;;
    --log) need_value "$@"; log=$2; shift 2 ;;
    -h | --help) usage; exit 0 ;;
    *) usage >&2; fail "unknown argument \`$1'" 2 ;;
  esac
done
[ ${#meshes[@]} -gt 0 ] || meshes=("$repo/assets/meshes/bunny.obj")
[[ $size =~ ^[0-9]+x[0-9]+$ ]] || fail "--size: expected WxH, e.g. 1280x720, got \`$size'" 2
for mode in $modes; do
  case $mode in fill | flat | gouraud | phong) ;; *) fail "--modes: unknown mode \`$mode'" 2 ;; esac
done
for mesh in "${meshes[@]}"; do
  [ -f "$mesh" ] || fail "$mesh: no such file"
done
[ -x "$phosphor" ] ||
  fail "$phosphor: no phosphor binary (cargo build --release -p phosphor-cli, or --phosphor PATH)"

# What this phosphor binary's bench offers: its modes, and whether it has --cull.
bench_help=$("$phosphor" bench --help)
# A mode is listed as `- MODE: ...` under "Possible values" (or in `[possible values: ...]`).
phosphor_mode() { grep -Eq -- "^ *- $1:|possible values:.*[ ,]$1[],]" <<<"$bench_help"; }
phosphor_cull=()
if [ "$cull" = 1 ]; then
  if grep -Eq -- "^ *--cull[ =<]" <<<"$bench_help"; then
    phosphor_cull=(--cull auto)
  else
    echo "warning: $phosphor bench has no --cull: Phosphor draws both sides, llvmpipe culls" >&2
  fi
fi
llvmpipe_cull=()
[ "$cull" = 1 ] && llvmpipe_cull=(--cull)

"$here/run.sh" --setup-only

keep_log=1
if [ -z "$log" ]; then
  log=$(mktemp)
  keep_log=0
fi
: >"$log"
info=$(mktemp)
scenes=$(mktemp -d)
trap 'rm -f "$info"; rm -rf "$scenes"; [ "$keep_log" = 1 ] || rm -f "$log"' EXIT

# S1 around each mesh: the bundled S1 scene with its `mesh` line naming the file (absolute).
s1_scene() { # MESH -> prints the scene's path
  local abs scene
  abs=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
  scene="$scenes/$(printf '%s' "$abs" | cksum | cut -d' ' -f1).toml"
  if [ ! -f "$scene" ]; then
    grep -q '^mesh = ' "$repo/assets/scenes/s1.toml" || fail "assets/scenes/s1.toml: no mesh line"
    awk -v m="$abs" '/^mesh = /{ gsub(/\\/, "\\\\", m); gsub(/"/, "\\\"", m); print "mesh = \"" m "\""; next } { print }' \
      "$repo/assets/scenes/s1.toml" >"$scene"
  fi
  printf '%s\n' "$scene"
}

load1() { cut -d' ' -f1 /proc/loadavg; }

# One measurement line, tagged with the round, the mesh file and the load when it ended.
record() { # ROUND MESH LINE...
  local round=$1 mesh=$2 line
  shift 2
  while IFS= read -r line; do
    [ -n "$line" ] && echo "round=$round file=$mesh load1=$(load1) $line" >>"$log"
  done
}

run_llvmpipe() { # ROUND MESH
  local want=()
  for mode in $modes; do want+=("$mode"); done
  "$here/run.sh" --mesh "$2" --modes "${want[@]}" --size "$size" --threads "$threads" \
    --frames "$frames" "${llvmpipe_cull[@]}" 2>>"$info" | record "$1" "$2"
}

run_phosphor() { # ROUND MESH
  for mode in $modes; do
    phosphor_mode "$mode" || continue
    "$phosphor" bench "$(s1_scene "$2")" --shading "$mode" --size "$size" --threads "$threads" \
      --frames "$frames" "${phosphor_cull[@]}" | sed 's/$/ renderer=phosphor/' | record "$1" "$2"
  done
}

load_before=$(cut -d' ' -f1-3 /proc/loadavg)
for round in $(seq "$rounds"); do
  for mesh in "${meshes[@]}"; do
    echo "round $round/$rounds: $(basename "$mesh") (load $(load1))" >&2
    if [ $((round % 2)) = 1 ]; then
      run_llvmpipe "$round" "$mesh"
      run_phosphor "$round" "$mesh"
    else
      run_phosphor "$round" "$mesh"
      run_llvmpipe "$round" "$mesh"
    fi
  done
done
load_after=$(cut -d' ' -f1-3 /proc/loadavg)

cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -n1)
echo "# CPU: ${cpu:-unknown} ($(nproc) CPUs online)"
echo "# $(grep -m1 '^# ' "$info" | sed 's/^# //; s/, LP_NUM_THREADS.*//')"
grep '^warning:' "$info" | sort -u || true
phosphor_note=""
if [ "$cull" = 1 ]; then
  phosphor_note=" (bench --cull auto)"
  [ ${#phosphor_cull[@]} -gt 0 ] || phosphor_note=" (its bench has no --cull: it draws both sides)"
fi
echo "# phosphor: $phosphor$phosphor_note"
echo "# S1 at $size, $threads threads, cull $([ "$cull" = 1 ] && echo on || echo off), $frames frames" \
  "per measurement, $rounds interleaved rounds; load average before: $load_before, after: $load_after"
echo "# ms: median over the rounds of each round's median frame time [lowest-highest round]"
awk -v modes="$modes" '
  function field(name,   i) {
    for (i = 1; i <= NF; i++) if (index($i, name "=") == 1) return substr($i, length(name) + 2)
    return ""
  }
  function median_of(list,   n, v, i, j, t) {
    n = split(list, v, " ")
    for (i = 1; i <= n; i++) v[i] += 0
    for (i = 2; i <= n; i++) { t = v[i]; for (j = i - 1; j >= 1 && v[j] > t; j--) v[j + 1] = v[j]; v[j + 1] = t }
    lo = v[1]; hi = v[n]
    return n % 2 ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2
  }
  {
    file = field("file"); who = field("renderer"); mode = $4
    key = file SUBSEP who SUBSEP mode
    times[key] = times[key] " " field("median_ms")
    if (who == "llvmpipe") { tris[file] = field("triangles"); name[file] = field("mesh") }
    if (!(file in seen)) { seen[file] = 1; order[++files] = file }
    l = field("load1") + 0
    if (loads == 0 || l < load_lo) load_lo = l
    if (loads == 0 || l > load_hi) load_hi = l
    loads++
  }
  END {
    printf "%-18s %9s %-8s %24s %24s %10s\n", "mesh", "triangles", "mode", "llvmpipe ms", "phosphor ms", "phos/llvm"
    nm = split(modes, m, " ")
    for (f = 1; f <= files; f++) {
      file = order[f]
      for (k = 1; k <= nm; k++) {
        lk = file SUBSEP "llvmpipe" SUBSEP m[k]; pk = file SUBSEP "phosphor" SUBSEP m[k]
        lcell = "n/a"; pcell = "n/a"; ratio = "n/a"
        if (lk in times) { lm = median_of(times[lk]); lcell = sprintf("%.2f [%.2f-%.2f]", lm, lo, hi) }
        if (pk in times) { pm = median_of(times[pk]); pcell = sprintf("%.2f [%.2f-%.2f]", pm, lo, hi) }
        if ((lk in times) && (pk in times) && lm > 0) ratio = sprintf("%.2f", pm / lm)
        label = (file in name) ? name[file] : file
        printf "%-18s %9s %-8s %24s %24s %10s\n", label, tris[file], m[k], lcell, pcell, ratio
      }
    }
    printf "# 1-minute load average during the measurements: %.2f-%.2f\n", load_lo, load_hi
  }
' "$log"
[ "$keep_log" = 1 ] && echo "# every measurement: $log"
exit 0
