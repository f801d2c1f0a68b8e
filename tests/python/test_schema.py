# SPDX-License-Identifier: MIT
"""(a) The pd-file schema and its two validators: data-schema/check_pd_file.py (h5py) and
`pd-post --check` (C++, the same JSON embedded). Valid files pass; mutated copies are rejected
with messages naming the dataset path; a newer MAJOR schema_version is refused; both validators
report the same violations; the JSON agrees with lib/store/schema.hpp and data-schema/pd-file.md."""

import json
import re
import shutil
import subprocess
import sys

import h5py
import numpy as np
import pytest

import check_pd_file
from conftest import REPO, SCHEMA_DIR

CHECKER = SCHEMA_DIR / "check_pd_file.py"
PREFIX = re.compile(r"^pd-post: error: ")


def mutate(src, dst, fn):
    shutil.copyfile(src, dst)
    with h5py.File(dst, "a") as f:
        fn(f)
    return dst


def run_checker(path):
    return subprocess.run([sys.executable, str(CHECKER), str(path)], capture_output=True, text=True)


def run_pd_post_check(exe, path):
    """(exit status, violations listed on stderr without the 'pd-post: error: FILE: ' prefix)."""
    r = subprocess.run([str(exe), "--check", str(path)], capture_output=True, text=True)
    out = []
    for line in r.stderr.splitlines():
        line = PREFIX.sub("", line)
        if line.startswith(str(path) + ": "):
            line = line[len(str(path)) + 2:]
        if not re.match(r"^/: \d+ violation", line):
            out.append(line)
    return r.returncode, out, r.stderr


def replace(f, path, data, unit=None):
    unit = unit if unit is not None else f[path].attrs.get("unit")
    del f[path]
    f[path] = data
    if unit is not None:
        f[path].attrs["unit"] = unit


def _set_z(f):
    d = f["particles/nodes/velocity/value"]
    d[0, 0, 2] = 1.0


# name -> (mutation, expected message fragment, checked by pd-post --check too)
MUTATIONS = {
    "missing_dataset": (lambda f: f.__delitem__("nodes/volume"), "/nodes/volume: missing", True),
    "missing_unit": (lambda f: f["bodies/center"].attrs.__delitem__("unit"),
                     "/bodies/center: missing unit attribute", True),
    "wrong_unit": (lambda f: f["nodes/volume"].attrs.__setitem__("unit", "m2"),
                   "/nodes/volume: unit 'm2', expected 'm3'", True),
    "shape": (lambda f: replace(f, "contact/friction", np.zeros(3)),
              "/contact/friction: shape (3,) expected (np,)=(1,)", True),
    "dtype": (lambda f: replace(f, "nodes/body", f["nodes/body"][()].astype(np.int64)),
              "/nodes/body: dtype int64, expected int32", True),
    "index_range": (lambda f: f["bonds/neighbor"].__setitem__(0, 10**6),
                    "/bonds/neighbor: values in [0, 1000000], expected within [0, n-1=", True),
    "nan": (lambda f: f["particles/nodes/damage/value"].__setitem__((0, 0), np.nan),
            "/particles/nodes/damage/value: 1 non-finite values", True),
    "csr": (lambda f: f["bonds/offsets"].__setitem__(3, 0),
            "/bonds/offsets: offsets decrease at row", True),
    "planar_z": (_set_z, "/particles/nodes/velocity/value: z component is not 0", True),
    "attr_value": (lambda f: f["h5md/creator"].attrs.__setitem__("name", "other"),
                   "/h5md/creator@name: is 'other', expected 'pdgrain'", True),
    "attr_enum": (lambda f: f.attrs.__setitem__("planar", "plane"), "/@planar: is 'plane'", True),
    "attr_missing": (lambda f: f["solver"].attrs.__delitem__("integrator"),
                     "/solver@integrator: missing", True),
    "no_materials": (lambda f: [f.__delitem__("materials/" + k) for k in list(f["materials"])],
                     "/materials: holds 0 groups, expected at least 1", True),
    "newer_major": (lambda f: f.attrs.__setitem__("schema_version", "2.0.0"),
                    "/@schema_version: file is pd-file 2.0.0, a newer MAJOR version", True),
    "not_pd_file": (lambda f: f.attrs.__setitem__("schema", "other"), "/@schema: is 'other'", True),
    # Checked by the Python validator only: the h5 layer of pd-post cannot see these yet.
    "attr_dtype": (lambda f: f.attrs.__setitem__("dimension", np.int64(2)),
                   "/@dimension: dtype int64, expected int32", False),
    "hard_link": (lambda f: replace(f, "observables/momentum/step",
                                    f["observables/momentum/step"][()]),
                  "/observables/momentum/step: is not a hard link", False),
}


# ---------------------------------------------------------------------------------------------
# hand-made file: no pipeline needed


def test_synthetic_file_is_valid(synthetic_file):
    assert check_pd_file.check(synthetic_file) == []


@pytest.mark.parametrize("name", sorted(MUTATIONS))
def test_python_validator_names_the_path(synthetic_file, tmp_path, name):
    fn, expected, _ = MUTATIONS[name]
    bad = mutate(synthetic_file, tmp_path / ("%s.h5" % name), fn)
    problems = check_pd_file.check(str(bad))
    assert any(expected in p for p in problems), problems
    r = run_checker(bad)
    assert r.returncode == 1, r.stdout + r.stderr
    assert expected in r.stdout


