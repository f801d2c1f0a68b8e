#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The install test (ctest install.consumer): `cmake --install` into a temporary prefix, a project
# outside the tree (consumer/) configured with find_package(pdgrain) against that prefix, built,
# and run (it packs and solves a scene through the library); then the installed tools and the
# installed Python package, from the prefix alone (build/ is not on any path).
# Usage: test_install.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$1"
src="$2"
tmp="$(mktemp -d "${TMPDIR:-/tmp}/pd-install.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"

cmake --install "$build" --prefix "$prefix" > "$tmp/install.log"
for f in bin/pd-pack bin/pd-partition bin/pd-solve bin/pd-post lib/libpd_pipeline.a \
         lib/cmake/pdgrain/pdgrainConfig.cmake lib/cmake/pdgrain/pdgrainConfigVersion.cmake \
         include/pdgrain/pipeline/simulation.hpp include/pdgrain/core/version.hpp \
         share/pdgrain/data-schema/check_pd_file.py; do
  [ -e "$prefix/$f" ] || { echo "not installed: $f" >&2; exit 1; }
done

# The consumer: configure and build against the prefix only.
cmake -S "$src/tests/install/consumer" -B "$tmp/consumer" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_PREFIX_PATH="$prefix" > "$tmp/configure.log" 2>&1 || { cat "$tmp/configure.log"; exit 1; }
cmake --build "$tmp/consumer" > "$tmp/build.log" 2>&1 || { cat "$tmp/build.log"; exit 1; }
out="$("$tmp/consumer/consumer" "$src/examples/two_discs/scene.json" "$tmp/lib.h5")"
echo "consumer: $out"
case "$out" in nodes*steps*) ;; *) echo "unexpected consumer output" >&2; exit 1 ;; esac

# The installed tools on the consumer's file and a new one.
"$prefix/bin/pd-solve" --version
"$prefix/bin/pd-pack" "$src/examples/two_discs/scene.json" -o "$tmp/tools.h5" -q \
    --set solver.final_time=2e-5
"$prefix/bin/pd-solve" "$tmp/tools.h5" -q
"$prefix/bin/pd-post" "$tmp/lib.h5" -o "$tmp/post" -q
/usr/bin/python3 "$prefix/share/pdgrain/data-schema/check_pd_file.py" "$tmp/lib.h5" > /dev/null

# The library run and the tools' run of the same scene: the same frames (provenance aside).
/usr/bin/python3 - "$tmp/lib.h5" "$tmp/tools.h5" <<'PY'
import sys, h5py, numpy as np
a, b = (h5py.File(p, "r") for p in sys.argv[1:])
pa = a["particles/nodes/position/value"][()]
pb = b["particles/nodes/position/value"][()]
assert pa.shape == pb.shape and np.array_equal(pa, pb), "library and tool frames differ"
print("frames equal:", pa.shape)
PY

# The installed Python package.
if [ -d "$prefix/lib/python3/dist-packages/pdgrain" ]; then
  PYTHONPATH="$prefix/lib/python3/dist-packages" /usr/bin/python3 -c \
    "import pdgrain; print('import pdgrain', pdgrain.__version__, pdgrain.__file__)"
fi
echo "install test: ok"
