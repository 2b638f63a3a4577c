"""The configuration's schema: frozen, strictly typed section models with their ranges.

Each field's type and bounds are the single statement of what a key accepts: the loader
validates with them and the messages and the parameters page read them back. The keys a law
alone reads, and the names ``material.rheology``, ``material.friction`` and
``material.packing`` accept, are the
laws' registrations (``physics/laws.py``): ``law_sections`` makes ``[material]`` and
``[layer]`` from them, again when a law registers later (the loader asks first).
"""

from __future__ import annotations

import math
from types import NoneType
from typing import Annotated, Any, Literal, NamedTuple, get_args, get_origin

from pydantic import AfterValidator, BaseModel, ConfigDict, Field, create_model, model_validator
from pydantic_core import PydanticCustomError

import granflow.physics  # noqa: F401  (the built-in laws register)
from granflow.config.kinds import KIND_RULES, kind_names
from granflow.physics import laws


class ConfigError(ValueError):
    """Invalid configuration; the message is one line naming the key, value and allowed range."""


class ConfigNote(UserWarning):
    """A valid configuration that does something the user may not expect (a warning; the
    command line prints it as one ``granflow: note:`` line)."""


# Ranges a physical run can use (SI): wide enough for laboratory to field scales, narrow
# enough that no value overflows, underflows or makes Netgen mesh for hours.
Positive = Annotated[float, Field(gt=0)]
NonNegative = Annotated[float, Field(ge=0)]
Angle = Annotated[float, Field(ge=0, lt=90)]
Fraction = Annotated[float, Field(gt=0, lt=1)]
Length = Annotated[float, Field(gt=0, le=1e4)]           # m
Duration = Annotated[float, Field(gt=0, le=1e4)]         # s
Step = Annotated[float, Field(ge=1e-12, le=100)]         # s, a time step
Penalty = Annotated[float, Field(ge=1, le=1e20)]
Count = Annotated[int, Field(ge=0, le=10**9)]
ShearRate = Annotated[float, Field(gt=0, le=1e6)]        # 1/s
Coordinate = Annotated[float, Field(ge=-1e5, le=1e5)]    # m
Point = Annotated[list[Coordinate], Field(min_length=2, max_length=2)]   # [x, z]
Points = Annotated[list[Point], Field(min_length=1, max_length=100_000)]
FilePath = Annotated[str, Field(min_length=1, max_length=4096)]


class Floor(NamedTuple):
    """The smallest value of a key whose natural bound is 0, and why (a subnormal value
    passed validation and failed mid-run); docs/parameters.md shows the reason."""

    value: float
    why: str


FLOORS = {
    "material.gravity": Floor(1e-4, "the surface gravity of a 300 m asteroid"),
    "material.grain_diameter": Floor(1e-9, "a nanometre: no grain is smaller than a "
                                           "molecule"),
    "gate.speed": Floor(1e-4, "a tenth of the speed below which a cell counts as at rest "
                              "(1 mm/s)"),
    "boundary.channel_width": Floor(1e-3, "a millimetre: a channel a few grains wide"),
    "numerics.eps": Floor(1e-12, "a strain rate that shears by 1e-8 in the longest run "
                                 "allowed (1e4 s)"),
    "numerics.eps_friction": Floor(1e-12, "a slip of 10 nm in the longest run allowed "
                                          "(1e4 s)"),
    "numerics.tol_init": Floor(1e-14, "round-off, as numerics.tol"),
    "time.t_end": Floor(1e-6, "a microsecond: one first step"),
    "time.error_tol": Floor(1e-6, "the nonlinear solve's own tolerance bounds what a step's "
                                  "error can be told from"),
    "time.error_floor": Floor(1e-6, "a thousandth of the speed below which a cell counts as "
                                    "at rest (1 mm/s)"),
    "surface_tension.delta": Floor(1.0, "one surface node: any smaller extent acts on the "
                                        "critical node alone, as 1 does"),
    "gate.tau": Floor(1e-3, "a millisecond: the gate is at full speed within the first steps "
                            "of a collapse (glass beads: 0.13 s)"),
    "numerics.al_r": Floor(1e-3, "the smallest r the augmented Lagrangian balances it to "
                                 "(Pa s)"),
}
FLOORS["layer.grain_diameter"] = FLOORS["material.grain_diameter"]


