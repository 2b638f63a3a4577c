"""Points of a mass or a bed profile read from a user's file: CSV (two numbers per line,
x and z, an optional header line, ``#`` comments) or GeoJSON (a Polygon, a LineString, or a
Feature or FeatureCollection holding one). Nothing read is executed; a file that does not
exist, is too large or does not parse is a ``GeometryError`` with one line saying why."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np

MAX_BYTES = 2**22   # 4 MB: a profile of 100,000 points


class GeometryError(ValueError):
    """A geometry that cannot be used; the message is one line (without the key's name)."""


def read_points(path: str | Path, kind: str) -> np.ndarray:
    """The (n, 2) points of ``path``; ``kind`` is "polygon" (its exterior ring, closed as
    written) or "line"."""
    file = Path(path)
    try:
        if not file.is_file():
            raise GeometryError(f"'{file}' not found" if not file.exists()
                                else f"'{file}' is not a regular file")
        if file.stat().st_size > MAX_BYTES:
            raise GeometryError(f"'{file}' is larger than {MAX_BYTES // 2**20} MB")
        text = file.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as err:
        raise GeometryError(f"cannot read '{file}': {err}") from None
    if file.suffix.lower() in (".json", ".geojson"):
        return _geojson_points(text, file, kind)
    return _csv_points(text, file)


def _csv_points(text: str, file: Path) -> np.ndarray:
    rows: list[tuple[float, float]] = []
    lines = [(i + 1, line) for i, line in enumerate(text.splitlines())
             if line.strip() and not line.lstrip().startswith("#")]
    for k, (number, line) in enumerate(lines):
        cells = [c.strip() for c in next(csv.reader([line.replace(";", ",")]))]
        cells = [c for c in cells if c] if len(cells) > 2 else cells
        if len(cells) == 1:
            cells = cells[0].split()
        try:
            values = [float(c) for c in cells]
        except ValueError:
            if k == 0:        # a header line (x,z)
                continue
            raise GeometryError(f"'{file}' line {number}: {line.strip()!r} is not two "
                                "numbers x, z") from None
        if len(values) != 2 or not all(math.isfinite(v) for v in values):
            raise GeometryError(f"'{file}' line {number}: {line.strip()!r} is not two finite "
                                "numbers x, z")
        rows.append((values[0], values[1]))
    if not rows:
        raise GeometryError(f"'{file}' holds no points (lines of x, z)")
    return np.array(rows, dtype=float)


def _geojson_points(text: str, file: Path, kind: str) -> np.ndarray:
    try:
        data = json.loads(text)
    except (json.JSONDecodeError, RecursionError) as err:
        raise GeometryError(f"'{file}' is not JSON: {err}") from None
    want = "Polygon" if kind == "polygon" else "LineString"
    geometry = _single_geometry(data, want, file)
    coords = geometry.get("coordinates")
    ring = coords[0] if want == "Polygon" and isinstance(coords, list) and coords else coords
    if want == "Polygon" and isinstance(coords, list) and len(coords) > 1:
        raise GeometryError(f"'{file}': the Polygon has holes; a mass is one ring")
    try:
        points = np.array(ring, dtype=float)
    except (TypeError, ValueError):
        raise GeometryError(f"'{file}': the {want}'s coordinates are not numbers") from None
    if points.ndim != 2 or points.shape[1] < 2 or not np.all(np.isfinite(points)):
        raise GeometryError(f"'{file}': the {want}'s coordinates are not finite [x, z] pairs")
    return points[:, :2]


def _single_geometry(data: object, want: str, file: Path) -> dict[str, object]:
    """The one geometry of type ``want`` in a GeoJSON object."""
    if isinstance(data, dict) and data.get("type") == "FeatureCollection":
        features = data.get("features")
        found = [f.get("geometry") for f in features or [] if isinstance(f, dict)
                 and isinstance(f.get("geometry"), dict)
                 and f["geometry"].get("type") == want]
        if len(found) != 1:
            raise GeometryError(f"'{file}' holds {len(found)} {want} features; give one")
        return found[0]
    if isinstance(data, dict) and data.get("type") == "Feature":
        data = data.get("geometry")
    if not isinstance(data, dict) or data.get("type") != want:
        found = data.get("type") if isinstance(data, dict) else type(data).__name__
        raise GeometryError(f"'{file}' is a GeoJSON {found}, not a {want}")
    return data
