"""The packing fraction on the moving mesh (``physics/packing.py``) and its coupling to the
flow: the continuity row of (3.2) gains the dilatancy, div u = gamma_dot tan(psi), the law
reads phi (its friction tan(psi)) and the density rho_s phi, and after each accepted step
phi moves with the material and relaxes towards phi_eq(I).

The field is phi - phi_0 per triangle (L2 of order 0), phi_0 each material's initial
packing: 0 at t = 0, and 0 to the last digit wherever the packing has not changed, so that
a run with K = 0 is the incompressible run itself. After a step of length dt in which the
material moved with u and the mesh's vertices by a displacement (the mesh velocity w of the
step, linear on each triangle):

1. transport, D phi / Dt = 0 along the material between relaxations: in the frame of the
   moving mesh d phi / dt + (u - w) . grad phi = 0, by the upwind (finite-volume) step of
   ``fem/mobilisation_field.py`` written in differences, phi_K <- phi_K + dt / |K| sum_e
   F_e (phi_e - phi_K) with F_e the in-flux through edge e (so a uniform field stays
   uniform to the last digit), cut into substeps that keep it a convex combination;
2. compaction or dilation at the step's gamma_dot (cell means) and phi_eq, the exact
   solution of D phi / Dt = - gamma_dot K phi (phi - phi_eq) (``CriticalState.relaxed``);
   then phi_eq(I) of the accepted state (cell means) for the next step.

phi_eq is lagged by a step (phi_c at rest before the first): the continuity row's source
div u = gamma_dot K (phi - phi_eq) then reads the pressure of no iterate. Read at the
iterate, I's steep fall to phi_min as p -> 0 near the free surface (I grows as
1 / sqrt(p)) switched the source on and off between iterates, and the fixed point (3.2)
stalled (500 iterations) in a coarse rectangle at 0.07 s; with phi_eq lagged, or with a = 0,
it converges. The friction tan(psi) of the stress reads I at the iterate, as mu(I) does.

Both stay within the values they start from and phi_eq: a packing outside (0, 0.7405] is a
failure of the run (``PackingOutOfRange``), never clipped.

Mass. The grains' mass is M = sum_K rho_K |K|, rho_K = rho_s phi_K (with a layer: the two
materials' blended by the share of layer material). The flow's volume changes by the
integral of div u; the column's free-surface fix (``ale/column_mover.py``) keeps the mass
instead of the area, through ``volume_excess``: with one material the measure the material
would fill at its initial packing, |Omega| + sum_K (phi_K - phi_0) / phi_0 |K|, the area
itself while the packing has not changed. With a layer of another packing that measure is
not the mass: the departure and the share of layer material are carried by different
schemes, the departure crosses the interface, and a measure that assumed each material's
mass kept let the mass drift by 1e-4 in a tenth of a second. The excess is then the mass's
own, (M - M_0) / rho_0 + |Omega_0| - sum_K |K| with rho_0 the column's initial density
and M_0, |Omega_0| the mass and measure at t = 0 (0 before they are taken: the initial
state; 0 with K = 0, the incompressible run): the fix keeps the two materials' mass
together, to round-off, after every accepted step and every change of the share
(``scenarios/column_discretisation.py``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import ngsolve as ngs
import numpy as np

from granflow.fem.coupling import Carriers, Coupling, Flow, Site
from granflow.fem.engine import NGSOLVE_OPS
from granflow.fem.forms import Symbols
from granflow.fem.measure import PLANE, Coordinates
from granflow.fem.sampling import cell_means, triangles
from granflow.physics.packing import DENSEST, CriticalState
from granflow.physics.regions import blend
from granflow.state.spec import REAL, Share, array, assign, may_lack


class PackingOutOfRange(ValueError):
    """The packing fraction left (0, 0.7405]: the run cannot go on."""


class PackingField:
    """phi - phi_0 per triangle of ``mesh`` (``departure``, what the laws read) and its
    transport (module docstring)."""

    def __init__(self, mesh: ngs.Mesh, coords: Coordinates = PLANE) -> None:
        self.mesh, self.coords = mesh, coords
        self.space = ngs.L2(mesh, order=0, dgjumps=True)
        self.departure = ngs.GridFunction(self.space)
        self.equilibrium = ngs.GridFunction(self.space)   # phi_eq - phi_0 (module docstring)
        self._mesh_velocity = ngs.GridFunction(ngs.VectorH1(mesh, order=1))
        self.triangles = triangles(mesh)
        self._fluxes: tuple[ngs.CoefficientFunction, ngs.BilinearForm] | None = None

    @property
    def values(self) -> np.ndarray:
        """phi - phi_0 per triangle, a writable view."""
        return self.departure.vec.FV().NumPy()

    def cell_measures(self, xy: np.ndarray) -> np.ndarray:
        """Each triangle's share of the section's measure with its vertices at ``xy``: its
        area, or in r-z the volume it sweeps about the axis (2 pi r_c area, Pappus)."""
        a, b, c = (xy[self.triangles[:, k]] for k in range(3))
        areas = 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                             - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1]))
        if not self.coords.axisymmetric:
            return areas
        return 2.0 * math.pi * areas * (a[:, 0] + b[:, 0] + c[:, 0]) / 3.0

    def in_fluxes(self, velocity: ngs.CoefficientFunction, displacement: np.ndarray,
                  dt: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(cell, neighbour, F): the in-flux F >= 0 of (u - w) . n through each edge into
        its cell from its neighbour, w = displacement / dt at the vertices (the section's
        measure: r-weighted in r-z)."""
        nv = self.mesh.nv
        for c, component in enumerate(self._mesh_velocity.components):
            component.vec.FV().NumPy()[:nv] = displacement[:, c] / dt
        form = self._flux_form(velocity)
        form.Assemble()
        rows, columns, values = (np.asarray(a) for a in form.mat.COO())
        into = (rows != columns) & (values < 0.0)   # on a wall there is no neighbour
        return rows[into], columns[into], -values[into]

    def _flux_form(self, velocity: ngs.CoefficientFunction) -> ngs.BilinearForm:
        """The form of the in-fluxes with ``velocity``, built once for it (a run passes
        the flow's velocity field every step) and assembled each step."""
        if self._fluxes is None or self._fluxes[0] is not velocity:
            flux = (velocity - self._mesh_velocity) * ngs.specialcf.normal(self.mesh.dim)
            phi, v = self.space.TnT()
            inward = ngs.IfPos(flux, 0.0, flux)          # -[-(u - w) . n]_+
            form = ngs.BilinearForm(self.space)
            form += self.coords.dx(inward * phi.Other() * v, element_boundary=True)
            self._fluxes = (velocity, form)
        return self._fluxes[1]

    def advect(self, velocity: ngs.CoefficientFunction, displacement: np.ndarray,
               dt: float) -> int:
        """Carry the field over a step (module docstring, 1.); returns the substeps."""
        if dt <= 0:
            return 0
        cell, neighbour, flux = self.in_fluxes(velocity, displacement, dt)
        weight = ngs.x if self.coords.axisymmetric else ngs.CF(1.0)
        volumes = ngs.Integrate(weight, self.mesh, element_wise=True).NumPy()
        n = len(volumes)
        rate = np.bincount(cell, weights=flux, minlength=n) / volumes
        substeps = max(1, math.ceil(dt * float(np.max(rate, initial=0.0))))
        h = dt / substeps
        values = self.values
        for _ in range(substeps):
            gain = np.bincount(cell, weights=flux * (values[neighbour] - values[cell]),
                               minlength=n)
            values += h * gain / volumes
        return substeps


