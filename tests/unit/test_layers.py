"""The layers of docs/architecture.md, read from the code: every import of a granflow module
points to its own layer or one below, and the packages import one another without a
cycle."""

from __future__ import annotations

import ast
from pathlib import Path

SOURCE = Path(__file__).resolve().parents[2] / "src" / "granflow"
LAYERS = [   # top to bottom, as the architecture page lists them
    ["cli", "converge", "convergence_report", "sweep", "api", "resuming", "verify", "runner",
     "__main__", "__init__"],
    ["scenarios", "io", "studies"],
    ["diagnostics", "ale"],
    ["fem"],
    ["simulation", "reference"],
    ["config", "physics", "geometry", "data"],
]
RANK = {name: i for i, names in enumerate(LAYERS) for name in names}


def package(module: str) -> str:
    """granflow.io.plots -> io; granflow.cli -> cli; granflow -> __init__."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


def imports() -> list[tuple[str, str, str]]:
    """(importing file, its package, imported package) for every granflow import."""
    out = []
    for path in SOURCE.rglob("*.py"):
        parts = path.relative_to(SOURCE).with_suffix("").parts
        mine = parts[0]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("granflow"):
                out.append((str(path.relative_to(SOURCE)), mine, package(node.module or "")))
            elif isinstance(node, ast.Import):
                out += [(str(path.relative_to(SOURCE)), mine, package(a.name))
                        for a in node.names if a.name.startswith("granflow")]
    return out


def test_every_package_has_a_layer() -> None:
    found = {p.relative_to(SOURCE).parts[0].removesuffix(".py") for p in SOURCE.iterdir()
             if p.suffix == ".py" or (p.is_dir() and (p / "__init__.py").exists())}
    assert found <= set(RANK), found - set(RANK)


def test_imports_point_down_the_layers() -> None:
    upward = [(f, other) for f, mine, other in imports() if RANK[other] < RANK[mine]]
    assert upward == []


def test_packages_import_one_another_without_a_cycle() -> None:
    graph: dict[str, set[str]] = {}
    for _, mine, other in imports():
        if mine != other and other != "__init__":
            graph.setdefault(mine, set()).add(other)

    def reaches(start: str, goal: str, seen: set[str]) -> bool:
        for nxt in graph.get(start, ()):
            if nxt == goal or (nxt not in seen and reaches(nxt, goal, seen | {nxt})):
                return True
        return False

    cycles = [p for p in graph if reaches(p, p, {p})]
    assert cycles == []
