"""PETSc's fieldsplit solve of the linear systems of (3.2) (``numerics.linear_solver =
'fieldsplit'``), on one process or on the ranks of a distributed mesh.

The matrix goes to PETSc through ngspetsc (a MATIS of the ranks' local matrices on the free
degrees of freedom's global numbering, converted to AIJ; on one process the free rows and
columns as they are), the velocity and pressure rows as two index sets. The system is
scaled symmetrically by its diagonal (``fieldsplit_parts.scaling``: unscaled, the rigid
cells' rows, 1 / eps times the flowing ones', are all the residual's norm sees). Flexible
GMRes (FGMRes, unrestarted, modified Gram-Schmidt), judged on the scaled system's true
relative residual ``TOLERANCE``, preconditioned by the Schur complement factorisation
``full``: the velocity block by GMRes to ``VELOCITY_TOLERANCE`` preconditioned by
algebraic multigrid (GAMG) told the velocity's rigid-body modes, the Schur complement by
PETSc's least-squares commutator scaled by the velocity block's diagonal (LSC, its pressure
Poisson solve by one GAMG cycle). Every part is distributed. ``VARIANTS`` holds the others
benchmarks/three_d_fieldsplit.py measures (``selfp``, A11 - A10 diag(A00)^-1 A01 with one
GAMG cycle, dearer per solve than LSC, and Cahouet-Chabard among them); docs/three_d.md
gives the measurements and why this one.

Why not one GAMG cycle on the velocity inside left-preconditioned GMRes (``selfp-gamg``):
on the collapse's own systems a few steps in its preconditioned residual stagnated and the
steps failed, while the inner velocity solve inside FGMRes ran them. A solve that stops
short of its tolerance raises ``LinearSolveFailed``: the time loop rejects the step and
retries it smaller.

petsc4py and ngspetsc are optional installs, imported when a solve is built.
"""

from __future__ import annotations

from typing import Any

import ngsolve as ngs
import numpy as np

FIELDSPLIT = "fieldsplit"
TOLERANCE = 1e-10      # FGMRes' true relative residual (granflow's variant)
VELOCITY_TOLERANCE = 1e-4   # the inner velocity solve's relative residual
INNER_STEPS = 200      # its GMRes steps at most
BENCHMARK_TOLERANCE = 1e-8  # the left-preconditioned variants' preconditioned residual
MAX_STEPS = 400        # outer steps (unrestarted) before the solve counts as failed
PREFIX = "granflow_fieldsplit_"
# The Schur factorisation's parts by variant (benchmarks/three_d_fieldsplit.py measures
# them all): the Schur complement's approximation, the velocity's and the pressure's
# preconditioners, and (``inner``) the velocity's own Krylov solve inside flexible GMRes.
# granflow solves with "lsc-gamg-flexible" (module docstring).
VARIANTS = {
    "lsc-lu": {"schur": "self", "u": "lu", "p": "lsc"},
    "lsc-gamg": {"schur": "self", "u": "gamg", "p": "lsc"},
    "selfp-lu": {"schur": "selfp", "u": "lu", "p": "lu"},
    "selfp-gamg": {"schur": "selfp", "u": "gamg", "p": "gamg"},
    "mass-lu": {"schur": "user", "u": "lu", "p": "jacobi"},
    "selfp-gamg-flexible": {"schur": "selfp", "u": "gamg", "p": "gamg", "inner": "gmres"},
    "lsc-gamg-flexible": {"schur": "self", "u": "gamg", "p": "lsc", "inner": "gmres"},
    "cahouet-chabard": {"schur": "user", "u": "gamg", "p": "shell", "inner": "gmres"},
}
SOLVER_VARIANT = "lsc-gamg-flexible"


KRYLOV_KEYS = ("krylov_iterations", "krylov_solves", "krylov_largest")   # summary.json


def combined_work(*works: dict[str, int]) -> dict[str, int]:
    """Several solves' ``FieldsplitSolve.work`` as one: the steps and the solves summed,
    the most steps of one solve the largest; empty when none has any (direct solves)."""
    present = [w for w in works if w]
    if not present:
        return {}
    iterations, solves, largest = KRYLOV_KEYS
    return {iterations: sum(w[iterations] for w in present),
            solves: sum(w[solves] for w in present),
            largest: max(w[largest] for w in present)}


class LinearSolveFailed(RuntimeError):
    """GMRes stopped short of its tolerance: the step fails (and is retried smaller)."""


