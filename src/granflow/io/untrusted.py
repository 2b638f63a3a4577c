"""Reading a run directory as untrusted data: a run directory may come from someone else, so
its files are read without following links, without blocking and within a size limit.

Every reader of a run directory's files goes through this module: a file must be a regular
file (a symbolic link, a FIFO, a device or a folder in its place is refused at once, never
opened for reading), at most ``limit`` bytes, text must be UTF-8, XML has no DTD (so no
entity expansion), and a NumPy archive's members are checked (names, declared sizes, no
object arrays) before any is read, so that a few MB of deflated zeros cannot become GBs.
Each refusal is a ``RunDirError`` with one line naming the file.
"""

from __future__ import annotations

import errno
import io
import os
import re
import stat
import zipfile
from collections.abc import Collection
from pathlib import Path
from typing import Any

import numpy as np

MB = 2**20
TEXT_LIMIT = 256 * MB      # a CSV or JSON of a run (diagnostics.csv: ~300 B per step)
ARCHIVE_MEMBERS = 10_000   # a checkpoint holds a few dozen arrays, a frame a handful
_MEMBER = re.compile(r"[A-Za-z0-9_]{1,100}\.npy")


class RunDirError(Exception):
    """The run directory cannot be created or used (the message says why)."""


def read_bytes(path: Path, limit: int = TEXT_LIMIT) -> bytes:
    """The content of the regular file ``path`` (at most ``limit`` bytes)."""
    flags = os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0)
    try:
        fd = os.open(path, flags)
    except OSError as err:
        if err.errno == errno.ELOOP:
            raise RunDirError(f"'{path}' is a symbolic link; the files of a run directory "
                              "are regular files") from None
        raise RunDirError(f"cannot read '{path}': {err.strerror or err}") from None
    mode = os.fstat(fd).st_mode
    if not stat.S_ISREG(mode):
        os.close(fd)
        raise RunDirError(f"'{path}' is not a regular file (it is {_kind(mode)})")
    with os.fdopen(fd, "rb") as f:
        try:
            data = f.read(limit + 1)
        except OSError as err:
            raise RunDirError(f"cannot read '{path}': {err.strerror or err}") from None
    if len(data) > limit:
        raise RunDirError(f"'{path}' is larger than {limit // MB} MB; a granflow run "
                          "never writes such a file")
    return data


def read_text(path: Path, limit: int = TEXT_LIMIT) -> str:
    """The UTF-8 text of the regular file ``path``."""
    data = read_bytes(path, limit)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as err:
        raise RunDirError(f"'{path}' is not UTF-8 text (byte {err.start})") from None


def is_regular(path: Path) -> bool:
    """True if ``path`` is a regular file itself (not a link to one)."""
    try:
        return stat.S_ISREG(os.lstat(path).st_mode)
    except OSError:
        return False


def parse_xml(data: bytes, path: Path) -> Any:
    """The root element of the XML ``data`` of ``path``, refused with any DTD (entity
    declarations, external references) whatever its encoding (``defusedxml``)."""
    from defusedxml import DefusedXmlException
    from defusedxml.ElementTree import ParseError, fromstring

    try:
        return fromstring(data, forbid_dtd=True)
    except DefusedXmlException as err:
        raise RunDirError(f"'{path}' is refused: {err}") from None
    except (ParseError, ValueError) as err:
        raise RunDirError(f"'{path}' is not valid XML: {err}") from None


def load_npz(data: bytes, path: Path, member_limit: int,
             names: Collection[str] | None = None, spent: int = 0) -> dict[str, np.ndarray]:
    """The arrays of the NumPy archive ``data`` (of ``path``), each checked before it is
    read: a plain name, its declared size at most ``member_limit`` bytes and consistent with
    its header's shape, no object dtype (never pickle). With ``names``, only those members
    are read (each must be there), and their declared sizes and ``spent`` (bytes read
    already) add up to at most ``member_limit``."""
    arrays = {}
    try:
        with zipfile.ZipFile(io.BytesIO(data)) as archive:
            members = archive.infolist()
            if len(members) > ARCHIVE_MEMBERS:
                raise RunDirError(f"'{path}' holds {len(members)} arrays; a granflow file "
                                  f"holds at most {ARCHIVE_MEMBERS}")
            if names is not None:
                members = _named(members, names, path, member_limit, spent)
            for info in members:
                name = _member_name(info, path, member_limit)    # checked before it is read
                arrays[name] = _read_member(archive, info, path)
    except (zipfile.BadZipFile, zipfile.LargeZipFile, EOFError, OSError, ValueError,
            NotImplementedError, RuntimeError, MemoryError) as err:
        raise RunDirError(f"'{path}' is not a readable NumPy archive: {err}") from None
    return arrays


def _named(members: list[zipfile.ZipInfo], names: Collection[str], path: Path,
           limit: int, spent: int = 0) -> list[zipfile.ZipInfo]:
    """The members called ``names`` (+ ".npy"), their sizes and ``spent`` within ``limit``
    together."""
    by_name = {info.filename.removesuffix(".npy"): info for info in members}
    missing = sorted(set(names) - set(by_name))
    if missing:
        raise RunDirError(f"'{path}' lacks the member {missing[0][:60]!r} its state names")
    chosen = [by_name[name] for name in names]
    total = spent + sum(info.file_size for info in chosen)
    if total > limit:
        what = "the members its state names" + (" and the state" if spent else "")
        raise RunDirError(f"'{path}': {what} declare {total} bytes together (at most "
                          f"{limit // MB} MB)")
    return chosen


def _member_name(info: zipfile.ZipInfo, path: Path, member_limit: int) -> str:
    if not _MEMBER.fullmatch(info.filename):
        raise RunDirError(f"'{path}' holds an unexpected member {info.filename[:60]!r}")
    if info.file_size > member_limit:
        raise RunDirError(f"'{path}': member {info.filename} declares {info.file_size} "
                          f"bytes (at most {member_limit // MB} MB)")
    return info.filename.removesuffix(".npy")


def _read_member(archive: zipfile.ZipFile, info: zipfile.ZipInfo, path: Path) -> np.ndarray:
    """One .npy member: its header's shape and dtype must account for its declared size."""
    fmt = np.lib.format
    with archive.open(info) as f:
        version = fmt.read_magic(f)
        if version not in ((1, 0), (2, 0)):
            raise RunDirError(f"'{path}': member {info.filename} has a .npy version "
                              f"{version} granflow does not write")
        reader = fmt.read_array_header_1_0 if version == (1, 0) else fmt.read_array_header_2_0
        shape, fortran, dtype = reader(f)
        if dtype.hasobject:
            raise RunDirError(f"'{path}': member {info.filename} holds Python objects "
                              "(pickle), which granflow never reads")
        size = int(np.prod(shape, dtype=np.int64)) * dtype.itemsize
        if f.tell() + size != info.file_size:
            raise RunDirError(f"'{path}': member {info.filename}'s shape {shape} does not "
                              "match its size")
        values = np.frombuffer(f.read(size), dtype=dtype)
    if values.nbytes != size:
        raise RunDirError(f"'{path}': member {info.filename} is cut short")
    order = "F" if fortran else "C"
    return values.reshape(shape, order=order).copy()


def _kind(mode: int) -> str:
    for test, name in ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO"),
                       (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "not a regular file"
