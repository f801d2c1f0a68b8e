#!/bin/bash
# SPDX-License-Identifier: MIT
# Runs `make quick` in every examples/<name>/ whose Makefile has a `quick:` target (an example
# joins by having one), with BIN and OUT passed down, and prints one line per example: passed,
# PENDING (its output says "PENDING:": a known, documented gap, e.g. a fix not yet merged) or
# FAILED, with its CPU time (user + sys of make and everything it ran, MPI ranks included) and
# wall time. Exit 1 if any failed, else 0. Logs: OUT_DIR/<name>.log.
#
#   examples/run_quick.sh BIN_DIR OUT_DIR [NAME ...]     (default: every example with quick)
set -u
here=$(cd "$(dirname "$0")" && pwd)
bin=$(realpath "${1:?usage: run_quick.sh BIN_DIR OUT_DIR [NAME ...]}")
out=$(realpath -m "${2:?usage: run_quick.sh BIN_DIR OUT_DIR [NAME ...]}")
shift 2
if [ ! -x "$bin/pd-solve" ]; then
    echo "run_quick.sh: $bin/pd-solve not found (build first: make build)" >&2
    exit 2
fi
names=("$@")
if [ ${#names[@]} -eq 0 ]; then
    for mk in "$here"/*/Makefile; do
        grep -q '^quick:' "$mk" && names+=("$(basename "$(dirname "$mk")")")
    done
fi
mkdir -p "$out"
failed=0
summary=()
for name in "${names[@]}"; do
    log="$out/$name.log"
    echo "== examples/$name: make quick (log: $log)"
    /usr/bin/time -f '%U %S %e' -o "$out/$name.time" \
        make -C "$here/$name" quick BIN="$bin" OUT="$out/$name" >"$log" 2>&1
    rc=$?
    # the last line (time puts "Command exited with non-zero status N" first)
    read -r u s e < <(tail -n 1 "$out/$name.time" 2>/dev/null) || { u=0; s=0; e=0; }
    cpu=$(awk -v u="${u:-0}" -v s="${s:-0}" 'BEGIN { printf "%.1f", u + s }')
    if [ $rc -eq 0 ]; then
        status=passed
    elif grep -q 'PENDING:' "$log"; then
        status="PENDING ($(grep -m1 -o 'PENDING:.*' "$log" | cut -c10-120))"
    else
        status="FAILED (exit $rc)"
        failed=1
        tail -n 20 "$log"
    fi
    summary+=("$(printf '%-22s %-8s CPU %7s s  wall %7s s' "$name" "${status%% *}" "$cpu" "${e:-?}")  ${status#* }")
done
echo "== make examples: ${#names[@]} example(s)"
for line in "${summary[@]}"; do
    # "passed" has no detail after the status word
    echo "$line" | sed 's/  passed$//'
done
exit $failed
