"""PETSc's fieldsplit solve of the linear systems of (3.2) (``numerics.linear_solver =
'fieldsplit'``), on one process or on the ranks of a distributed mesh.

The matrix goes to PETSc through ngspetsc (a MATIS of the ranks' local matrices on the free
degrees of freedom's global numbering, converted to AIJ; on one process the free rows and
columns as they are), the velocity and pressure rows as two index sets. Flexible GMRes
(FGMRes, unrestarted, modified Gram-Schmidt), judged on the true relative residual
``TOLERANCE``, preconditioned by the Schur complement factorisation ``full``: the velocity
block by GMRes to ``VELOCITY_TOLERANCE`` preconditioned by algebraic multigrid (GAMG) told
the velocity's rigid-body modes, the Schur complement by A11 - A10 diag(A00)^-1 A01
(``selfp``) with one GAMG cycle. Every part is distributed.

Why not one GAMG cycle on the velocity inside left-preconditioned GMRes, the variant
``selfp-gamg`` that benchmarks/three_d_fieldsplit.py measured on the column's first
systems: on the collapse's own systems a few steps in its preconditioned residual
stagnated and the steps failed, while this variant ran them (docs/three_d.md, which also
says where this one is still short of the direct solve). A solve that stops short of its
tolerance raises ``LinearSolveFailed``: the time loop rejects the step and retries it
smaller.

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
# granflow solves with "selfp-gamg-flexible" (module docstring).
VARIANTS = {
    "lsc-lu": {"schur": "self", "u": "lu", "p": "lsc"},
    "lsc-gamg": {"schur": "self", "u": "gamg", "p": "lsc"},
    "selfp-lu": {"schur": "selfp", "u": "lu", "p": "lu"},
    "selfp-gamg": {"schur": "selfp", "u": "gamg", "p": "gamg"},
    "mass-lu": {"schur": "user", "u": "lu", "p": "jacobi"},
    "selfp-gamg-flexible": {"schur": "selfp", "u": "gamg", "p": "gamg", "inner": "gmres"},
}
SOLVER_VARIANT = "selfp-gamg-flexible"


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
              steps: int = MAX_STEPS) -> None:
    """GMRes with the fieldsplit preconditioner of ``variant`` (``VARIANTS``) on ``ksp``,
    whose operator is set; ``velocity``, ``pressure``: the two fields' index sets;
    ``mass``: the Schur complement's preconditioner for the variant "mass-lu"."""
    from petsc4py import PETSc

    kind = VARIANTS[variant]
    inner = kind.get("inner")
    # flexible: the true residual; else left-preconditioned, the preconditioned residual
    ksp.setType("fgmres" if inner else "gmres")
    ksp.setGMRESRestart(steps)
    ksp.setTolerances(rtol=TOLERANCE if inner else BENCHMARK_TOLERANCE, atol=0.0,
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
                        "fieldsplit_p_ksp_type": "preonly", "fieldsplit_p_pc_type": kind["p"],
                        **({"fieldsplit_p_lsc_ksp_type": "preonly",
                            "fieldsplit_p_lsc_pc_type": "lu"} if lsc else {})}.items():
        options[prefix + name] = value
    factors = [f"fieldsplit_{f}_" for f in ("u", "p") if kind[f] == "lu"]
    for factor in factors + (["fieldsplit_p_lsc_"] if lsc else []):
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
        if near_null_space:
            self.velocity.compose("nearnullspace", self._rigid_modes())

    def _rigid_modes(self) -> Any:
        """The rigid-body modes on the free velocity rows, orthonormal (GAMG's near-null
        space; PCFIELDSPLIT hands what is composed on the index set to its block)."""
        from petsc4py import PETSc

        state = ngs.GridFunction(self.space)
        basis = []
        for mode in rigid_modes(self.space.mesh):
            state.vec[:] = 0.0
            state.components[0].Set(mode)
            whole = self.mapping.petscVec(state.vec)
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
    and raises ``LinearSolveFailed`` when GMRes stops short. ``steps`` counts GMRes steps."""

    def __init__(self, form: ngs.BilinearForm, freedofs: ngs.BitArray,
                 near_null_space: bool = True, max_steps: int = MAX_STEPS) -> None:
        self._form, self._freedofs = form, freedofs
        self._max_steps = max_steps
        self._near_null_space = near_null_space
        self._system: PetscSystem | None = None
        self._ksp: Any = None
        self.factorisations = 0
        self.steps = 0
        self.solves = 0

    def reset(self) -> None:
        """Forget the index sets and the solver (the space or its free dofs changed)."""
        if self._ksp is not None:
            self._ksp.destroy()
        self._ksp = self._system = None

    def set_free_dofs(self, freedofs: ngs.BitArray) -> None:
        self._freedofs = freedofs
        self.reset()

    def update(self) -> None:
        """Hand the reassembled matrix to PETSc; the preconditioner is rebuilt from it."""
        from petsc4py import PETSc

        if self._system is None:
            self._system = PetscSystem(self._form.space, self._freedofs,
                                       self._near_null_space)
        matrix = self._system.matrix(self._form.mat)
        if self._ksp is None:
            self._ksp = PETSc.KSP().create(comm=matrix.getComm())
            self._ksp.setOptionsPrefix(PREFIX)
            self._ksp.setOperators(matrix)
            configure(self._ksp, SOLVER_VARIANT, self._system.velocity,
                      self._system.pressure, steps=self._max_steps)
        else:
            self._ksp.setOperators(matrix)
        self.factorisations += 1

    def solve(self, rhs: ngs.BaseVector, out: ngs.BaseVector) -> None:
        assert self._system is not None and self._ksp is not None, "update() first"
        b = self._system.vector(rhs)
        x = b.duplicate()
        x.set(0.0)
        self._ksp.solve(b, x)
        steps, reason = self._ksp.getIterationNumber(), int(self._ksp.getConvergedReason())
        self.steps += steps
        self.solves += 1
        if reason <= 0:
            raise LinearSolveFailed(
                f"the fieldsplit FGMRes stopped after {steps} steps short of its relative "
                f"residual {TOLERANCE:g} (PETSc's reason {reason})")
        self._system.back(x, out)
