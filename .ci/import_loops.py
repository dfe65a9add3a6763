#!/usr/bin/env python3
"""Finds modules that import each other in a loop, inside each crate of the workspace.

A module is a file (`foo.rs` or `foo/mod.rs`); it imports another when it names it in a
`use crate::…`, `use super::…` or `crate::…::` path. Test modules (`tests.rs`, files under a
`tests/` folder, and everything after `#[cfg(test)]`) are left out: tests may use anything.
Prints each loop and exits 1 when there is one.
"""
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CRATES = {"hairlod": "src"}
for name in sorted(os.listdir(os.path.join(ROOT, "crates"))):
    CRATES[name] = os.path.join("crates", name, "src")


def module_of(src, path):
    rel = os.path.relpath(path, src)[:-3].split(os.sep)
    if rel[-1] in ("mod", "lib", "main"):
        rel = rel[:-1]
    return tuple(rel)


def code_of(path):
    text = open(path, encoding="utf-8").read()
    cut = text.find("#[cfg(test)]")
    if cut >= 0:
        text = text[:cut]
    # Comments (doc links name modules without importing them).
    return re.sub(r"//[^\n]*", "", text)


def paths_in(code):
    """Every `crate::a::b` / `super::a` path, with `use` groups expanded one level."""
    found = []
    for match in re.finditer(r"\b(crate|super(?:::super)*|self)::([A-Za-z_][\w:]*)(::\{([^}]*)\})?", code):
        head, body, _, group = match.groups()
        parts = body.split("::")
        if group:
            for item in group.split(","):
                item = item.strip().split(" as ")[0].split("::")
                if item and item[0]:
                    found.append((head, parts + item))
        else:
            found.append((head, parts))
    return found


DEFINITION = re.compile(
    r"^\s*pub(?:\([^)]*\))?\s+(?:const\s+fn|async\s+fn|unsafe\s+fn|fn|struct|enum|trait|type|const|static|mod)\s+([A-Za-z_]\w*)",
    re.M,
)


def resolve(module, head, parts, modules, defined):
    if head == "crate":
        base = ()
    elif head == "self":
        base = module
    else:
        base = module[: len(module) - head.count("super")]
    target = base
    best = None
    depth = 0
    for part in parts:
        target = target + (part,)
        if target in modules:
            best = target
            depth += 1
        else:
            break
    if best is None and head == "crate":
        best = ()
    if best is not None and depth < len(parts):
        # An item re-exported by `best` from a child: the child is what is imported.
        item = parts[depth]
        if item not in defined.get(best, ()):
            owners = [m for m, names in defined.items()
                      if m[: len(best)] == best and m != best and item in names]
            if len(owners) == 1:
                best = owners[0]
    return best or None


def loops_in(crate, src):
    modules = {}
    for folder, dirs, files in os.walk(os.path.join(ROOT, src)):
        dirs[:] = [d for d in dirs if d != "tests"]
        for file in files:
            if file.endswith(".rs") and file != "tests.rs":
                path = os.path.join(folder, file)
                modules[module_of(os.path.join(ROOT, src), path)] = path
    edges = {m: set() for m in modules}
    defined = {m: set(DEFINITION.findall(code_of(path))) for m, path in modules.items()}
    for module, path in modules.items():
        for head, parts in paths_in(code_of(path)):
            target = resolve(module, head, parts, modules, defined)
            # A module may use its own children and its ancestors' items freely: only edges
            # between modules neither of which contains the other count.
            if target is None or target == module:
                continue
            if target[: len(module)] == module or module[: len(target)] == target:
                continue
            edges[module].add(target)
    # Tarjan's strongly connected components.
    index, low, stack, on, loops, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(edges[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                loops.append(sorted(component))

    sys.setrecursionlimit(10000)
    for v in sorted(modules):
        if v not in index:
            visit(v)
    return [(crate, [("::".join(m) or "lib") for m in c], edges) for c in loops]


def self_test():
    """A made-up crate with one loop (a → b → a, through a re-export) and one child that uses
    its parent (not a loop): exactly the loop is found."""
    import tempfile

    global ROOT
    saved = ROOT
    with tempfile.TemporaryDirectory() as root:
        src = os.path.join(root, "src")
        os.makedirs(os.path.join(src, "b"))
        files = {
            "lib.rs": "mod a;\nmod b;\nmod c;\n",
            "a.rs": "use crate::b::Thing;\npub struct A;\n",
            "b/mod.rs": "mod inner;\npub use inner::Thing;\nuse super::c::C;\n",
            "b/inner.rs": "use crate::a::A;\nuse super::Other;\npub struct Thing;\n",
            "c.rs": "pub struct C;\n#[cfg(test)]\nmod tests { use crate::a::A; }\n",
        }
        for name, text in files.items():
            with open(os.path.join(src, name), "w") as f:
                f.write(text)
        ROOT = root
        try:
            loops = [component for _, component, _ in loops_in("made-up", "src")]
        finally:
            ROOT = saved
    assert loops == [["a", "b::inner"]], loops
    print("self-test passed")


def main():
    if sys.argv[1:] == ["--self-test"]:
        self_test()
        return
    found = 0
    for crate, src in CRATES.items():
        if not os.path.isdir(os.path.join(ROOT, src)):
            continue
        for crate, component, edges in loops_in(crate, src):
            found += 1
            print(f"{crate}: modules that import each other in a loop: {', '.join(component)}")
    if found:
        sys.exit(1)
    print("no module imports another in a loop")


if __name__ == "__main__":
    main()