def floor(key: str) -> float:
    return FLOORS[key].value


class _Section(BaseModel):
    """Base of every model: frozen, strict types (no str -> float coercion), no extra keys."""

    model_config = ConfigDict(frozen=True, extra="forbid", strict=True, allow_inf_nan=False)

    @model_validator(mode="before")
    @classmethod
    def _unset_none(cls, data: Any) -> Any:
        # TOML has no null: the string "none" unsets an optional field. An integer written
        # as a float (1e3, 100.0) is that integer.
        if not isinstance(data, dict):
            return data
        return {
            k: None if _is_none(v) and k in cls.model_fields and _optional(cls, k)
            else int(v) if _integral(v) and k in cls.model_fields and _int_field(cls, k)
            else v
            for k, v in data.items()
        }


def _is_none(value: Any) -> bool:
    return isinstance(value, str) and value.lower() == "none"


def _optional(model: type[BaseModel], key: str) -> bool:
    return NoneType in get_args(model.model_fields[key].annotation)


def _integral(value: Any) -> bool:
    return (isinstance(value, float) and math.isfinite(value) and value.is_integer()
            and abs(value) < 2**63)


def _int_field(model: type[BaseModel], key: str) -> bool:
    tp = model.model_fields[key].annotation
    return tp is int or int in get_args(tp) or any(
        get_origin(a) is Annotated and get_args(a)[0] is int for a in get_args(tp))


PresetName = Literal["glass-beads"]     # physics/presets.py: PRESETS


class MaterialKeys(_Section):
    """The keys of every material; ``Material`` adds the registered laws' own keys."""

    preset: PresetName | None  # every constant of a named material, for the law it runs with
    density: Annotated[float, Field(ge=1, le=1e5)]  # rho (kg/m^3)
    viscosity: Annotated[float, Field(ge=1e-9, le=1e6)]  # dynamic viscosity eta (Pa s)
    friction_angle_deg: Angle  # delta, mu_s = tan(delta); 0 = the purely viscous limit
    rheology: str  # a registered law's name
    gravity: Annotated[float, Field(ge=floor("material.gravity"), le=100)]  # g (m/s^2)
    grain_diameter: Annotated[float, Field(ge=floor("material.grain_diameter"),
                                           le=10)]  # d (m)
    grain_density: Annotated[float, Field(ge=1, le=1e5)]  # rho_s (kg/m^3)
    friction: str  # a registered friction's name
    packing: str  # a registered packing's name

    @property
    def mu_s(self) -> float:
        """Internal friction coefficient tan(delta); kappa = sqrt(2) mu_s [p]_+ (2.13)."""
        return math.tan(math.radians(self.friction_angle_deg))

    @property
    def kinematic_viscosity(self) -> float:
        """nu = eta / rho (m^2/s)."""
        return self.viscosity / self.density


class LayerKeys(_Section):
    """The erodible layer's own material; every key left "none" is [material]'s (one
    material everywhere, today's runs). Gravity is [material]'s. ``Layer`` adds the
    registered laws' own keys."""

    preset: PresetName | None  # the layer's constants from a named material
    density: Annotated[float, Field(ge=1, le=1e5)] | None  # rho of the layer (packing)
    viscosity: Annotated[float, Field(ge=1e-9, le=1e6)] | None  # eta (Pa s)
    friction_angle_deg: Angle | None  # delta of the layer, mu_s = tan(delta)
    rheology: str | None
    grain_diameter: Annotated[float, Field(ge=floor("layer.grain_diameter"),
                                           le=10)] | None  # m
    grain_density: Annotated[float, Field(ge=1, le=1e5)] | None  # kg/m^3
    friction: str | None
    packing: str | None


def _key_type(key: laws.Key) -> Any:
    """A law key's annotation: a number in its range, or one of its words."""
    number = Annotated[float, Field(ge=key.low, le=key.high, gt=key.above, lt=key.below)]
    return Literal[key.choices] | number if key.choices else number   # type: ignore[valid-type]


def _names(table: dict[str, laws.Law]) -> Any:
    return Literal[tuple(table)]   # type: ignore[valid-type]


