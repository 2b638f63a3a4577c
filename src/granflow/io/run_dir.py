"""The run directory: every file of a run, written so that a killed run leaves each file it
had finished readable.

Whole files (config, summary, profiles, figures, fields) are written atomically: to a
temporary file in the same folder, flushed and fsync'ed, then renamed over the target with
``os.replace``. Logs that grow during the run (``diagnostics.csv``) are append-only and
flushed after every row, so at worst the last row is missing.
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import math
import os
import shutil
import tempfile
from collections.abc import Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any, TextIO

from filelock import FileLock, Timeout

__all__ = ["CsvLog", "RunDir", "RunDirError", "atomic_file", "atomic_write_bytes",
           "atomic_write_text"]

# A folder is a granflow run directory if its config.toml starts with this line prefix.
RUN_MARKER_FILE = "config.toml"
RUN_MARKER_PREFIX = "# granflow"
LOCK_FILE = ".granflow.lock"   # held (flock) by the process writing into the folder


class RunDirError(Exception):
    """The run directory cannot be created or used (the message says why)."""


def atomic_write_bytes(target: Path, data: bytes) -> None:
    """Write ``data`` to ``target`` all at once: temp file, fsync, rename."""
    with _atomic(target) as tmp, open(tmp, "wb") as f:
        f.write(data)
        f.flush()
        os.fsync(f.fileno())


def atomic_write_text(target: Path, text: str) -> None:
    """``Path.write_text`` done atomically (for benchmarks and ``verify``)."""
    atomic_write_bytes(Path(target), text.encode("utf-8"))


@contextlib.contextmanager
def atomic_file(target: Path) -> Iterator[Path]:
    """A temporary path to write (matplotlib, csv) that replaces ``target`` on success."""
    with _atomic(Path(target)) as tmp:
        yield tmp


@contextlib.contextmanager
def _atomic(target: Path) -> Iterator[Path]:
    """Yield a temporary path beside ``target`` (same suffix); rename it over ``target``
    if the block succeeds, delete it otherwise."""
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, name = tempfile.mkstemp(dir=target.parent, prefix=f".{target.stem}.", suffix=target.suffix)
    os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        os.chmod(tmp, 0o644)  # mkstemp makes it 0600
        os.replace(tmp, target)
    finally:
        tmp.unlink(missing_ok=True)


def _json_safe(obj: Any) -> Any:
    """Plain JSON types: NaN and infinities become null, numpy scalars and arrays Python ones."""
    if isinstance(obj, Mapping):
        return {str(k): _json_safe(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_json_safe(v) for v in obj]
    if hasattr(obj, "tolist") and callable(obj.tolist):  # numpy array or scalar
        return _json_safe(obj.tolist())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, Path):
        return str(obj)
    return obj


class RunDir:
    """A run's output folder. All paths given to its methods are relative to it."""

    def __init__(self, root: Path) -> None:
        self.root = Path(root)
        self._lock: FileLock | None = None

    @classmethod
    def create(cls, path: Path, force: bool = False) -> RunDir:
        """Create the folder (and parents) for a new run.

        An existing folder is accepted if it is empty. One that already holds a run is
        refused unless ``force``, which clears it first (under the lock, so old and new
        files never mix); a foreign non-empty folder is always refused.
        """
        path = Path(path)
        if str(path).strip() == "" or path == Path("."):
            raise RunDirError("--out must name a folder for the run (got an empty path)")
        try:
            if path.exists() and not path.is_dir():
                raise RunDirError(f"output path '{path}' exists and is not a folder")
            if path.is_dir() and any(p.name != LOCK_FILE for p in path.iterdir()):
                if not cls.is_run_dir(path):
                    raise RunDirError(f"output folder '{path}' is not empty and is not a "
                                      "granflow run directory; choose another --out")
                if not force:
                    raise RunDirError(f"output folder '{path}' already holds a run; use --force "
                                      f"to replace it, or `granflow resume {path}` to continue it")
                run = cls(path)
                with run.lock():
                    run._clear()
                return run
            path.mkdir(parents=True, exist_ok=True)
            probe = path / f".{LOCK_FILE}.probe"
            probe.write_bytes(b"")          # writable? (a read-only folder fails here)
            probe.unlink()
        except OSError as err:
            raise RunDirError(f"cannot use output folder '{path}': {err.strerror or err}") from None
        return cls(path)

    def _clear(self) -> None:
        """Delete everything in the folder except the lock file."""
        for entry in self.root.iterdir():
            if entry.name == LOCK_FILE:
                continue
            if entry.is_dir() and not entry.is_symlink():
                shutil.rmtree(entry)
            else:
                entry.unlink()

    @contextlib.contextmanager
    def lock(self) -> Iterator[None]:
        """Hold the folder's lock: a second process writing into it is refused at once.

        An OS file lock (``filelock``): the kernel releases it when the holder dies, so a
        killed run leaves no stale lock. Re-entrant within one process.
        """
        if self._lock is None:
            self._lock = FileLock(self.root / LOCK_FILE, timeout=0)
        try:
            self._lock.acquire()
        except Timeout:
            raise RunDirError(f"run directory '{self.root}' is in use by another granflow "
                              "process; wait for it to end or choose another --out") from None
        try:
            yield
        finally:
            self._lock.release()

    @property
    def locked(self) -> bool:
        """True while this process holds the folder's lock (inside ``lock()``)."""
        return self._lock is not None and self._lock.is_locked

    @staticmethod
    def is_run_dir(path: Path) -> bool:
        """True if ``path`` holds a config.toml written by granflow."""
        marker = Path(path) / RUN_MARKER_FILE
        try:
            with open(marker, encoding="utf-8") as f:
                return f.readline().startswith(RUN_MARKER_PREFIX)
        except (OSError, UnicodeDecodeError):
            return False

    @staticmethod
    def summary(path: Path) -> dict[str, Any]:
        """``path``/summary.json, or {} without a readable one."""
        try:
            summary = json.loads((Path(path) / "summary.json").read_text())
        except (OSError, ValueError):
            return {}
        return summary if isinstance(summary, dict) else {}

    @staticmethod
    def status(path: Path) -> str | None:
        """The ``status`` in ``path``/summary.json, or None without a readable one."""
        return RunDir.summary(path).get("status")

    def path(self, relpath: str | Path) -> Path:
        """Absolute path of ``relpath`` inside the run directory; its parent folders exist."""
        target = (self.root / relpath).resolve()
        if not target.is_relative_to(self.root.resolve()):
            raise RunDirError(f"'{relpath}' is outside the run directory '{self.root}'")
        target.parent.mkdir(parents=True, exist_ok=True)
        return target

    @contextlib.contextmanager
    def atomic_path(self, relpath: str | Path) -> Iterator[Path]:
        """For writers that want a file name (meshio, matplotlib): write to the yielded
        temporary path (same suffix); it replaces ``relpath`` when the block ends cleanly."""
        with _atomic(self.path(relpath)) as tmp:
            yield tmp
            with open(tmp, "rb+") as f:
                os.fsync(f.fileno())

    def write_bytes(self, relpath: str | Path, data: bytes) -> Path:
        target = self.path(relpath)
        atomic_write_bytes(target, data)
        return target

    def write_text(self, relpath: str | Path, text: str) -> Path:
        return self.write_bytes(relpath, text.encode("utf-8"))

    def write_json(self, relpath: str | Path, obj: Any) -> Path:
        """JSON with indent 2; NaN and infinities are written as null."""
        text = json.dumps(_json_safe(obj), indent=2, allow_nan=False)
        return self.write_text(relpath, text + "\n")

    def write_csv(
        self, relpath: str | Path, header: Sequence[str], rows: Iterable[Sequence[Any]]
    ) -> Path:
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(header)
        writer.writerows(rows)
        return self.write_text(relpath, buffer.getvalue())

    def csv_log(self, relpath: str | Path, header: Sequence[str], resume: bool = False) -> CsvLog:
        """An append-only CSV log in this run directory (see :class:`CsvLog`)."""
        return CsvLog(self.path(relpath), header, resume=resume)


class CsvLog:
    """Append-only CSV file, one row per call of :meth:`append`, flushed at once.

    A new log replaces any file of that name; ``resume=True`` continues an existing log,
    which must have the same header.
    """

    def __init__(self, path: Path, header: Sequence[str], resume: bool = False) -> None:
        self.path = Path(path)
        self.header = list(header)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        existing = resume and self.path.is_file() and self.path.stat().st_size > 0
        if existing:
            with open(self.path, newline="", encoding="utf-8") as f:
                found = next(csv.reader(f), [])
            if found != self.header:
                raise RunDirError(f"cannot append to '{self.path}': its header {found} "
                                  f"differs from {self.header}")
        self._file: TextIO = open(self.path, "a" if existing else "w",  # noqa: SIM115
                                  newline="", encoding="utf-8")
        self._writer = csv.writer(self._file, lineterminator="\n")
        if not existing:
            self._writer.writerow(self.header)
            self._file.flush()

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
