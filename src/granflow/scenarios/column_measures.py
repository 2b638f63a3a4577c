"""What the outputs read from a collapse: the front, the free surface, the static/flowing
interface, velocity sections, animation frames, the diagnostics history, the summary and the
figures (``io/collapse_plots.py``), declared as the collapse's callback
(``simulation/outputs.py``). Read-only on the flow; its state is the history of the rows it
was given and, for mu(I), the inertial numbers it accumulates (both checkpointed). For a
cylinder of radius 10 cm the section at X_g - 10 cm is the axis itself."""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, ClassVar

import ngsolve as ngs
import numpy as np

from granflow.ale.remesh import shape_quality
from granflow.config import Config
from granflow.diagnostics import front as front_diag
from granflow.diagnostics.inertial import InertialNumbers
from granflow.diagnostics.interface import lower_envelope
from granflow.diagnostics.state import FLOWING_SPEED, flowing_cells
from granflow.fem.engine import NGSOLVE_OPS
from granflow.fem.measure import coordinates_of
from granflow.fem.sampling import cell_means, point_values, triangles, vertex_samples
from granflow.geometry.domains import column
from granflow.geometry.mesh import signed_areas
from granflow.geometry.sources import GeometryError
from granflow.physics import MuI
from granflow.scenarios.column_discretisation import ColumnDiscretisation
from granflow.scenarios.column_remesher import ColumnRemesher
from granflow.scenarios.column_setup import ColumnSetup
from granflow.simulation.outputs import Outputs
from granflow.simulation.simulation import RunResult, Simulation
from granflow.state.spec import (
    ANY_NUMBER,
    Share,
    dataclass_of,
    list_of,
    may_lack,
    or_none,
    record,
)

SECTION_OFFSETS = (-0.10, 0.0, 0.10)  # m, around X_g = the initial front (section 5.2)
Table = tuple[list[str], np.ndarray]  # column names, rows


def _history() -> dict[str, list[float]]:
    return {"t": [], "front_x": [], "front_speed": [], "flowing_fraction": [],
            "kinetic_energy": [], "wall_height": []}


def collapse_figures(run_dir: Any, config: Config) -> None:
    """The figures of a collapse and its animation (``io/collapse_plots.py``), with its
    set-up's section, initial domain and bed profile."""
    from granflow.io.collapse_plots import Drawn, plot_collapse

    try:
        setup = ColumnSetup.of(config)
    except GeometryError:          # a profile's file gone since the run: the built-in shape
        g = config.geometry
        points = np.asarray(column(g.shape, g.width, g.height, g.front_angle_deg,
                                   g.erodible_thickness, g.bed_length).points, dtype=float)
        drawn = Drawn(coordinates_of(g), np.vstack([points, points[:1]]))
    else:
        points = np.asarray(setup.scene.polygon.points, dtype=float)
        drawn = Drawn(setup.coordinates, np.vstack([points, points[:1]]),
                      None if setup.paper_bed else setup.bed.points)
    plot_collapse(run_dir, config, drawn)