def petsc_missing() -> str | None:
    """Which of petsc4py and ngspetsc is not installed (None: both are). Found, not
    imported: importing petsc4py initialises PETSc, collectively over the MPI ranks,
    which rank 0 must not do alone while the others wait for its commands
    (``fem/distributed_flow.py``); the first solve imports it on every rank at once."""
    from importlib.util import find_spec

    for module, name in (("petsc4py", "petsc4py"), ("ngsPETSc", "ngspetsc")):
        if find_spec(module) is None:
            return name
    return None


def refusal() -> str | None:
    """The one line refusing ``numerics.linear_solver = 'fieldsplit'`` here, or None."""
    missing = petsc_missing()
    if missing is None:
        return None
    return (f"numerics.linear_solver = 'fieldsplit' needs petsc4py and ngspetsc ({missing} "
            "is not installed); install them (docs/three_d.md) or use 'auto'")


def configure(ksp: Any, variant: str, velocity: Any, pressure: Any, mass: Any = None,
              steps: int = MAX_STEPS, tolerance: float = TOLERANCE) -> None:
    """GMRes with the fieldsplit preconditioner of ``variant`` (``VARIANTS``) on ``ksp``,
    whose operator is set; ``velocity``, ``pressure``: the two fields' index sets;
    ``mass``: the Schur complement's preconditioner for the variant "mass-lu"."""
    from petsc4py import PETSc

    kind = VARIANTS[variant]
    inner = kind.get("inner")
    # flexible: the true residual; else left-preconditioned, the preconditioned residual
    ksp.setType("fgmres" if inner else "gmres")
    ksp.setGMRESRestart(steps)
    ksp.setTolerances(rtol=tolerance if inner else BENCHMARK_TOLERANCE, atol=0.0,
                      max_it=steps)
    pc = ksp.getPC()
    pc.setType("fieldsplit")
    pc.setFieldSplitIS(("u", velocity), ("p", pressure))
    pc.setFieldSplitType(PETSc.PC.CompositeType.SCHUR)
    pc.setFieldSplitSchurFactType(PETSc.PC.FieldSplitSchurFactType.FULL)
    pre = {"self": PETSc.PC.FieldSplitSchurPreType.SELF,
           "selfp": PETSc.PC.FieldSplitSchurPreType.SELFP,
           "user": PETSc.PC.FieldSplitSchurPreType.USER}[kind["schur"]]
    pc.setFieldSplitSchurPreType(pre, mass if kind["schur"] == "user" else None)
    p_pc = {"shell": "none"}.get(kind["p"], kind["p"])   # the shell is set after set-up
    options = PETSc.Options()
    prefix = ksp.getOptionsPrefix() or ""
    lsc = kind["p"] == "lsc"
    if inner:
        options[prefix + "ksp_orthogonalization"] = "mgs"
        options[prefix + "fieldsplit_u_ksp_rtol"] = VELOCITY_TOLERANCE
        options[prefix + "fieldsplit_u_ksp_max_it"] = INNER_STEPS
        options[prefix + "fieldsplit_u_ksp_gmres_restart"] = INNER_STEPS
    for name, value in {"fieldsplit_u_ksp_type": inner or "preonly",
                        "fieldsplit_u_pc_type": kind["u"],
                        "fieldsplit_p_ksp_type": "preonly", "fieldsplit_p_pc_type": p_pc,
                        **({"fieldsplit_p_lsc_ksp_type": "preonly",
                            "fieldsplit_p_lsc_pc_type": "gamg" if inner else "lu"}
                           if lsc else {})}.items():
        options[prefix + name] = value
    factors = [f"fieldsplit_{f}_" for f in ("u", "p") if kind[f] == "lu"]
    for factor in factors + (["fieldsplit_p_lsc_"] if lsc and not inner else []):
        # PETSc's zero-pivot test is relative to the row's sum: the contrast of 1 / eps in
        # the weighted pressure blocks trips it, and LU needs no pivoting on these blocks
        options[prefix + factor + "pc_factor_zeropivot"] = 0.0
    if lsc:
        options[prefix + "fieldsplit_p_pc_lsc_scale_diag"] = None
    ksp.setFromOptions()


def rigid_modes(mesh: ngs.Mesh) -> list[ngs.CoefficientFunction]:
    """The rigid-body motions of the mesh's dimension: its translations and rotations
    (3 + 3 in 3D, 2 + 1 in 2D), about the origin."""
    x, y, z = ngs.x, ngs.y, ngs.z
    if mesh.dim == 2:
        return [ngs.CF((1, 0)), ngs.CF((0, 1)), ngs.CF((-y, x))]
    return [ngs.CF((1, 0, 0)), ngs.CF((0, 1, 0)), ngs.CF((0, 0, 1)),
            ngs.CF((-y, x, 0)), ngs.CF((0, -z, y)), ngs.CF((z, 0, -x))]


