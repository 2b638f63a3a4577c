"""Geometry from the user (``geometry/scene.py``, ``config/geometry_rules.py``): a mass
polygon and a bed profile inline or from CSV/GeoJSON files, the labelled domain they make,
and every bad input refused with one line naming the key, before anything is computed."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from granflow.config import ConfigError, load_config
from granflow.geometry.domains import column
from granflow.geometry.scene import build_scene

TOP = 0.297 - 0.25 / math.tan(math.radians(70.0))
TRAPEZOID = [[0.0, 0.0], [0.297, 0.0], [TOP, 0.25], [0.0, 0.25], [0.0, 0.0]]
HILL = [[0.0, 1.0], [1.0, 0.5], [2.0, 0.5], [3.0, 0.6]]     # 26.6 degrees, level, rising
SLAB = [[0.2, 0.9], [1.4, 0.5], [1.4, 0.7], [0.6, 1.0], [0.2, 0.9]]   # across the corner


def scene(*overrides: str):  # type: ignore[no-untyped-def]
    config = load_config("trapezoid-rigid", list(overrides))
    return build_scene(config.geometry, config.gate)


def test_the_paper_columns_are_unchanged() -> None:
    """Without a profile or a mass, the domain is the paper's polygon as ``column`` builds
    it; the trapezoid written as a polygon on a level profile is the same domain."""
    assert scene().polygon == column("trapezoid", 0.297, 0.25, 70.0)
    mine = scene(f"geometry.mass={TRAPEZOID}", "geometry.bed_profile=[[0.0, 0.0], [1.0, 0.0]]")
    assert mine.polygon.points == pytest.approx(np.asarray(column(
        "trapezoid", 0.297, 0.25, 70.0).points), abs=0)
    assert mine.polygon.labels == ("bed", "surface", "surface", "wall")


def test_a_mass_across_a_slope_change_follows_the_bed() -> None:
    """The slab's bottom edge joins two points on the bed across the corner at x = 1: it
    follows the bed (the corner inserted), labelled bed; a user's mass sets width and
    height (its extent along x and its greatest height above the bed)."""
    s = scene(f"geometry.bed_profile={HILL}", f"geometry.mass={SLAB}",
              "geometry.left_wall=false")
    assert s.polygon.points[:3] == ((0.2, 0.9), (1.0, 0.5), (1.4, 0.5))
    assert s.polygon.labels == ("bed", "bed", "surface", "surface", "surface")
    config = load_config("trapezoid-rigid", [f"geometry.bed_profile={HILL}",
                                             f"geometry.mass={SLAB}", "geometry.left_wall=false"])
    assert config.geometry.width == pytest.approx(1.2)
    assert config.geometry.height == pytest.approx(0.3 * math.cos(math.atan(0.5)))


def test_a_built_in_shape_stands_on_the_first_segment() -> None:
    """geometry.shape on a 10-degree profile: the trapezoid turned into the segment's frame,
    its wall normal to the segment."""
    t = math.radians(10)
    s = scene(f"geometry.bed_profile=[[0.0, 0.0], [{2 * math.cos(t)!r}, {-2 * math.sin(t)!r}]]")
    assert s.local == column("trapezoid", 0.297, 0.25, 70.0)
    assert s.mass[1] == pytest.approx([0.297 * math.cos(t), -0.297 * math.sin(t)], abs=1e-15)
    assert s.wall is not None and s.wall.direction == pytest.approx((math.sin(t), math.cos(t)))


def test_files_are_read_from_the_folder_of_the_toml_file(tmp_path: Path) -> None:
    """A CSV profile (with a header) and a GeoJSON mass named by relative paths in a TOML
    file are read from that file's folder; nothing in them is executed."""
    folder = tmp_path / "case"
    folder.mkdir()
    (folder / "bed.csv").write_text("x,z\n" + "\n".join(f"{x},{z}" for x, z in HILL) + "\n")
    (folder / "mass.geojson").write_text(json.dumps({"type": "Feature", "geometry": {
        "type": "Polygon", "coordinates": [SLAB]}}))
    (folder / "run.toml").write_text('scenario = "trapezoid-rigid"\n[geometry]\n'
                                     'bed_profile_file = "bed.csv"\nmass_file = "mass.geojson"\n'
                                     "left_wall = false\n")
    config = load_config(folder / "run.toml")
    assert Path(config.geometry.mass_file).is_absolute()
    s = build_scene(config.geometry, config.gate)
    assert s.bed.points.tolist() == HILL
    assert s.polygon.points[1] == (1.0, 0.5)


