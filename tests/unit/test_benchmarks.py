"""benchmarks/ as the documentation uses it: every results file or folder a page (or the
code's own docstrings and comments) cites is in benchmarks/results/, and
benchmarks/README.md has one row for each script."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BENCHMARKS = ROOT / "benchmarks"
PAGES = [ROOT / "README.md", ROOT / "CHANGELOG.md", *sorted((ROOT / "docs").glob("*.md")),
         *sorted((ROOT / "src" / "granflow").rglob("*.py"))]
CITED = re.compile(r"benchmarks/results/[\w./*-]*")


def cited_paths() -> dict[str, str]:
    """Every benchmarks/results path the pages name -> the first page naming it."""
    found: dict[str, str] = {}
    for page in PAGES:
        for match in CITED.findall(page.read_text(encoding="utf-8")):
            found.setdefault(match.rstrip("."), page.name)
    return found


def present(cited: str) -> bool:
    """A file is there; a folder (or a glob) holds at least one file."""
    if "*" in cited:
        return any(p.is_file() for p in ROOT.glob(cited))
    path = ROOT / cited
    return path.is_file() or (path.is_dir() and any(p.is_file() for p in path.rglob("*")))


def test_the_pages_cite_results() -> None:
    assert len(cited_paths()) > 30       # the scan reads the pages (a test that can fail)


@pytest.mark.parametrize("cited", sorted(cited_paths()))
def test_every_results_path_a_page_cites_is_there(cited: str) -> None:
    assert present(cited), f"{cited_paths()[cited]} cites {cited}, which is not there"


def test_the_readme_lists_every_script_once() -> None:
    readme = (BENCHMARKS / "README.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| `([\w.]+\.py)` \|", readme, flags=re.MULTILINE)
    scripts = sorted(p.name for p in BENCHMARKS.glob("*.py"))
    assert sorted(rows) == scripts, (
        f"not listed: {sorted(set(scripts) - set(rows))}; listed but absent or twice: "
        f"{sorted(set(rows) - set(scripts)) or [r for r in rows if rows.count(r) > 1]}")