class PetscSystem:
    """The free degrees of freedom of a Taylor-Hood space (``fem/spaces.py``) as PETSc
    sees them: the vector map, the velocity's and the pressure's index sets, and the
    velocity's rigid-body modes (GAMG's near-null space) on request."""

    def __init__(self, space: ngs.FESpace, freedofs: ngs.BitArray,
                 near_null_space: bool = True) -> None:
        from ngsPETSc import VectorMapping
        from petsc4py import PETSc

        self.space, self.freedofs = space, freedofs
        self.description = (space.ParallelDofs(), freedofs, {"bsize": [1]})
        self.mapping = VectorMapping(self.description)
        field = ngs.GridFunction(space).vec        # +1 on the velocity, -1 on the pressure
        field.FV().NumPy()[:] = np.where(np.arange(len(field)) < space.Range(0).stop, 1.0, -1.0)
        sign = self.mapping.petscVec(field)
        comm = sign.getComm()
        owned = sign.getOwnershipRange()[0] + np.arange(sign.getLocalSize(),
                                                        dtype=PETSc.IntType)
        self.velocity = PETSc.IS().createGeneral(owned[sign.getArray() > 0], comm=comm)
        self.pressure = PETSc.IS().createGeneral(owned[sign.getArray() < 0], comm=comm)
        self._modes: list[Any] | None = None
        if near_null_space:
            self.velocity.compose("nearnullspace", self.rigid_modes())

    def rigid_modes(self, d: Any = None) -> Any:
        """The rigid-body modes on the free velocity rows, orthonormal (GAMG's near-null
        space; PCFIELDSPLIT hands what is composed on the index set to its block); with
        ``d``, those of the system scaled by diag(d) (each mode divided by d)."""
        from petsc4py import PETSc

        if self._modes is None:
            state = ngs.GridFunction(self.space)
            self._modes = []
            for mode in rigid_modes(self.space.mesh):
                state.vec[:] = 0.0
                state.components[0].Set(mode)
                self._modes.append(self.mapping.petscVec(state.vec))
        basis = []
        for mode in self._modes:
            whole = mode.copy()
            if d is not None:
                whole.pointwiseDivide(whole, d)
            part = whole.getSubVector(self.velocity)
            vector = part.copy()
            whole.restoreSubVector(self.velocity, part)
            for other in basis:
                vector.axpy(-vector.dot(other), other)
            vector.normalize()
            basis.append(vector)
        return PETSc.NullSpace().create(vectors=basis, comm=basis[0].getComm())

    def matrix(self, matrix: ngs.BaseMatrix) -> Any:
        """``matrix``'s free rows and columns as a PETSc AIJ matrix."""
        from ngsPETSc import Matrix

        return Matrix(matrix, self.description).mat

    def vector(self, vec: ngs.BaseVector) -> Any:
        """``vec``'s free entries as a PETSc vector."""
        return self.mapping.petscVec(vec)

    def back(self, vector: Any, out: ngs.BaseVector) -> None:
        """``vector`` into ``out``'s free entries, 0 elsewhere, consistent on every rank."""
        self.mapping.ngsVec(vector, out)
        if self.description[0] is not None:
            out.SetParallelStatus(ngs.la.PARALLEL_STATUS.CUMULATED)