@dataclass
class ColumnMeasures(Outputs):
    """Measures of the current state of a collapse (``current`` follows the remeshes)."""

    figures = (collapse_figures,)
    animated = True
    share: ClassVar[Share] = {
        "history": record({name: list_of(ANY_NUMBER, length="history steps")
                           for name in _history()}),
        "inertial": may_lack(or_none(dataclass_of(InertialNumbers)))}

    setup: ColumnSetup
    current: ColumnDiscretisation
    remesher: ColumnRemesher
    simulation: Simulation
    inertial: InertialNumbers | None = None     # mu(I) runs: I in the flowing cells
    history: dict[str, list[float]] = field(default_factory=_history)

    def front(self) -> float:
        """Front X: the rightmost point of the mass; over an erodible layer of thickness
        h_e, the rightmost surface point more than 1 mm above the undisturbed layer."""
        if not self.setup.erodible:
            return front_diag.front_position(self.current.mesh.ngmesh.Coordinates())
        return front_diag.thick_front(self.surface_above_bed(), self.setup.thickness + 1e-3)

    def surface_above_bed(self) -> np.ndarray:
        """The free surface as (x, height above the bed profile)."""
        surface = self.surface().copy()
        surface[:, 1] = self.current.mover.support.bed.height(surface)
        return surface

    def wall_height(self, xy: np.ndarray) -> float:
        """Height of the mass along the left wall (0 without one)."""
        return front_diag.wall_height(xy, self.current.mover.support.wall)

    @cached_property
    def initial_front(self) -> float:
        """X_g: the mass's front on the bed at t = 0 (the base width on the paper's bed)."""
        scene = self.setup.scene
        on_bed = np.abs(scene.bed.height(scene.mass)) <= 1e-9 * max(scene.size, 1e-9)
        return float(scene.mass[on_bed, 0].max()) if on_bed.any() else scene.front_x()

    def _start_x(self, xy: np.ndarray) -> float:
        """Where stations start: the wall x = 0 of the paper's bed, else the mass's left."""
        return 0.0 if self.setup.paper_bed else float(xy[:, 0].min())

    def shape_measures(self, cell_speed: np.ndarray) -> dict[str, float]:
        """Front, its speed (cells touching the front vertex) and the height at the wall."""
        mesh, mover = self.current.mesh, self.current.mover
        xy = mesh.ngmesh.Coordinates()
        tri = triangles(mesh)
        x_front = self.front()
        front_vertex = int(np.argmin(np.abs(xy[:, 0] - x_front)))
        at_front = np.any(tri == front_vertex, axis=1)
        speed = float(cell_speed[at_front].max())      # cells touching the front vertex
        out = {"front_x": x_front, "front_speed": speed,
               "wall_height": self.wall_height(xy)}
        if self.inertial is not None:
            self._add_inertial_numbers(cell_speed > FLOWING_SPEED)
        out["area_correction"] = mover.step_correction
        out["remesh_area_change"] = self.remesher.unrecorded_change
        tension = mover.tension
        if tension is not None:
            out["tension_on"] = float(tension.state.active)
            out["tension_x"] = tension.state.critical_x if tension.state.active else np.nan
        return out

    def _add_inertial_numbers(self, flowing: np.ndarray) -> None:
        """This step's I in the flowing cells (``diagnostics/inertial.py``)."""
        solver = self.current.solver
        shear_rate = math.sqrt(2.0) * solver.strain_rate_norm()
        law = getattr(solver.rheology, "flow", solver.rheology)   # a hysteretic friction's
        assert isinstance(law, MuI) and self.inertial is not None
        values, areas = cell_means(self.current.mesh,
                                   law.inertial_number(shear_rate, solver.pressure, NGSOLVE_OPS))
        self.inertial.add(values[flowing], areas[flowing] * self.simulation.dt)

    def diagnostics(self, sim: Simulation, cell_speed: np.ndarray) -> dict[str, float]:
        return self.shape_measures(cell_speed)

    def record(self, row: dict[str, float]) -> None:
        for key, values in self.history.items():
            values.append(row[key])
        self.remesher.recorded()

    def flowing(self) -> np.ndarray:
        flags, _ = flowing_cells(self.current.mesh, self.current.solver.velocity)
        return flags

    def flowing_fraction(self) -> float:
        """Area fraction of the cells faster than the flowing threshold (1 mm/s)."""
        flags, areas = flowing_cells(self.current.mesh, self.current.solver.velocity)
        return float(areas[flags].sum() / areas.sum())

    def surface(self) -> np.ndarray:
        return self.current.mover.chain.surface_polyline()

    def interface(self, stations: np.ndarray) -> np.ndarray:
        mesh = self.current.mesh
        return lower_envelope(mesh.ngmesh.Coordinates(), triangles(mesh), self.flowing(),
                              stations)

    def sections(self) -> list[tuple[float, np.ndarray, np.ndarray]]:
        """(X, Z samples, velocity samples) on the verticals X_g - 10 cm, X_g, X_g + 10 cm.

        Samples run from the bed to the highest crossing of the vertical with the surface;
        points outside the mesh (under an overhang) are left out.
        """
        surface = self.surface()
        out = []
        for dx in SECTION_OFFSETS:
            x = self.initial_front + dx
            top = _highest_crossing(surface, x)
            if top is None:
                continue
            bottom = float(self.current.mover.support.bed.z(x)[0])
            z = np.linspace(bottom, top, 41)[:-1] + 1e-9
            z, u = point_values(self.current.mesh, self.current.solver.velocity, x, z)
            if len(z):
                out.append((x, z, u))
        return out

    def profiles(self, t: float | None = None) -> dict[str, Table]:
        """Free surface, velocity sections and interface of the current state, as
        ``io/profiles.py`` writes them."""
        rows = [[x, zi, ui[0], ui[1]] for x, z, u in self.sections()
                for zi, ui in zip(z, u, strict=True)]
        xy = self.current.mesh.ngmesh.Coordinates()
        stations = np.linspace(self._start_x(xy), front_diag.front_position(xy), 200)
        out = {"free_surface": (["x", "z"], self.surface()),
               "velocity_sections": (["section_x", "z", "u_x", "u_z"], np.array(rows)),
               "interface": (["x", "z"],
                             np.column_stack([stations, self.interface(stations)]))}
        return out

    def frame(self, sim: Simulation) -> dict[str, Any]:
        """A frame of the animation: mesh, cell speeds, the speed of the P2 velocity at the
        vertices (for smooth shading) and the interface."""
        mesh = self.current.mesh
        velocity = self.current.solver.velocity
        speed, _ = cell_means(mesh, ngs.Norm(velocity))
        xy = mesh.ngmesh.Coordinates().copy()
        stations = np.linspace(self._start_x(xy), xy[:, 0].max(), 120)
        return {"t": sim.t, "xy": xy, "tri": triangles(mesh), "speed": speed,
                "vertex_speed": np.linalg.norm(vertex_samples(mesh, velocity), axis=1),
                "interface": np.column_stack([stations, self.interface(stations)])}

    def summary(self, result: RunResult) -> dict[str, Any]:
        mesh, mover = self.current.mesh, self.current.mover
        h = {k: np.asarray(v) for k, v in self.history.items()}
        xy = mesh.ngmesh.Coordinates()
        surface = self.surface()
        revolved = self.setup.axisymmetric
        stop = front_diag.stop_time(h["t"], h["flowing_fraction"],
                                    self.setup.config.time.rest_fraction)
        return {
            "runout_m": self.front(),
            "runout_1mm_m": front_diag.thick_front(
                self.surface_above_bed(), self.setup.thickness + 1e-3),
            "surface_edge_spread": front_diag.surface_edge_spread(surface),
            "stop_time_s": stop,
            "all_cells_static_s": front_diag.stop_time(h["t"], h["flowing_fraction"]),
            "runout_at_stop_m": float(np.interp(stop, h["t"], h["front_x"])) if stop else None,
            "front_stop_time_s": front_diag.front_stop_time(h["t"], h["front_speed"]),
            "front_settle_time_s": front_diag.settle_time(h["t"], h["front_x"]),
            "wall_height_m": self.wall_height(xy),
            **({"axis_height_m": self.wall_height(xy)}      # h_inf of a cylinder
               if revolved else {}),
            ("initial_volume_m3" if revolved else "initial_area_m2"):
                mover.initial_area - self.remesher.added,   # what the free-surface fix
                                                            # conserves (less a lengthening)
            "deposited_segments": mover.relabelled_segments,
            "dt_limited_steps": mover.limited_steps,
            "min_triangle_area_m2": float(np.min(signed_areas(mesh))),
            "min_triangle_quality": float(np.min(shape_quality(mesh, self.remesher.stretch))),
            **self.remesher.summary(),
            "area_correction_total": mover.correction_abs,   # sum of |relative fixes|
            "area_correction_net": mover.correction_net,     # their signed sum
            "surface_tension_steps": (mover.tension.state.active_steps
                                      if mover.tension is not None else None),
            "inertial_number_flowing": (self.inertial.summary()
                                        if self.inertial is not None else None),
            **({"volume_relative_error": abs(mover.area() / mover.initial_area - 1.0)}
               if self.remesher.added else {}),   # against the lengthened layer's
        }

    def save_state(self) -> dict[str, Any]:
        return {"history": copy.deepcopy(self.history), "inertial": copy.deepcopy(self.inertial)}

    def restore_state(self, state: dict[str, Any]) -> None:
        self.history = copy.deepcopy(state["history"])
        self.inertial = copy.deepcopy(state.get("inertial", self.inertial))


def _highest_crossing(polyline: np.ndarray, x: float) -> float | None:
    """Highest Z where the polyline crosses the vertical X = x."""
    best = None
    for (x0, z0), (x1, z1) in zip(polyline[:-1], polyline[1:], strict=True):
        if min(x0, x1) <= x <= max(x0, x1) and x0 != x1:
            z = z0 + (z1 - z0) * (x - x0) / (x1 - x0)
            best = z if best is None else max(best, z)
    return best
