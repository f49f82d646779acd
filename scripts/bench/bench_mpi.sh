#!/usr/bin/env bash
# Usage: scripts/bench/bench_mpi.sh [build-dir] [frames]
# The parts of the many-machine scaling model (docs/benchmarks/mpi.md), measured on this machine:
# the colon phantom's stereo ic5 fly-through (full-size walls, conformal map, 2 mm apart)
#  - as 1 process with lavapipe on 2 threads, and as 2 ranks of 1 thread each (mpirun,
#    --distribute frames and walls): the same cores, split two ways;
#  - a 1-frame run: what a rank pays before its first frame (volume read and upload, map from the
#    cache, pipelines), and the bytes one frame writes;
#  - rank 0's serial part: the time it spent on sheets of frames whose walls rank 1 rendered
#    (from its summary line).
# Prints seconds; the runs alternate so that drifting load falls on each alike.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
frames=${2:-20}
cvc=$(realpath "$build/app/cvc")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mpirun=(mpirun -np 2 --oversubscribe --bind-to none)
[ "$(id -u)" -eq 0 ] && mpirun+=(--allow-run-as-root)

"$cvc" phantom --force -o "$work/colon.nrrd" >/dev/null
# Wall-clock seconds of a command; its summary line goes to $work/last.txt.
seconds() { local start end; start=$(date +%s.%N); "$@" >"$work/last.txt" 2>/dev/null; end=$(date +%s.%N); awk "BEGIN {print $end - $start}"; }
# Rank 0's serial part of the last shared run: "N sheet(s) of other ranks' walls in S s".
sheets() { grep -o "wrote [0-9]* sheet(s) of other ranks' walls in [0-9.e-]* s" "$work/last.txt" | sed 's/^wrote //'; }
render=("$cvc" render "$work/colon.nrrd" --display ic5 --path "$work/colon.json" --force)
"${render[@]}" --frames 1 -o "$work/warm" >/dev/null 2>&1  # the map into the cache

one=$(LP_NUM_THREADS=2 seconds "${render[@]}" --frames 1 -o "$work/one")
bytes=$(du -sb "$work/one/frame_0000" | cut -f1)
single=$(LP_NUM_THREADS=2 seconds "${render[@]}" --frames "$frames" -o "$work/single")
by_frames=$(seconds "${mpirun[@]}" "${render[@]}" --frames "$frames" --distribute frames -o "$work/frames")
sheets_frames=$(sheets)
by_walls=$(seconds "${mpirun[@]}" "${render[@]}" --frames "$frames" --distribute walls -o "$work/walls")
sheets_walls=$(sheets)
single2=$(LP_NUM_THREADS=2 seconds "${render[@]}" --frames "$frames" -o "$work/single")
same=yes
for layout in frames walls; do diff -rq "$work/single" "$work/$layout" >/dev/null || same=no; done

echo "1-frame run (load + one frame), 1 rank x 2 threads: $one s; one frame writes $bytes bytes"
echo "$frames frames, 1 rank x 2 threads: $single s, again at the end: $single2 s"
echo "$frames frames, 2 ranks x 1 thread, --distribute frames: $by_frames s (rank 0: $sheets_frames)"
echo "$frames frames, 2 ranks x 1 thread, --distribute walls: $by_walls s (rank 0: $sheets_walls)"
echo "folders equal to the single-process one, byte for byte: $same"
