"""Collapse of a granular column over a rigid or erodible bed (configuration (b), sections 3
and 5): the scenario builder assembles the mesh, the flow solver, the moving mesh with its
free-surface treatments (``ale/``) and the loop."""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field
from typing import Any

import ngsolve as ngs
import numpy as np

from granflow.ale.column_mover import ColumnMover
from granflow.ale.mesh_motion import ElasticMeshVelocity, LagrangeMeshVelocity
from granflow.ale.remesh import EdgeSize, boundary_edge_sizes, remesh, shape_quality
from granflow.ale.surface_tension import SurfaceTension
from granflow.ale.transfer import StateTransfer, transfer_tensor
from granflow.config import Config
from granflow.diagnostics import front as front_diag
from granflow.diagnostics.inertial import InertialNumbers
from granflow.diagnostics.interface import lower_envelope
from granflow.diagnostics.state import FLOWING_SPEED, flowing_cells
from granflow.fem.engine import NGSOLVE_OPS
from granflow.fem.flow import FlowSolver
from granflow.fem.forms import FrictionWall
from granflow.fem.linalg import direct_solver
from granflow.fem.sampling import cell_means, point_values, triangles
from granflow.geometry.domains import Polygon, column
from granflow.geometry.mesh import BED, END, SURFACE, WALL, polygon_mesh, signed_areas
from granflow.io.run_dir import RunDir
from granflow.physics import CoulombFriction, MuI, gravity_vector
from granflow.physics.well_posedness import well_posed_window
from granflow.scenarios.materials import augmentation, build_rheology, build_side_walls
from granflow.simulation.rest import RestCriterion
from granflow.simulation.simulation import RunResult, Simulation
from granflow.simulation.timestep import step_policy

SECTION_OFFSETS = (-0.10, 0.0, 0.10)  # m, around X_g = the initial front (section 5.2)


