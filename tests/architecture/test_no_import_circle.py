"""No import circle inside reasoner/: every module of the reasoner imports only modules that do not
import it back, however far round (issue 38: explanation.py and investigation.py imported each
other, one of them inside a function). Every import counts: at the top, inside a function, or
under TYPE_CHECKING, since each is a dependency a reader must follow."""
from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).parents[2]
PACKAGE = "reasoner"


def module_files(package: str = PACKAGE) -> dict[str, Path]:
    """Every module of the package by its dotted name (a package by its own name)."""
    out = {}
    for path in (ROOT / package).rglob("*.py"):
        parts = list(path.relative_to(ROOT).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        out[".".join(parts)] = path
    return out


def imported(name: str, path: Path, modules: set[str]) -> set[str]:
    """The package's modules that the module `name` (at `path`) imports."""
    here = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = here.split(".")[:len(here.split(".")) - node.level + 1]
                base = ".".join([*anchor, *([base] if base else [])])
            found |= {f"{base}.{a.name}" if f"{base}.{a.name}" in modules else base for a in node.names}
    return {m for m in found if m in modules and m != name}


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected groups of more than one module (Tarjan's algorithm, iteratively)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out: list[list[str]] = []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, edges = work[-1]
            nxt = next(edges, None)
            if nxt is not None:
                if nxt not in index:
                    index[nxt] = low[nxt] = len(index)
                    stack.append(nxt)
                    on_stack.add(nxt)
                    work.append((nxt, iter(sorted(graph[nxt]))))
                elif nxt in on_stack:
                    low[node] = min(low[node], index[nxt])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                group = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    group.append(member)
                    if member == node:
                        break
                if len(group) > 1:
                    out.append(sorted(group))
    return out


def graph_of(package: str = PACKAGE) -> dict[str, set[str]]:
    files = module_files(package)
    return {name: imported(name, path, set(files)) for name, path in files.items()}


def test_no_module_of_the_reasoner_imports_itself_round_a_circle():
    assert circles(graph_of()) == []


def test_a_circle_is_found_however_it_is_imported():
    assert circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert circles({"a": {"b"}, "b": set()}) == []


def test_relative_imports_are_read_as_the_modules_they_name():
    files = module_files()
    graph = graph_of()
    assert "reasoner.judge.pipeline" in files and "reasoner.judge" in files
    assert {"reasoner.judge.court", "reasoner.judge.sanctions", "reasoner.model"} <= graph["reasoner.judge.pipeline"]
    assert "reasoner.explanation" in graph["reasoner.investigation"]


def test_an_import_for_the_types_alone_counts():
    """The last circle was one: le/terms.py named sentences.Vocabulary under TYPE_CHECKING, for a
    field of the document, while sentences.py reads terms. The document (le/parsed.py) names the
    matcher now; the terms import nothing of the LE reader."""
    graph = graph_of()
    assert "reasoner.le.sentences" in graph["reasoner.le.parsed"]      # under TYPE_CHECKING, still read
    assert graph["reasoner.le.terms"] == set()
