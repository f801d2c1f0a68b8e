#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Runs the libFuzzer harnesses of the instrumented build (build-asan, `make fuzz`) for a bounded time each (CI: 60 s) on a scratch copy
# of the stored corpus (tests/fuzz/corpus/<target>), after replaying every stored regression
# input (tests/fuzz/regressions/<target>/*: inputs that once crashed; each must pass now).
# Prints executions and findings per target; exit 1 if a harness crashed, leaked or hung
# (the reproducer is left in $out/<target>/ and named in the output).
# usage: tests/fuzz/run.sh BUILD_DIR [SECONDS]
set -euo pipefail
build="$(cd "$1" && pwd)"
seconds="${2:-60}"
here="$(cd "$(dirname "$0")" && pwd)"
out="$build/fuzz-run"
# Debian's clang-16 package brings no llvm-symbolizer; llvm 14's (the default one) reads its DWARF.
sym=/usr/bin/llvm-symbolizer
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:suppressions=$here/../asan/ubsan.supp:external_symbolizer_path=$sym"
export ASAN_SYMBOLIZER_PATH="$sym"
export ASAN_OPTIONS="detect_leaks=0"
failed=0
for t in fuzz_scene fuzz_file; do
  exe="$build/fuzz/$t"
  name="${t#fuzz_}"
  rm -rf "$out/$t" && mkdir -p "$out/$t/corpus"
  cp "$here/corpus/$name"/* "$out/$t/corpus/"
  regress=("$here/regressions/$name"/*)
  if [ -e "${regress[0]}" ]; then
    if ! "$exe" "${regress[@]}" > "$out/$t/regressions.log" 2>&1; then
      echo "fuzz: $t: a stored regression input fails again:"; tail -30 "$out/$t/regressions.log"
      failed=1
    else
      echo "fuzz: $t: ${#regress[@]} regression inputs pass"
    fi
  fi
  dict=()
  [ -f "$here/$name.dict" ] && dict=("-dict=$here/$name.dict")
  set +e
  (cd "$out/$t" && "$exe" corpus "${dict[@]}" -max_total_time="$seconds" -timeout=20 \
     -rss_limit_mb=3072 -max_len=4096 -print_final_stats=1 -artifact_prefix="$out/$t/" \
     > run.log 2>&1)
  rc=$?
  set -e
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$out/$t/run.log" | grep -o '[0-9]*$' || echo 0)
  crashes=$(ls "$out/$t" | grep -cE '^(crash|leak|timeout|oom|slow-unit)-' || true)
  echo "fuzz: $t: ${seconds} s, ${execs} executions, ${crashes} findings (exit $rc)"
  if [ "$rc" -ne 0 ] || [ "$crashes" -gt 0 ]; then
    failed=1
    grep -E 'ERROR|SUMMARY|exception outside|Test unit written' "$out/$t/run.log" | head -20 || true
  fi
done
exit $failed
