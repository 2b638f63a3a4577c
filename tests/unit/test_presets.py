"""Material presets: ``material.preset = "glass-beads"`` sets every constant of the beads for
the law a material runs with, a value the user writes wins, and a law that runs with another
law's friction angle gets a one-line note."""

from __future__ import annotations

import math
import typing
import warnings
from pathlib import Path

import pytest

from granflow.config import Config, ConfigError, ConfigNote, config_to_toml, load_config
from granflow.config.schema import PresetName
from granflow.physics.laws import FRICTIONS, RHEOLOGIES
from granflow.physics.presets import GLASS_BEADS, PRESETS
from granflow.reference import beads

LAWS = [(rheology, friction) for rheology in RHEOLOGIES for friction in FRICTIONS
        if not (rheology == "nonlocal" and friction == "hysteretic")]   # refused together


def notes(record: list[warnings.WarningMessage]) -> list[str]:
    return [str(w.message) for w in record if issubclass(w.category, ConfigNote)]


def test_the_schema_names_every_preset_and_every_law_has_its_angle() -> None:
    assert set(typing.get_args(PresetName)) == set(PRESETS)
    for preset in PRESETS.values():
        assert set(preset.angle_by_rheology) == set(RHEOLOGIES)


def test_the_glass_beads_constants_agree_with_their_sources() -> None:
    """b = (mu_2 - mu_s) / I0 of the beads' mu(I) (Henann & Kamrin 2013); mu_s and mu_2 are
    the angles of the beads' stopping-height fit; the bulk density is the grains' at a
    packing of 0.62; the start angle (avalanche) above the flowing one (repose)."""
    shared = GLASS_BEADS.shared
    mu_s, mu_2 = (math.tan(math.radians(a)) for a in (GLASS_BEADS.angle_by_rheology["mu-i"],
                                                      shared["mu_2_deg"]))
    assert shared["nonlocal_b"] == pytest.approx((mu_2 - mu_s) / shared["i0"], abs=1e-4)
    assert GLASS_BEADS.angle_by_rheology["nonlocal"] == beads.THETA1_DEG
    assert shared["mu_2_deg"] == beads.THETA2_DEG
    assert shared["density"] / shared["grain_density"] == pytest.approx(0.62)
    assert shared["start_friction_angle_deg"] > GLASS_BEADS.angle_hysteretic


@pytest.mark.parametrize("rheology, friction", LAWS)
def test_a_preset_sets_every_constant_for_the_law_it_runs_with(rheology: str,
                                                                friction: str) -> None:
    config = load_config("rectangle-rigid", {"material.preset": "glass-beads",
                                             "material.rheology": rheology,
                                             "material.friction": friction})
    wanted = GLASS_BEADS.values(rheology, friction)
    assert {k: getattr(config.material, k) for k in wanted} == wanted
    angle = wanted["friction_angle_deg"]
    assert angle == (23.5 if (rheology, friction) == ("drucker-prager", "hysteretic")
                     else 25.5 if rheology == "drucker-prager" else 20.9)


def test_a_value_the_user_sets_wins_over_the_preset(tmp_path: Path) -> None:
    by_set = load_config("rectangle-rigid", ["material.preset=glass-beads",
                                             "material.rheology=nonlocal",
                                             "material.friction_angle_deg=22"])
    assert by_set.material.friction_angle_deg == 22.0
    assert by_set.material.grain_diameter == 0.53e-3
    case = tmp_path / "beads.toml"
    case.write_text('scenario = "rectangle-rigid"\n[material]\npreset = "glass-beads"\n'
                    'rheology = "mu-i"\ni0 = 0.3\n', encoding="utf-8")
    from_file = load_config(case)
    assert (from_file.material.i0, from_file.material.friction_angle_deg) == (0.3, 20.9)
    # a built-in scenario's values lie below a preset the user names: incline-mu-i's
    # 1500 kg/m^3 gives way to the beads' 1550
    incline = load_config("incline-mu-i", ["material.preset=glass-beads"])
    assert incline.material.density == 1550.0


