"""Configuration: layering, validation messages, built-in scenarios and the TOML round trip."""

from __future__ import annotations

import math
from pathlib import Path

import pydantic
import pytest

from granflow.config import (
    CUSTOM,
    Config,
    ConfigError,
    ConfigNote,
    apply_overrides,
    builtin_scenarios,
    config_to_toml,
    load_config,
)

CONTRACT_SCENARIOS = {"plug-flow", "trapezoid-rigid", "rectangle-rigid", "trapezoid-erodible"}


def error_of(source: str | Path = "plug-flow", *overrides: str) -> str:
    with pytest.raises(ConfigError) as info:
        load_config(source, overrides)
    message = str(info.value)
    assert "\n" not in message
    return message


# ---------------------------------------------------------------- built-in scenarios


def test_builtin_scenarios_are_the_contract_ones_with_descriptions() -> None:
    scenarios = builtin_scenarios()
    assert set(scenarios) >= CONTRACT_SCENARIOS     # extensions (incline-mu-i) are allowed
    assert all(len(text) > 20 and "\n" not in text for text in scenarios.values())


@pytest.mark.parametrize("name", sorted(builtin_scenarios()))
def test_every_builtin_scenario_loads(name: str) -> None:
    config = load_config(name)
    assert config.scenario == name
    assert all(0 < t <= config.time.t_end for t in config.time.output_times)


def test_plug_flow_is_the_papers_section_4() -> None:
    c = load_config("plug-flow")
    assert c.geometry.kind == "periodic-layer"
    assert (c.geometry.slope_deg, c.geometry.length, c.geometry.height) == (1.0, 1.5, 6.0)
    assert c.material.mu_s == pytest.approx(math.tan(math.radians(1.0)) + 1e-2, rel=1e-15)
    assert c.material.kinematic_viscosity == pytest.approx(1.0)
    assert (c.initial.shear_rate, c.initial.plug_base) == (1.0, 3.5)
    assert (c.mesh.size, c.numerics.eps, c.numerics.tol) == (0.125, 1e-6, 1e-7)
    assert (c.time.t_end, c.time.dt, c.time.output_times) == (0.2, 3.12e-3, [0.2])
    assert c.numerics.mesh_velocity == "fixed"


def test_collapse_scenarios_match_the_papers_section_5() -> None:
    shapes = {name: load_config(name).geometry for name in CONTRACT_SCENARIOS - {"plug-flow"}}
    assert (shapes["trapezoid-rigid"].width, shapes["trapezoid-rigid"].height) == (0.297, 0.25)
    assert shapes["rectangle-rigid"].shape == "rectangle"
    assert shapes["trapezoid-erodible"].erodible_thickness == 0.005
    c = load_config("trapezoid-rigid")
    assert c.boundary.mu_bed == pytest.approx(math.tan(math.radians(25.5)))
    assert c.boundary.mu_wall == pytest.approx(math.tan(math.radians(10.2)))
    assert (c.time.dt, c.time.dt_init, c.time.dt_max) == (None, 1e-5, 1e-3)   # fast path
    assert c.time.adaptive and c.time.stop_at_rest
    paper = apply_overrides(c, PAPERS_ALGORITHM)
    assert (paper.time.adaptive, paper.time.dt_init, paper.time.dt_max, paper.time.dt_growth,
            paper.numerics.tol, paper.numerics.tol_init) == (False, 1e-8, 1e-4, 1.1, 1e-4, 1e-6)


PAPERS_ALGORITHM = ["numerics.linearization=picard", "time.adaptive=false",
                    "time.dt_init=1e-8", "time.dt_growth=1.1", "time.dt_max=1e-4",
                    "numerics.tol=1e-4"]


# ---------------------------------------------------------------- files and layering


def test_file_inherits_from_a_builtin_and_set_overrides_the_file(tmp_path: Path) -> None:
    path = tmp_path / "mine.toml"
    path.write_text('scenario = "plug-flow"\n[time]\nt_end = 0.1\noutput_times = [0.05]\n')
    config = load_config(path, ["time.t_end=0.08"])
    assert config.scenario == "plug-flow"
    assert config.time.t_end == 0.08  # --set beats the file
    assert config.time.output_times == [0.05]  # the file beats the scenario
    assert config.time.dt == 3.12e-3  # the scenario beats the defaults
    assert config.output.checkpoint_every == 100  # package default