class FieldsplitSolve:
    """``ReusableLU``'s interface (``fem/linalg.py``) with PETSc's fieldsplit GMRes
    (module docstring): ``update`` hands the reassembled matrix to PETSc, ``solve`` solves
    and raises ``LinearSolveFailed`` when GMRes stops short. ``variant``: ``VARIANTS``'s
    name; ``scaled``: the system scaled by its diagonal (``fieldsplit_parts.scaling``);
    ``schur``: the Cahouet-Chabard forms (``fieldsplit_parts.schur_forms``), reassembled
    at each update, for the variant "cahouet-chabard". ``steps``, ``solves`` and
    ``largest`` count the GMRes steps, the solves and the most steps of one solve."""

    def __init__(self, form: ngs.BilinearForm, freedofs: ngs.BitArray,
                 near_null_space: bool = True, max_steps: int = MAX_STEPS,
                 variant: str = SOLVER_VARIANT, scaled: bool = True,
                 schur: tuple[ngs.BilinearForm, ngs.BilinearForm] | None = None,
                 tolerance: float = TOLERANCE) -> None:
        self._form, self._freedofs = form, freedofs
        self._max_steps = max_steps
        self._near_null_space = near_null_space
        self.variant, self.scaled, self.schur, self.tolerance = variant, scaled, schur, tolerance
        self._system: PetscSystem | None = None
        self._ksp: Any = None
        self._d: Any = None
        self._shell: Any = None
        self.factorisations = 0
        self.steps = 0
        self.solves = 0
        self.largest = 0

    def reset(self) -> None:
        """Forget the index sets and the solver (the space or its free dofs changed)."""
        if self._ksp is not None:
            self._ksp.destroy()
        self._ksp = self._system = self._shell = None

    def set_free_dofs(self, freedofs: ngs.BitArray) -> None:
        self._freedofs = freedofs
        self.reset()

    def update(self) -> None:
        """Hand the reassembled matrix to PETSc; the preconditioner is rebuilt from it."""
        from petsc4py import PETSc

        from granflow.fem.fieldsplit_parts import CahouetChabard, scaling

        if self._system is None:
            self._system = PetscSystem(self._form.space, self._freedofs,
                                       self._near_null_space and not self.scaled)
        system = self._system
        matrix = system.matrix(self._form.mat)
        if self.scaled:
            self._d = scaling(matrix, system.velocity, system.pressure)
            matrix.diagonalScale(L=self._d, R=self._d)
            if self._near_null_space:
                system.velocity.compose("nearnullspace", system.rigid_modes(self._d))
        if self._ksp is None:
            self._ksp = PETSc.KSP().create(comm=matrix.getComm())
            self._ksp.setOptionsPrefix(PREFIX + self.variant.replace("-", "_") + "_")
            self._ksp.setOperators(matrix)
            placeholder = (matrix.createSubMatrix(system.pressure, system.pressure)
                           if VARIANTS[self.variant]["p"] == "shell" else None)
            configure(self._ksp, self.variant, system.velocity, system.pressure,
                      placeholder, steps=self._max_steps, tolerance=self.tolerance)
        else:
            self._ksp.setOperators(matrix)
        if VARIANTS[self.variant]["p"] == "shell":
            assert self.schur is not None, "the Cahouet-Chabard variant needs its forms"
            mass, laplace = (self._pressure_matrix(form) for form in self.schur)
            if self._shell is None:
                self._shell = CahouetChabard()
                self._ksp.setUp()
                schur_pc = self._ksp.getPC().getFieldSplitSubKSP()[1].getPC()
                schur_pc.setType("python")
                schur_pc.setPythonContext(self._shell)
            self._shell.update(mass, laplace, self._pressure_scaling())
        self.factorisations += 1

    def _pressure_scaling(self) -> Any:
        """The pressure rows' part of the diagonal scaling (None unscaled)."""
        if self._d is None or self._system is None:
            return None
        part = self._d.getSubVector(self._system.pressure)
        pressure_d = part.copy()
        self._d.restoreSubVector(self._system.pressure, part)
        return pressure_d

    def _pressure_matrix(self, form: ngs.BilinearForm) -> Any:
        assert self._system is not None
        form.Assemble()
        whole = self._system.matrix(form.mat)
        return whole.createSubMatrix(self._system.pressure, self._system.pressure)

    def solve(self, rhs: ngs.BaseVector, out: ngs.BaseVector) -> None:
        assert self._system is not None and self._ksp is not None, "update() first"
        b = self._system.vector(rhs)
        if self._d is not None:
            b.pointwiseMult(b, self._d)
        x = b.duplicate()
        x.set(0.0)
        self._ksp.solve(b, x)
        steps, reason = self._ksp.getIterationNumber(), int(self._ksp.getConvergedReason())
        self.steps += steps
        self.solves += 1
        self.largest = max(self.largest, steps)
        if reason <= 0:
            raise LinearSolveFailed(
                f"the fieldsplit FGMRes stopped after {steps} steps short of its relative "
                f"residual {self.tolerance:g} (PETSc's reason {reason})")
        self._system.back(self.unscaled(x), out)

    def unscaled(self, x: Any) -> Any:
        """A solution of the (scaled) system PETSc solves as the unscaled unknowns."""
        if self._d is not None:
            x.pointwiseMult(x, self._d)
        return x

    def work(self) -> dict[str, int]:
        """The GMRes steps of every solve so far, the solves, the most steps of one
        (summary.json's ``KRYLOV_KEYS``)."""
        return dict(zip(KRYLOV_KEYS, (self.steps, self.solves, self.largest), strict=True))

    @property
    def ksp(self) -> Any:
        """PETSc's solver (set by ``update``)."""
        return self._ksp
