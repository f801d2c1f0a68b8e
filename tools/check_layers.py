#!/usr/bin/python3
"""The include rules of lib/ and tools/ (ARCHITECTURE.md, "Include rules"), checked on the source:

1. A file of lib/<m>/ includes "<x>/..." only for x = m or a module m links (pd::x in m's
   pd_add_module, PUBLIC or PRIVATE, and what those link PUBLIC, transitively).
2. The modules' include graph has no cycle.
3. Each third-party library with a heavy or global header is included by one module only:
   hdf5.h -> h5, CGAL -> geometry, gmsh.h -> mesh, metis.h -> partition, vtk* -> post,
   yaml-cpp -> pipeline, CLI11 -> core (and the tools' mains), Eigen -> post and solver.
4. tools/<t>/main.cpp includes core/tool.hpp, pipeline/<step>.hpp and CLI11 only.

Usage: check_layers.py [SOURCE_DIR]  (exit 1 and one line per violation)."""
import pathlib
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]', re.M)
THIRD_PARTY = {  # header prefix -> the one module that may include it
    "hdf5.h": "h5", "H5": "h5", "CGAL/": "geometry", "gmsh.h": "mesh", "metis.h": "partition",
    # Eigen is header-only: the 3D Kabsch fit (post), the Lanczos stability estimate (solver)
    "vtk": "post", "yaml-cpp/": "pipeline", "CLI/": "core", "Eigen/": ("post", "solver")}


def module_deps(lib):
    """{module: set of pd:: modules it links} from lib/<m>/CMakeLists.txt."""
    deps = {}
    public = {}
    for cm in sorted(lib.glob("*/CMakeLists.txt")):
        text = cm.read_text()
        m = re.search(r"pd_add_module\((\w+)(.*?)\)\s*$", text, re.S | re.M)
        if not m:
            continue
        name, body = m.group(1), m.group(2)
        pub = re.search(r"PUBLIC_DEPS(.*?)(PRIVATE_DEPS|$)", body, re.S)
        public[name] = set(re.findall(r"pd::(\w+)", pub.group(1))) if pub else set()
        deps[name] = set(re.findall(r"pd::(\w+)", body))
    closure = {}
    for name in deps:
        seen, todo = set(), list(deps[name])
        while todo:
            d = todo.pop()
            if d not in seen:
                seen.add(d)
                todo += public.get(d, set())
        closure[name] = seen
    return closure


def includes(path):
    return INCLUDE.findall(path.read_text(errors="replace"))


def check(src):
    lib, bad = src / "lib", []
    allowed = module_deps(lib)
    modules = set(allowed)
    graph = {m: set() for m in modules}
    for f in sorted(p for p in lib.rglob("*") if p.suffix in (".hpp", ".cpp", ".in", ".def")):
        m = f.relative_to(lib).parts[0]
        if m not in modules:
            continue
        for inc in includes(f):
            top = inc.split("/")[0]
            if top in modules and "/" in inc:
                graph[m].add(top) if top != m else None
                if top != m and top not in allowed[m]:
                    bad.append(f"{f.relative_to(src)}: includes {inc}, but {m} does not link "
                               f"pd::{top}")
            for prefix, owner in THIRD_PARTY.items():
                owners = (owner,) if isinstance(owner, str) else owner
                if inc.startswith(prefix) and m not in owners:
                    bad.append(f"{f.relative_to(src)}: includes {inc}, only "
                               f"{' or '.join(owners)} may")
    # 2. no cycle (depth-first search)
    state = {}

    def visit(m, stack):
        state[m] = 1
        for d in graph[m]:
            if state.get(d) == 1:
                bad.append("include cycle: " + " -> ".join(stack + [m, d]))
            elif d not in state:
                visit(d, stack + [m])
        state[m] = 2

    for m in sorted(modules):
        if m not in state:
            visit(m, [])
    for main in sorted(src.glob("tools/*/main.cpp")):
        for inc in includes(main):
            if not (inc == "core/tool.hpp" or re.fullmatch(r"pipeline/\w+\.hpp", inc)
                    or inc.startswith("CLI/")):
                bad.append(f"{main.relative_to(src)}: includes {inc} (a tool's main includes "
                           "core/tool.hpp, pipeline/<step>.hpp and CLI11 only)")
    return bad, graph


def main():
    src = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).parents[1])
    bad, graph = check(src)
    for line in bad:
        print(line)
    if not bad:
        print("include rules hold: " + "; ".join(
            f"{m} -> {', '.join(sorted(graph[m])) or '-'}" for m in sorted(graph)))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
