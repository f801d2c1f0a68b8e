# SPDX-License-Identifier: MIT
"""data-schema/scene.schema.json stays in step with what pd-pack accepts: (a) every example scene
validates, (b) the key set of every object in the schema equals a key list of a check_keys call in
the scene parser (lib/pipeline/scene.cpp and lib/pipeline/scene/*.cpp, one file per section) and
the other way round, (c) an unknown key is refused by pd-pack with exit 2 naming the key and the
closest valid key."""

import json
import re

import pytest

from conftest import REPO, run

SCHEMA = REPO / "data-schema" / "scene.schema.json"
SCENE_CPP = [REPO / "lib" / "pipeline" / "scene.cpp",
             *sorted((REPO / "lib" / "pipeline" / "scene").glob("*.cpp"))]
EXAMPLES = sorted(REPO.glob("examples/*/scene*.json"))


def strip_comments(text):
    """Removes // comments outside strings (scene files allow them)."""
    out, i, in_str = [], 0, False
    while i < len(text):
        c = text[i]
        if in_str:
            out.append(c)
            if c == "\\":
                out.append(text[i + 1])
                i += 1
            elif c == '"':
                in_str = False
        elif c == '"':
            in_str = True
            out.append(c)
        elif text.startswith("//", i):
            while i < len(text) and text[i] != "\n":
                i += 1
            continue
        else:
            out.append(c)
        i += 1
    return "".join(out)


def load_scene(path):
    return json.loads(strip_comments(path.read_text()))


@pytest.fixture(scope="module")
def schema():
    return json.loads(SCHEMA.read_text())


def test_schema_is_valid_draft_2020_12(schema):
    jsonschema = pytest.importorskip("jsonschema")
    jsonschema.Draft202012Validator.check_schema(schema)


@pytest.mark.parametrize("scene", EXAMPLES, ids=[p.parent.name + p.stem[5:] for p in EXAMPLES])
def test_examples_validate(schema, scene):
    jsonschema = pytest.importorskip("jsonschema")
    errors = sorted(jsonschema.Draft202012Validator(schema).iter_errors(load_scene(scene)),
                    key=lambda e: list(e.path))
    assert not errors, "\n".join(f"{list(e.path)}: {e.message}" for e in errors[:5])


def cpp_key_sets():
    """Key lists of every check_keys(...) call in the scene parser, resolving the named vectors."""
    src = "\n".join(p.read_text() for p in SCENE_CPP)
    named = {m.group(1): re.findall(r'"([^"]*)"', m.group(2))
             for m in re.finditer(r"std::vector<std::string>\s+(\w+)\s*=\s*\{(.*?)\};", src, re.S)}
    # keys = shape_keys; keys.insert(keys.end(), {...})
    for m in re.finditer(r"auto\s+(\w+)\s*=\s*(\w+);\s*\1\.insert\(\1\.end\(\),\s*\{(.*?)\}\);",
                         src, re.S):
        named[m.group(1)] = named[m.group(2)] + re.findall(r'"([^"]*)"', m.group(3))
    sets = set()
    for m in re.finditer(r"check_keys\((.*?)\);", src, re.S):
        args = m.group(1)
        if args.startswith("const json&"):
            continue  # the definition
        # check_keys(obj, where, LIST): LIST is {...}, a named vector, or with(vector, {...})
        keys = []
        third = re.split(r",", args, maxsplit=2)[2]
        for name, ks in named.items():
            if re.search(rf"\b{name}\b", third):
                keys += ks
        brace = third[third.find("{"):] if "{" in third else ""
        keys += re.findall(r'"([^"]*)"', brace)
        sets.add(frozenset(keys))
    return sets


def schema_key_sets(node, out):
    if isinstance(node, dict):
        if node.get("type") == "object" and "properties" in node:
            assert node.get("additionalProperties") is False, sorted(node["properties"])
            out.add(frozenset(node["properties"]))
        for v in node.values():
            schema_key_sets(v, out)
    elif isinstance(node, list):
        for v in node:
            schema_key_sets(v, out)
    return out


def test_schema_keys_match_scene_cpp(schema):
    cpp = cpp_key_sets()
    assert len(cpp) >= 15, cpp  # the parser found the calls
    sch = schema_key_sets(schema, set())
    fmt = lambda ss: sorted(sorted(s) for s in ss)
    assert not (cpp - sch), f"accepted by the scene parser, missing in the schema: {fmt(cpp - sch)}"
    assert not (sch - cpp), f"in the schema, not accepted by the scene parser: {fmt(sch - cpp)}"


@pytest.mark.parametrize("where,bad,good", [
    ("solver", "final_tme", "final_time"),
    ("discretization", "horizon_factr", "horizon_factor"),
    ("particles.0", "materal", "material"),
    ("", "material", "materials"),
])
def test_unknown_key_refused(pd_pack, tmp_path, where, bad, good):
    scene = load_scene(REPO / "examples" / "two_discs" / "scene.json")
    obj = scene
    for part in filter(None, where.split(".")):
        obj = obj[int(part)] if part.isdigit() else obj[part]
    if bad == "material":  # top level: a misspelt block
        scene["material"] = scene.pop("materials")
    else:
        obj[bad] = obj.pop(good)
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(scene))
    out = tmp_path / "out.h5"
    r = run(pd_pack, path, "-o", out)
    assert r.returncode == 2, r.stderr
    assert bad in r.stderr and f"did you mean '{good}'" in r.stderr, r.stderr
    assert not out.exists()