def test_file_without_scenario_starts_from_the_package_defaults(tmp_path: Path) -> None:
    path = tmp_path / "col.toml"
    path.write_text('[geometry]\nkind = "column"\nheight = 0.2\n')
    config = load_config(str(path))
    assert config.scenario == CUSTOM
    assert (config.material.density, config.geometry.width, config.mesh.size) == (
        1550.0, 0.297, 0.025)


def test_geometry_kind_has_no_default(tmp_path: Path) -> None:
    path = tmp_path / "empty.toml"
    path.write_text("")
    assert error_of(path).startswith("geometry.kind is not set")


@pytest.mark.parametrize("text, expected", [
    ("[numerics]\nepsilon = 1e-4\n",
     "unknown configuration key 'numerics.epsilon' (known keys in [numerics]: eps, eps_friction"),
    ("[numeric]\neps = 1e-4\n", "unknown configuration section 'numeric'"),
    ("eps = 1e-4\n", "unknown configuration section 'eps'"),
    ('scenario = "plug-flo"\n', "unknown scenario 'plug-flo'"),
    ("[time\n", "cannot read scenario file"),
])
def test_bad_files_are_reported(tmp_path: Path, text: str, expected: str) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(text)
    assert expected in error_of(path)


def test_missing_file_and_unknown_name() -> None:
    assert "not found" in error_of("no/such/file.toml")
    assert error_of("plugflow").startswith("unknown scenario 'plugflow'; built-in scenarios:")


# ---------------------------------------------------------------- --set values


@pytest.mark.parametrize("assignment, section, key, value", [
    ("numerics.eps=1e-4", "numerics", "eps", 1e-4),
    ("numerics.max_iterations=20", "numerics", "max_iterations", 20),
    ("time.output_times=[0.1, 0.2]", "time", "output_times", [0.1, 0.2]),
    ("numerics.mesh_velocity=vertical", "numerics", "mesh_velocity", "vertical"),
    ('numerics.mesh_velocity="vertical"', "numerics", "mesh_velocity", "vertical"),
    ("output.progress=false", "output", "progress", False),
    ("time.dt=none", "time", "dt", None),
    ("mesh.cells_x=4", "mesh", "cells_x", 4),
    ("surface_tension.gamma0=0.5", "surface_tension", "gamma0", 0.5),
    ("mesh.size=.25", "mesh", "size", 0.25),
])
def test_set_values_are_toml_literals(assignment: str, section: str, key: str,
                                      value: object) -> None:
    scenario = "trapezoid-erodible" if section == "surface_tension" else "plug-flow"
    config = load_config(scenario, [assignment])
    assert getattr(getattr(config, section), key) == value


def test_apply_overrides_revalidates() -> None:
    config = apply_overrides(load_config("plug-flow"), ["time.t_end=0.1", "time.output_times=[]"])
    assert config.time.t_end == 0.1
    with pytest.raises(ConfigError, match="time.output_times"):
        apply_overrides(config, ["time.output_times=[0.5]"])


def test_inherited_output_times_follow_a_shorter_t_end_with_a_note() -> None:
    with pytest.warns(ConfigNote, match=r"\[0.48, 0.66, 0.78, 1.02\] .* time\.t_end = 0\.4 s"):
        config = load_config("trapezoid-rigid", ["time.t_end=0.4"])
    assert config.time.output_times == [0.18, 0.3]


def test_output_times_the_user_sets_are_not_noted(recwarn: pytest.WarningsRecorder) -> None:
    load_config("trapezoid-rigid", ["time.t_end=0.4", "time.output_times=[0.1]"])
    load_config("trapezoid-rigid", ["time.t_end=2.0"])
    assert not [w for w in recwarn if issubclass(w.category, ConfigNote)]


def test_config_is_frozen() -> None:
    config = load_config("plug-flow")
    with pytest.raises(pydantic.ValidationError):
        config.numerics.eps = 1.0  # type: ignore[misc]


# ---------------------------------------------------------------- validation messages


