"""The constitutive laws a configuration asks for, built once for every scenario."""

from __future__ import annotations

from typing import Any

from granflow.config import Config
from granflow.config.kinds import erodible_layer
from granflow.config.schema import Material
from granflow.physics import DruckerPrager, MuI, Rheology, SideWallFriction
from granflow.physics.hysteresis import Hysteretic, Relaxation
from granflow.physics.nonlocal_fluidity import NonlocalFluidity


def build_rheology(config: Config, fluidity: Any = 0.0) -> Rheology:
    """``material.rheology``: the regularised Drucker-Prager law (2.13), mu(I) or the
    nonlocal fluidity law (reading the field ``fluidity``)."""
    return material_law(config.material, config.numerics.eps, fluidity)


def hysteretic(config: Config) -> bool:
    """Whether a material of the run has a hysteretic friction (and so a mobilisation
    state, ``physics/hysteresis.py``)."""
    layer = layer_material(config)
    return config.material.friction == "hysteretic" or (
        layer is not None and layer.friction == "hysteretic")


def relaxation(mat: Material) -> Relaxation:
    """The relaxation of a material's mobilisation (its hysteretic-friction keys)."""
    return Relaxation(mobilisation_time=mat.mobilisation_time, rest_time=mat.rest_time,
                      shear_rate=mat.mobilisation_shear_rate)


def friction_law(mat: Material, eps: float, mobilisation: Any = 0.0,
                 per_triangle: Any = None, fluidity: Any = 0.0) -> Rheology:
    """The law of one material with its friction: ``material_law``, or with a hysteretic
    friction that law as mu_flow beside Drucker-Prager at mu_start, blended with the
    mobilisation s (``mobilisation``: its field; ``per_triangle``: its cell values). A
    nonlocal law reads the fluidity field ``fluidity`` (it has no hysteretic friction:
    config/rules.py)."""
    flow = material_law(mat, eps, fluidity)
    if mat.friction != "hysteretic":
        return flow
    start = DruckerPrager(viscosity=mat.viscosity,
                          friction_angle_deg=mat.start_friction_angle_deg, eps=eps)
    return Hysteretic(flow=flow, start=start, relaxation=relaxation(mat),
                      mobilisation=mobilisation, per_triangle=per_triangle,
                      initial=mat.initial_mobilisation)


def material_law(mat: Material, eps: float, fluidity: Any = 0.0) -> Rheology:
    """The law of one material: (2.13), mu(I) or the nonlocal fluidity law, with its
    parameters."""
    if mat.rheology == "nonlocal":
        return nonlocal_law(mat, eps, fluidity)
    if mat.rheology == "mu-i":
        return MuI(viscosity=mat.viscosity, friction_angle_deg=mat.friction_angle_deg,
                   mu_2_deg=mat.mu_2_deg, i0=mat.i0, grain_diameter=mat.grain_diameter,
                   grain_density=mat.grain_density, eps=eps)
    return DruckerPrager(viscosity=mat.viscosity, friction_angle_deg=mat.friction_angle_deg,
                         eps=eps)


def nonlocal_law(mat: Material, eps: float, fluidity: Any = 0.0) -> NonlocalFluidity:
    """The nonlocal fluidity law of a material (``physics/nonlocal_fluidity.py``)."""
    return NonlocalFluidity(viscosity=mat.viscosity, friction_angle_deg=mat.friction_angle_deg,
                            b=mat.nonlocal_b, amplitude=mat.nonlocal_amplitude,
                            grain_diameter=mat.grain_diameter,
                            grain_density=mat.grain_density, eps=eps,
                            time=mat.fluidity_time, fluidity=fluidity,
                            friction_cap_deg=mat.mu_2_deg)


def nonlocal_materials(config: Config) -> tuple[Material, ...]:
    """The run's materials when they follow the nonlocal law ([material], and [layer]'s
    when it is a material of its own), else (): the rules allow both or neither."""
    if config.material.rheology != "nonlocal":
        return ()
    layer = layer_material(config)
    return (config.material,) if layer is None else (config.material, layer)


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
    if bnd.channel_width is None or config.geometry.kind != "column":
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
