#!/usr/bin/env python3
"""Part 8 of check-layering.sh (issue 48): in the product's code no source file over 700 lines,
no folder over 14 sources, no include cycle between the files of a module. A file is its header
and its source together (x.hpp + x.cpp), so x.cpp including y.hpp while y.cpp includes x.hpp is
a cycle. A header without a source of its own (inline helpers, a private header of several
sources) is no file of its own here: what it includes counts for each file that includes it, as
the compiler sees it. An include is resolved as the compiler would find it (the file's folder,
its parents, the module's source and include folders). Usage: check_sizes_cycles.py REPO_ROOT"""
import os
import re
import sys

MODULES = ["names", "model", "devices", "db", "acquisition", "ui", "python"]
MAX_LINES, MAX_SOURCES = 700, 14
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"', re.M)


def product_files(root):
    for module in MODULES:
        for folder, dirs, files in os.walk(os.path.join(root, module)):
            dirs[:] = sorted(d for d in dirs if d != "tests" and not d.startswith("."))
            for f in sorted(files):
                if f.endswith((".cpp", ".hpp", ".h")):
                    yield module, os.path.relpath(os.path.join(folder, f), root)


def resolve(root, module, path, inc):
    here = os.path.dirname(path)
    candidates = [os.path.join(here, inc)]
    # ui/cli/x.cpp includes "capture/y.hpp"; a module's sources include "room/private.hpp".
    parts = here.split(os.sep)
    for k in range(len(parts), 0, -1):
        candidates.append(os.path.join(*parts[:k], inc))
    candidates.append(os.path.join(module, "src", inc))
    candidates.append(os.path.join(module, "include", inc))
    for c in candidates:
        c = os.path.normpath(c)
        if os.path.isfile(os.path.join(root, c)):
            return c
    return None


def unit(path):
    """x.hpp and x.cpp are one file: a header folder's twin is the source folder's."""
    base = os.path.splitext(path)[0]
    parts = base.split(os.sep)
    if len(parts) > 3 and parts[1] == "include" and parts[2] == "leafdig":
        # module/include/leafdig/module/room/x -> module/src/room/x
        return os.path.join(parts[0], "src", *parts[4:])
    return base


def main(root):
    fail = False
    per_folder = {}
    includes = {}  # file -> the module's files it includes
    module_of = {}
    for module, path in product_files(root):
        with open(os.path.join(root, path), encoding="utf-8", errors="replace") as fh:
            text = fh.read()
        lines = text.count("\n")
        if lines > MAX_LINES:
            print(f"{path}: {lines} lines, more than {MAX_LINES}: split it by job (docs/architecture.md)")
            fail = True
        if path.endswith(".cpp"):
            per_folder.setdefault(os.path.dirname(path), []).append(path)
        module_of[path] = module
        found = []
        for inc in INCLUDE.findall(text):
            target = resolve(root, module, path, inc)
            if target is not None and target.startswith(module + os.sep):
                found.append(target)
        includes[path] = found
    compiled = {unit(p) for p in includes if p.endswith(".cpp")}
    graph = {}

    def reach(path, seen):
        """The compiled files `path` depends on, through headers of no source of their own."""
        out = set()
        for target in includes.get(path, ()):
            if target in seen:
                continue
            seen.add(target)
            if unit(target) in compiled:
                out.add(unit(target))
            else:
                out |= reach(target, seen)
        return out

    for path in includes:
        me = unit(path)
        if me not in compiled:
            continue
        for other in reach(path, {path}):
            if other != me:
                graph.setdefault((module_of[path], me), set()).add((module_of[path], other))
    for folder, files in sorted(per_folder.items()):
        if len(files) > MAX_SOURCES:
            print(f"{folder}/: {len(files)} sources, more than {MAX_SOURCES}: give it rooms (folders by concern)")
            fail = True
    # Tarjan's strongly connected components: any of more than one file is a cycle.
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in sorted(graph):
        if v not in index:
            visit(v)
    for comp in out:
        names = ", ".join(u for _, u in comp)
        print(f"include cycle in {comp[0][0]}/: {names} include each other (through their .hpp/.cpp):"
              " move what both need into a third file")
        fail = True
    return 1 if fail else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "."))
