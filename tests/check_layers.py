#!/usr/bin/env python3
"""The layer rule of src/ (docs/architecture.md), checked from the sources themselves.

ALLOWED below is the one list of which folder may include which: a folder includes only folders
listed for it, and the list has no cycle, so the folders form layers. The check also reads each
folder's CMakeLists.txt: the tumble_* libraries its library links must be exactly the folders its
files include (no hidden dependency, no stale link).

usage: check_layers.py REPO_ROOT    exit 0 when every rule holds, 1 otherwise (each breach printed)
"""
import os
import re
import sys

# folder -> the folders its files may include (lower layers). Bottom first.
ALLOWED = {
    "base": set(),  # vec3, particles, errors, hashing, text, version, Student t, halo env
    "h5": {"base"},  # HDF5 wrapper (base: the error types of a corrupt file)
    "projection": set(),  # Lambert equal-area grid
    "scene": {"base"},
    "contact": {"base", "scene"},
    "geometry": {"base"},
    "neighbor": {"base"},
    "parallel": {"base", "neighbor"},
    "engine": {"base", "contact", "geometry", "neighbor", "parallel", "scene"},
    "analysis": {"base", "h5", "projection", "scene"},
    "cm": {"base", "h5", "projection"},
    "islands": {"base", "h5", "projection", "scene", "analysis", "cm"},
    "io": {"base", "h5", "scene", "contact", "geometry", "engine", "analysis", "cm"},
    "run": {"base", "h5", "scene", "contact", "geometry", "engine", "io", "analysis", "cm"},
    "campaign": {"base", "h5", "projection", "scene", "engine", "io", "analysis", "islands", "cm",
                 "run"},
    "app": {"base", "h5", "scene", "contact", "engine", "io", "analysis", "islands", "cm", "run",
            "campaign"},
}
EXTERNAL = {"tumble_deps", "tumble_version"}
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"', re.M)


def acyclic(graph):
    state = {}

    def visit(v):
        if state.get(v) == 1:
            return False
        if state.get(v) == 2:
            return True
        state[v] = 1
        ok = all(visit(w) for w in graph.get(v, ()))
        state[v] = 2
        return ok

    return all(visit(v) for v in graph)


def main(root):
    src = os.path.join(root, "src")
    errors = []
    if not acyclic(ALLOWED):
        errors.append("ALLOWED itself has a cycle")
    folders = sorted(d for d in os.listdir(src) if os.path.isdir(os.path.join(src, d)))
    used = {f: set() for f in folders}
    n_includes = 0
    for f in folders:
        if f not in ALLOWED:
            errors.append(f"src/{f}: a folder with no place in ALLOWED (tests/check_layers.py)")
            continue
        for dp, _, files in os.walk(os.path.join(src, f)):
            for name in files:
                if not name.endswith((".hpp", ".cpp", ".h")):
                    continue
                path = os.path.join(dp, name)
                for inc in INCLUDE.findall(open(path, encoding="utf-8").read()):
                    top = inc.split("/")[0]
                    if "/" not in inc or top not in folders:
                        continue
                    n_includes += 1
                    if top == f:
                        continue
                    used[f].add(top)
                    if top not in ALLOWED[f]:
                        errors.append(f"{os.path.relpath(path, root)} includes \"{inc}\": "
                                      f"{f} may not include {top}")
        cmake = os.path.join(src, f, "CMakeLists.txt")
        if not os.path.exists(cmake):
            errors.append(f"src/{f}: no CMakeLists.txt (each folder is one library)")
            continue
        text = re.sub(r"#.*", "", open(cmake, encoding="utf-8").read())
        target = "tumble" if f == "app" else f"tumble_{f}"
        links = set()
        for m in re.finditer(r"target_link_libraries\(\s*(\S+)([^)]*)\)", text):
            if m.group(1) == target:
                links |= {w for w in m.group(2).split() if w.startswith("tumble_")}
        linked = {w[len("tumble_"):] for w in links - EXTERNAL}
        if linked != used[f]:
            errors.append(f"src/{f}/CMakeLists.txt links {sorted(linked)} but its files include "
                          f"{sorted(used[f])}")
    edges = sum(len(v) for v in used.values())
    for e in errors:
        print("layer rule broken:", e)
    print(f"{len(folders)} folders, {edges} folder edges from {n_includes} project includes, "
          f"{len(errors)} breaches")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "."))
