"""The bed profile z_b(x) and the straight walls (``geometry/profile.py``): nodes kept on
them, sliding through corners, landing times, and the paper's level bed handled exactly."""

import math

import numpy as np
import pytest

from granflow.ale.remesh import straddled_corners, with_bed_corners
from granflow.geometry.gate import GateLaw
from granflow.geometry.profile import BedProfile, Line

# a 20-degree slope down to a level floor at x = 1 (concave corner), then up at 10 degrees
# from x = 2 (concave) to x = 3, then level again (convex)
T20, T10 = math.tan(math.radians(20)), math.tan(math.radians(10))
VALLEY = BedProfile(np.array([[0.0, T20], [1.0, 0.0], [2.0, 0.0], [3.0, T10], [4.0, T10]]))


def test_the_level_bed_is_handled_exactly() -> None:
    """On z = 0: projecting sets z = 0 and keeps x bit for bit; heights are z; landing
    times are z / -w_z, as the paper's flat-bed formulas."""
    bed = BedProfile.flat(0.0, 1.0)
    rng = np.random.default_rng(1)
    xy = rng.uniform(-0.5, 2.0, (50, 2))
    w = rng.normal(size=(50, 2))
    foot = bed.project(xy)
    assert np.array_equal(foot[:, 0], xy[:, 0]) and np.all(foot[:, 1] == 0.0)
    assert np.array_equal(bed.height(xy), xy[:, 1])
    with np.errstate(divide="ignore"):
        expected = np.where(w[:, 1] < 0, xy[:, 1] / -w[:, 1], np.inf)
    assert np.array_equal(bed.landing_time(xy, w), expected)
    wall = Line.through(np.zeros(2), np.array([0.0, 1.0]), np.array([1.0, 0.0]))
    assert np.array_equal(wall.height(xy), xy[:, 0])
    assert np.all(wall.project(xy)[:, 0] == 0.0)
    assert np.array_equal(wall.project(xy)[:, 1], xy[:, 1])


def test_z_and_heights_on_a_profile() -> None:
    """z_b(x) interpolates the points and continues the end segments; the height of a point
    straight above a segment is its distance along that segment's normal."""
    assert VALLEY.z(np.array([0.5, 1.5, 2.5, 5.0, -1.0])) == pytest.approx(
        [0.5 * T20, 0.0, 0.5 * T10, T10, 2 * T20], rel=1e-14)
    p = np.array([[0.5, 0.5 * T20 + 0.1]])      # 0.1 above the 20-degree segment
    assert VALLEY.height(p)[0] == pytest.approx(0.1 * math.cos(math.radians(20)), rel=1e-12)
    assert VALLEY.height(np.array([[1.5, -0.2]]))[0] == pytest.approx(-0.2, rel=1e-12)
    assert len(VALLEY.corners()) == 3


def test_a_node_slides_through_a_corner() -> None:
    """A node carried along the 20-degree segment past the valley's corner at x = 1 is put
    on the level floor beyond it (the nearest point of the bed), and a node past the convex
    corner at x = 3 onto the level top: always on the bed, never cut off at the corner."""
    t = np.array([math.cos(math.radians(20)), -math.sin(math.radians(20))])
    beyond = np.array([1.0, 0.0]) + 0.05 * t       # 5 cm past the corner, below the floor
    foot = VALLEY.project(beyond[None])[0]
    assert foot == pytest.approx([1.0 + 0.05 * t[0], 0.0], abs=1e-15)
    u = np.array([math.cos(math.radians(10)), math.sin(math.radians(10))])
    over = np.array([3.0, T10]) + 0.05 * u           # past the crest, above the level top
    foot = VALLEY.project(over[None])[0]
    assert foot == pytest.approx([3.0 + 0.05 * u[0] * 1.0, T10], abs=1e-15)
    assert VALLEY.height(VALLEY.project(np.array([beyond, over]))) == pytest.approx(
        [0.0, 0.0], abs=1e-15)