@dataclass
class ColumnCollapse:
    """The assembled collapse: mesh, solver, moving mesh, loop, and its diagnostics."""

    config: Config
    polygon: Polygon
    mesh: ngs.Mesh
    solver: FlowSolver
    mover: ColumnMover
    simulation: Simulation
    history: dict[str, list[float]] = field(
        default_factory=lambda: {"t": [], "front_x": [], "front_speed": [],
                                 "flowing_fraction": [],
                                 "kinetic_energy": [], "wall_height": []})
    remeshes: int = 0
    fresh_quality: float = 1.0
    remesh_changes: list[float] = field(default_factory=list)  # relative area, per remesh
    remesh_restored: list[float] = field(default_factory=list)  # area its simplification lost
    unrecorded_change: float = 0.0   # area change of the remeshes since the last diagnostics row
    inertial: InertialNumbers | None = None     # mu(I) runs: I in the flowing cells

    # --- remeshing (the loop calls these; they replace mesh, solver and mover) ----------
    def needs_remesh(self) -> bool:
        """Worst triangle below mesh.remesh_quality, or below half of what a fresh mesh of
        this domain achieved (a sharp front tip caps the quality any mesh can reach)."""
        floor = min(self.config.mesh.remesh_quality, 0.5 * self.fresh_quality)
        return floor > 0 and float(shape_quality(self.mesh).min()) < floor

    def degraded(self) -> bool:
        """Worst triangle below mesh.failure_remesh_quality: a failed nonlinear solve on
        this mesh is answered by a remesh before a smaller step."""
        floor = self.config.mesh.failure_remesh_quality
        return floor > 0 and float(shape_quality(self.mesh).min()) < floor

    def remesh(self) -> None:
        """New mesh of the same boundary; (u, p) at t^n and t^{n-1} transferred onto it
        (``ale/transfer.py``: interpolation inside the old domain, then a divergence-free
        projection)."""
        old_solver, old_mover = self.solver, self.mover
        remeshed = remesh(self.mesh, self.config.mesh.size, layer_edge_sizes(self.config))
        mesh = remeshed.mesh
        solver, mover = _flow_and_motion(self.config, mesh)
        change = (mover.area() - old_mover.area()) / old_mover.initial_area
        self.remesh_changes.append(change)
        self.remesh_restored.append(remeshed.area_restored)
        self.unrecorded_change += change
        transfer = StateTransfer(solver.space, [BED, WALL, END], self.config.boundary.penalty)
        solver.scheme.inherit(old_solver.scheme, transfer.apply)
        solver.solution.vec.data = solver.previous.vec
        solver.extrapolation_won = old_solver.extrapolation_won
        if old_solver.augmented is not None:     # the augmented Lagrangian's warm start
            transfer_tensor(old_solver.strain, solver.strain)
            transfer_tensor(old_solver.multiplier, solver.multiplier)
            solver.augmentation.Set(old_solver.augmentation.Get())
            solver.augmented.remember()
        mover.inherit(old_mover)
        self.mesh, self.solver, self.mover = mesh, solver, mover
        self.simulation.replace(solver, mover)
        self.remeshes += 1
        self.fresh_quality = float(shape_quality(mesh).min())

    # --- checkpoint (io/run_state.py) ---------------------------------------------
    def save_state(self) -> dict[str, Any]:
        """The scenario's share of the run state: the mesh (with its boundary labels, which
        deposition changes), the flow history, the mover, the diagnostics history (animation
        frames are files, ``frames/``)."""
        return {"mesh": self.mesh, "fields": self.solver.save_history(),
                "mover": self.mover.save_state(), "history": copy.deepcopy(self.history),
                "remeshes": self.remeshes,
                "fresh_quality": self.fresh_quality, "remesh_changes": list(self.remesh_changes),
                "remesh_restored": list(self.remesh_restored),
                "inertial": copy.deepcopy(self.inertial)}

    def restore_state(self, state: dict[str, Any]) -> None:
        """Continue from ``save_state``: solver and mover rebuilt on the saved mesh."""
        mesh = state["mesh"]
        solver, mover = _flow_and_motion(self.config, mesh)
        solver.restore_history(state["fields"])
        mover.restore_state(state["mover"])
        self.mesh, self.solver, self.mover = mesh, solver, mover
        self.simulation.replace(solver, mover)
        self.history = copy.deepcopy(state["history"])
        self.remeshes, self.fresh_quality = state["remeshes"], state["fresh_quality"]
        self.remesh_changes = list(state["remesh_changes"])
        self.remesh_restored = list(state["remesh_restored"])
        self.inertial = copy.deepcopy(state.get("inertial", self.inertial))

    # --- observers' side ---------------------------------------------------------------
    def front(self) -> float:
        """Front X: the rightmost point of the mass; over an erodible layer of thickness
        h_e, the rightmost surface point more than 1 mm above the undisturbed layer."""
        he = self.config.geometry.erodible_thickness
        if he <= 0:
            return front_diag.front_position(self.mesh.ngmesh.Coordinates())
        return front_diag.thick_front(self.surface(), he + 1e-3)

    def shape_measures(self, cell_speed: np.ndarray) -> dict[str, float]:
        """Front, its speed (cells touching the front vertex) and the height at the wall."""
        xy = self.mesh.ngmesh.Coordinates()
        tri = triangles(self.mesh)
        x_front = self.front()
        front_vertex = int(np.argmin(np.abs(xy[:, 0] - x_front)))
        at_front = np.any(tri == front_vertex, axis=1)
        speed = float(cell_speed[at_front].max())      # cells touching the front vertex
        out = {"front_x": x_front, "front_speed": speed,
               "wall_height": front_diag.wall_height(xy)}
        if self.inertial is not None:
            self._add_inertial_numbers(cell_speed > FLOWING_SPEED)
        out["area_correction"] = self.mover.step_correction
        out["remesh_area_change"] = self.unrecorded_change
        tension = self.mover.tension
        if tension is not None:
            out["tension_on"] = float(tension.state.active)
            out["tension_x"] = tension.state.critical_x if tension.state.active else np.nan
        return out

    def _add_inertial_numbers(self, flowing: np.ndarray) -> None:
        """This step's I in the flowing cells (``diagnostics/inertial.py``)."""
        solver = self.solver
        shear_rate = math.sqrt(2.0) * solver.strain_rate_norm()
        law = solver.rheology
        assert isinstance(law, MuI) and self.inertial is not None
        values, areas = cell_means(self.mesh, law.inertial_number(shear_rate, solver.pressure,
                                                                  NGSOLVE_OPS))
        dt = self.simulation.dt
        self.inertial.add(values[flowing], areas[flowing] * dt)

    def record(self, row: dict[str, float]) -> None:
        for key, values in self.history.items():
            values.append(row[key])
        self.unrecorded_change = 0.0

    def flowing(self) -> np.ndarray:
        flags, _ = flowing_cells(self.mesh, self.solver.velocity)
        return flags

    def flowing_fraction(self) -> float:
        """Area fraction of the cells faster than the flowing threshold (1 mm/s)."""
        flags, areas = flowing_cells(self.mesh, self.solver.velocity)
        return float(areas[flags].sum() / areas.sum())

    def surface(self) -> np.ndarray:
        return self.mover.chain.surface_polyline()

    def interface(self, stations: np.ndarray) -> np.ndarray:
        xy = self.mesh.ngmesh.Coordinates()
        return lower_envelope(xy, triangles(self.mesh), self.flowing(), stations)

    def sections(self) -> list[tuple[float, np.ndarray, np.ndarray]]:
        """(X, Z samples, velocity samples) on the verticals X_g - 10 cm, X_g, X_g + 10 cm.

        Samples run from the bed to the highest crossing of the vertical with the surface;
        points outside the mesh (under an overhang) are left out.
        """
        surface = self.surface()
        out = []
        for dx in SECTION_OFFSETS:
            x = self.config.geometry.width + dx
            top = _highest_crossing(surface, x)
            if top is None:
                continue
            z = np.linspace(0.0, top, 41)[:-1] + 1e-9
            z, u = point_values(self.mesh, self.solver.velocity, x, z)
            if len(z):
                out.append((x, z, u))
        return out

    def write_profiles(self, run_dir: RunDir, t: float, label: str | None = None) -> None:
        """Free surface, velocity sections and interface as profiles/KIND_LABEL.csv (LABEL
        defaults to tT.TTT)."""
        label = label or f"t{t:.3f}"
        surface = self.surface()
        run_dir.write_csv(f"profiles/free_surface_{label}.csv", ["x", "z"], surface.tolist())
        rows = [[x, zi, ui[0], ui[1]] for x, z, u in self.sections()
                for zi, ui in zip(z, u, strict=True)]
        run_dir.write_csv(f"profiles/velocity_sections_{label}.csv",
                          ["section_x", "z", "u_x", "u_z"], rows)
        stations = np.linspace(0.0, front_diag.front_position(self.mesh.ngmesh.Coordinates()),
                               200)
        run_dir.write_csv(f"profiles/interface_{label}.csv", ["x", "z"],
                          np.column_stack([stations, self.interface(stations)]).tolist())

    def frame(self, sim: Simulation) -> dict[str, Any]:
        """A frame of the animation: mesh, cell speeds and the interface."""
        speed, _ = cell_means(self.mesh, ngs.Norm(self.solver.velocity))
        xy = self.mesh.ngmesh.Coordinates().copy()
        stations = np.linspace(0.0, xy[:, 0].max(), 120)
        return {"t": sim.t, "xy": xy, "tri": triangles(self.mesh), "speed": speed,
                "interface": np.column_stack([stations, self.interface(stations)])}

    def summary(self, result: RunResult) -> dict[str, Any]:
        h = {k: np.asarray(v) for k, v in self.history.items()}
        xy = self.mesh.ngmesh.Coordinates()
        surface = self.surface()
        return {
            "runout_m": self.front(),
            "runout_1mm_m": front_diag.thick_front(
                surface, self.config.geometry.erodible_thickness + 1e-3),
            "surface_edge_spread": front_diag.surface_edge_spread(surface),
            "stop_time_s": (stop := front_diag.stop_time(h["t"], h["flowing_fraction"],
                                                         self.config.time.rest_fraction)),
            "all_cells_static_s": front_diag.stop_time(h["t"], h["flowing_fraction"]),
            "runout_at_stop_m": float(np.interp(stop, h["t"], h["front_x"])) if stop else None,
            "front_stop_time_s": front_diag.front_stop_time(h["t"], h["front_speed"]),
            "front_settle_time_s": front_diag.settle_time(h["t"], h["front_x"]),
            "wall_height_m": front_diag.wall_height(xy),
            "initial_area_m2": self.mover.initial_area,
            "deposited_segments": self.mover.relabelled_segments,
            "dt_limited_steps": self.mover.limited_steps,
            "min_triangle_area_m2": float(np.min(signed_areas(self.mesh))),
            "min_triangle_quality": float(np.min(shape_quality(self.mesh))),
            "remeshes": self.remeshes,
            "remesh_area_change_max": max(map(abs, self.remesh_changes), default=0.0),
            "remesh_area_restored_max": max(map(abs, self.remesh_restored), default=0.0),
            "area_correction_total": self.mover.correction_abs,   # sum of |relative fixes|
            "area_correction_net": self.mover.correction_net,     # their signed sum
            "surface_tension_steps": (self.mover.tension.state.active_steps
                                      if self.mover.tension is not None else None),
            "inertial_number_flowing": (self.inertial.summary()
                                        if self.inertial is not None else None),
        }

    def plot(self, run_dir: RunDir) -> None:
        from granflow.io.collapse_plots import plot_collapse

        plot_collapse(run_dir, self.config)