def _blended(laws: tuple[CriticalState, ...], share: Any, value: Any) -> Any:
    """``value(law)`` of one material, or of a column's and a layer's blended by the
    share of layer material."""
    if len(laws) == 1:
        return value(laws[0])
    return blend(value(laws[0]), value(laws[1]), share)


@dataclass(frozen=True)
class DilatancySource:
    """-q gamma_dot tan(psi) on the right-hand side of the continuity row of (3.2):
    -q div u = -q gamma_dot tan(psi), with gamma_dot at u_lin (the iterate in Picard's
    form, the unknowns in Newton's), phi and phi_eq of the accepted state (module
    docstring)."""

    coupling: PackingCoupling
    rhs_reads_iterate = True

    def lhs(self, s: Symbols, mesh: ngs.Mesh) -> None:
        return None

    def rhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals:
        return s.coords.dx(-s.q * self.coupling.volumetric_rate(s.u_lin, s.coords))


@dataclass(frozen=True)
class PackingSpec:
    """The packing of a run's materials (one, or a column's and its layer's, blended with
    the share of layer material the couplings before it hand the law)."""

    laws: tuple[CriticalState, ...]

    def build(self, site: Site, fields: Mapping[str, Any]) -> PackingCoupling:
        return PackingCoupling(PackingField(site.mesh, site.coordinates), self.laws,
                               fields.get("share"))


