"""The run directory: every file of a run, written so that a killed run leaves each file it
had finished readable, and never anything outside the folder.

Whole files (config, summary, profiles, figures, fields) are written atomically: to a
temporary file created exclusively beside the target (a fresh random name, never through
an existing name or link), flushed and fsync'ed, then renamed over the target with
``os.replace`` (which replaces a link in the target's place, not the file it points to).
Logs that grow during the run (``diagnostics.csv``) are append-only and flushed after every
row, so at worst the last row is missing. A run directory may come from someone else: its
files are read through ``io/untrusted.py``.
"""

from __future__ import annotations

import contextlib
import csv
import errno
import io
import json
import math
import os
import re
import stat
import tempfile
from collections.abc import Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any, TextIO

from filelock import FileLock, Timeout

from granflow.io.untrusted import MB, RunDirError, is_regular, read_bytes, read_text

__all__ = ["CsvLog", "RunDir", "RunDirError", "atomic_file", "atomic_write_bytes",
           "atomic_write_text", "check_folder", "prepare_folder"]

# A folder is a granflow run directory if its config.toml starts with this line prefix.
RUN_MARKER_FILE = "config.toml"
RUN_MARKER_PREFIX = "# granflow"
LOCK_FILE = ".granflow.lock"   # held (flock) by the process writing into the folder
# What a run writes (``--force`` deletes these and nothing else): files at the top, and
# per folder the names of its files.
RUN_FILES = ("config.toml", "summary.json", "diagnostics.csv", "traceback.txt")
RUN_FOLDERS = {
    "profiles": re.compile(r"[a-z_]+_(t\d+(\.\d+)?|final)\.csv|units\.json|final_error\.txt"),
    "fields": re.compile(r"fields_\d+\.vtu|fields\.pvd"),
    "frames": re.compile(r"frame_\d+\.npz"),
    "plots": re.compile(r"[A-Za-z0-9_-]+\.(png|pdf|svg|gif)|error\.txt"),
    "checkpoint": re.compile(r"state\.(npz|pkl)"),
}
# temporary files: this module's (``_atomic``) and the fixed names of earlier versions
TEMPORARY = re.compile(r"\..+\.tmp(\.[A-Za-z0-9]+)?|\.granflow\.lock\.probe")
SUMMARY_LIMIT = 16 * MB
NAME_MAX = 255    # bytes in one name of a path (Linux, macOS, Windows)
CHECKPOINT = "checkpoint/state.npz"


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


def check_folder(path: Path, what: str = "the output", option: str = "--out") -> None:
    """What can be said of ``path`` as an output folder without creating anything: a name
    (not empty, not the current folder) of parts of at most 255 bytes, that is not a file
    or a device and is not under one; ``RunDirError`` otherwise."""
    path = Path(path)
    if str(path).strip() in ("", "."):
        raise RunDirError(f"{option} must name a folder for {what} (got an empty path or the "
                          "current folder)")
    if any(len(os.fsencode(part)) > NAME_MAX for part in path.parts):
        raise RunDirError(f"{option}: a name in '{str(path)[:80]}...' is longer than "
                          f"{NAME_MAX} bytes")
    for folder in [path, *path.parents]:
        if os.path.lexists(folder) and not folder.is_dir():
            raise RunDirError(f"{option} '{path}' exists and is not a folder" if folder == path
                              else f"{option} '{path}' is under '{folder}', which is not a "
                              "folder")


