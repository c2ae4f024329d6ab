#!/usr/bin/env python3
"""Checks the module layering: every `#include "rfsitl/..."` crosses only into a
module that the including module depends on (its CMake target_link_libraries,
directly or through them), and no two modules include each other, directly or
in a ring. A module's internal header included from another folder as
"<module>/.../x.hpp" (rooted at src/, e.g. "phy/gmsk/gmsk_pulse.hpp") counts the same.

A module is a folder: include/rfsitl/<m>/ with src/<m>/ (one per library), a
component folder src/<m>/<name>/ with its own CMakeLists.txt (a PHY such as
phy/gmsk, a position source such as position/mavlink) with
include/rfsitl/<m>/<name>/, and apps/. Usage:

    scripts/check_modules.py [ROOT]        # exit 0 when clean, 1 with the errors
"""

import os
import re
import sys

INCLUDE_RE = re.compile(r'^[ \t]*#[ \t]*include[ \t]+"rfsitl/([^"]+)"', re.M)
# A module's internal header included from another folder, rooted at src/
# ("phy/gmsk/gmsk_pulse.hpp", through rfsitl_internal_headers).
INTERNAL_INCLUDE_RE = re.compile(r'^[ \t]*#[ \t]*include[ \t]+"([a-z_]+/[^"]+)"', re.M)
CALL_RE = re.compile(
    r"\b(add_library|add_executable|target_link_libraries|rfsitl_component|SOAPY_SDR_MODULE_UTIL)"
    r"\s*\(([^)]*)\)", re.S)
COMPONENT_TARGET_RE = re.compile(r"\bTARGET\s+(\S+)")


def component_folders(root):
    """{'phy/gmsk', 'position/mavlink', ...}: folders src/<m>/<name>/ with a CMakeLists.txt."""
    found = set()
    src = os.path.join(root, "src")
    for m in os.listdir(src):
        if not os.path.isdir(os.path.join(src, m)):
            continue
        for name in os.listdir(os.path.join(src, m)):
            if os.path.isfile(os.path.join(src, m, name, "CMakeLists.txt")):
                found.add(f"{m}/{name}")
    return found


COMPONENTS = set()


def module_of(rel):
    """'src/phy/gmsk/x.cpp' -> 'phy/gmsk'; 'include/rfsitl/engine/e.hpp' -> 'engine'."""
    parts = rel.split("/")
    if parts[0] == "apps":
        return "apps"
    if parts[0] == "include":
        parts = parts[2:]  # drop include/rfsitl
    elif parts[0] == "src":
        parts = parts[1:]
    else:
        return None
    if len(parts) < 2:
        return None
    if len(parts) > 2 and f"{parts[0]}/{parts[1]}" in COMPONENTS:
        return f"{parts[0]}/{parts[1]}"
    return parts[0]


def read_cmake_graph(root):
    """{module: set of modules it links}, from every CMakeLists.txt under src/ and apps/."""
    target_module = {}
    links = {}
    compiled_in = {}
    component_targets = set()  # every rfsitl_component()'s library
    aliases = {}
    for top in ("src", "apps"):
        for dirpath, _, files in os.walk(os.path.join(root, top)):
            if "CMakeLists.txt" not in files:
                continue
            rel_dir = os.path.relpath(dirpath, root)
            with open(os.path.join(dirpath, "CMakeLists.txt"), encoding="utf-8") as f:
                text = re.sub(r"#[^\n]*", "", f.read())
            for kind, args in CALL_RE.findall(text):
                words = args.split()
                if not words:
                    continue
                name = words[0]
                if kind == "rfsitl_component":
                    component_targets.update(COMPONENT_TARGET_RE.findall(args))
                    continue
                if kind == "SOAPY_SDR_MODULE_UTIL":
                    # SoapySDR's macro: add_library(TARGET ...) linking LIBRARIES.
                    name = COMPONENT_TARGET_RE.findall(args)[0]
                    libraries = args.split("LIBRARIES", 1)[1].split() if "LIBRARIES" in args else []
                    kind, words = "add_library", [name]
                    links.setdefault(name, set()).update(
                        w for w in libraries if w.startswith("rfsitl_"))
                if kind == "add_library" and len(words) == 3 and words[1] == "ALIAS":
                    aliases[name] = words[2]  # rfsitl::rfsitl -> rfsitl_library
                    continue
                if kind in ("add_library", "add_executable"):
                    if not name.startswith("rfsitl"):
                        continue
                    parts = rel_dir.split("/")
                    if parts[0] == "apps":
                        module = "apps"
                    elif len(parts) >= 3:
                        module = f"{parts[1]}/{parts[2]}"
                    else:
                        module = name[len("rfsitl_"):]
                    target_module[name] = module
                    # A target that compiles another module's sources
                    # depends on that module.
                    for other in re.findall(r"/src/([a-z_]+)/[^/\s]+\.cpp", args):
                        compiled_in.setdefault(module, set()).add(other)
                else:
                    deps = links.setdefault(name, set())
                    for w in words[1:]:
                        w = aliases.get(w, w)
                        if w.startswith("rfsitl_") or w in (
                                "${RFSITL_COMPONENT_LIBRARIES}", "${RFSITL_LIBRARY_PARTS}"):
                            deps.add(w)
    graph = {m: set() for m in target_module.values()}
    for m, others in compiled_in.items():
        graph[m] |= {o for o in others if o in graph and o != m}
    for target, deps in links.items():
        if target not in target_module:
            continue
        m = target_module[target]
        for d in deps:
            if d == "${RFSITL_COMPONENT_LIBRARIES}":
                graph[m] |= {target_module[t] for t in component_targets if t in target_module}
            elif d == "${RFSITL_LIBRARY_PARTS}":
                # librfsitl: every library of src/ linked whole.
                graph[m] |= {o for t, o in target_module.items()
                             if t != target and o != "apps" and o != "soapy"}
            elif d in target_module:
                graph[m].add(target_module[d])
        # A component folder nested in its module's folder (a mobility model
        # in position/mobility/orbit/) links its module: the same module.
        graph[m].discard(m)
    return graph