@pytest.mark.parametrize("assignment, expected", [
    ("numerics.eps=-1", "numerics.eps = -1: must be a number in [1e-12, 1000]"),
    ("numerics.eps=0", "numerics.eps = 0: must be a number in [1e-12, 1000]"),
    ("numerics.eps=abc", "numerics.eps = 'abc': must be a number in [1e-12, 1000]"),
    ("numerics.epsilon=1", "unknown configuration key 'numerics.epsilon' (known keys in"),
    ("numeric.eps=1", "unknown configuration section 'numeric'"),
    ("eps=1", "unknown configuration key 'eps'"),
    ("numerics.eps", "an override is section.key=value"),
    ("material.friction_angle_deg=90", "friction_angle_deg = 90: must be a number in [0, 90)"),
    ("material.friction_angle_deg=-1", "friction_angle_deg = -1: must be a number in [0, 90)"),
    ("time.dt=0", "time.dt = 0: must be a number in [1e-12, 100] or none"),
    ("time.dt=1e-320", "time.dt = 1e-320: must be a number in [1e-12, 100] or none"),
    ("time.dt_init=1.0", "time.dt_init = 1.0 must not exceed time.dt_max = 0.0001"),
    ("time.output_times=[0.3]", "time.output_times = [0.3]: 0.3 is not in (0, time.t_end = 0.2]"),
    ("time.output_times=[0.1, 0.05]", "time.output_times = [0.1, 0.05]: must be increasing"),
    ("mesh.size=2.0", "mesh.size = 2.0 must not exceed min(geometry.length, geometry.height)"),
    ("initial.plug_base=7", "geometry.height = 6.0 must be greater than initial.plug_base = 7.0"),
    ("geometry.length=1e308", "geometry.length = 1e+308: must be a number in (0, 10000]"),
    ("mesh.size=1e-6", "mesh.size = 1e-06 gives about 1.8e+13 triangles, about 5.9e+08 GB"),
    ("geometry.width=0.5", "geometry.width = 0.5 has no effect here: it describes a column"),
    ("numerics.tol=1", "numerics.tol = 1: must be a number in [1e-14, 1)"),
    ("numerics.max_iterations=0", "numerics.max_iterations = 0: must be an integer in [1, 100000]"),
    ("numerics.max_iterations=2.5", "numerics.max_iterations = 2.5: must be an integer in [1, 1"),
    ("mesh.cells_x=1", "mesh.cells_x = 1: must be an integer in [2, 100000] or none"),
    ("output.progress=yes", "output.progress = 'yes': must be true or false"),
    ("numerics.linearization=secant", "must be one of 'picard', 'newton', 'hybrid', 'primal-d"),
    ("surface_tension.gamma0=-1", "surface_tension.gamma0 = -1: must be 'auto' or a number in [0"),
    ("time.output_times=0.2",
     "time.output_times = 0.2: must be a list of at most 10 000 numbers"),
    ("numerics.eps=nan", "numerics.eps = nan: must be a number in [1e-12, 1000]"),
])
def test_invalid_values_give_one_line_naming_the_key(assignment: str, expected: str) -> None:
    assert expected in error_of("plug-flow", assignment)


@pytest.mark.parametrize("assignment, expected", [
    ("mesh.size=0.3", "mesh.size = 0.3 must not exceed min(geometry.width, geometry.height)"),
    ("geometry.bed_length=0.2", "geometry.bed_length = 0.2 has no effect here: it describes the "
                                "erodible layer"),
    ("geometry.erodible_thickness=0.005 --set geometry.bed_length=0.2",
     "geometry.bed_length = 0.2 must be greater than geometry.width"),
    ("geometry.erodible_thickness=0.3", "geometry.erodible_thickness = 0.3 must be less than"),
    ("geometry.front_angle_deg=10", "geometry.front_angle_deg = 10.0 is too shallow"),
])
def test_column_geometry_checks(assignment: str, expected: str) -> None:
    assert expected in error_of("trapezoid-rigid", *assignment.split(" --set "))


@pytest.mark.parametrize("assignment, expected", [
    ("material.mu_2_deg=20", "material.mu_2_deg = 20.0 must be greater than "
                             "material.friction_angle_deg = 25.5"),
    ("material.grain_density=1000", "material.grain_density = 1000.0 must be at least "
                                    "material.density = 1550.0"),
])
def test_mu_i_checks(assignment: str, expected: str) -> None:
    assert expected in error_of("trapezoid-rigid", "material.rheology=mu-i", assignment)


