# SPDX-License-Identifier: MIT
"""Prints the size of the bad-input matrix (test_safety.py + test_matrix.py + test_outputs.py) per
tool."""
import collections


def _tool(nodeid):
    low = nodeid.lower()
    for t in ("pd-pack", "pd-partition", "pd-solve", "pd-post"):
        if t in low or "test_" + t[3:] in low:
            return t
    return "pd-solve" if "restart" in low else "other"


def pytest_terminal_summary(terminalreporter):
    counts = collections.Counter()
    passed = 0
    for key in ("passed", "failed", "skipped"):
        for rep in terminalreporter.stats.get(key, []):
            if rep.when != "call" and key != "skipped":
                continue
            if any(f in rep.nodeid for f in ("test_safety.py", "test_matrix.py",
                                             "test_outputs.py")):
                counts[_tool(rep.nodeid)] += 1
                passed += key == "passed"
    if counts:
        per = ", ".join(f"{t} {n}" for t, n in sorted(counts.items()))
        terminalreporter.write_line(f"bad-input matrix: {sum(counts.values())} cases, "
                                    f"{passed} passed ({per})")