def _highest_crossing(polyline: np.ndarray, x: float) -> float | None:
    """Highest Z where the polyline crosses the vertical X = x."""
    best = None
    for (x0, z0), (x1, z1) in zip(polyline[:-1], polyline[1:], strict=True):
        if min(x0, x1) <= x <= max(x0, x1) and x0 != x1:
            z = z0 + (z1 - z0) * (x - x0) / (x1 - x0)
            best = z if best is None else max(best, z)
    return best


def layer_edge_sizes(config: Config) -> EdgeSize | None:
    """Over an erodible layer of thickness h_e: edges lying within 2 h_e of the bed get
    length h_e / mesh.layer_cells (the bed, the layer's top and its end), so that the
    layer has that many cells across; Netgen grades the rest up to mesh.size."""
    he, cells = config.geometry.erodible_thickness, config.mesh.layer_cells
    if he <= 0:
        return None
    fine, size = he / cells, config.mesh.size
    return lambda p, q: fine if max(p[1], q[1]) <= 2 * he else size


def _inertial_numbers(law: object) -> InertialNumbers | None:
    """mu(I) runs record their inertial numbers and the law's well-posed window."""
    if not isinstance(law, MuI):
        return None
    return InertialNumbers(well_posed=well_posed_window(law))


def build_column(config: Config) -> ColumnCollapse:
    """Netgen mesh of the column, friction walls, ALE mover, rest state with hydrostatic p."""
    geo, mat = config.geometry, config.material
    polygon = column(geo.shape, geo.width, geo.height, geo.front_angle_deg,
                     geo.erodible_thickness, geo.bed_length)
    mesh = polygon_mesh(polygon.points, polygon.labels, config.mesh.size,
                        boundary_edge_sizes(polygon.points, layer_edge_sizes(config)))
    solver, mover = _flow_and_motion(config, mesh)
    force = gravity_vector(mat.gravity, geo.slope_deg)
    xy = mesh.ngmesh.Coordinates()
    heights = np.array([polygon.surface_height(x) for x in xy[:, 0]])
    pressure = ngs.GridFunction(ngs.H1(mesh, order=1))
    pressure.vec.FV().NumPy()[:] = -mat.density * force[1] * np.maximum(heights - xy[:, 1], 0)
    solver.set_state(ngs.CF((0.0, 0.0)), pressure)                  # at rest, hydrostatic
    simulation = Simulation(solver=solver, steps_policy=step_policy(config),
                            t_end=config.time.t_end,
                            max_iterations=config.numerics.max_iterations, mesh_motion=mover,
                            velocity_floor=config.numerics.velocity_floor)
    problem = ColumnCollapse(config=config, polygon=polygon, mesh=mesh, solver=solver,
                             mover=mover, simulation=simulation,
                             inertial=_inertial_numbers(solver.rheology))
    simulation.remesher = problem
    if config.time.stop_at_rest:
        simulation.stop_criteria = [RestCriterion(problem.flowing_fraction,
                                                  config.time.rest_fraction,
                                                  config.time.rest_duration)]
    return problem


