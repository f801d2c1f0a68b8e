#!/usr/bin/env bash
# Stability map of pd-solve's time step (issue 11, item 3): dt = k x the stability estimate for
# k = 0.25 ... 3 on five scenes (two discs, notched PMB plate, pre-cracked LPS plate, pack500 in
# contact, two 3D spheres), stable or not, energy-balance drift, broken bonds, CPU time; then
# RESULTS.md (tables, with the map of the code before issue 11 from before.json) and
# stability_map.png. About 5 min of CPU (pack500 is 90 % of it).
# Usage: workflows/accuracy/stability/run.sh [BUILD_DIR]
#   QUICK=1   a subset (k = 0.25, 0.8, 1.25, 2; no pack500), for CI or a first look
#   WORK=DIR  where the solved files go (default: a temporary directory, removed)
#   BIN=DIR   the pd-pack and pd-solve to map (default: BUILD_DIR/bin)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../../.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
work="${WORK:-$(mktemp -d)}"
[ -n "${WORK:-}" ] || trap 'rm -rf "$work"' EXIT
py=/usr/bin/python3
args=()
out="$here/map_after.json"
if [ "${QUICK:-0}" = 1 ]; then
  args=(--k 0.25,0.8,1.25,2 --scenes two_discs,pmb_notched,lps_precracked,spheres_3d)
  out="$work/map_quick.json"
fi
rm -f "$out"
"$py" "$here/stability_map.py" run --bin "${BIN:-$build/bin}" --out "$out" --work "$work" "${args[@]}"
"$py" "$here/stability_map.py" report --after "$out" --before "$here/map_before.json" \
  --md "$here/RESULTS.md" --png "$here/stability_map.png"
echo "wrote $here/RESULTS.md and $here/stability_map.png"
