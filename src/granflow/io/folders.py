"""Output folders of the commands that write many run directories (``granflow sweep``,
``granflow converge``): checked, and made, before any work starts."""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

from granflow.io.untrusted import RunDirError

__all__ = ["NAME_MAX", "check_folder", "prepare_folder"]

NAME_MAX = 255    # bytes in one name of a path (Linux, macOS, Windows)


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
