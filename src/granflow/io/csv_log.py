"""Append-only CSV logs (``diagnostics.csv``): one row per call, flushed at once, so a
killed run loses at most its last row. A log is opened only if it is a regular file itself
(never through a link, never a FIFO, whose opening would block)."""

from __future__ import annotations

import csv
import errno
import io
import os
import stat
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, TextIO

from granflow.config.messages import fmt_value
from granflow.io.atomic import atomic_write_bytes
from granflow.io.untrusted import RunDirError, is_regular, read_text

__all__ = ["CsvLog"]


class CsvLog:
    """Append-only CSV file, one row per call of :meth:`append`, flushed at once.

    A new log replaces any file of that name; ``resume=True`` continues an existing log,
    which must have the same header.
    """

    def __init__(self, path: Path, header: Sequence[str], resume: bool = False) -> None:
        self.path = Path(path)
        self.header = list(header)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        existing = resume and is_regular(self.path) and self.path.stat().st_size > 0
        if existing:
            with io.StringIO(read_text(self.path), newline="") as f:
                found = next(csv.reader(f), [])
            if found != self.header:
                raise RunDirError(f"cannot append to '{self.path}': its header "
                                  f"{fmt_value(found)} differs from {fmt_value(self.header)}")
        else:   # a fresh log replaces whatever has the name (a link is not followed)
            atomic_write_bytes(self.path, _csv_line(self.header).encode("utf-8"))
        self._file: TextIO = _open_append(self.path)
        self._writer = csv.writer(self._file, lineterminator="\n")

    def append(self, row: Sequence[Any] | Mapping[str, Any]) -> None:
        """Append one row: a sequence in header order, or a mapping with every header key."""
        if isinstance(row, Mapping):
            missing = [k for k in self.header if k not in row]
            if missing:
                raise ValueError(f"{self.path.name}: row lacks {missing}")
            row = [row[k] for k in self.header]
        if len(row) != len(self.header):
            raise ValueError(f"{self.path.name}: row has {len(row)} values, header "
                             f"{len(self.header)}")
        self._writer.writerow(row)
        self._file.flush()

    write = append

    def close(self) -> None:
        if not self._file.closed:
            self._file.flush()
            os.fsync(self._file.fileno())
            self._file.close()

    def __enter__(self) -> CsvLog:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _csv_line(row: Sequence[Any]) -> str:
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="\n").writerow(row)
    return buffer.getvalue()


def _open_append(path: Path) -> TextIO:
    """``path`` opened to append, only if it is a regular file itself (not a link, not a
    FIFO: opening one to write would block)."""
    flags = os.O_WRONLY | os.O_APPEND | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC
    try:
        fd = os.open(path, flags)
    except OSError as err:
        reason = ("it is a symbolic link" if err.errno == errno.ELOOP
                  else err.strerror or str(err))
        raise RunDirError(f"cannot append to '{path}': {reason}") from None
    if not stat.S_ISREG(os.fstat(fd).st_mode):
        os.close(fd)
        raise RunDirError(f"cannot append to '{path}': not a regular file")
    os.set_blocking(fd, True)
    return open(fd, "a", newline="", encoding="utf-8")  # noqa: SIM115