def test_landing_time_picks_the_segment_reached_first() -> None:
    """A point falling straight down lands on the segment under it, at height / speed;
    one moving sideways over the floor lands on the rising segment ahead."""
    p = np.array([[1.5, 0.3], [1.8, 0.05]])
    w = np.array([[0.0, -2.0], [1.0, 0.0]])
    times = VALLEY.landing_time(p, w)
    assert times[0] == pytest.approx(0.15, rel=1e-12)
    # the rising segment z = (x - 2) tan 10 reaches z = 0.05 at x = 2 + 0.05 / tan 10
    assert times[1] == pytest.approx(2 + 0.05 / T10 - 1.8, rel=1e-12)
    assert VALLEY.landing_time(p, -w)[0] == np.inf


def test_the_layers_top_is_a_mitred_offset() -> None:
    """The curve h_e above the bed is h_e from the line of every segment it runs along
    (at a corner: from both segments' lines)."""
    top = VALLEY.offset(0.01, 0.0, VALLEY.arc_length(3.5)[0])
    assert len(top) == 5      # its ends and the three corners
    for i in range(4):        # top[i], top[i + 1] run along segment i
        n = VALLEY.normal(i)
        for p in top[i:i + 2]:
            assert (p - VALLEY.points[i]) @ n == pytest.approx(0.01, rel=1e-12)


def test_a_remesh_puts_the_corners_back() -> None:
    """A bed edge across the valley's corner (a node slid through it) is split at the
    corner; the mover asks for that remesh; a bed node just past a corner is put back on
    it, a contact point just past it is left until it is further."""
    chord = np.array([[[0.9, 0.1 * T20], [1.1, 0.0]]])
    assert straddled_corners(chord, np.array([[True, True]]), VALLEY, 1e-9) == 1
    on = np.array([[[0.9, 0.1 * T20], [1.0, 0.0]]])
    assert straddled_corners(on, np.array([[True, True]]), VALLEY, 1e-9) == 0
    loop = np.array([[0.9, 0.1 * T20], [1.1, 0.0], [1.1, 0.2], [0.9, 0.2]])
    labels = ["bed", "surface", "surface", "bed"]
    pts, out = with_bed_corners(loop, labels, VALLEY)
    assert pts[1] == pytest.approx([1.0, 0.0]) and out == ["bed", "bed", "surface",
                                                           "surface", "bed"]
    just = np.array([[0.9, 0.1 * T20], [1.001, 0.0], [1.1, 0.0], [1.1, 0.2], [0.9, 0.2]])
    held = ["bed", "bed", "surface", "surface", "bed"]     # 1.001: a bed node
    pts, _ = with_bed_corners(just, held, VALLEY)
    assert pts[1] == pytest.approx([1.0, 0.0]) and len(pts) == 5
    contact = ["bed", "surface", "surface", "surface", "bed"]   # 1.001: the contact point
    pts, _ = with_bed_corners(just, contact, VALLEY)
    assert np.array_equal(pts, just)
    assert straddled_corners(just[None, :2], np.array([[True, False]]), VALLEY, 1e-9) == 0


def test_the_gates_opening_is_the_integral_of_its_speed() -> None:
    """U (1 - exp(-t/tau)) integrated by the trapezoidal rule against the closed form, and
    the time the opening clears a face."""
    law = GateLaw("exponential", 0.7, 0.13)
    t = np.linspace(0.0, 0.5, 200_001)
    speed = np.array([law.velocity(x) for x in t])
    integral = np.sum(0.5 * (speed[1:] + speed[:-1]) * np.diff(t))
    assert law.opening(0.5) == pytest.approx(integral, rel=1e-9)
    assert law.opening(law.open_time(0.25)) == pytest.approx(0.25, rel=1e-12)
    assert GateLaw("constant", 0.7).opening(0.2) == pytest.approx(0.14, rel=1e-15)