BAD = {
    "open": ([f"geometry.mass={SLAB[:-1]}"], "geometry.mass is an open polygon"),
    "crossing": (["geometry.mass=[[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0], [0.0, 0.0]]"],
                 "geometry.mass is not a simple polygon: self-intersection at (0.5, 0.5)"),
    "below": (["geometry.mass=[[0.0, 0.0], [0.3, -0.1], [0.3, 0.2], [0.0, 0.2], [0.0, 0.0]]"],
              "geometry.mass: the mass crosses the bed profile"),
    "under": (["geometry.mass=[[0.1, -0.3], [0.3, -0.3], [0.3, -0.1], [0.1, -0.3]]"],
              "geometry.mass: the mass crosses the bed profile"),
    "floating": (["geometry.mass=[[0.1, 0.1], [0.3, 0.1], [0.3, 0.2], [0.1, 0.1]]"],
                 "geometry.mass: no edge of the mass lies on the bed profile"),
    "function": (["geometry.bed_profile=[[0.0, 0.0], [1.0, 0.0], [0.8, 0.5]]"],
                 "geometry.bed_profile is not a function of x"),
    "behind": (["geometry.mass=[[-0.1, 0.0], [0.3, 0.0], [0.3, 0.2], [-0.1, 0.2], [-0.1, 0.0]]"],
               "lies behind the left wall"),
    "missing": (["geometry.mass_file=/nonexistent/mass.csv"],
                "geometry.mass_file: '/nonexistent/mass.csv' not found"),
    "fast gate": (["gate.enabled=true", "gate.speed=80.0"], "gate.speed = 80.0: must be"),
    "gate on a layer": (["gate.enabled=true", "geometry.erodible_thickness=0.005"],
                        "gate.enabled = true needs a rigid bed"),
    "slope and profile": (["geometry.slope_deg=10", f"geometry.bed_profile={HILL}"],
                          "geometry.slope_deg = 10.0 with a bed profile"),
    "two masses": ([f"geometry.mass={SLAB}", "geometry.mass_file=x.csv"],
                   "geometry.mass and geometry.mass_file both give the mass"),
    "axisymmetric on a slope": (["geometry.axisymmetric=true", f"geometry.bed_profile={HILL}",
                                 "numerics.linearization=picard"],
                                "geometry.axisymmetric = true with a bed profile needs"),
    "width and mass": ([f"geometry.mass={TRAPEZOID}", "geometry.width=0.5"],
                       "geometry.width = 0.5 and the mass polygon both set the mass's width"),
    "shallow gate face": (["gate.enabled=true", "geometry.front_angle_deg=40",
                           "geometry.width=0.5"], "a gate needs a face at least 45 degrees"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_geometry_is_one_line_naming_the_key(case: str) -> None:
    overrides, start = BAD[case]
    with pytest.raises(ConfigError) as err:
        load_config("trapezoid-rigid", overrides)
    message = str(err.value)
    assert start in message and "\n" not in message


@pytest.mark.parametrize("text", ["x,z\n0,0\n1,abc\n", "0 0 0\n1 1 1\n", "", "x,z\n"])
def test_a_file_that_does_not_parse_is_one_line(tmp_path: Path, text: str) -> None:
    path = tmp_path / "bed.csv"
    path.write_text(text)
    with pytest.raises(ConfigError) as err:
        load_config("trapezoid-rigid", [f"geometry.bed_profile_file={path}"])
    assert str(err.value).startswith("geometry.bed_profile_file: ")
    assert "\n" not in str(err.value)


@pytest.mark.parametrize("text", ["{", '{"type": "Point", "coordinates": [0, 0]}',
                                  '{"type": "Polygon", "coordinates": [[["a", 0]]]}'])
def test_a_geojson_that_is_not_a_polygon_is_one_line(tmp_path: Path, text: str) -> None:
    path = tmp_path / "mass.geojson"
    path.write_text(text)
    with pytest.raises(ConfigError) as err:
        load_config("trapezoid-rigid", [f"geometry.mass_file={path}"])
    assert str(err.value).startswith("geometry.mass_file: ")


def test_a_resolved_geometry_reloads(tmp_path: Path) -> None:
    """The hillslope's resolved configuration (its profile, its mass and the width and
    height the mass sets) saved as TOML and loaded back is the same configuration."""
    config = load_config("hillslope")
    again = load_config(config.save(tmp_path / "config.toml"))
    assert again.geometry == config.geometry
