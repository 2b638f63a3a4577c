"""Plane strain or axisymmetry in the weak forms (the section's measures, names and units:
``geometry/section.py``, which ``Coordinates`` extends).

Plane strain, coordinates (x, z): the weak forms integrate over the section with dx and ds,
Du = (grad u + grad u^T) / 2 is 2 x 2 and div u = d_x u_x + d_z u_z (2.1).

Axisymmetric without swirl, coordinates (r, z) with r = x (the symmetry axis is x = 0):
a volume integral over the solid of revolution is 2 pi times the section's integral weighted
by r, so every weak form carries the weight r (the common factor 2 pi cancels); the strain
rate gains the hoop component u_r / r,

    Du = [[d_r u_r, (d_z u_r + d_r u_z) / 2, 0],
          [(d_z u_r + d_r u_z) / 2, d_z u_z, 0],
          [0, 0, u_r / r]],

which enters |Du| and Du : Dv (Frobenius, as in (2.13)), and div u = d_r u_r + u_r / r +
d_z u_z. On the axis u_r = 0 (imposed strongly on the velocity space, ``axis_region``);
quadrature points lie inside the triangles, never on r = 0, so u_r / r is always finite.
Convection (u . grad) u, gravity and the boundary terms keep their plane form, weighted.

Three dimensions, coordinates (x, y, z) with z normal to the bed: the plane expressions
carry over unchanged (dx over the body, Du 3 x 3 from the 3D gradient, div u the full
divergence); only the amounts (m^3, J) and the bed-normal coordinate (z, not y) differ.

The terms of (3.2) (``fem/forms.py``), the divergence-free transfer after a remesh
(``ale/transfer.py``) and the integrated diagnostics take their measure, strain rate and
divergence from a ``Coordinates``; in plane strain they are the plane expressions alone
(no term for the hoop part, not even a zero).
"""

from __future__ import annotations

import functools
import operator
from dataclasses import dataclass
from typing import Any

import ngsolve as ngs

from granflow.geometry.section import TWO_PI, Section


@dataclass(frozen=True)
class Coordinates(Section):
    """Plane strain (``axisymmetric=False``), axisymmetric r-z coordinates, or the three
    Cartesian coordinates of a 3D body (``dimension = 3``)."""

    @property
    def bed_normal(self) -> ngs.CoefficientFunction:
        """The coordinate normal to the bed: z in 3D, the section's second (y) in 2D."""
        return ngs.z if self.dimension == 3 else ngs.y

    def dx(self, integrand: ngs.CoefficientFunction, **kwargs: Any) -> ngs.SumOfIntegrals:
        """integrand dx over the section, times r in axisymmetry."""
        if self.axisymmetric:
            return (ngs.x * integrand) * ngs.dx(**kwargs)
        return integrand * ngs.dx(**kwargs)

    def ds(self, integrand: ngs.CoefficientFunction, **kwargs: Any) -> ngs.SumOfIntegrals:
        """integrand ds over boundary edges of the section, times r in axisymmetry."""
        if self.axisymmetric:
            return (ngs.x * integrand) * ngs.ds(**kwargs)
        return integrand * ngs.ds(**kwargs)

    def strain_rate(self, u: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
        """Du: 2 x 2 in plane strain, 3 x 3 with the hoop component u_r / r in axisymmetry."""
        if not self.axisymmetric:
            return ngs.Sym(ngs.Grad(u))
        g = ngs.Grad(u)
        shear = 0.5 * (g[0, 1] + g[1, 0])
        return ngs.CF((g[0, 0], shear, 0.0,
                       shear, g[1, 1], 0.0,
                       0.0, 0.0, self.hoop_strain(u)), dims=(3, 3))

    def strain_product_parts(self, u: ngs.CoefficientFunction,
                             v: ngs.CoefficientFunction) -> list[ngs.CoefficientFunction]:
        """Du : Dv as a sum of parts, to be integrated separately: the in-plane part, and in
        axisymmetry the hoop part u_r v_r / r^2. The same as ``InnerProduct(strain_rate(u),
        strain_rate(v))``, but NGSolve assembles the parts as two integrals in a quarter of
        the time of the 3 x 3 tensor form (benchmarks/axisymmetric_cost.py)."""
        plane = ngs.InnerProduct(ngs.Sym(ngs.Grad(u)), ngs.Sym(ngs.Grad(v)))
        if not self.axisymmetric:
            return [plane]
        return [plane, u[0] * v[0] / (ngs.x * ngs.x)]

    def hoop_strain(self, u: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
        """u_r / r, the hoop component of Du (axisymmetry only)."""
        return u[0] / ngs.x

    def strain_rate_sq(self, u: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
        """|Du|^2 (Frobenius), with the hoop part (u_r / r)^2 in axisymmetry."""
        return functools.reduce(operator.add, self.strain_product_parts(u, u))

    def div(self, u: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
        """div u, with + u_r / r in axisymmetry."""
        if not self.axisymmetric:
            return ngs.div(u)
        return ngs.div(u) + self.hoop_strain(u)

    def integrate(self, integrand: ngs.CoefficientFunction, mesh: ngs.Mesh,
                  order: int | None = None) -> float:
        """The integral over the body: per metre of width in plane strain (m^2 for 1), over
        the solid of revolution in axisymmetry (2 pi r weight; m^3 for 1), over the body in
        3D (m^3 for 1). ``order``: the
        quadrature order (NGSolve's default when None; one more for the weight r)."""
        if not self.axisymmetric:
            if order is None:
                return float(ngs.Integrate(integrand, mesh))
            return float(ngs.Integrate(integrand, mesh, order=order))
        weighted = ngs.x * integrand
        if order is None:
            return TWO_PI * float(ngs.Integrate(weighted, mesh))
        return TWO_PI * float(ngs.Integrate(weighted, mesh, order=order + 1))


PLANE = Coordinates(axisymmetric=False)
AXISYMMETRIC = Coordinates(axisymmetric=True)
SPACE = Coordinates(axisymmetric=False, dimension=3)


def coordinates_of(geometry: Any) -> Coordinates:
    """The coordinates of a run's ``[geometry]``: r-z for a cylinder
    (``geometry.axisymmetric``), else plane strain. The one place a problem reads that key."""
    return AXISYMMETRIC if geometry.axisymmetric else PLANE
