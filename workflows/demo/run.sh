#!/usr/bin/env bash
# The default pipeline on examples/two_discs: pack -> partition -> solve (2 MPI ranks) -> post,
# then a summary.
# Usage: workflows/demo/run.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
out="${2:-$root/out/two_discs}"
bin="$build/bin"
mkdir -p "$out"
start=$(date +%s.%N)
"$bin/pd-pack" "$root/examples/two_discs/scene.json" -o "$out/two_discs.h5" --overwrite
"$bin/pd-partition" "$out/two_discs.h5" -n 2
# two MPI ranks, one grain each (more ranks than cores is allowed, only slower)
mpi=(mpirun -np 2 --oversubscribe)
if [ "$(id -u)" -eq 0 ]; then mpi+=(--allow-run-as-root); fi
"${mpi[@]}" "$bin/pd-solve" "$out/two_discs.h5" --progress-every 5
"$bin/pd-post" "$out/two_discs.h5" -o "$out/post"
end=$(date +%s.%N)
/usr/bin/python3 "$root/workflows/demo/summary.py" "$out/two_discs.h5" "$out/post" \
  --wall "$(echo "$end - $start" | bc)"