def closure(graph, start):
    seen, todo = set(), [start]
    while todo:
        for d in graph.get(todo.pop(), ()):
            if d not in seen:
                seen.add(d)
                todo.append(d)
    return seen


def find_cycle(graph):
    """One cycle as a list of modules [a, b, ..., a], or None."""
    state = {}
    stack = []

    def visit(m):
        state[m] = "open"
        stack.append(m)
        for d in sorted(graph.get(m, ())):
            if state.get(d) == "open":
                return stack[stack.index(d):] + [d]
            if d not in state:
                found = visit(d)
                if found:
                    return found
        stack.pop()
        state[m] = "done"
        return None

    for m in sorted(graph):
        if m not in state:
            found = visit(m)
            if found:
                return found
    return None


def check(root):
    errors = []
    COMPONENTS.clear()
    COMPONENTS.update(component_folders(root))
    declared = read_cmake_graph(root)
    cycle = find_cycle(declared)
    if cycle:
        errors.append("CMake libraries link in a ring: " + " -> ".join(cycle))
    included = {}
    where = {}
    for top in ("include", "src", "apps"):
        for dirpath, _, files in os.walk(os.path.join(root, top)):
            for name in sorted(files):
                if not name.endswith((".hpp", ".cpp", ".h")):
                    continue
                path = os.path.join(dirpath, name)
                rel = os.path.relpath(path, root)
                mod = module_of(rel)
                if mod is None:
                    continue
                with open(path, encoding="utf-8", errors="replace") as f:
                    text = f.read()
                # (match, the include as written, the header's path in the tree)
                found = [(m, "rfsitl/" + m.group(1), "include/rfsitl/" + m.group(1))
                         for m in INCLUDE_RE.finditer(text)]
                found += [(m, m.group(1), "src/" + m.group(1))
                          for m in INTERNAL_INCLUDE_RE.finditer(text)
                          if os.path.isfile(os.path.join(root, "src", m.group(1)))]
                for match, written, header in found:
                    target = module_of(header)
                    if target is None or target == mod:
                        continue
                    line = text.count("\n", 0, match.start()) + 1
                    included.setdefault(mod, set()).add(target)
                    where.setdefault((mod, target), f"{rel}:{line}")
                    if mod not in declared:
                        errors.append(f"{rel}:{line}: module {mod} has no library in CMake")
                    elif target not in closure(declared, mod):
                        errors.append(
                            f"{rel}:{line}: includes {written} (module {target}), "
                            f"but module {mod} does not link it; declare the dependency in "
                            f"CMake or move the code")
    cycle = find_cycle(included)
    if cycle:
        steps = [f"{a} -> {b} ({where[(a, b)]})" for a, b in zip(cycle, cycle[1:])]
        errors.append("modules include each other in a ring: " + "; ".join(steps))
    return errors, declared


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    errors, declared = check(os.path.abspath(root))
    for e in errors:
        print(e)
    if not errors:
        print(f"module layering: {len(declared)} modules, includes follow the declared "
              f"dependencies, no cycles")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
