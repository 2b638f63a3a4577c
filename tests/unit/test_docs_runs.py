"""The numbers the pages quote from runs a user can repeat are the fresh runs' record.

benchmarks/docs_numbers.py runs each command the pages show and records what it printed,
its summary's figures and its processor time (benchmarks/results/docs_numbers/); its
``CLAIMS``, ``RANGES`` and ``BLOCKS`` say where each is quoted. Here: every claim against the
record; every result-like number of a page (a number with a unit of time or length, a count
of triangles or steps, a percentage) covered by a claim of the record or of a benchmark's
results file (tests/unit/test_docs_numbers.py), or counted against the page's backlog of
numbers no claim covers yet, which may only shrink; and (slow) each case run fresh against
the record within ``TOLERANCES``.

The earlier test checked only the numbers it declared, against results files that nothing
compared with a fresh run: the getting-started page's printed lines and the user guide's
erodible run were declared nowhere, and the README's stop time was declared against a
benchmark's record made before a change of MKL's kernels. Rerunning
``python benchmarks/docs_numbers.py --update-docs`` after a change to the numerics rewrites
them all.
"""

from __future__ import annotations

import importlib.util
import json
import re
import sys
from pathlib import Path
from types import ModuleType

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _module(path: Path, name: str) -> ModuleType:
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


NUMBERS = _module(ROOT / "benchmarks" / "docs_numbers.py", "docs_numbers")
RESULT_CLAIMS = _module(Path(__file__).with_name("test_docs_numbers.py"), "docs_claims").CLAIMS
RECORD = json.loads(NUMBERS.RECORD.read_text(encoding="utf-8"))

# a result as the pages quote one: a number and its unit
RESULT = re.compile(r"(?<![\w.-])(\d[\d,]*(?:\.\d+)?(?:e-?\d+)?)\s?"
                    r"(s|ms|m|mm|cm|%|triangles|steps|iterations)(?![\w²³/])")
# the numbers of each page no claim covers yet (inputs such as a column's 29.7 cm among
# them): the count may fall, never rise; lower it when it falls. (The slab's and the rigid
# bed's sections raised erosion.md from 38, model.md from 9, verification.md from 616 and
# user_guide.md from 51: their inputs, the slab's and layers' thicknesses, speeds and cells,
# and ranges read off the claimed tables. The erosion study on the no-slip bed raised
# erosion.md from 86 and verification.md from 665: its rule's thresholds, the fronts' clock
# times and the layers' thicknesses; its rows at 10 and 16 degrees in the channel raised
# erosion.md from 130: their clock times, thicknesses and the predicted ranges; the rows
# carried to rest and the level gain's checks on two meshes raised erosion.md from 158 and
# verification.md from 672: their end times, thicknesses, column heights and mesh sizes.)
BACKLOG = {
    "README.md": 16, "docs/getting_started.md": 5, "docs/user_guide.md": 52,
    "docs/python_api.md": 2, "docs/examples.md": 1, "docs/erosion.md": 199, "docs/index.md": 0,
    "docs/model.md": 19, "docs/outputs.md": 5, "docs/architecture.md": 1,
    "docs/verification.md": 676, "docs/performance.md": 523, "docs/three_d.md": 15,
}
PAGES = sorted(BACKLOG)


def value(path: object, spec: str) -> str:
    return NUMBERS.formatted(NUMBERS.lookup(RECORD, path), spec, NUMBERS.SCALES.get(path, 1.0))


@pytest.mark.parametrize("page, text, path, spec", NUMBERS.CLAIMS,
                         ids=[f"{c[0]}:{c[1][:40]}" for c in NUMBERS.CLAIMS])
def test_a_quoted_run_number_is_the_records(page: str, text: str, path: object,
                                            spec: str) -> None:
    found = NUMBERS.find_claim(page, text)
    assert found is not None, f"{page} should say {text!r}"
    assert found.match[1] == value(path, spec), (
        f"{page} says {found.match[0]!r}; the record ({path}) gives {value(path, spec)}: "
        "run python benchmarks/docs_numbers.py --update-docs")


@pytest.mark.parametrize("page, text, path", NUMBERS.RANGES,
                         ids=[f"{c[0]}:{c[1][:40]}" for c in NUMBERS.RANGES])
