# SPDX-License-Identifier: MIT
"""tools/check_layers.py: the include rules of ARCHITECTURE.md hold on the source, and the
checker reports each kind of violation planted in a copy of the module tree."""
import importlib.util
import pathlib
import shutil

REPO = pathlib.Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location("check_layers", REPO / "tools" / "check_layers.py")
check_layers = importlib.util.module_from_spec(spec)
spec.loader.exec_module(check_layers)


def test_the_include_rules_hold_on_the_source():
    bad, graph = check_layers.check(REPO)
    assert bad == []
    # The layering of STYLE.md 2.1 as it stands: model and solver below store and pipeline.
    assert graph["core"] == set()
    assert graph["model"] == {"core"}
    assert graph["solver"] == {"core", "model"}
    assert "solver" in graph["pipeline"] and "pipeline" not in set().union(*graph.values())


def planted(tmp_path, files):
    for cm in (REPO / "lib").glob("*/CMakeLists.txt"):
        dst = tmp_path / "lib" / cm.parent.name / "CMakeLists.txt"
        dst.parent.mkdir(parents=True)
        shutil.copy(cm, dst)
    for rel, text in files.items():
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_text(text)
    return check_layers.check(tmp_path)[0]


def test_an_upward_include_a_cycle_a_foreign_header_and_a_fat_main_are_reported(tmp_path):
    bad = planted(tmp_path, {
        "lib/model/a.hpp": '#include "solver/solver.hpp"\n',   # model does not link solver
        "lib/solver/b.hpp": '#include "model/model.hpp"\n',
        "lib/core/c.cpp": '#include "h5/file.hpp"\n#include <hdf5.h>\n',
        "lib/h5/d.cpp": '#include "core/log.hpp"\n',
        "tools/pd-x/main.cpp": '#include "store/frames.hpp"\n'})
    text = "\n".join(bad)
    assert "lib/model/a.hpp: includes solver/solver.hpp, but model does not link" in text
    assert "lib/core/c.cpp: includes h5/file.hpp, but core does not link pd::h5" in text
    assert sum("include cycle" in b for b in bad) == 2  # core <-> h5, model <-> solver
    assert "lib/core/c.cpp: includes hdf5.h, only h5 may" in text
    assert "tools/pd-x/main.cpp: includes store/frames.hpp" in text
    assert len(bad) == 6  # solver -> model and h5 -> core alone are allowed
