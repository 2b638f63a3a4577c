"""The constitutive laws a configuration asks for, built once for every scenario."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import ngsolve as ngs

from granflow.config import Config
from granflow.config.kinds import erodible_layer
from granflow.config.schema import Material
from granflow.fem.flow import FlowSolver
from granflow.fem.material_share import MaterialShare
from granflow.physics import Rheology, SideWallFriction
from granflow.physics.hysteresis import HYSTERETIC
from granflow.physics.laws import FRICTIONS, RHEOLOGIES, LawFields, bulk_density, packed
from granflow.physics.nonlocal_fluidity import NONLOCAL, NonlocalFluidity
from granflow.physics.regions import TwoMaterials, blend


def build_rheology(config: Config, fluidity: Any = 0.0) -> Rheology:
    """``material.rheology``: the regularised Drucker-Prager law (2.13), mu(I) or the
    nonlocal fluidity law (reading the field ``fluidity``)."""
    return material_law(config.material, config.numerics.eps, fluidity)


def friction_law(mat: Material, eps: float, mobilisation: Any = 0.0,
                 per_triangle: Any = None, fluidity: Any = 0.0, packing: Any = None) -> Rheology:
    """The law of one material with its friction and packing (``physics/laws.py``):
    ``material_law`` wrapped by its friction, which reads the mobilisation s
    (``mobilisation``: its field; ``per_triangle``: its cell values), and by its packing,
    which reads the packing fraction (``packing``)."""
    fields = LawFields(fluidity=fluidity, mobilisation=mobilisation, per_triangle=per_triangle,
                       packing=packing)
    return packed(mat, eps, fields, FRICTIONS[mat.friction].build(
        mat, eps, fields, material_law(mat, eps, fluidity)))


def material_law(mat: Material, eps: float, fluidity: Any = 0.0) -> Rheology:
    """The law of one material, as its rheology registered it (``physics/laws.py``); the
    nonlocal law through ``nonlocal_law``, the name a script replaces to change it."""
    if mat.rheology == NONLOCAL.name:
        return nonlocal_law(mat, eps, fluidity)
    return RHEOLOGIES[mat.rheology].build(mat, eps, LawFields(fluidity=fluidity))  # type: ignore[no-any-return]


def nonlocal_law(mat: Material, eps: float, fluidity: Any = 0.0) -> NonlocalFluidity:
    """The nonlocal fluidity law of a material (``physics/nonlocal_fluidity.py``)."""
    return NONLOCAL.build(mat, eps, LawFields(fluidity=fluidity))  # type: ignore[no-any-return]


@dataclass(frozen=True)
class RunMaterials:
    """The materials of a run, resolved once: [material], and an erodible layer's own
    (``layer_material``; None when the layer is the column's material, or there is none)."""

    column: Material
    layer: Material | None = None

    @property
    def all(self) -> tuple[Material, ...]:
        """[material], and [layer]'s when the layer is a material of its own."""
        return (self.column,) if self.layer is None else (self.column, self.layer)

    @property
    def of_layer(self) -> Material:
        """What the erodible layer is made of: its own material, else the column's."""
        return self.column if self.layer is None else self.layer

    @property
    def hysteretic(self) -> bool:
        """Whether a material of the run has a hysteretic friction (and so a mobilisation
        state, ``physics/hysteresis.py``)."""
        return any(mat.friction == HYSTERETIC.name for mat in self.all)

    @property
    def nonlocal_(self) -> tuple[Material, ...]:
        """The run's materials when they follow the nonlocal law, else (): the rules allow
        both or neither."""
        return self.all if self.column.rheology == NONLOCAL.name else ()

    def law(self, eps: float, fields: LawFields | None = None) -> tuple[Rheology, Any]:
        """The run's law and density. One material: [material]'s. A layer of its own: both
        blended with ``fields.share``, the piecewise constant share of layer material per
        triangle (``physics/regions.py``), which the walls read from the adjacent triangle
        (``fem/engine.py: read_on_walls``: a plain L2 function is 0 on a boundary element,
        which would give the Coulomb walls' load under the layer the column's law). A
        hysteretic friction reads the mobilisation (``fields.mobilisation``,
        ``fields.per_triangle``), a nonlocal law the fluidity, a packing law the packing
        fraction, which also sets the density (``friction_law``, ``bulk_density``)."""
        f = fields if fields is not None else LawFields()
        column = friction_law(self.column, eps, f.mobilisation, f.per_triangle, f.fluidity,
                              f.packing)
        if self.layer is None or f.share is None:
            return column, bulk_density(self.column, f)
        layer = friction_law(self.layer, eps, f.mobilisation, f.per_triangle, f.fluidity,
                             f.packing)
        return (TwoMaterials(column, layer, f.share, f.share),
                blend(bulk_density(self.column, f), bulk_density(self.layer, f), f.share))


@dataclass(frozen=True)
class MaterialLaw:
    """The run's law and density from the fields its couplings hand them, on every mesh
    (``fem/flow_factory.py``)."""

    materials: RunMaterials
    eps: float

    def __call__(self, fields: LawFields) -> tuple[Rheology, Any]:
        return self.materials.law(self.eps, fields)


def run_materials(config: Config) -> RunMaterials:
    """The run's materials (``RunMaterials``)."""
    return RunMaterials(config.material, layer_material(config))


def layer_material(config: Config) -> Material | None:
    """The erodible layer's material: [material] with the keys [layer] sets over it, or
    None when the layer is the column's material (one material: the law and density of
    [material] everywhere, exactly as without the [layer] section)."""
    if not erodible_layer(config):
        return None
    own = {k: v for k, v in config.layer.model_dump().items() if v is not None}
    layer = config.material.model_copy(update=own)
    return None if layer == config.material else layer


def build_side_walls(config: Config) -> SideWallFriction | None:
    """The channel's side walls (``boundary.channel_width``), or None without them."""
    bnd = config.boundary
    if bnd.channel_width is None:      # (a periodic layer has none: the key is inert there)
        return None
    return SideWallFriction(bnd.channel_width, bnd.side_wall_friction_deg,
                            config.numerics.eps_friction)


def augmentation(config: Config) -> float | None:
    """r of the augmented Lagrangian method (``numerics.al_r``), or None for the regularised
    law: the starting value, which the iteration then balances (fem/augmented_lagrangian.py).
    auto = 20 x viscosity: of r a decade apart, the one with which the plug flow's first
    step converges in the fewest iterations (benchmarks/augmented_lagrangian.py, its choice
    of r)."""
    num = config.numerics
    if num.method != "augmented-lagrangian":
        return None
    return 20.0 * config.material.viscosity if num.al_r == "auto" else float(num.al_r)


def share_of(solver: FlowSolver) -> ngs.GridFunction | None:
    """A solver's share of layer material per triangle, None with one material."""
    share = solver.coupling(MaterialShare)
    return share.fraction if share is not None else None