def _flow_and_motion(config: Config, mesh: ngs.Mesh) -> tuple[FlowSolver, ColumnMover]:
    """The flow solver (3.2) with Coulomb walls and the ALE mover (3.6)/(3.7) on ``mesh``."""
    geo, mat, bnd, num = config.geometry, config.material, config.boundary, config.numerics
    load = bnd.normal_load
    walls = [FrictionWall(BED, CoulombFriction(bnd.bed_friction_deg, num.eps_friction), load),
             FrictionWall(WALL, CoulombFriction(bnd.wall_friction_deg, num.eps_friction), load)]
    if geo.erodible_thickness > 0:   # the layer's far end: frictionless, u.N = 0 (domains.py)
        walls.append(FrictionWall(END, CoulombFriction(0.0, num.eps_friction), load))
    st = config.surface_tension
    solver = FlowSolver(mesh, rheology=build_rheology(config), density=mat.density,
                        body_force=gravity_vector(mat.gravity, geo.slope_deg),
                        walls=walls, penalty=bnd.penalty, linearization=num.linearization,
                        linear_solver=direct_solver(num.linear_solver),
                        initial_guess=num.initial_guess,
                        surface_tension_on=SURFACE if st.enabled else None,
                        side_walls=build_side_walls(config),
                        augmentation=augmentation(config),
                        scheme=config.time.scheme)
    tension = (SurfaceTension(solver.surface_tension, st.delta, st.gamma0,
                              st.trigger_angle_deg, config.mesh.size,
                              st.release_angle_deg) if st.enabled else None)
    velocity_cls = LagrangeMeshVelocity if num.mesh_velocity == "lagrange" else (
        ElasticMeshVelocity)
    source = ngs.GridFunction(solver.space.components[0])
    w_solver = velocity_cls(mesh, source, solver.mesh_velocity, num.mesh_penalty,
                            solver=direct_solver(num.linear_solver))
    mover = ColumnMover(mesh, w_solver,
                        source=source, flow=solver, target=solver.mesh_velocity,
                        extrapolate=num.ale_extrapolation,
                        conserve_volume=num.volume_correction, tension=tension)
    return solver, mover
