"""The recipe of docs/architecture.md for a new kind of problem, exercised: a kind registered
from outside the package (its configuration rules with ``config/kinds.py``, its builder with
``scenarios/registry.py``) is validated by its own rules, estimated, refined by a convergence
study, run, written and redrawn, with no file of granflow changed."""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

import granflow
from granflow.config import ConfigError, estimated_triangles, load_config
from granflow.config import kinds as config_kinds
from granflow.converge import level_overrides
from granflow.scenarios import plug_flow_rules, registry
from granflow.scenarios.plug_flow import PlugFlowOutputs, build_plug_flow

TINY = ["time.t_end=0.01248", "time.output_times=[0.00624]"]   # 4 steps of 3.12 ms


def gentle_slopes(c: Any) -> Iterator[str]:
    """The toy kind's own rule, beside those of the periodic layer it reuses."""
    yield from plug_flow_rules.problems(c)
    if c.geometry.slope_deg > 5:
        yield f"geometry.slope_deg = {c.geometry.slope_deg!r} must be at most 5 on a toy layer"


TOY = dataclasses.replace(
    plug_flow_rules.PERIODIC_LAYER_RULES, name="toy-layer", problems=gentle_slopes,
    describe=lambda c: f"toy layer {c.geometry.height:g} m",
    refine_space=lambda c, factor: {"mesh.size": c.mesh.size / factor / 2})


@pytest.fixture
def toy_kind(monkeypatch: pytest.MonkeyPatch) -> None:
    """The toy kind registered for one test: its rules and its builder (the periodic
    layer's, under the new name), removed afterwards."""
    registry.problem_kind("periodic-layer")           # the built-in kinds first
    monkeypatch.setitem(config_kinds.KIND_RULES, TOY.name, TOY)
    monkeypatch.setitem(registry.KINDS, TOY.name, registry.ProblemKind(
        TOY.name, build_plug_flow, PlugFlowOutputs.figures))


def test_an_unregistered_kind_is_refused_by_name() -> None:
    with pytest.raises(ConfigError, match=r"geometry.kind = 'toy-layer': must be one of "
                                          r"'column', 'periodic-layer', 'slab'$"):
        load_config("plug-flow", ["geometry.kind=toy-layer"])


def test_a_registered_kind_is_checked_estimated_and_refined_by_its_rules(toy_kind: None) -> None:
    config = load_config("plug-flow", ["geometry.kind=toy-layer"])
    assert "toy layer 6 m" in repr(config)
    assert estimated_triangles(config) == plug_flow_rules.triangles(config)
    assert level_overrides(config, "space", 1) == {"mesh.size": config.mesh.size / 4}
    with pytest.raises(ConfigError, match="must be at most 5 on a toy layer"):
        config.set("geometry.slope_deg", 6.0)
    with pytest.raises(ConfigError, match="geometry.width = .* has no effect here"):
        config.set("geometry.width", 0.5)           # the keys it declares inert


def test_a_registered_kind_runs_writes_and_redraws(toy_kind: None, tmp_path: Path) -> None:
    run = granflow.run(load_config("plug-flow", ["geometry.kind=toy-layer", *TINY]),
                       out=tmp_path / "run", progress=False)
    assert run.summary.ok and run.summary.steps == 4
    assert (tmp_path / "run" / "diagnostics.csv").is_file()
    assert registry.plot_run(tmp_path / "run")      # its figures, from its files
