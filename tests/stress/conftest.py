# SPDX-License-Identifier: MIT
"""Fixtures of the stress suite (`/usr/bin/python3 -m pytest tests/stress`).

Environment:
  PD_BIN_DIR        build bin directory with pd-pack and pd-solve (runs are skipped when unset)
  PD_SOURCE_DIR     the source tree (examples/); default: this file's repository
  PD_STRESS_REPORT  optional: a file that receives the table of every run's checks
  PD_STRESS_KEEP    optional: a directory where the solved files are kept (else pytest's tmp)
The table is also printed at the end of the session (pytest -rA or -s not needed)."""

import os
import pathlib
import sys

import pytest

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
# check_run.py, the checker of every run (a user-facing script since issue 28)
sys.path.insert(0, str(HERE.parents[1] / "workflows" / "analysis"))

ROWS = []  # (scene, exit code, seconds, [(check, ok, value, bound)], verdict)


@pytest.fixture(scope="session")
def report():
    return ROWS


def format_table(rows):
    out = ["%-34s %4s %6s  %s" % ("scene", "exit", "sec", "checks (value/bound; F = fails)")]
    for scene, rc, sec, checks, verdict in rows:
        cells = []
        for name, ok, value, bound in checks:
            mark = {True: "", False: "F", None: "-"}[ok]
            if ok is None:
                cells.append("%s:-" % short(name))
            else:
                cells.append("%s%s:%.3g/%.3g" % (mark, short(name), value, bound))
        out.append("%-34s %4d %6.1f  %s  => %s" % (scene, rc, sec, " ".join(cells), verdict))
    return "\n".join(out)


def short(name):
    return {"no_interpenetration": "pen", "no_wall_body_penetration": "wallpen",
            "no_node_below_rigid_wall": "floor", "energy_no_creation": "Ecreate",
            "kinetic_energy_bound": "KEbound", "elastic_energy_nonnegative": "el>=0",
            "energy_balance": "Ebal", "momentum": "p", "speed_bound": "v"}.get(name, name)


def pytest_terminal_summary(terminalreporter):
    if not ROWS:
        return
    text = format_table(ROWS)
    terminalreporter.write_sep("=", "stress runs")
    terminalreporter.write_line(text)
    path = os.environ.get("PD_STRESS_REPORT")
    if path:
        pathlib.Path(path).write_text(text + "\n")
