#!/usr/bin/env bash
# Error against CPU time of the accuracy problems (issue 11): RESULTS.md, results.json and one PNG
# per problem in this folder. Usage: workflows/accuracy/run.sh [BUILD] [accuracy.py options]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="${1:-build}"
shift || true
exec /usr/bin/python3 "$here/accuracy.py" --build "$build" "$@"
