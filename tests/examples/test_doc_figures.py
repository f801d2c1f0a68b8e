#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Docs checked against the runs (issue 28 item 7): a figure that README.md or an
examples/*/README.md quotes from a `make quick` carries a marker

    <!-- quick-figure RUN.json KEY SCALE "TEXT" TOL -->

RUN.json: a file the example's quick target writes under build/examples/ (check_impact.py
--json and the like); KEY: a dotted path into it; SCALE: the factor from the stored number to the
quoted one (100 for a percentage); TEXT: how the README prints the figure (it must appear in the
document, the marker is no substitute); TOL: the absolute tolerance on the quoted number. The
test fails when the run's number, scaled, is more than TOL from the quoted one, so a figure
cannot go stale without a failing test. Runs after the examples' quick targets (ctest DEPENDS);
a run file that is missing fails the test (run the example first: make examples)."""
import json
import os
import pathlib
import re
import shlex

import pytest

SRC = pathlib.Path(os.environ.get("PD_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
RUNS = pathlib.Path(os.environ.get("PD_EXAMPLES_OUT", SRC / "build" / "examples"))
MARK = re.compile(r"^<!--\s*quick-figure\s+(.*?)\s*-->", re.M)  # at a line start


def markers():
    docs = [SRC / "README.md", SRC / "examples" / "README.md"]
    docs += sorted((SRC / "examples").glob("*/README.md"))
    for doc in docs:
        text = doc.read_text()
        for m in MARK.finditer(text):
            run, key, scale, quoted, tol = shlex.split(m.group(1))
            yield pytest.param(doc, text, run, key, float(scale), quoted, float(tol),
                               id=f"{doc.relative_to(SRC)}:{run}:{key}")


def number(quoted):
    return float(re.search(r"[-+]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?", quoted).group(0))


def lookup(data, key):
    for part in key.split("."):
        data = data[part]
    return float(data)


def test_docs_have_markers():
    assert list(markers()), "no quick-figure marker in README.md or examples/*/README.md"


@pytest.mark.parametrize("doc, text, run, key, scale, quoted, tol", list(markers()))
def test_quoted_figure_matches_the_quick_run(doc, text, run, key, scale, quoted, tol):
    assert quoted in MARK.sub("", text), f"{doc}: the marker quotes {quoted!r}, not in the text"
    path = RUNS / run
    assert path.is_file(), f"{path} missing: run the example's quick target first (make examples)"
    got = scale * lookup(json.loads(path.read_text()), key)
    want = number(quoted)
    assert abs(got - want) <= tol, (f"{doc}: quotes {quoted} ({key} of {run}), the quick run "
                                    f"gives {got:.6g}: update the document")
