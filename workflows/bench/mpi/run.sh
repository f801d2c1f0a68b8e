#!/bin/bash
# SPDX-License-Identifier: MIT
# MPI benchmarks (issue 5): strong scaling 1 -> 2 ranks on the 500-grain pack and on a
# 1 million-bond plate, checkpoint write and read time, METIS against a naive block split.
# Usage: [REPEAT=3] workflows/bench/mpi/run.sh [BUILD_DIR] [STEPS]   (prints Markdown tables)
# Times: the step loop (pd-solve's wall time minus its set-up), least of REPEAT runs.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../../.." && pwd)
build=${1:-$src/build}
steps=${2:-200}
bin=$build/bin
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

timer() { awk -v t="$1" '$1 == t {print $3}'; }
# the least of $REPEAT runs (the machine is shared: the minimum is the least disturbed run);
# the step loop only: wall minus set-up
loop() { awk '$1 == "wall" {w = $2} $1 == "pd::setup" {s = $3} END {print w - s}'; }
best() {
  local t m=""
  for _ in $(seq "${REPEAT:-3}"); do
    t=$("$@" | loop)
    m=$(awk -v a="$t" -v b="$m" 'BEGIN {print (b == "" || a < b) ? a : b}')
  done
  echo "$m"
}

echo "| scene | nodes | ranks x threads | steps | loop s | speed-up | efficiency |"
echo "|---|---|---|---|---|---|---|"
for scene in pack500 plate_1m; do
  if [ $scene = pack500 ]; then json=$src/examples/pack500/scene.json; by=grain;
  else json=$here/plate_1m.json; by=node; fi
  "$bin/pd-pack" "$json" -o "$work/$scene.h5" -q
  nodes=$(/usr/bin/python3 -c "import h5py; print(h5py.File('$work/$scene.h5')['nodes/volume'].shape[0])")
  cp "$work/$scene.h5" "$work/${scene}_2.h5"
  part=$("$bin/pd-partition" "$work/${scene}_2.h5" -n 2 --by $by)
  echo "$part" > "$work/${scene}_partition.txt"
  t1=$(best "$bin/pd-solve" "$work/$scene.h5" --overwrite --steps "$steps")
  t2=$(best mpirun --oversubscribe -np 2 "$bin/pd-solve" "$work/${scene}_2.h5" --overwrite --steps "$steps")
  t12=$(OMP_NUM_THREADS=2 best "$bin/pd-solve" "$work/$scene.h5" --overwrite --steps "$steps")
  awk -v s=$scene -v n=$nodes -v st=$steps -v a=$t1 -v b=$t2 -v c=$t12 'BEGIN {
    printf "| %s | %d | 1 x 1 | %d | %.3f | 1.00 | 1.00 |\n", s, n, st, a;
    printf "| %s | %d | 2 x 1 | %d | %.3f | %.2f | %.2f |\n", s, n, st, b, a / b, a / b / 2;
    printf "| %s | %d | 1 x 2 | %d | %.3f | %.2f | %.2f |\n", s, n, st, c, a / c, a / c / 2 }'
done
echo
echo "Partitions (2 parts):"
for scene in pack500 plate_1m; do echo "- $scene: $(cat "$work/${scene}_partition.txt")"; done
echo
# Checkpoint write (every rank its rows, collective) and read (every rank reads all) of the
# plate: one checkpoint at the end of a short run, then a restart that reads it.
echo "| checkpoint of plate_1m | ranks | write s | read s | per million nodes (write, read) |"
echo "|---|---|---|---|---|"
for ranks in 1 2; do
  f=$work/ck_$ranks.h5
  cp "$work/plate_1m.h5" "$f"
  run=(); [ $ranks -gt 1 ] && run=(mpirun --oversubscribe -np $ranks)
  w=$("${run[@]}" "$bin/pd-solve" "$f" --steps 10 | timer pd::store::checkpoint)
  r=$("${run[@]}" "$bin/pd-solve" "$f" --restart --steps 1 | sed -n 's/.*read in \([0-9.e+-]*\) s.*/\1/p')
  nodes=$(/usr/bin/python3 -c "import h5py; print(h5py.File('$f')['nodes/volume'].shape[0])")
  awk -v k=$ranks -v w=$w -v r=$r -v n=$nodes 'BEGIN {
    printf "| %d nodes | %d | %.3f | %.3f | %.3f, %.3f |\n", n, k, w, r, w / n * 1e6, r / n * 1e6 }'
done
