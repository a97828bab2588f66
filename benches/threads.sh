#!/usr/bin/env bash
# How `phosphor bench` scales with threads: S1's view (the bundled S1 scene, its `mesh` line
# naming each mesh), for each size, mode and thread count, one line per measurement and a
# table of median frame times and speed-ups against one thread. For machines with more cores
# than the 2-core development machine: are bands still sized so that every core has work?
#
#   benches/threads.sh                                  # bunny, 1080p and 2160p, 1..nproc
#   benches/threads.sh --mesh target/llvmpipe/meshes/sphere_640x640.obj --threads "1 4 16"
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/.." && pwd)

usage() {
  cat <<EOF
usage: benches/threads.sh [options]

  --mesh FILE         mesh drawn in S1 (repeatable; default assets/meshes/bunny.obj)
  --modes "M ..."     shading modes (default "flat phong")
  --sizes "WxH ..."   image sizes (default "1920x1080 3840x2160")
  --threads "N ..."   thread counts (default: 1 2 4 8 ... up to nproc, and nproc)
  --frames N          timed frames per measurement (default 20)
  --rounds R          rounds, each over every thread count in turn (default 3)
  --phosphor PATH     the binary (default target/release/phosphor)
EOF
}

fail() { echo "error: $*" >&2; exit "${2:-1}"; }
meshes=()
modes="flat phong"
sizes="1920x1080 3840x2160"
threads=""
frames=20
rounds=3
phosphor="$repo/target/release/phosphor"
while [ $# -gt 0 ]; do
  [ $# -ge 2 ] || [ "$1" = -h ] || [ "$1" = --help ] || { usage >&2; fail "$1 needs a value" 2; }
  case $1 in
    --mesh) meshes+=("$2"); shift 2 ;;
    --modes) modes=$2; shift 2 ;;
    --sizes) sizes=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    --phosphor) phosphor=$2; shift 2 ;;
    -h | --help) usage; exit 0 ;;
    *) usage >&2; fail "unknown argument \`$1'" 2 ;;
  esac
done
[ ${#meshes[@]} -gt 0 ] || meshes=("$repo/assets/meshes/bunny.obj")
[ -x "$phosphor" ] || fail "$phosphor: no phosphor binary (cargo build --release -p phosphor-cli)"
if [ -z "$threads" ]; then
  n=$(nproc)
  t=1
  while [ "$t" -lt "$n" ]; do threads="$threads $t"; t=$((t * 2)); done
  threads="$threads $n"
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "# $(lscpu | sed -n 's/^Model name: *//p' | head -n1), $(nproc) CPUs, $("$phosphor" --version)"
printf '%-22s %-10s %-6s %7s %10s %8s\n' mesh size mode threads median_ms speedup
for mesh in "${meshes[@]}"; do
  [ -f "$mesh" ] || fail "$mesh: no such file"
  abs=$(cd "$(dirname "$mesh")" && pwd)/$(basename "$mesh")
  scene="$work/$(basename "$mesh" .obj).toml"
  awk -v m="$abs" '/^mesh = /{ print "mesh = \"" m "\""; next } { print }' \
    "$repo/assets/scenes/s1.toml" >"$scene"
  for size in $sizes; do
    for mode in $modes; do
      log="$work/log"
      : >"$log"
      for r in $(seq "$rounds"); do
        for t in $threads; do
          ms=$("$phosphor" bench "$scene" --shading "$mode" --size "$size" --threads "$t" \
            --frames "$frames" | sed -n 's/.*median_ms=\([0-9.]*\).*/\1/p')
          echo "$t $ms" >>"$log"
        done
      done
      for t in $threads; do
        med=$(awk -v t="$t" '$1 == t { print $2 }' "$log" | sort -g | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }')
        [ "$t" = "$(echo $threads | cut -d' ' -f1)" ] && one=$med
        printf '%-22s %-10s %-6s %7s %10s %8.2f\n' "$(basename "$mesh")" "$size" "$mode" "$t" "$med" \
          "$(awk -v a="$one" -v b="$med" 'BEGIN { print a / b }')"
      done
    done
  done
done
