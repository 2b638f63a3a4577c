"""The run directory: every file of a run, written so that a killed run leaves each file it
had finished readable, and never anything outside the folder.

Whole files (config, summary, profiles, figures, fields) are written atomically
(``io/atomic.py``: a temporary file created exclusively, renamed over the target); logs that
grow during the run (``diagnostics.csv``) are append-only and flushed after every row
(``io/csv_log.py``), so at worst the last row is missing. A run directory may come from
someone else: its files are read through ``io/untrusted.py``.
"""

from __future__ import annotations

import contextlib
import csv
import fnmatch
import io
import json
import math
import os
import re
import stat
from collections.abc import Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

from filelock import FileLock, Timeout

from granflow.io.atomic import atomic_file, atomic_write_bytes, atomic_write_text
from granflow.io.csv_log import CsvLog
from granflow.io.folders import check_folder, prepare_folder
from granflow.io.untrusted import MB, RunDirError, is_regular, read_bytes, read_text

__all__ = ["CsvLog", "RunDir", "RunDirError", "atomic_file", "atomic_write_bytes",
           "atomic_write_text", "check_folder", "prepare_folder"]

# A folder is a granflow run directory if its config.toml starts with this line prefix.
RUN_MARKER_FILE = "config.toml"
RUN_MARKER_PREFIX = "# granflow"
LOCK_FILE = ".granflow.lock"   # held (flock) by the process writing into the folder
# Every file and folder a run asks for, one relative path a line, appended before it is
# written: ``--force`` deletes what it lists, and of that only names of the layout below.
MANIFEST = ".granflow.manifest"
# What a run writes: files at the top, and per folder the names of its files.
RUN_FILES = ("config.toml", "summary.json", "diagnostics.csv", "traceback.txt")
RUN_FOLDERS = {
    "profiles": re.compile(r"[a-z_]+_(t\d+(\.\d+)?|final)\.csv|units\.json|final_error\.txt"),
    "fields": re.compile(r"fields_\d+\.vtu|fields\.pvd"),
    "frames": re.compile(r"frame_\d+\.npz"),
    "plots": re.compile(r"[A-Za-z0-9_-]+\.(png|pdf|svg|gif)|error\.txt"),
    "checkpoint": re.compile(r"state\.(npz|pkl)"),
}
# temporary files: those of io/atomic.py (".NAME.<8 random>.tmp.SUFFIX" beside NAME) and the
# fixed names of earlier versions (".NAME.tmp", ".STEM.tmp.SUFFIX"); one is a run's only when
# the file it stands for is one the manifest lists (``temporary_of``)
TEMPORARY = re.compile(r"\.(?P<target>.+?)(?P<random>\.[a-z0-9_]{8})?\.tmp"
                       r"(?P<suffix>\.[A-Za-z0-9]+)?")
