"""Built-in scenarios: TOML files shipped in this package, one per scenario.

A scenario file holds only the keys that differ from the package defaults
(``granflow/defaults.toml``); its first line is a ``#`` comment giving the one-line
description that ``granflow scenarios`` prints.
"""

from __future__ import annotations

from importlib import resources
from importlib.resources.abc import Traversable

_PACKAGE = "granflow.scenarios"   # the TOML files are package data there


def _scenario_files() -> dict[str, Traversable]:
    root = resources.files(_PACKAGE)
    files = {f.name.removesuffix(".toml"): f for f in root.iterdir() if f.name.endswith(".toml")}
    return dict(sorted(files.items()))


def builtin_scenarios() -> dict[str, str]:
    """Name -> one-line description of every built-in scenario, sorted by name."""
    out = {}
    for name, file in _scenario_files().items():
        first = file.read_text(encoding="utf-8").splitlines()[:1]
        out[name] = first[0].lstrip("#").strip() if first and first[0].startswith("#") else ""
    return out


def scenario_text(name: str) -> str:
    """TOML text of the built-in scenario ``name`` (KeyError if there is none)."""
    files = _scenario_files()
    if name not in files:
        raise KeyError(name)
    return files[name].read_text(encoding="utf-8")
