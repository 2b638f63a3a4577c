"""Writing a benchmark's results under ``benchmarks/results/``: its JSON record, its
markdown table and the one-line records it prints as it goes. Each file is replaced whole
(``granflow.io.run_dir.atomic_write_text``), so a study stopped mid-way leaves its last
complete files, and a resumable study reads back what it wrote (``read_results``) and
rewrites its files after every run."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from granflow.io.run_dir import atomic_write_text

Markdown = str | Sequence[str]     # a text as it is, or lines (each ended by a newline)


def read_results(path: Path) -> dict:
    """The record a study wrote before ({} when there is none): a rerun adds to it."""
    return json.loads(path.read_text()) if path.is_file() else {}


def write_json(path: Path, data: Any, indent: int = 2, end: str = "") -> None:
    """``data`` as indented JSON, followed by ``end``."""
    atomic_write_text(path, json.dumps(data, indent=indent) + end)


def markdown_text(markdown: Markdown) -> str:
    """A text as it is, or the lines joined, each ended by a newline."""
    return markdown if isinstance(markdown, str) else "\n".join(markdown) + "\n"


def write_markdown(path: Path, markdown: Markdown, show: bool = False) -> None:
    """The markdown (``markdown_text``) into ``path``; ``show`` also prints it."""
    text = markdown_text(markdown)
    atomic_write_text(path, text)
    if show:
        print(text.removesuffix("\n"))


def write_results(out: Path, name: str, data: Any, markdown: Markdown | None = None,
                  show: bool = False) -> None:
    """OUT/NAME.json and, with ``markdown``, OUT/NAME.md (printed when ``show``)."""
    write_json(out / f"{name}.json", data)
    if markdown is not None:
        write_markdown(out / f"{name}.md", markdown, show)


def report(label: str, data: Any) -> None:
    """One record as a line: the label (if any), then the data as JSON, flushed at once
    (a long study's progress, read while it runs)."""
    print(*([label] if label else []), json.dumps(data), flush=True)