def prepare_folder(path: Path, what: str = "the output", option: str = "--out") -> None:
    """Make sure, before any work, that ``path`` is (or has been made) a folder this process
    can write into (``check_folder``, then created and a file written and removed in it).
    A refusal is one ``RunDirError`` and leaves nothing behind (the folders it made are
    removed)."""
    path = Path(path)
    check_folder(path, what, option)
    made = []
    try:
        for folder in reversed([path, *path.parents]):
            if not os.path.lexists(folder):
                folder.mkdir()
                made.append(folder)
        fd, probe = tempfile.mkstemp(dir=path, prefix=".granflow-probe.")
        os.close(fd)
        os.unlink(probe)
    except OSError as err:
        for folder in reversed(made):
            with contextlib.suppress(OSError):
                folder.rmdir()
        raise RunDirError(f"cannot write into {option} '{path}': "
                          f"{err.strerror or err}") from None


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
                    run.clear()
                return run
            path.mkdir(parents=True, exist_ok=True)
            probe = path / f".{LOCK_FILE}.probe"
            probe.write_bytes(b"")          # writable? (a read-only folder fails here)
            probe.unlink()
        except OSError as err:
            raise RunDirError(f"cannot use output folder '{path}': {err.strerror or err}") from None
        return cls(path)

    def clear(self) -> None:
        """Delete what a run wrote (``RUN_FILES``, the files of ``RUN_FOLDERS`` and the
        temporary files) and nothing else: other files stay, and so do the folders that
        hold them. A link in a run file's place is deleted, never followed."""
        for name in RUN_FILES:
            _unlink(self.root / name)
        self.remove_temporary_files()
        for folder, names in RUN_FOLDERS.items():
            path = self.root / folder
            if path.is_symlink() or (path.exists() and not path.is_dir()):
                _unlink(path)
                continue
            if not path.is_dir():
                continue
            for entry in path.iterdir():
                if names.fullmatch(entry.name) and not _is_folder(entry):
                    _unlink(entry)
            with contextlib.suppress(OSError):
                path.rmdir()            # only if nothing else is left in it

    def check_layout(self) -> None:
        """Before a run writes into an existing folder: each file of the layout is a file
        (or absent) and each folder a folder of its own, so that writing cannot fail half
        way (a folder where a file goes) or leave the directory (a linked folder)."""
        for name in (*RUN_FILES, "fields/fields.pvd", "profiles/units.json", CHECKPOINT):
            if _is_folder(self.root / name):
                raise RunDirError(f"'{self.root / name}' is a folder where the run writes a "
                                  "file; remove it or choose another run directory")
        for folder, names in RUN_FOLDERS.items():
            path = self.root / folder
            if path.is_symlink() or (os.path.lexists(path) and not _is_folder(path)):
                raise RunDirError(f"'{path}' is not a folder of the run directory (a link "
                                  "or a file); remove it or choose another run directory")
            clash = next((e for e in path.iterdir() if names.fullmatch(e.name)
                          and _is_folder(e)), None) if path.is_dir() else None
            if clash is not None:
                raise RunDirError(f"'{clash}' is a folder where the run writes a file; remove "
                                  "it or choose another run directory")

    def remove_temporary_files(self) -> None:
        """The temporary files a killed run left behind (never renamed into place)."""
        for folder in (self.root, *(self.root / f for f in RUN_FOLDERS)):
            if not folder.is_dir() or folder.is_symlink():
                continue
            for entry in folder.iterdir():
                if TEMPORARY.fullmatch(entry.name) and not _is_folder(entry):
                    _unlink(entry)

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
        """True if ``path`` holds a config.toml written by granflow (a regular file)."""
        try:
            return read_bytes(Path(path) / RUN_MARKER_FILE, MB).startswith(
                RUN_MARKER_PREFIX.encode())
        except RunDirError:
            return False

    @staticmethod
    def summary(path: Path) -> dict[str, Any]:
        """``path``/summary.json, or {} without a readable one (missing, not a regular
        file, not JSON, not an object)."""
        try:
            summary = json.loads(read_text(Path(path) / "summary.json", SUMMARY_LIMIT))
        except (RunDirError, ValueError, RecursionError):
            return {}
        return summary if isinstance(summary, dict) else {}

    @staticmethod
    def status(path: Path) -> str | None:
        """The ``status`` in ``path``/summary.json, or None without a readable one."""
        return RunDir.summary(path).get("status")

    def path(self, relpath: str | Path) -> Path:
        """Absolute path of ``relpath`` inside the run directory; its parent folders exist.
        A folder on the way that leads out of the run directory (a link) is refused; the
        file itself may be a link: writers replace it (``os.replace``), never follow it."""
        path = self.root / relpath
        try:
            parent, inside = path.parent.resolve(), self.root.resolve()
            leads_out = path.is_dir() and not path.resolve().is_relative_to(inside)
            if not parent.is_relative_to(inside) or path.name in ("", "..", ".") or leads_out:
                raise RunDirError(f"'{path}' leads outside the run directory '{self.root}' "
                                  "(a symbolic link?); refused")
            parent.mkdir(parents=True, exist_ok=True)
        except OSError as err:
            raise RunDirError(f"cannot create the folder '{path.parent}' of the run: "
                              f"{err.strerror or err}") from None
        return parent / path.name

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
        try:
            atomic_write_bytes(target, data)
        except OSError as err:       # a full disk, a folder in the file's place
            raise RunDirError(f"cannot write '{target}': {err.strerror or err}") from None
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
        existing = resume and is_regular(self.path) and self.path.stat().st_size > 0
        if existing:
            with io.StringIO(read_text(self.path), newline="") as f:
                found = next(csv.reader(f), [])
            if found != self.header:
                raise RunDirError(f"cannot append to '{self.path}': its header {found} "
                                  f"differs from {self.header}")
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


def _is_folder(path: Path) -> bool:
    """A folder itself (a link to one is not)."""
    try:
        return stat.S_ISDIR(os.lstat(path).st_mode)
    except OSError:
        return False


def _unlink(path: Path) -> None:
    """Delete the file or link ``path`` (a folder in its place is left alone)."""
    if not _is_folder(path):
        with contextlib.suppress(FileNotFoundError):
            path.unlink()
