"""No import circles in kbm and numerics (issue 23: the models' and the paper friction
figures' circles are settled).

Every ``import`` of the two packages is read from the source (ast), at module level and
inside functions, and the strongly connected components of the graph are computed
(Tarjan).  A deferred import inside a function still ties two modules together, so both
levels are checked.  The circle once kept (the homotopy of ``numerics.cycles.shooting``
continued cycles in its parameter, and the continuation starts from a shot cycle) is gone:
the homotopy sits in ``numerics.cycles.every_cycle``, above both.
"""

from __future__ import annotations

import ast
import functools
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: no circle is kept (see the module docstring)
ALLOWED: set = set()


def _modules() -> dict[str, Path]:
    mods = {}
    for pkg in ("kbm", "numerics"):
        for f in (ROOT / pkg).rglob("*.py"):
            name = ".".join(f.relative_to(ROOT).with_suffix("").parts)
            mods[name.removesuffix(".__init__")] = f
    return mods


def _targets(mods, cur: str, node) -> list[str]:
    base = cur if mods[cur].name == "__init__.py" else cur.rsplit(".", 1)[0]
    if isinstance(node, ast.ImportFrom):
        if node.level:
            parts = base.split(".")
            parts = parts[:len(parts) - (node.level - 1)]
            m = ".".join(parts + ([node.module] if node.module else []))
        else:
            m = node.module or ""
        subs = [f"{m}.{a.name}" for a in node.names if f"{m}.{a.name}" in mods]
        names = subs if len(subs) == len(node.names) else [m, *subs]
    else:
        names = [a.name for a in node.names]
    out = []
    for m in names:
        while m and m not in mods and "." in m:
            m = m.rsplit(".", 1)[0]
        if m in mods and m != cur:
            out.append(m)
    return out


@functools.lru_cache(maxsize=1)
def _graphs() -> tuple[dict, dict, dict]:
    """``(modules, module-level graph, graph with the deferred imports)``: every file parsed
    once for both tests (the parse is most of their time)."""
    mods = _modules()
    shallow, deep = defaultdict(set), defaultdict(set)
    for name, f in mods.items():
        tree = ast.parse(f.read_text())
        for graph, nodes in ((shallow, tree.body), (deep, ast.walk(tree))):
            for node in nodes:
                if isinstance(node, (ast.Import, ast.ImportFrom)):
                    graph[name].update(_targets(mods, name, node))
    return mods, dict(shallow), dict(deep)


def _circles(deep: bool) -> list[frozenset]:
    mods, shallow, deep_graph = _graphs()
    graph = defaultdict(set, deep_graph if deep else shallow)
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):  # Tarjan, iterative enough for this graph's depth
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = set()
            while True:
                w = stack.pop()
                on.discard(w)
                comp.add(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(frozenset(comp))

    for v in sorted(mods):
        if v not in index:
            visit(v)
    return out


def test_no_circle_at_module_level():
    assert _circles(deep=False) == []


def test_no_circle_through_deferred_imports():
    assert set(_circles(deep=True)) <= ALLOWED