def _material_model() -> type[MaterialKeys]:
    own = {k: (_key_type(spec), spec.default) for k, spec in laws.law_keys().items()}
    return create_model("Material", __base__=MaterialKeys,   # type: ignore[no-any-return]
                        rheology=(_names(laws.RHEOLOGIES), ...),
                        friction=(_names(laws.FRICTIONS), ...),
                        packing=(_names(laws.PACKINGS), ...), **own)


def _layer_model() -> type[LayerKeys]:
    own = {k: (_key_type(spec) | None, None) for k, spec in laws.law_keys().items()}
    return create_model("Layer", __base__=LayerKeys,   # type: ignore[no-any-return]
                        rheology=(_names(laws.RHEOLOGIES) | None, ...),
                        friction=(_names(laws.FRICTIONS) | None, ...),
                        packing=(_names(laws.PACKINGS) | None, ...), **own)


def _law_floors() -> None:
    for k, spec in laws.law_keys().items():
        if spec.floor and spec.low is not None:
            FLOORS[f"material.{k}"] = FLOORS[f"layer.{k}"] = Floor(spec.low, spec.floor)


_law_floors()
Material = _material_model()
Layer = _layer_model()


class RegisteredKind:
    """A field's mark: its value is the name of a registered problem kind
    (``config/kinds.py``), checked when the configuration is validated."""

    def __call__(self, value: str) -> str:
        if value not in KIND_RULES:
            raise PydanticCustomError("granflow_config", "{message}", {
                "message": f"geometry.kind = {value!r}: must be {self.allowed()}"})
        return value

    @staticmethod
    def allowed() -> str:
        return "one of " + ", ".join(map(repr, kind_names()))


class Geometry(_Section):
    kind: Annotated[str, RegisteredKind(), AfterValidator(RegisteredKind())]
    slope_deg: Angle  # bed inclination theta
    length: Length  # periodic layer: length l
    height: Length  # layer height h, or column height h0
    shape: Literal["trapezoid", "rectangle"]  # column
    width: Length  # column BASE width l0 (the paper's l0; top width = l0 - h0 / tan(alpha0))
    front_angle_deg: Annotated[float, Field(gt=0, le=90)]  # column front angle alpha0
    erodible_thickness: Annotated[float, Field(ge=0, le=1e4)]  # column: he, 0 = rigid bed
    bed_length: Length  # column on an erodible layer: where the layer ends
    axisymmetric: bool  # column: a cylinder in r-z (width = its radius r0; x = 0 is the axis)
    bed_profile: Points | None  # column: the rigid bed z_b(x) as [x, z] points; None = z = 0
    bed_profile_file: FilePath | None  # column: the same from a CSV or GeoJSON file
    mass: Points | None  # column: the initial mass as a closed polygon; None = shape
    mass_file: FilePath | None  # column: the same from a CSV or GeoJSON file
    left_wall: bool  # column: a wall at the profile's first point, normal to its first segment
    dimension: Literal[2, 3]  # 2: a section (plane strain, r-z); 3: a 3D body (docs/three_d.md)
    half_channel: bool  # 3D column: half the channel meshed, the centre plane a symmetry plane


class Gate(_Section):
    """A gate on the mass's front face, withdrawn along itself (``geometry/gate.py``)."""

    enabled: bool
    speed_law: Literal["constant", "exponential"]  # U, or U (1 - exp(-t / tau))
    speed: Annotated[float, Field(ge=floor("gate.speed"), le=50)]  # U or U_inf (m/s)
    tau: Annotated[float, Field(ge=floor("gate.tau"), le=100)]  # s, of the exponential law
    friction_deg: Angle  # Coulomb friction of the gate, mu_g = tan(angle)


class Boundary(_Section):
    bed: Literal["coulomb", "no-slip", "material"]  # the rigid bed's law (physics/bed.py)
    bed_friction_deg: Angle  # Coulomb mu_b = tan(angle)
    wall_friction_deg: Angle  # Coulomb mu_l = tan(angle)
    penalty: Penalty  # enforces u.n = 0 on the bed and the wall
    normal_load: Literal["pressure", "reaction"]  # friction load: [p - sigma'_N]_+ or [xi u.N]_+
    non_penetration: Literal["penalty", "strong"]  # u.N = 0: the penalty (2.7), or held (3D)
    channel_width: Annotated[float, Field(ge=floor("boundary.channel_width"),
                                          le=1e4)] | None  # side walls W; None = none
    side_wall_friction_deg: Angle  # Coulomb mu_w = tan(angle) of the side walls
    bed_fluidity: Literal["zero-flux", "zero"]  # nonlocal law: g's condition on a Coulomb bed

    @property
    def mu_bed(self) -> float:
        return math.tan(math.radians(self.bed_friction_deg))

    @property
    def mu_wall(self) -> float:
        return math.tan(math.radians(self.wall_friction_deg))


