#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Moved to workflows/analysis/check_run.py (issue 28: a checker for users, documented in
workflows/analysis/README.md). This shim keeps `tests/stress/check_run.py FILE.h5` and
`import check_run` from this folder working."""
import importlib.util
import pathlib
import runpy
import sys

_TARGET = pathlib.Path(__file__).resolve().parents[2] / "workflows" / "analysis" / "check_run.py"

if __name__ == "__main__":
    sys.argv[0] = str(_TARGET)
    runpy.run_path(str(_TARGET), run_name="__main__")
else:
    _spec = importlib.util.spec_from_file_location("_pd_check_run", _TARGET)
    _mod = importlib.util.module_from_spec(_spec)
    sys.modules["_pd_check_run"] = _mod
    _spec.loader.exec_module(_mod)
    globals().update({k: v for k, v in vars(_mod).items() if not k.startswith("__")})
