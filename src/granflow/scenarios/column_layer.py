"""The erodible layer followed through a collapse: its material line and markers carried
with the flow (``geometry/layer_material.py``), the indicator of a layer of its own material
refreshed after every accepted step, and what entrainment the outputs read.

Entrainment measures (diagnostics columns, profiles, summary):
* ``layer_mobilised_area``: layer material now faster than the flowing threshold (1 mm/s);
* ``layer_displaced_area``: layer material that has moved further than one grain diameter
  from where it started (``layer.grain_diameter``, else ``material.grain_diameter``);
* ``erosion_front_x``: the furthest layer material in motion; ``column_front_x``: the
  furthest column material (the flow's own front over the bed);
* ``erosion_depth_max``: the deepest displacement below the layer's top; the profile
  ``erosion_depth`` gives it along the bed (by original position);
* ``layer_area_drift``: layer material in the domain over the layer's initial amount, minus
  one: the conservation error of the tracking (the flow is incompressible).
Units: m^2 per metre of width in plane strain; in r-z the amounts are volumes of revolution
(m^3: what an axisymmetric incompressible flow conserves, not the section's area), each
marker standing for the ring it started on (``geometry/section.py``).

The layer declares its own outputs (``simulation/outputs.py``): these diagnostics columns,
the profiles ``layer_line``, ``layer_markers`` and ``erosion_depth``, the cell data
``layer_fraction`` of a layer of its own material, its summary members, its checkpoint
state and the erosion figure (``io/erosion_plots.py``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar

import ngsolve as ngs
import numpy as np
import shapely

from granflow.config import Config
from granflow.diagnostics.state import FLOWING_SPEED
from granflow.fem.locator import PointLocator
from granflow.fem.measure import coordinates_of
from granflow.geometry.layer_material import LayerMaterial
from granflow.scenarios.column_discretisation import ColumnDiscretisation
from granflow.scenarios.column_setup import ColumnSetup
from granflow.simulation.outputs import Outputs
from granflow.simulation.simulation import RunResult, Simulation
from granflow.state.spec import (
    REAL,
    Share,
    array,
    may_lack,
    number,
    record,
    tuple_of,
)

POSITIVE = number(0.0, above=True)
MATERIAL: Share = {      # geometry/layer_material.py: LayerMaterial.save_state
    "line": array(None, 2, rows=2), "markers": array("markers", 2), "origins": array("markers", 2),
    "travel": array("markers"), "spacing": POSITIVE, "thickness": POSITIVE,
    "marker_area": POSITIVE, "surgery_area": may_lack(REAL),
    "heights": may_lack(array("markers")), "outline": may_lack(array(None, 2, rows=3))}

Table = tuple[list[str], np.ndarray]
WINDOW = 0.05   # m: how far behind the last column front its new one is looked for first
COLUMNS = ("layer_mobilised_area", "layer_displaced_area", "erosion_front_x",
           "column_front_x", "erosion_depth_max", "layer_area_drift")


def displacement_threshold(setup: ColumnSetup) -> float:
    """One grain diameter of the layer material: what counts as displaced."""
    return setup.materials.of_layer.grain_diameter


def erosion_figure(run_dir: Any, config: Config) -> None:
    """plots/erosion.png (``io/erosion_plots.py``), if the run wrote the layer's profiles."""
    from granflow.io.erosion_plots import plot_erosion

    plot_erosion(run_dir, config, coordinates_of(config.geometry))