class Initial(_Section):
    shear_rate: Annotated[float, Field(ge=0, le=1e4)]  # plug flow: U0 = rate [Z - plug_base]_+
    plug_base: Annotated[float, Field(ge=0, le=1e4)]
    fluidity: Annotated[float, Field(ge=0, le=10)]  # periodic nonlocal layer: g / g_local
    slab_speed: Annotated[float, Field(ge=0, le=100)]  # slab: its speed along the bed (m/s)


class Mesh(_Section):
    size: Annotated[float, Field(gt=0, le=1e3)]  # target edge length (m)
    cells_x: Annotated[int, Field(ge=2, le=10**5)] | None  # periodic layer; None = length/size
    # column: cells across its smaller side (sets size = min(width, height) / cells_across)
    cells_across: Annotated[int, Field(ge=1, le=1000)] | None
    remesh_quality: Annotated[float, Field(ge=0, lt=1)]  # column: also remesh below; 0 = off
    failure_remesh_quality: Annotated[float, Field(ge=0, lt=1)]  # remesh a failed solve below
    layer_cells: Annotated[int, Field(ge=1, le=16)]  # cells across an erodible layer
    layer_aspect: Annotated[float, Field(ge=1, le=32)]  # their length along it / across it
    layer_ahead: Annotated[float, Field(ge=0, le=1e3)]  # meshed layer ahead of the flow (m)
    adaptive: bool  # column: sizes from the flow (fine where it moves); false: uniform
    rest_coarsening: Annotated[float, Field(ge=1, le=16)]  # bulk at rest: mesh.size x this
    layer_rest_coarsening: Annotated[float, Field(ge=1, le=64)]  # layer at rest: its cells x
    flow_margin: Annotated[float, Field(ge=0.5, le=100)]  # x mesh.size around moving material


class Numerics(_Section):
    eps: Annotated[float, Field(ge=floor("numerics.eps"), le=1e3)]  # of (2.13) (1/s)
    eps_friction: Annotated[float, Field(ge=floor("numerics.eps_friction"),
                                         le=1e3)]  # of the Coulomb friction (m/s)
    tol: Annotated[float, Field(ge=1e-14, lt=1)]  # stopping tolerance of (3.2); >= round-off
    tol_init: Annotated[float, Field(ge=floor("numerics.tol_init"), lt=1)] | None  # ramp
    # start tolerance; None = tol
    max_iterations: Annotated[int, Field(ge=1, le=10**5)]
    linearization: Literal["picard", "newton", "hybrid", "primal-dual"]
    mesh_velocity: Literal["fixed", "vertical", "elastic", "lagrange"]
    mesh_penalty: Penalty
    velocity_floor: Annotated[float, Field(ge=0, le=1e3)]  # m/s, floor of ||u|| in (3.2)
    volume_correction: bool  # restore the initial area after each ALE move (column only)
    ale_extrapolation: bool  # mesh velocity of the extrapolated mid-step velocity (2nd order)
    linear_solver: Literal["auto", "umfpack", "pardiso",
                           "fieldsplit"]  # auto: PARDISO when MKL is there; fieldsplit: 3D
    initial_guess: Literal["previous", "extrapolated", "auto"]  # first iterate of (3.2)
    anderson_depth: Annotated[int, Field(ge=0, le=10)]  # Anderson mixing of (3.2); 0 = off
    method: Literal["regularized", "augmented-lagrangian"]  # (2.13) with eps, or ALG2
    al_r: Literal["auto"] | Annotated[float, Field(ge=floor("numerics.al_r"),
                                                   le=1e12)]  # augmentation r (Pa s)
    fluidity_coupling: Literal["lagged", "iterated"]  # nonlocal: g per step or per iterate

    @property
    def tol_start(self) -> float:
        """The tolerance the ramp of section 3.1 starts from: ``tol_init``, or ``tol`` when
        it is unset (the ramp then holds ``tol`` throughout)."""
        return self.tol if self.tol_init is None else self.tol_init