def test_a_quoted_processor_time_holds_the_records(page: str, text: str, path: str) -> None:
    found = NUMBERS.find_claim(page, text, ("{lo}", "{hi}"))
    assert found is not None, f"{page} should say {text!r}"
    quoted = (int(found.match[1]), int(found.match[2]))
    assert quoted == NUMBERS.nice_range(NUMBERS.lookup(RECORD, path)), (
        f"{page} quotes {quoted} s; the record gives "
        f"{NUMBERS.nice_range(NUMBERS.lookup(RECORD, path))}: run python "
        "benchmarks/docs_numbers.py --update-docs --no-run")


@pytest.mark.parametrize("page, case, opening", NUMBERS.BLOCKS)
def test_a_printed_block_is_what_the_run_printed(page: str, case: str, opening: str) -> None:
    where = NUMBERS.find_block(page, opening)
    assert where is not None, f"{page}: no block opening with {opening!r}"
    assert where[2] == NUMBERS.block_lines(RECORD, case, opening)


def covered_spans(page: str) -> list[tuple[int, int]]:
    """Where on the page a claim (of the record or of a results file) stands."""
    text = (ROOT / page).read_text(encoding="utf-8")
    spans = []
    claims = [(p, t, ("{}",)) for p, t, *_ in [*NUMBERS.CLAIMS, *RESULT_CLAIMS]]
    claims += [(p, t, ("{lo}", "{hi}")) for p, t, _ in NUMBERS.RANGES]
    for claim_page, claim, slots in claims:
        if claim_page == page:
            spans += [m.span() for m in NUMBERS.pattern(claim, slots).finditer(text)]
    lines = text.splitlines(keepends=True)
    for claim_page, _, opening in NUMBERS.BLOCKS:
        where = NUMBERS.find_block(page, opening) if claim_page == page else None
        if where is not None:
            start = sum(len(line) for line in lines[:where[0]])
            spans.append((start, start + sum(len(line) for line in lines[where[0]:where[1]])))
    return spans


def unclaimed(page: str) -> list[str]:
    text = (ROOT / page).read_text(encoding="utf-8")
    spans = covered_spans(page)
    return [m[0] for m in RESULT.finditer(text)
            if not any(a <= m.start() and m.end() <= b for a, b in spans)]


def test_every_page_is_counted() -> None:
    pages = {"README.md", *(f"docs/{p.name}" for p in (ROOT / "docs").glob("*.md"))}
    generated = {"docs/parameters.md", "docs/api.md", "docs/changelog.md"}
    assert pages - generated == set(PAGES)
    assert sum(len(unclaimed(p)) for p in PAGES) > 100     # the scan finds numbers


@pytest.mark.parametrize("page", PAGES)
def test_no_page_adds_a_result_no_claim_covers(page: str) -> None:
    found = unclaimed(page)
    assert len(found) <= BACKLOG[page], (
        f"{page}: {len(found)} numbers no claim covers (at most {BACKLOG[page]}): claim the "
        f"new one in benchmarks/docs_numbers.py or tests/unit/test_docs_numbers.py; the "
        f"last ones: {found[-8:]}")


@pytest.mark.slow
@pytest.mark.numerics
@pytest.mark.parametrize("case", sorted(NUMBERS.CASES))
def test_the_record_is_what_a_fresh_run_gives(case: str, tmp_path: Path) -> None:
    fresh = NUMBERS.run_case(case, tmp_path)
    recorded = RECORD["cases"][case]
    assert fresh["summary"]["status"] == recorded["summary"]["status"]
    for key, (rel, absolute) in NUMBERS.TOLERANCES.items():
        new = fresh["summary"].get(key, fresh.get(key))
        old = recorded["summary"].get(key, recorded.get(key))
        if old is None or new is None:
            assert old is new, (case, key, old, new)
            continue
        assert new == pytest.approx(old, rel=rel, abs=absolute), (case, key, old, new)
    for page, text, path in NUMBERS.RANGES:
        if path == f"{case}.cpu_s":
            found = NUMBERS.find_claim(page, text, ("{lo}", "{hi}"))
            assert found is not None
            # a faster processor is no stale page; a run slower than the page's upper
            # bound (twice the record) is
            assert fresh["cpu_s"] <= float(found.match[2]), (page, fresh["cpu_s"])
    assert len(fresh["printed"]) == len(recorded["printed"])