SUMMARY_LIMIT = 16 * MB
CHECKPOINT = "checkpoint/state.npz"


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
        self._listed: set[str] | None = None      # the manifest's entries, once read

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
                if not os.path.lexists(path / MANIFEST):
                    raise RunDirError(f"output folder '{path}' holds a run of an earlier "
                                      "granflow, which kept no list of the files it wrote: "
                                      "--force deletes only those; remove the folder yourself "
                                      "or choose another --out")
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
        """Delete what a run wrote: the files its manifest lists whose names are of the
        layout (``RUN_FILES``, the files of ``RUN_FOLDERS``), the temporary files, then the
        run's folders that are left empty; nothing else, whatever its name. A link in a
        run file's place is deleted, never followed."""
        listed = [Path(entry) for entry in sorted(self.listed()) if _of_the_layout(entry)]
        for entry in listed:
            if len(entry.parts) == 1 and entry.name in RUN_FOLDERS:
                continue
            folder = self.root / entry.parts[0]
            if len(entry.parts) == 2 and (folder.is_symlink() or not folder.is_dir()):
                continue                # never through a link
            _unlink(self.root / entry)
        self.remove_temporary_files()
        for folder in RUN_FOLDERS:
            path = self.root / folder
            if path.is_symlink() or (os.path.lexists(path) and not path.is_dir()):
                _unlink(path)           # a link or a file where the run's folder goes
            elif path.is_dir():
                with contextlib.suppress(OSError):
                    path.rmdir()        # only if nothing else is left in it
        _unlink(self.root / MANIFEST)
        self._listed = None

    def listed(self) -> set[str]:
        """The paths the manifest lists (what this folder's runs asked to write)."""
        if self._listed is None:
            path = self.root / MANIFEST
            text = read_text(path, SUMMARY_LIMIT) if os.path.lexists(path) else ""
            self._listed = set(text.splitlines())
        return self._listed

    def has_manifest(self) -> bool:
        """Whether the folder lists what its runs wrote (a run of granflow 0.2 on)."""
        return os.path.lexists(self.root / MANIFEST)

    def adopt_layout(self, names: Iterable[str]) -> None:
        """In a folder without a manifest (a run of an earlier granflow, being resumed),
        list those of ``names`` it holds: the files that run's own records name (its
        files, its checkpoint, the snapshots and frames its state counts, the profiles of
        its output times; ``app/resume.py``), which a later --force deletes with the resumed
        session's. A user's file of a layout-like name is none of them."""
        if self.has_manifest():
            return
        for entry in names:
            parts = entry.split("/")
            folder = self.root / parts[0]
            if _of_the_layout(entry) and (len(parts) == 1 or not folder.is_symlink()) and \
                    is_regular(self.root / entry):
                self._record(entry)

    def written(self, pattern: str) -> list[Path]:
        """The files of the layout the manifest lists whose paths match ``pattern`` (a
        glob): files of an earlier session, never a user's of the same name."""
        return [self.root / entry for entry in sorted(self.listed())
                if _of_the_layout(entry) and fnmatch.fnmatchcase(entry, pattern)]

    def _record(self, relpath: str) -> None:
        """Add ``relpath`` to the manifest (before it is written: a killed run's files are
        listed); the manifest itself is never followed through a link."""
        if relpath in self.listed():
            return
        flags = os.O_WRONLY | os.O_CREAT | os.O_APPEND | os.O_NOFOLLOW | os.O_NONBLOCK
        try:
            fd = os.open(self.root / MANIFEST, flags, 0o644)
            with os.fdopen(fd, "a", encoding="utf-8") as f:
                f.write(relpath + "\n")
        except OSError as err:
            raise RunDirError(f"cannot write '{self.root / MANIFEST}': "
                              f"{err.strerror or err}") from None
        self.listed().add(relpath)

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
        """The temporary files a killed run left behind (never renamed into place): those
        of files the manifest lists, nothing named like them by anyone else."""
        for folder in ("", *RUN_FOLDERS):
            path = self.root / folder
            if not path.is_dir() or path.is_symlink():
                continue
            for entry in path.iterdir():
                targets = [f"{folder}/{t}" if folder else t for t in temporary_of(entry.name)]
                if any(t in self.listed() for t in targets) and not _is_folder(entry):
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
        file, not JSON, not an object). Members granflow reads that have the wrong type (a
        status that is not text, a time that is not a number) are left out, as if
        missing; so are lists of times longer than ``SUMMARY_LIST_LIMIT``."""
        try:
            summary = json.loads(read_text(Path(path) / "summary.json", SUMMARY_LIMIT))
        except (RunDirError, ValueError, RecursionError):
            return {}
        if not isinstance(summary, dict):
            return {}
        return {k: v for k, v in summary.items() if _summary_member_ok(k, v)}

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
        self._record(Path(relpath).as_posix())
        return parent / path.name

    @contextlib.contextmanager
    def atomic_path(self, relpath: str | Path) -> Iterator[Path]:
        """For writers that want a file name (meshio, matplotlib): write to the yielded
        temporary path (same suffix); it replaces ``relpath`` when the block ends cleanly."""
        with atomic_file(self.path(relpath)) as tmp:
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


SUMMARY_LIST_LIMIT = 10_000      # times in one summary list (a run remeshes a few hundred)
_SUMMARY_LISTS = frozenset({"outputs_at_rest", "remesh_times_s", "deposition_times_s"})
_SUMMARY_TEXT = frozenset({"scenario", "status", "message", "linear_solver"})
_SUMMARY_NUMBERS = frozenset({
    "t_final", "final_profiles_t", "stop_time_s", "wall_time_s", "runout_m", "steps",
    "wall_height_m", "axis_height_m", "volume_relative_error", "velocity_relative_error_l2",
    "nonlinear_iterations"})


def _summary_member_ok(key: str, value: Any) -> bool:
    """A summary.json member of the type granflow reads it as."""
    def number(x: Any) -> bool:
        return isinstance(x, int | float) and not isinstance(x, bool)

    if key in _SUMMARY_TEXT:
        return isinstance(value, str)
    if key in _SUMMARY_NUMBERS:
        return value is None or number(value)
    if key in _SUMMARY_LISTS:
        return isinstance(value, list) and len(value) <= SUMMARY_LIST_LIMIT and all(
            number(x) for x in value)
    return True


def _of_the_layout(entry: str) -> bool:
    """A manifest's entry that names a file of the layout (or one of its folders), inside
    the run directory."""
    parts = entry.split("/")
    if len(parts) == 1:
        return entry in RUN_FILES or entry in RUN_FOLDERS
    return len(parts) == 2 and parts[0] in RUN_FOLDERS and bool(
        RUN_FOLDERS[parts[0]].fullmatch(parts[1]))


def temporary_of(name: str) -> list[str]:
    """The names of the files that ``name`` may be the temporary file of (``TEMPORARY``),
    none if it is no temporary name."""
    found = TEMPORARY.fullmatch(name)
    if found is None:
        return []
    target, suffix = found["target"], found["suffix"] or ""
    if found["random"]:                       # io/atomic.py: the target's own suffix
        return [target] if Path(target).suffix == suffix else []
    return [target + suffix] if suffix else [target]


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