@pytest.mark.parametrize("assignment, reason", [
    ("material.i0=0.3", "material.rheology = 'drucker-prager'"),
    ("boundary.side_wall_friction_deg=20", "boundary.channel_width = none"),
])
def test_keys_of_an_unused_part_are_refused(assignment: str, reason: str) -> None:
    assert reason in error_of("trapezoid-rigid", assignment)


@pytest.mark.parametrize("velocity", ["elastic", "lagrange"])
def test_periodic_layer_refuses_free_surface_mesh_velocities(velocity: str) -> None:
    assert error_of("plug-flow", f"numerics.mesh_velocity={velocity}") == (
        f"numerics.mesh_velocity = '{velocity}' is not available for geometry.kind = "
        "'periodic-layer'; use 'fixed' or 'vertical'")


# ---------------------------------------------------------------- round trip


@pytest.mark.parametrize("name, overrides", [
    *[(name, []) for name in sorted(CONTRACT_SCENARIOS)],
    ("plug-flow", ["time.dt=none", "mesh.cells_x=4", "numerics.tol_init=1e-3"]),
    ("trapezoid-rigid", ["surface_tension.enabled=true", "surface_tension.gamma0=0.25",
                         "time.dt=1e-3", "output.progress=false"]),
])
def test_config_to_toml_round_trips(tmp_path: Path, name: str, overrides: list[str]) -> None:
    config = load_config(name, overrides)
    path = tmp_path / "config.toml"
    path.write_text(config_to_toml(config))
    again = load_config(path)
    assert isinstance(again, Config)
    assert again == config
    assert config_to_toml(again) == config_to_toml(config)


def test_custom_config_round_trips(tmp_path: Path) -> None:
    source = tmp_path / "col.toml"
    source.write_text('[geometry]\nkind = "column"\nheight = 0.2\n')
    config = load_config(source)
    path = tmp_path / "config.toml"
    path.write_text(config_to_toml(config))
    assert load_config(path) == config


# ---------------------------------------------------------------- strict but not wrong


@pytest.mark.parametrize("source, overrides", [
    ("plug-flow", ["geometry.slope_deg=5"]),             # steeper than friction: keeps flowing
    ("trapezoid-rigid", ["material.friction_angle_deg=0"]),  # the purely viscous limit
    ("trapezoid-rigid", ["geometry.width=1.2"]),         # wider than the unused bed_length
    ("trapezoid-rigid", ["numerics.max_iterations=1e3", "output.checkpoint_every=2e2"]),
    ("plug-flow", ["geometry.width=0.297"]),             # inert but equal to its value: harmless
])
def test_physical_inputs_are_accepted(source: str, overrides: list[str]) -> None:
    config = load_config(source, overrides)
    assert config.numerics.max_iterations == (1000 if "1e3" in str(overrides) else
                                              config.numerics.max_iterations)
    assert isinstance(config.numerics.max_iterations, int)


def test_a_resolved_config_reloads_although_it_lists_inert_keys(tmp_path: Path) -> None:
    config = load_config("trapezoid-rigid", ["time.t_end=0.5"])
    path = tmp_path / "config.toml"
    path.write_text(config_to_toml(config))
    assert load_config(path) == config


def test_layer_keys_act_only_over_a_layer_and_follow_its_law() -> None:
    """[layer] keys are refused without an erodible layer; a mu(I) layer under a
    Drucker-Prager column takes [material]'s mu(I) parameters, which then act."""
    with pytest.raises(ConfigError, match="layer.density"):
        load_config("trapezoid-rigid", ["layer.density=1400"])
    config = load_config("trapezoid-erodible", ["layer.rheology=mu-i", "material.mu_2_deg=40"])
    assert config.material.mu_2_deg == 40
    with pytest.raises(ConfigError, match="layer.i0"):
        load_config("trapezoid-erodible", ["layer.i0=0.5"])    # the layer's law is (2.13)
    with pytest.raises(ConfigError, match="augmented-lagrangian"):
        load_config("trapezoid-erodible", ["layer.density=1400",
                                           "numerics.method=augmented-lagrangian"])
