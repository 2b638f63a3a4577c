"""A VTU snapshot checked before meshio reads it: an untrusted file must not make the reader
expand entities or inflate compressed blocks without bound.

Accepted is what ``VtkSeries`` writes through meshio: an XML ``UnstructuredGrid`` without a
DTD, its arrays inline (ASCII, base64, or base64 of zlib blocks), at most ``MAX_ITEMS``
points and cells. For a compressed array each block must inflate to exactly the size its
header declares, and the declared sizes stay within ``DATA_LIMIT``: meshio inflates each
block whole, so without the check a few MB of deflated zeros would become GBs.
"""

from __future__ import annotations

import base64
import binascii
import zlib
from pathlib import Path
from typing import Any

import numpy as np

from granflow.io.untrusted import MB, RunDirError, parse_xml

VTU_LIMIT = 512 * MB     # the file; the largest mesh allowed (100,000 triangles) writes ~20 MB
DATA_LIMIT = 1024 * MB   # its arrays once inflated
MAX_ITEMS = 10**7        # points or cells of one snapshot
MAX_BLOCKS = 10**6       # compressed blocks of one array (meshio writes 32 kB blocks)
HEADER_TYPES = {"UInt32": 4, "UInt64": 8}


def check_vtu(data: bytes, path: Path) -> None:
    """Raise ``RunDirError`` unless ``data`` (the file ``path``) is a VTU that meshio can
    read within the limits (module docstring)."""
    root = parse_xml(data, path)
    if root.tag != "VTKFile" or root.get("type") != "UnstructuredGrid":
        raise RunDirError(f"'{path}' is not a VTU file (an UnstructuredGrid VTKFile)")
    compressor = root.get("compressor")
    if compressor not in (None, "vtkZLibDataCompressor"):
        raise RunDirError(f"'{path}': compressor {compressor[:40]!r} is not read (granflow "
                          "writes zlib)")
    if root.find(".//AppendedData") is not None:
        raise RunDirError(f"'{path}': appended raw data is not read (granflow writes its "
                          "arrays inline)")
    itemsize = HEADER_TYPES.get(root.get("header_type", "UInt32"))
    if itemsize is None or root.get("byte_order", "LittleEndian") not in (
            "LittleEndian", "BigEndian"):
        raise RunDirError(f"'{path}': unknown header type or byte order")
    order = "<" if root.get("byte_order", "LittleEndian") == "LittleEndian" else ">"
    header = np.dtype(f"{order}u{itemsize}")
    for piece in root.iter("Piece"):
        for key in ("NumberOfPoints", "NumberOfCells"):
            value = piece.get(key, "")
            if not value.isdigit() or int(value) > MAX_ITEMS:
                raise RunDirError(f"'{path}': {key} = {value[:20]!r} is not a count of at "
                                  f"most {MAX_ITEMS}")
    total = 0
    for array in root.iter("DataArray"):
        if array.get("format", "ascii") not in ("ascii", "binary"):
            raise RunDirError(f"'{path}': array format {array.get('format')[:20]!r} is not "
                              "read")
        if compressor is not None and array.get("format") == "binary":
            total += _inflated_size(array, header, path)
            if total > DATA_LIMIT:
                raise RunDirError(f"'{path}': its arrays inflate to more than "
                                  f"{DATA_LIMIT // MB} MB")


def _inflated_size(array: Any, header: np.dtype, path: Path) -> int:
    """The size of one zlib-compressed array once inflated, each block checked to inflate
    to exactly its declared size."""
    text = (array.text or "").strip()
    name = (array.get("Name") or "?")[:40]
    try:
        count = _b64(text, header.itemsize, header)[0]
        if count > MAX_BLOCKS:
            raise RunDirError(f"'{path}': array {name} declares {count} blocks")
        items = 3 + int(count)
        head = _b64(text, items * header.itemsize, header)
        blob = base64.b64decode(text[_chars(items * header.itemsize):])
    except (binascii.Error, ValueError, IndexError):
        raise RunDirError(f"'{path}': array {name} has no valid block header") from None
    largest, last, sizes = int(head[1]), int(head[2]), head[3:].astype(np.int64)
    expected = [largest] * len(sizes)
    if expected:
        expected[-1] = last or largest
    if sum(expected) > DATA_LIMIT or int(sizes.sum()) > len(blob):
        raise RunDirError(f"'{path}': array {name} declares more data than it holds or than "
                          f"{DATA_LIMIT // MB} MB")
    start = 0
    for size, want in zip(sizes, expected, strict=True):
        inflater = zlib.decompressobj()
        try:
            out = inflater.decompress(blob[start:start + int(size)], want)
        except zlib.error as err:
            raise RunDirError(f"'{path}': array {name}: {err}") from None
        if len(out) != want or not inflater.eof or inflater.unconsumed_tail:
            raise RunDirError(f"'{path}': array {name} has a block that does not inflate to "
                              "its declared size")
        start += int(size)
    return sum(expected)


def _b64(text: str, nbytes: int, dtype: np.dtype) -> np.ndarray:
    """The first ``nbytes`` bytes of base64 ``text`` as header integers."""
    raw = base64.b64decode(text[:_chars(nbytes)])[:nbytes]
    if len(raw) != nbytes:
        raise ValueError("short header")
    return np.frombuffer(raw, dtype)


def _chars(nbytes: int) -> int:
    """Base64 characters that encode ``nbytes`` bytes (as meshio reads headers)."""
    return -(-nbytes // 3) * 4