def test_a_resolved_configuration_is_read_back_unchanged(tmp_path: Path) -> None:
    config = load_config("trapezoid-erodible", ["material.preset=glass-beads",
                                                "material.rheology=nonlocal"])
    saved = tmp_path / "config.toml"
    saved.write_text(config_to_toml(config), encoding="utf-8")
    assert load_config(saved).model_dump() | {"scenario": 0} == (
        config.model_dump() | {"scenario": 0})


def test_config_set_follows_the_preset_for_a_new_law_and_keeps_the_users_values() -> None:
    beads = Config.load("rectangle-rigid", {"material.preset": "glass-beads"})
    assert beads.material.friction_angle_deg == 25.5
    assert beads.set("material.rheology", "mu-i").material.friction_angle_deg == 20.9
    own = beads.set("material.friction_angle_deg", 24.0).set("material.rheology", "mu-i")
    assert own.material.friction_angle_deg == 24.0
    assert Config.load("rectangle-rigid").set("material.preset", "glass-beads").material \
        .grain_diameter == 0.53e-3


def test_a_layer_preset_sets_the_layers_constants_for_its_own_law() -> None:
    config = load_config("trapezoid-erodible", ["layer.preset=glass-beads",
                                                "layer.rheology=mu-i"])
    assert (config.layer.friction_angle_deg, config.layer.i0) == (20.9, 0.279)
    assert config.material.friction_angle_deg == 25.5          # the column keeps its own


def test_an_unknown_preset_is_one_line_naming_the_key() -> None:
    with pytest.raises(ConfigError, match=r"^material\.preset = 'sand': must be "
                                          r"'glass-beads' or none$"):
        load_config("rectangle-rigid", ["material.preset=sand"])


@pytest.mark.parametrize("rheology, fitted", [("nonlocal", "nonlocal_b = 0.9377"),
                                               ("mu-i", "i0 = 0.279")])
def test_a_law_run_with_another_laws_angle_gets_a_note(rheology: str, fitted: str) -> None:
    with pytest.warns(ConfigNote, match=rf"material\.rheology = '{rheology}' runs with "
                                        rf"material\.friction_angle_deg = 25\.5.*{fitted}.*"
                                        r"go with 20\.9") as record:
        load_config("rectangle-rigid", [f"material.rheology={rheology}"])
    assert len(notes(record.list)) == 1


def test_no_note_where_the_angle_is_chosen_or_consistent() -> None:
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        load_config("rectangle-rigid", ["material.rheology=nonlocal",
                                        "material.preset=glass-beads"])
        load_config("rectangle-rigid", ["material.rheology=nonlocal",
                                        "material.friction_angle_deg=25.5"])
        load_config("incline-mu-i")                       # mu(I) at 20.9
        load_config("rectangle-rigid")
    assert notes(record) == []


def test_a_layer_run_with_the_columns_angle_gets_a_note() -> None:
    with pytest.warns(ConfigNote, match=r"layer\.rheology = 'mu-i' runs with "
                                        r"layer\.friction_angle_deg = 25\.5.*layer\.preset"):
        load_config("trapezoid-erodible", ["material.preset=glass-beads",
                                           "layer.rheology=mu-i"])


@pytest.mark.filterwarnings("ignore::granflow.config.ConfigNote")
def test_mu_2_is_a_key_of_the_nonlocal_law_also_over_a_layer() -> None:
    """The nonlocal law holds material at rest up to mu_2 = tan mu_2_deg: the key has an
    effect (it was refused as a parameter of mu(I) alone over an erodible layer)."""
    config = load_config("trapezoid-erodible", ["material.rheology=nonlocal",
                                                "material.mu_2_deg=30"])
    assert config.material.mu_2_deg == 30.0
    with pytest.raises(ConfigError, match=r"material\.i0 = 0\.3 has no effect here"):
        load_config("trapezoid-erodible", ["material.rheology=nonlocal", "material.i0=0.3"])