class PackingCoupling(Coupling):
    """The packing fraction beside the flow (module docstring): the law reads phi - phi_0,
    the continuity row its dilatancy; moved and relaxed on acceptance, kept in the
    checkpoint, carried through a remesh per triangle; the free-surface fix keeps its
    mass."""

    name = "packing"
    share_of_checkpoint: Share = {"packing": may_lack(array("cells")),
                                  "packing_equilibrium": may_lack(array("cells")),
                                  "packing_initial_mass": may_lack(REAL),
                                  "packing_initial_measure": may_lack(REAL),
                                  "packing_vertices": may_lack(array("vertices", None))}

    def __init__(self, field: PackingField, laws: tuple[CriticalState, ...],
                 share: ngs.GridFunction | None) -> None:
        self.field, self.laws, self.fraction = field, laws, share
        # the vertices phi was last carried to: the accepted state's, before the free-surface
        # fix that may follow the acceptance (the next step's transport carries it)
        self._xy = field.mesh.ngmesh.Coordinates().copy()
        self._flow: Flow | None = None
        self._initial_mass: float | None = None
        self._initial_measure: float | None = None   # |Omega_0|, taken with the mass
        self._at_rest = True       # phi_eq not yet set from a flow (``start_step``)

    # --- the law and the forms -------------------------------------------------------------
    def law_fields(self) -> Mapping[str, Any]:
        return {"packing": self.field.departure}

    def terms(self) -> tuple[DilatancySource]:
        return (DilatancySource(self),)

    def volumetric_rate(self, u: ngs.CoefficientFunction,
                        coords: Coordinates) -> ngs.CoefficientFunction:
        """div u = gamma_dot K (phi - phi_eq) at u, phi and phi_eq of the accepted state."""
        shear = self.laws[0].shear_rate(coords.strain_rate_sq(u), NGSOLVE_OPS)
        dilatancy = _blended(self.laws, self.fraction, lambda law: law.dilatancy)
        return shear * dilatancy * (self.field.departure - self.field.equilibrium)

    def start_step(self, dt: float) -> None:
        """At the first step: phi_eq = phi_c, the packing of material at rest (I = 0)."""
        if self._at_rest:
            self._at_rest = False
            initial = np.array([law.initial for law in self.laws])[self._main_material()]
            critical = np.array([law.critical for law in self.laws])[self._main_material()]
            self.field.equilibrium.vec.FV().NumPy()[:] = critical - initial

    def bind(self, flow: Flow) -> None:
        self._flow = flow
        self._velocity = flow.solution.components[0]   # one object: its form is kept

    # --- through a step ------------------------------------------------------------------
    def accept(self, dt: float) -> None:
        """Move and relax the packing over the step just solved (module docstring)."""
        assert self._flow is not None
        field, xy = self.field, self.field.mesh.ngmesh.Coordinates()
        self.initial_mass()                   # (at t = 0: before the first step changes it)
        u, p = self._velocity, self._flow.solution.components[1]
        field.advect(u, xy - self._xy, dt)
        main = self._main_material()
        square = self._flow.coordinates.strain_rate_sq(u)
        mesh = field.mesh
        shear = cell_means(mesh, self.laws[0].shear_rate(square, NGSOLVE_OPS))[0]
        values, lagged = field.values, field.equilibrium.vec.FV().NumPy()
        for k, law in enumerate(self.laws):
            cells = main == k
            if not cells.any():
                continue
            equilibrium = law.initial + lagged[cells]
            packing = law.relaxed(law.initial + values[cells], shear[cells], equilibrium, dt)
            values[cells] = packing - law.initial
            inertial = law.inertial_number(square, p, NGSOLVE_OPS)
            lagged[cells] = cell_means(mesh, law.equilibrium(inertial, NGSOLVE_OPS))[0][
                cells] - law.initial
        self._check()
        self._xy = xy.copy()

    def _main_material(self) -> np.ndarray:
        """Per triangle, the material holding most of it (0: the column, 1: the layer)."""
        if self.fraction is None or len(self.laws) == 1:
            return np.zeros(len(self.field.values), dtype=np.int64)
        return (self.fraction.vec.FV().NumPy() >= 0.5).astype(np.int64)

    def _check(self) -> None:
        packing = self.packing()
        bad = ~np.isfinite(packing) | (packing <= 0.0) | (packing > DENSEST)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            centre = self.field.mesh.ngmesh.Coordinates()[self.field.triangles[k]].mean(axis=0)
            raise PackingOutOfRange(
                f"the packing fraction left its physical range (0, {DENSEST:.4f}]: phi = "
                f"{packing[k]:.6g} in the triangle at ({centre[0]:.4g}, {centre[1]:.4g}) m "
                f"({int(bad.sum())} triangles); lower material.packing_dilatancy (K) or "
                "time.dt_max, or check the material's density / grain_density")

    # --- checkpoint, remesh --------------------------------------------------------------
    def share(self) -> Share:
        return self.share_of_checkpoint      # restore says if it is missing

    def save(self) -> dict[str, object]:
        return {"packing": self.field.values.copy(),
                "packing_equilibrium": self.field.equilibrium.vec.FV().NumPy().copy(),
                "packing_initial_mass": self.initial_mass(),
                "packing_initial_measure": self._initial_measure,
                "packing_vertices": self._xy.copy()}

    def restore(self, state: Mapping[str, object]) -> None:
        if "packing" not in state:
            raise ValueError("this checkpoint was written without a packing fraction; "
                             "run the case again from the start")
        assign(self.field.values, state["packing"], "the checkpoint's packing fraction")
        assign(self.field.equilibrium.vec.FV().NumPy(), state["packing_equilibrium"],
               "the checkpoint's packing of steady flow")
        self._at_rest = False
        self._initial_mass = float(state["packing_initial_mass"])   # type: ignore[arg-type]
        self._xy = self.field.mesh.ngmesh.Coordinates().copy()
        if "packing_vertices" in state:       # (a checkpoint written before it was kept)
            assign(self._xy, state["packing_vertices"], "the checkpoint's packing vertices")
        measure = state.get("packing_initial_measure")
        self._initial_measure = (None if measure is None
                                 else float(measure))   # type: ignore[arg-type]
        if self._initial_measure is None and len(self.laws) > 1:
            # written before it was kept: the excess it was written with (the measure at
            # the initial packing) taken for the state as it stands, the mass kept from it
            measures = self.field.cell_measures(self._xy)
            then = float(np.sum(self.field.values / self._initial_packing() * measures))
            self._initial_measure = 0.0
            self._initial_measure = then - self.volume_excess(self._xy)

    def inherit(self, old: Coupling, carry: Carriers) -> None:
        assert isinstance(old, PackingCoupling)
        carry.cells(old.field.departure, self.field.departure)
        carry.cells(old.field.equilibrium, self.field.equilibrium)
        self._at_rest = old._at_rest
        self._initial_mass = old.initial_mass()
        self._initial_measure = old._initial_measure
        self._xy = self.field.mesh.ngmesh.Coordinates().copy()

    # --- what the free-surface fix and the outputs read ------------------------------------
    def _initial_packing(self) -> Any:
        """phi_0 per triangle: the materials' blended by the share of layer material."""
        share = None if self.fraction is None else self.fraction.vec.FV().NumPy()
        return _blended(self.laws, share, lambda law: law.initial)

    def volume_excess(self, xy: np.ndarray) -> float:
        """What the free-surface fix adds to the measure |Omega| at the vertices ``xy`` to
        keep the mass (module docstring): with one material sum_K (phi_K - phi_0) / phi_0
        |K|; with two (M - M_0) / rho_0 + |Omega_0| - sum_K |K|, 0 before M_0 is taken."""
        measures = self.field.cell_measures(xy)
        if len(self.laws) == 1:
            return float(np.sum(self.field.values / self._initial_packing() * measures))
        if self._initial_mass is None or self._initial_measure is None:
            return 0.0                                 # the initial state, unchanged
        if not any(law.dilatancy for law in self.laws):
            return 0.0              # K = 0: the incompressible flow, its packing unchanged
        column = self.laws[0]
        reference = column.grain_density * column.initial
        mass = float(np.sum(self._densities() * measures))
        return ((mass - self._initial_mass) / reference
                + (self._initial_measure - float(np.sum(measures))))

    def packing(self) -> np.ndarray:
        """phi per triangle (its main material's phi_0 plus the departure)."""
        initial = np.array([law.initial for law in self.laws])[self._main_material()]
        return initial + self.field.values

    def mass(self, xy: np.ndarray | None = None) -> float:
        """The grains' mass, sum_K rho_s phi_K |K| (kg per metre in plane strain)."""
        xy = self.field.mesh.ngmesh.Coordinates() if xy is None else xy
        return float(np.sum(self._densities() * self.field.cell_measures(xy)))

    def _densities(self) -> Any:
        """rho_s phi per triangle, the materials' blended by the share of layer material."""
        share = None if self.fraction is None else self.fraction.vec.FV().NumPy()
        departure = self.field.values
        return _blended(self.laws, share,
                        lambda law: law.grain_density * (law.initial + departure))

    def initial_mass(self) -> float:
        """The mass at t = 0 (taken on the first mesh before the first step moves it, with
        the section's measure then)."""
        if self._initial_mass is None:
            self._initial_mass = self.mass(self._xy)
            self._initial_measure = float(np.sum(self.field.cell_measures(self._xy)))
        return self._initial_mass
