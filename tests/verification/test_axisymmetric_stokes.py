"""Axisymmetric r-z Stokes flow against a manufactured solution: granflow's own terms
(``fem/forms.py`` with ``fem/measure.py``'s r-z coordinates) on Taylor-Hood P2/P1 must
converge at the element's orders, 3 for the velocity in L2, 2 in H1 and 2 for the pressure
in L2 (all norms weighted by r, the natural ones of the solid of revolution).

The solution, on the section (r, z) in [0, 1] x [0, 1] with the axis at r = 0: from the
Stokes stream function psi = r^2 sin(pi z), u_r = -(1/r) d_z psi = -pi r cos(pi z) and
u_z = (1/r) d_r psi = 2 sin(pi z), so div u = (1/r) d_r(r u_r) + d_z u_z = 0 and u_r = 0 on
the axis; p = cos(pi r) sin(pi z). With a constant viscosity eta, div(2 eta Du) = eta times
the vector Laplacian, whose r component is Delta u_r - u_r / r^2 = pi^3 r cos(pi z) and whose
z component is Delta u_z = -2 pi^2 sin(pi z); the body force is f = -eta Lap u + grad p.
"""

from __future__ import annotations

import math

import ngsolve as ngs
import numpy as np
import pytest
from netgen.geom2d import unit_square

from granflow.fem.forms import Incompressibility, ViscoplasticStress, fixed_point_forms
from granflow.fem.measure import AXISYMMETRIC, PLANE
from granflow.fem.spaces import taylor_hood
from granflow.physics import DruckerPrager

ETA = 1.0
PI = math.pi
R, Z = ngs.x, ngs.y
U_EXACT = ngs.CF((-PI * R * ngs.cos(PI * Z), 2.0 * ngs.sin(PI * Z)))
GRAD_U = ngs.CF((-PI * ngs.cos(PI * Z), PI * PI * R * ngs.sin(PI * Z),
                 0.0, 2.0 * PI * ngs.cos(PI * Z)), dims=(2, 2))
P_EXACT = ngs.cos(PI * R) * ngs.sin(PI * Z)
FORCE = ngs.CF((-ETA * PI**3 * R * ngs.cos(PI * Z) - PI * ngs.sin(PI * R) * ngs.sin(PI * Z),
                2.0 * ETA * PI**2 * ngs.sin(PI * Z) + PI * ngs.cos(PI * R) * ngs.cos(PI * Z)))
NEWTONIAN = DruckerPrager(viscosity=ETA, friction_angle_deg=0.0, eps=1.0)  # 2 eta Du


def solve(h: float) -> tuple[float, float, float]:
    """(velocity L2, velocity H1 seminorm, pressure L2) errors on a mesh of size h, r-weighted.

    The matrix is granflow's (the stress and incompressibility terms through
    ``fixed_point_forms``); u is prescribed on the bed and the outer wall, u_r = 0 on the
    axis, and the exact traction on the top, which also fixes the pressure's constant.
    """
    mesh = ngs.Mesh(unit_square.GenerateMesh(maxh=h, quad_dominated=False))
    # the unit square's boundaries: bottom, right, top, left (= the axis, r = 0)
    space = taylor_hood(mesh, dirichlet="bottom|right", axis="left")
    terms = [ViscoplasticStress(NEWTONIAN, AXISYMMETRIC), Incompressibility()]
    x = ngs.GridFunction(space)
    forms = fixed_point_forms(space, terms, x, AXISYMMETRIC)
    forms.iterate.Assemble()
    forms.constant.Assemble()
    v = space.TestFunction()[0]
    traction = ngs.CF((ETA * (GRAD_U[0, 1] + GRAD_U[1, 0]), 2.0 * ETA * GRAD_U[1, 1] - P_EXACT))
    f = ngs.LinearForm(space)
    f += AXISYMMETRIC.dx(FORCE * v)
    f += AXISYMMETRIC.ds(traction * v, definedon=mesh.Boundaries("top"))
    f.Assemble()
    matrix = forms.iterate.mat.CreateMatrix()
    matrix.AsVector().data = forms.iterate.mat.AsVector() + forms.constant.mat.AsVector()
    x.components[0].Set(U_EXACT, ngs.BND)
    res = f.vec.CreateVector()
    res.data = f.vec - matrix * x.vec
    x.vec.data += matrix.Inverse(space.FreeDofs(), inverse="umfpack") * res
    uh, ph = x.components
    e_u = uh - U_EXACT
    e_g = ngs.Grad(uh) - GRAD_U
    errors = [math.sqrt(AXISYMMETRIC.integrate(e, mesh, order=8))
              for e in (e_u * e_u, ngs.InnerProduct(e_g, e_g), (ph - P_EXACT) ** 2)]
    return errors[0], errors[1], errors[2]


def test_plane_strain_forms_are_the_plane_expressions() -> None:
    """Plane strain keeps Sym(Grad u) and div u: the r-z operators reduce to them only
    where they must (a guard against a weight leaking into plane runs)."""
    mesh = ngs.Mesh(unit_square.GenerateMesh(maxh=0.3))
    gf = ngs.GridFunction(ngs.VectorH1(mesh, order=2))
    gf.Set(ngs.CF((ngs.x * ngs.y, ngs.x - ngs.y)))
    plane = ngs.Integrate(ngs.InnerProduct(PLANE.strain_rate(gf), PLANE.strain_rate(gf)), mesh)
    direct = ngs.Integrate(ngs.InnerProduct(ngs.Sym(ngs.Grad(gf)), ngs.Sym(ngs.Grad(gf))),
                           mesh)
    assert plane == direct
    assert PLANE.integrate(ngs.CF(1.0), mesh) == ngs.Integrate(ngs.CF(1.0), mesh)


def test_taylor_hood_orders_in_r_z() -> None:
    """Measured: orders 3.03, 2.01, 2.34 between h = 1/16 and 1/32 (about 0.5 s in all)."""
    sizes = [0.25, 0.125, 0.0625, 0.03125]
    errors = np.array([solve(h) for h in sizes])
    orders = np.log2(errors[:-1] / errors[1:])
    velocity_l2, velocity_h1, pressure_l2 = orders[-1]
    assert velocity_l2 == pytest.approx(3.0, abs=0.3), orders
    assert velocity_h1 == pytest.approx(2.0, abs=0.3), orders
    assert pressure_l2 >= 1.8, orders
    assert errors[-1, 0] < 3e-5 and errors[-1, 2] < 1e-3, errors
