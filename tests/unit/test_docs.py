"""The user guide's parameter table is generated from the schema: it must be current;
the README stays short."""

from __future__ import annotations

import importlib.util
from pathlib import Path

DOCS = Path(__file__).resolve().parents[2] / "docs"


def test_parameters_md_is_generated_from_the_current_schema() -> None:
    spec = importlib.util.spec_from_file_location("make_parameters", DOCS / "make_parameters.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert (DOCS / "parameters.md").read_text(encoding="utf-8") == module.table(), (
        "docs/parameters.md is stale: run `python docs/make_parameters.py`")


def test_the_readme_stays_short() -> None:
    """At most 150 lines: the detail belongs in docs/."""
    lines = (DOCS.parent / "README.md").read_text(encoding="utf-8").splitlines()
    assert len(lines) <= 150, f"README.md has {len(lines)} lines; move detail into docs/"