@dataclass
class LayerTracking(Outputs):
    """The layer's material, advanced after each accepted step (the loop's callback)."""

    columns = COLUMNS
    figures = (erosion_figure,)
    share: ClassVar[Share] = {"layer_material": may_lack(record(MATERIAL)),   # restore says
                              "layer_largest": may_lack(tuple_of(REAL, REAL))}  # if missing

    setup: ColumnSetup
    current: ColumnDiscretisation
    material: LayerMaterial
    line_velocity: np.ndarray = field(init=False)
    marker_velocity: np.ndarray = field(init=False)
    _rates: tuple[np.ndarray, np.ndarray] | None = field(init=False, default=None)
    _locator: PointLocator | None = field(init=False, default=None)   # of the current mesh
    _triangles: dict[str, np.ndarray] = field(init=False, default_factory=dict)  # last found
    _last_front: float = field(init=False, default=float("nan"))   # column_front_x
    threshold: float = field(init=False)    # what counts as displaced (m)
    largest_drift: float = 0.0
    largest_mobilised: float = 0.0

    def __post_init__(self) -> None:
        self.threshold = displacement_threshold(self.setup)
        self.sample()

    @classmethod
    def start(cls, setup: ColumnSetup, current: ColumnDiscretisation) -> LayerTracking:
        """The layer at t = 0: [0, bed_length] x [0, h_e] on the paper's bed, else along
        the bed profile."""
        geo, cells = setup.config.geometry, setup.config.mesh.layer_cells
        if setup.paper_bed:
            material = LayerMaterial.initial(setup.thickness, geo.bed_length, cells)
        else:
            material = LayerMaterial.along_bed(setup.thickness, setup.bed, geo.bed_length,
                                               cells)
        return cls(setup, current, material)

    def sample(self) -> None:
        """The velocity u^n of the accepted state at the line and the markers, and its rate
        (u^n - u^{n-1}) / dt_{n-1} when the mesh moves with the extrapolated mid-step
        velocity (``numerics.ale_extrapolation``): what carries them over the next step, as
        the ALE carries the free surface (to the same order in time). Both point sets are
        located and evaluated in one pass, u^n and u^{n-1} together; the rate is NGSolve's
        (u^n - u^{n-1}) * (1 / dt_{n-1}), the same numbers."""
        solver = self.current.solver
        u = solver.velocity
        extrapolate = self.setup.config.numerics.ale_extrapolation and solver.dt_previous > 0
        fields = ngs.CF((u, solver.before_previous.components[0])) if extrapolate else u
        line, markers = self.material.line, self.material.markers
        values = self._values(fields, {"line": line, "markers": markers})
        self.line_velocity, self.marker_velocity = values["line"][:, :2], values["markers"][:, :2]
        self._rates = None
        if extrapolate:
            scale = 1.0 / solver.dt_previous
            self._rates = tuple((v[:, :2] - v[:, 2:]) * scale
                                for v in (values["line"], values["markers"]))

    def _values(self, u: ngs.CoefficientFunction, named: dict[str, np.ndarray]
                ) -> dict[str, np.ndarray]:
        """``u`` at each set of points; 0 beyond the meshed layer's end
        (``mesh.layer_ahead``), where the layer is at rest. All the sets are located and
        evaluated together; each point's search starts from the triangle it was found in at
        the last step (the set of that name; the line's points keep their order along it
        while a few are inserted or dropped each step, so the i-th of n starts from the
        triangle of the same fraction of the last step's)."""
        locator = self.locator()
        points = np.vstack(list(named.values()))
        guesses = []
        for name, at in named.items():
            guess = self._triangles.get(name)
            if guess is None:
                guess = np.full(len(at), -1, dtype=np.int64)
            elif len(guess) != len(at):
                guess = (guess[np.round(np.linspace(0, len(guess) - 1, len(at))).astype(int)]
                         if len(guess) else np.full(len(at), -1, dtype=np.int64))
            guesses.append(guess)
        guess = np.concatenate(guesses)
        out = np.zeros((len(points), u.dim))
        meshed = points[:, 0] <= self.current.mover.end_x
        found = np.full(len(points), -1, dtype=np.int64)
        if meshed.any():
            at = points[meshed]
            element, lam = locator.locate(at, guess[meshed])
            out[meshed] = locator.evaluate(u, at, element, lam)
            found[meshed] = element
        ends = np.cumsum([len(at) for at in named.values()])[:-1]
        for name, part in zip(named, np.split(found, ends), strict=True):
            self._triangles[name] = part
        return dict(zip(named, np.split(out, ends), strict=True))

    def locator(self) -> PointLocator:
        """The point location of the current mesh (built again after a remesh, which
        also forgets the triangles the points were found in)."""
        if self._locator is None or self._locator.mesh is not self.current.mesh:
            self._locator = PointLocator(self.current.mesh)
            self._triangles = {}
        return self._locator

    def unmeshed(self) -> shapely.Geometry:
        """The layer at rest beyond the meshed layer's end (``mesh.layer_ahead``)."""
        end, length = self.current.mover.end_x, self.setup.config.geometry.bed_length
        if end >= length:
            return shapely.Polygon()
        return shapely.box(end, 0.0, length, self.material.thickness)

    def __call__(self, sim: Simulation) -> None:
        """After an accepted step (and its remesh): move the layer, refresh the indicator
        of a layer of its own material (with a packing, the mass's fix may then move the
        free surface), sample the new velocity on the mesh as it is now."""
        line, markers = self.line_velocity, self.marker_velocity
        if self._rates is not None:      # the extrapolated mid-step velocity
            line = line + 0.5 * sim.dt * self._rates[0]
            markers = markers + 0.5 * sim.dt * self._rates[1]
        self.material.advance(line, markers, sim.dt)
        self.current.set_fraction(self.material, moved=True)   # (may move the surface)
        self.sample()

    # --- what the outputs read ---------------------------------------------------------
    def domain(self) -> shapely.Geometry:
        """The material's domain: the mesh's (its boundary loop, in order), and the layer
        at rest beyond its end."""
        xy = self.current.mesh.ngmesh.Coordinates()
        meshed = shapely.Polygon(xy[self.locator().loop])
        unmeshed = self.unmeshed()
        return meshed if unmeshed.is_empty else shapely.union(meshed, unmeshed)

    def measures(self) -> dict[str, float]:
        """This step's entrainment measures (module docstring)."""
        mat = self.material
        speed = np.hypot(*self.marker_velocity.T)
        moving = speed > FLOWING_SPEED
        displaced = mat.displaced(self.threshold)
        try:
            domain, region = self.domain(), mat.region()
            inside = self.size(shapely.intersection(region, domain))
            drift = inside / self.size(mat.initial_shape()) - 1.0
            column_front = _column_front(domain, region, 0.1 * mat.thickness,
                                         self._last_front)
            self._last_front = column_front
            self.largest_drift = max(self.largest_drift, abs(drift))
        except shapely.errors.GEOSException:    # a degenerate fold: not measured this step
            drift = column_front = float("nan")
        weight = self.marker_weights()
        mobilised = float(weight[moving].sum())
        self.largest_mobilised = max(self.largest_mobilised, mobilised)
        return {
            "layer_mobilised_area": mobilised,
            "layer_displaced_area": float(weight[displaced].sum()),
            "erosion_front_x": float(mat.markers[moving, 0].max()) if moving.any() else np.nan,
            "column_front_x": column_front,
            "erosion_depth_max": mat.deepest(self.threshold),
            "layer_area_drift": drift,
        }

    def size(self, shape: shapely.Geometry) -> float:
        """Area of a region of the section, or in r-z its volume of revolution."""
        return self.current.solver.coordinates.region(shape)

    def marker_weights(self) -> np.ndarray:
        """The amount of layer material each marker stands for: its share of the section's
        area, or in r-z the ring it started on."""
        mat = self.material
        return self.current.solver.coordinates.weights(mat.origins[:, 0], mat.marker_area)

    def erosion_depth(self) -> tuple[np.ndarray, np.ndarray]:
        """Bin centres along the bed (original position) and the depth displaced there:
        one bin per column of markers (a quarter of the layer's thickness wide)."""
        length = self.setup.config.geometry.bed_length
        bins = np.linspace(0.0, length, max(1, round(length / self.material.pitch)) + 1)
        depth = self.material.erosion_depth(self.threshold, bins)
        return 0.5 * (bins[1:] + bins[:-1]), depth

    # --- its outputs ------------------------------------------------------------------
    def diagnostics(self, sim: Simulation, cell_speed: np.ndarray) -> dict[str, float]:
        return self.measures()

    def fields(self) -> dict[str, np.ndarray]:
        """The share of layer material per triangle, of a layer of its own material."""
        fraction = self.current.fraction
        return {} if fraction is None else {"layer_fraction": fraction.vec.FV().NumPy().copy()}

    def profiles(self, t: float | None = None) -> dict[str, Table]:
        """The material line, the markers (now, origin, largest travel, speed) and the
        erosion depth along the bed."""
        mat = self.material
        speed = np.hypot(*self.marker_velocity.T)
        x0, depth = self.erosion_depth()
        return {
            "layer_line": (["x", "z"], mat.line),
            "layer_markers": (["x", "z", "x0", "z0", "travel", "speed"],
                              np.column_stack([mat.markers, mat.origins, mat.travel, speed])),
            "erosion_depth": (["x0", "depth"], np.column_stack([x0, depth])),
        }

    def summary(self, result: RunResult | None = None) -> dict[str, Any]:
        """End-of-run figures: eroded amounts (now and largest), depth, conservation."""
        now = self.measures()
        section = self.current.solver.coordinates
        amount, unit = section.amount, section.unit
        return {
            "two_materials": self.current.fraction is not None,
            f"layer_displaced_{amount}_{unit}": now["layer_displaced_area"],
            f"layer_mobilised_{amount}_max_{unit}": self.largest_mobilised,
            "erosion_depth_max_m": now["erosion_depth_max"],
            "column_front_m": now["column_front_x"],
            "layer_area_drift": now["layer_area_drift"],
            "layer_area_drift_max": self.largest_drift,
            "layer_line_points": len(self.material.line),
            # the section's area the line's untangling and coarsening changed, all steps
            "layer_line_correction_m2": self.material.surgery_area,
        }

    def save_state(self) -> dict[str, Any]:
        return {"layer_material": self.material.save_state(),
                "layer_largest": [self.largest_drift, self.largest_mobilised]}

    def restore_state(self, state: dict[str, Any]) -> None:
        """The tracked layer of a checkpoint, on the problem's restored discretisation."""
        if "layer_material" not in state:
            raise ValueError("this checkpoint of a run over an erodible layer was written by "
                             "a granflow that did not track the layer's material; run it "
                             "again from the start")
        self.material = LayerMaterial.from_state(state["layer_material"])
        self.largest_drift, self.largest_mobilised = map(float, state["layer_largest"])
        self.current.set_fraction(self.material)
        self.sample()


def _column_front(domain: shapely.Geometry, region: shapely.Geometry, thin: float,
                  near: float = float("nan")) -> float:
    """Rightmost column material: the domain less the layer region, without the films
    thinner than ``thin`` where the tracked line and the mesh's free surface (which the
    ALE moves to first order, and the area fix shifts) do not quite coincide.

    Measured in a window x >= x0 only, from ``near`` (the last step's answer) less
    WINDOW, widened until it holds column material: the films are removed by an inward
    offset of 0.5 thin, and the offset of the part beyond x0 is the whole offset's part
    beyond x0 + 0.5 thin, so its rightmost point is the same once it is not empty."""
    left, bottom, right, top = domain.bounds
    width = WINDOW
    start = near - WINDOW if np.isfinite(near) else right - WINDOW
    while True:
        x0 = max(min(start, right - width), left - thin)
        box = shapely.box(x0, bottom - thin, right + thin, top + thin)
        column = shapely.difference(shapely.clip_by_rect(domain, *box.bounds),
                                    region).buffer(-0.5 * thin)
        if not column.is_empty or x0 <= left - thin:
            return float(column.bounds[2] + 0.5 * thin) if not column.is_empty else float("nan")
        width, start = 4 * width, x0 - 3 * width
