"""Whole files written atomically: to a temporary file created exclusively beside the
target (``mkstemp``: a fresh random name, O_CREAT | O_EXCL, so never through an existing
name or a link planted in the folder), flushed and fsync'ed, then renamed over the target
with ``os.replace`` (which replaces a link in the target's place, not the file it points
to). A killed writer leaves the previous file intact."""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path

__all__ = ["atomic_file", "atomic_write_bytes", "atomic_write_text"]


def atomic_write_bytes(target: Path, data: bytes) -> None:
    """Write ``data`` to ``target`` all at once: temp file, fsync, rename."""
    with _atomic(target, data):
        pass


def atomic_write_text(target: Path, text: str) -> None:
    """``Path.write_text`` done atomically (for benchmarks and ``verify``)."""
    atomic_write_bytes(Path(target), text.encode("utf-8"))


@contextlib.contextmanager
def atomic_file(target: Path) -> Iterator[Path]:
    """A temporary path to write (matplotlib, meshio, PIL) that replaces ``target`` on
    success; the file exists (empty) under a fresh random name, so a writer that opens the
    path by name writes into it and nowhere else."""
    with _atomic(Path(target)) as tmp:
        yield tmp


@contextlib.contextmanager
def _atomic(target: Path, data: bytes | None = None) -> Iterator[Path]:
    """Yield a temporary path beside ``target`` (same suffix), created exclusively
    (``mkstemp``: O_CREAT | O_EXCL, a random name); ``data``, if given, is written through
    that descriptor. The file is renamed over ``target`` if the block succeeds, deleted
    otherwise."""
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, name = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.",
                                suffix=f".tmp{target.suffix}")
    tmp = Path(name)
    try:
        with os.fdopen(fd, "wb") as f:
            if data is not None:
                f.write(data)
                f.flush()
                os.fsync(f.fileno())
        yield tmp
        os.chmod(tmp, 0o644)  # mkstemp makes it 0600
        os.replace(tmp, target)
    finally:
        tmp.unlink(missing_ok=True)