@pytest.mark.parametrize("name", sorted(k for k, v in MUTATIONS.items() if v[2]))
def test_validators_agree(synthetic_file, tmp_path, pd_post, name):
    """pd-post --check lists exactly the violations check_pd_file.py finds."""
    fn, expected, _ = MUTATIONS[name]
    bad = mutate(synthetic_file, tmp_path / ("%s.h5" % name), fn)
    code, cpp, stderr = run_pd_post_check(pd_post, bad)
    assert code == 2, stderr
    assert any(expected in p for p in cpp), stderr
    py = check_pd_file.check(str(bad))
    assert sorted(cpp) == sorted(py)


def test_pd_post_check_accepts_synthetic(synthetic_file, pd_post):
    r = subprocess.run([str(pd_post), "--check", synthetic_file], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "valid pd-file" in r.stdout


def test_unreadable_file_exit_2(tmp_path, synthetic_file):
    data = open(synthetic_file, "rb").read()
    trunc = tmp_path / "truncated.h5"
    trunc.write_bytes(data[: len(data) // 2])
    for path in (trunc, tmp_path / "does_not_exist.h5"):
        r = run_checker(path)
        assert r.returncode == 2, r.stdout + r.stderr
        assert str(path) in r.stderr
        with pytest.raises(check_pd_file.UnreadableFile):
            check_pd_file.check(str(path))


# ---------------------------------------------------------------------------------------------
# the pipeline's file


def test_pipeline_file_is_valid(h5file):
    assert check_pd_file.check(str(h5file)) == []
    r = run_checker(h5file)
    assert r.returncode == 0, r.stdout + r.stderr


def test_pipeline_file_passes_pd_post_check(h5file, pd_post):
    r = subprocess.run([str(pd_post), "--check", str(h5file)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_missing_volume_rejected(h5file, tmp_path, pd_post):
    bad = mutate(h5file, tmp_path / "no_volume.h5", lambda f: f.__delitem__("nodes/volume"))
    assert "/nodes/volume: missing" in check_pd_file.check(str(bad))
    r = run_checker(bad)
    assert r.returncode == 1 and "/nodes/volume" in r.stdout
    code, _, stderr = run_pd_post_check(pd_post, bad)
    assert code == 2
    assert "/nodes/volume" in stderr


def test_newer_major_version_refused(h5file, tmp_path, pd_post):
    bad = mutate(h5file, tmp_path / "v2.h5",
                 lambda f: f.attrs.__setitem__("schema_version", "2.0.0"))
    problems = check_pd_file.check(str(bad))
    assert len(problems) == 1 and "2.0.0" in problems[0], problems
    r = run_checker(bad)
    assert r.returncode == 1 and "2.0.0" in r.stdout
    code, _, stderr = run_pd_post_check(pd_post, bad)
    assert code == 2 and "2.0.0" in stderr
    # The export mode refuses it too (store::check_version), and leaves the file untouched.
    before = bad.read_bytes()
    r = subprocess.run([str(pd_post), str(bad), "-o", str(tmp_path / "out")], capture_output=True,
                       text=True)
    assert r.returncode == 2 and "2.0.0" in r.stderr
    assert bad.read_bytes() == before


def test_newer_minor_version_accepted(h5file, tmp_path):
    ok = mutate(h5file, tmp_path / "v1_99.h5",
                lambda f: f.attrs.__setitem__("schema_version", "1.99.0"))
    assert check_pd_file.check(str(ok)) == []


# ---------------------------------------------------------------------------------------------
# the schema documents agree


def schema():
    return json.loads((SCHEMA_DIR / "pd-file.schema.json").read_text())


def test_schema_agrees_with_store_header():
    """Every path constant and the version in lib/store/schema.hpp appear in the JSON."""
    hpp = (REPO / "lib" / "store" / "schema.hpp").read_text()
    s = schema()
    version = re.search(r'schema_version\s*=\s*"([^"]+)"', hpp).group(1)
    assert version == s["version"]
    # raise_version compares the integers: they must spell the same version (they said 1.2.0
    # while the string said 1.8.0, so a 1.5.0 file that pd-solve added to was never raised).
    ints = [re.search(r"schema_%s\s*=\s*(\d+)" % k, hpp).group(1) for k in ("major", "minor", "patch")]
    assert ".".join(ints) == version
    assert re.search(r'schema_name\s*=\s*"([^"]+)"', hpp).group(1) == s["schema"]
    paths = {e["path"] for e in s["entries"]}
    consts = re.findall(r'constexpr const char\*\s+\w+\s*=\s*"(/[^"]*)"', hpp)
    assert consts, "no path constants found in schema.hpp"
    for p in consts:
        assert p in paths, "%s (lib/store/schema.hpp) is not in pd-file.schema.json" % p


def test_doc_lists_every_entry():
    doc = (SCHEMA_DIR / "pd-file.md").read_text()
    missing = [e["path"] for e in schema()["entries"] if "`%s`" % e["path"] not in doc]
    assert not missing, "pd-file.md does not list: %s" % ", ".join(missing)


def test_schema_entries_are_well_formed():
    s = schema()
    tools = set(s["tools"]) | {"any"}
    for e in s["entries"]:
        assert e["kind"] in ("group", "dataset", "attribute"), e
        assert e["written_by"] in tools, e
        assert set(e["read_by"]) <= tools | {"external"}, e
        if e["kind"] != "group":
            assert e["dtype"] in ("float", "int", "uint", "string"), e
            assert e["rank"] == len(e["shape"]), e
        if e["kind"] == "dataset" and e["dtype"] != "string" and not e["path"].endswith("/step"):
            assert e.get("unit"), "physical dataset without unit: %s" % e["path"]
    assert len({e["path"] for e in s["entries"]}) == len(s["entries"]), "duplicate paths"
