"""The recipe of docs/architecture.md for a new law, exercised: a law registered from outside
the package (its key with its type, range and default, its check, its builder; no 1D
reference) is validated, refused where it has no effect, run on the periodic layer (which
says in one line that it has no reference), on a column, and continued from a checkpoint,
with no file of granflow changed."""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

import granflow
from granflow.config import ConfigError, load_config
from granflow.config.schema import law_sections
from granflow.physics import NUMPY_OPS, Ops, laws

TINY_LAYER = ["time.t_end=0.00936", "time.output_times=[]"]          # 3 steps of 3.12 ms
TINY_COLUMN = {"mesh.size": 0.05, "time.t_end": 0.004, "time.output_times": [],
               "output.checkpoint_every": 5}


@dataclass(frozen=True)
class Cohesive:
    """Drucker-Prager with a cohesion c (Pa): kappa = sqrt(2) (mu_s [p]_+ + c)."""

    viscosity: float
    friction_angle_deg: float
    cohesion: float
    eps: float

    @property
    def mu_s(self) -> float:
        return math.tan(math.radians(self.friction_angle_deg))

    def effective_viscosity_sq(self, strain_rate_sq: Any, pressure: Any,
                               ops: Ops = NUMPY_OPS) -> Any:
        kappa = math.sqrt(2.0) * (self.mu_s * ops.positive_part(pressure) + self.cohesion)
        return 2.0 * self.viscosity + kappa / ops.sqrt(strain_rate_sq + self.eps**2)

    def effective_viscosity(self, strain_rate_norm: Any, pressure: Any,
                            ops: Ops = NUMPY_OPS) -> Any:
        return self.effective_viscosity_sq(strain_rate_norm**2, pressure, ops)


def cohesion_checks(material: Any, section: str, eps: float) -> Iterator[str]:
    if material.cohesion > 100.0 * material.density:      # c / (rho g) > 10 m
        yield f"{section}.cohesion = {material.cohesion!r} holds up more than 10 m of it"


TOY = laws.Law(
    "cohesive", {"cohesion": laws.Key(0.0, "cohesive: c (Pa)", low=0.0, high=1e6)},
    lambda m, eps, fields: Cohesive(m.viscosity, m.friction_angle_deg, m.cohesion, eps),
    cohesion_checks, words="the cohesive law")


@pytest.fixture
def toy_law() -> Iterator[None]:
    """The toy law registered for one test, removed afterwards."""
    laws.register_rheology(TOY)
    yield
    del laws.RHEOLOGIES[TOY.name]
    laws.REGISTERED[0] += 1
    law_sections()


def test_an_unregistered_law_and_its_key_are_refused() -> None:
    with pytest.raises(ConfigError, match="material.rheology = 'cohesive'"):
        load_config("plug-flow", ["material.rheology=cohesive"])
    with pytest.raises(ConfigError, match="unknown configuration key 'material.cohesion'"):
        load_config("plug-flow", ["material.cohesion=5"])


def test_a_registered_law_has_its_key_range_check_and_inert_rule(toy_law: None) -> None:
    config = load_config("plug-flow", ["material.rheology=cohesive", "material.cohesion=50"])
    assert config.material.cohesion == 50.0
    assert load_config("plug-flow").material.cohesion == 0.0      # its default
    with pytest.raises(ConfigError, match=r"material.cohesion = -1.0: .*\[0, 1e\+06\]"):
        config.set("material.cohesion", -1.0)
    with pytest.raises(ConfigError, match="holds up more than 10 m of it"):
        config.set("material.cohesion", 2e5)
    with pytest.raises(ConfigError, match="material.cohesion = 5 has no effect here: it is "
                                          "a parameter of the cohesive law"):
        load_config("plug-flow", ["material.cohesion=5"])


def test_a_registered_law_runs_on_the_periodic_layer_without_a_reference(
        toy_law: None, tmp_path: Path) -> None:
    run = granflow.run(load_config("plug-flow", ["material.rheology=cohesive",
                                                 "material.cohesion=50", *TINY_LAYER]),
                       out=tmp_path / "layer", progress=False)
    assert run.summary.ok and run.summary.steps == 3
    assert run.summary.extra["reference_note"] == (
        "no reference: material.rheology = 'cohesive' registers no 1D reference of a "
        "periodic layer")
    assert run.summary.extra["velocity_relative_error_l2"] is None


def test_a_registered_law_runs_a_column_and_continues_from_its_checkpoint(
        toy_law: None, tmp_path: Path) -> None:
    case = {**TINY_COLUMN, "material.rheology": "cohesive", "material.cohesion": 20.0}
    run = granflow.run("rectangle-rigid", case, tmp_path / "column", progress=False)
    steps = run.summary.steps
    assert run.summary.ok and steps is not None and steps > 5
    assert "cohesion = 20.0" in (tmp_path / "column" / "config.toml").read_text()
    again = granflow.resume(tmp_path / "column", {"time.t_end": 0.008})
    assert again.summary.ok and again.summary.steps > steps
    assert again.summary.t_final == pytest.approx(0.008)
    assert again.config.material.cohesion == 20.0