class Time(_Section):
    t_end: Annotated[float, Field(ge=floor("time.t_end"), le=1e4)]  # s
    dt: Step | None  # fixed step; overrides the ramp
    dt_init: Step
    dt_max: Step
    dt_growth: Annotated[float, Field(ge=1, le=10)]
    adaptive: bool  # error-controlled steps; false keeps the paper's ramp (section 3.1)
    scheme: Literal["implicit-euler", "bdf2"]  # time scheme of (3.2a): order 1 or 2
    error_tol: Annotated[float, Field(ge=floor("time.error_tol"), lt=1)]  # adaptive:
    # local velocity error per step / RMS speed
    error_floor: Annotated[float, Field(ge=floor("time.error_floor"), le=1e3)]  # adaptive:
    # m/s, RMS speed floor
    dt_max_slow: Step | None  # adaptive: the largest step while the flow is slow
    slow_courant: Annotated[float, Field(ge=0, le=100)]  # slow: a step carries the flow's
    # RMS speed at most this many mesh.size
    stop_at_rest: bool  # end the run once the mass has come to rest
    rest_fraction: Annotated[float, Field(ge=0, lt=1)]  # flowing area at rest, at most
    rest_duration: Annotated[float, Field(ge=0, le=1e4)]  # s at rest before the run ends
    output_times: Annotated[list[float], Field(max_length=10_000)]


class SurfaceTension(_Section):
    enabled: bool
    delta: Annotated[float, Field(ge=floor("surface_tension.delta"), le=1e4)]  # (3.11):
    # extent in surface nodes
    gamma0: Literal["auto"] | Annotated[float, Field(ge=0, le=1e9)]  # gamma0-bar of (3.11)
    trigger_angle_deg: Annotated[float, Field(ge=0, le=180)]  # on where the surface turns >=
    release_angle_deg: Annotated[float, Field(ge=0, le=180)]  # stays on while it turns >=
    length: Literal["mesh_size", "local_edge"]  # what gamma0-bar scales with


class Output(_Section):
    vtk_every: Count  # 0 = only at output_times
    checkpoint_every: Count  # 0 = only at the end and when interrupted or failed
    progress: bool
    figure_format: Literal["png", "pdf", "svg"]  # plots/*.png, .pdf or .svg
    dpi: Annotated[int, Field(ge=50, le=1200)]  # raster resolution (dots per inch)


class ConfigModel(_Section):
    """The sections of one run's configuration (``Config`` adds loading and the
    cross-field rules)."""

    scenario: str
    material: Material
    layer: Layer
    geometry: Geometry
    gate: Gate
    boundary: Boundary
    initial: Initial
    mesh: Mesh
    numerics: Numerics
    time: Time
    surface_tension: SurfaceTension
    output: Output


FIGURE_FORMATS: tuple[str, ...] = get_args(Output.model_fields["figure_format"].annotation)

SECTIONS: dict[str, type[_Section]] = {
    name: field.annotation
    for name, field in ConfigModel.model_fields.items()
    if isinstance(field.annotation, type) and issubclass(field.annotation, _Section)
}
_BUILT_WITH = [laws.REGISTERED[0]]   # the registrations [material] and [layer] were made from


def law_sections() -> None:
    """Make [material] and [layer] again if a law registered since they were made: its
    keys and its name join them, in ``SECTIONS`` and in every configuration model."""
    if _BUILT_WITH[0] == laws.REGISTERED[0]:
        return
    global Material, Layer
    _law_floors()
    Material, Layer = _material_model(), _layer_model()
    SECTIONS["material"], SECTIONS["layer"] = Material, Layer
    models: list[type[BaseModel]] = [ConfigModel]
    for model in models:                      # and every subclass (``Config``)
        models += model.__subclasses__()
        model.model_fields["material"].annotation = Material
        model.model_fields["layer"].annotation = Layer
        model.model_rebuild(force=True)
    _BUILT_WITH[0] = laws.REGISTERED[0]


