"""Every member of a checkpoint's state is checked before any part reads it: each part
declares its share (``state/spec.py``) and ``runner.checked_state`` checks the
three shares in one place.

Generated from real states (a rigid collapse; an erodible one with a layer of its own
hysteretic material; the augmented Lagrangian with BDF2; a hysteretic plug flow; the
nonlocal fluidity law in a collapse and a plug flow): every
member is declared (nothing a part saves is dropped), and each member in turn replaced by
a value of the wrong type names itself in one ``StateError``; arrays of the wrong shape,
dtype or size and a file name that leaves the fields folder too.
"""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Iterator
from typing import Any

import ngsolve as ngs
import numpy as np
import pytest

from granflow.config import load_config
from granflow.io.run_state import SimulationState
from granflow.runner import build_problem, checked_state
from granflow.scenarios.registry import Problem
from granflow.state.spec import StateError

CASES = {
    "rigid": ("trapezoid-rigid", ["mesh.size=0.05", "time.t_end=0.004"]),
    "layer-hysteretic": ("trapezoid-erodible", [
        "mesh.size=0.05", "time.t_end=0.004", "layer.friction_angle_deg=20",
        "material.friction=hysteretic", "material.rheology=mu-i"]),
    "augmented-bdf2": ("rectangle-rigid", [
        "mesh.size=0.05", "time.t_end=0.004", "numerics.method=augmented-lagrangian",
        "time.scheme=bdf2"]),
    "plug-hysteretic": ("plug-flow", ["time.t_end=0.01", "material.friction=hysteretic"]),
    "nonlocal": ("rectangle-rigid", ["mesh.size=0.05", "time.t_end=0.004",
                                     "material.rheology=nonlocal"]),
    "plug-nonlocal": ("plug-flow", ["time.t_end=0.01", "material.rheology=nonlocal"]),
    "slab-hysteretic": ("slab", [
        "time.t_end=0.01", "geometry.erodible_thickness=0.005", "material.rheology=mu-i",
        "material.friction=hysteretic", "layer.initial_mobilisation=0.5"]),
}


@pytest.fixture(scope="module", params=list(CASES))
def run(request: pytest.FixtureRequest) -> tuple[Problem, SimulationState]:
    """A problem after a few steps and its state as the runner checkpoints it."""
    name, overrides = CASES[request.param]
    problem = build_problem(load_config(name, [*overrides, "output.progress=false"]))
    problem.simulation.run()
    outputs = {"volume0": 0.06, "remesh_times": [0.001], "deposition_times": [],
               "pending_times": [0.18], "animation_next": 0.02, "diagnostic_rows": 4,
               "vtk_entries": [(0.0, "fields_00000.vtu")], "frames_written": 1}
    return problem, SimulationState(loop=problem.simulation.save_state(),
                                    scenario=problem.save_state(), outputs=outputs)


def leaves(value: Any, path: str) -> Iterator[tuple[str, Any]]:
    """(path, member) of every member of ``value``, containers before their members."""
    if path.count(".") > 0 or "[" in path:
        yield path, value
    if isinstance(value, dict):
        for key, member in value.items():
            yield from leaves(member, f"{path}.{key}")
    elif isinstance(value, list | tuple):
        for i, member in enumerate(value):
            yield from leaves(member, f"{path}[{i}]")
    elif dataclasses.is_dataclass(value) and not isinstance(value, type):
        for f in dataclasses.fields(value):
            yield from leaves(getattr(value, f.name), f"{path}.{f.name}")


def replaced(value: Any, steps: list[str | int], new: Any) -> Any:
    """A copy of ``value`` with the member at ``steps`` replaced (the rest shared)."""
    if not steps:
        return new
    step, rest = steps[0], steps[1:]
    if isinstance(value, dict):
        return {**value, step: replaced(value[step], rest, new)}
    if isinstance(value, list | tuple):
        items = list(value)
        items[step] = replaced(items[step], rest, new)   # type: ignore[index]
        return type(value)(items)
    out = copy.copy(value)
    setattr(out, step, replaced(getattr(value, step), rest, new))   # type: ignore[arg-type]
    return out


def steps_of(path: str) -> list[str | int]:
    return [int(s) if s.isdigit() else s
            for s in path.replace("[", ".").replace("]", "").split(".")]


def tampered(state: SimulationState, path: str, value: Any) -> SimulationState:
    share, *steps = steps_of(path)
    parts = {"loop": state.loop, "scenario": state.scenario, "outputs": state.outputs}
    parts[share] = replaced(parts[share], steps, value)   # type: ignore[index]
    return SimulationState(**parts)


def test_every_member_a_part_saves_is_declared(run: tuple[Problem, SimulationState]) -> None:
    problem, state = run
    checked = checked_state(state, problem)
    saved = [p for share in ("loop", "scenario", "outputs")
             for p, _ in leaves(getattr(state, share), share)]
    kept = [p for share in ("loop", "scenario", "outputs")
            for p, _ in leaves(getattr(checked, share), share)]
    assert kept == saved


def test_each_member_of_the_wrong_type_is_one_error_naming_it(
        run: tuple[Problem, SimulationState]) -> None:
    problem, state = run
    paths = [p for share in ("loop", "scenario", "outputs")
             for p, v in leaves(getattr(state, share), share) if not isinstance(v, str)]
    assert len(paths) > 40
    for path in paths:
        with pytest.raises(StateError) as err:
            checked_state(tampered(state, path, "x"), problem)
        message = str(err.value)
        assert message.startswith(f"{path} = 'x' is not ") and "\n" not in message, message


def test_the_issues_four_members(run: tuple[Problem, SimulationState]) -> None:
    """Each ended in a traceback after the run had started (at the measures, the front, the
    runner)."""
    problem, state = run
    if "mover" not in state.scenario:
        pytest.skip("a column's members")
    for path, value in (("scenario.mover.initial_area", "x"), ("scenario.history", "abc"),
                        ("scenario.history.t", "abc"), ("scenario.remeshes", "x")):
        with pytest.raises(StateError, match=f"^{path.replace('.', '[.]')} = "):
            checked_state(tampered(state, path, value), problem)


def arrays(state: SimulationState) -> list[tuple[str, np.ndarray]]:
    return [(p, v) for share in ("loop", "scenario", "outputs")
            for p, v in leaves(getattr(state, share), share) if isinstance(v, np.ndarray)]


@pytest.mark.parametrize("change, why", [
    (lambda a: a.astype(np.complex128), "is not an array of finite floats"),
    (lambda a: a.astype(np.int64), "is not an array of finite floats"),
    (lambda a: a[..., None], "is not an array"),
    (lambda a: np.where(np.arange(a.size).reshape(a.shape) == 0, np.nan, a), "finite"),
    (lambda a: a[:1], "has 1 |is not an array|shape"),
], ids=["complex", "integers", "one-more-axis", "nan", "one-row"])
def test_arrays_of_the_wrong_kind_shape_or_size(run: tuple[Problem, SimulationState],
                                                change: Any, why: str) -> None:
    problem, state = run
    for path, value in arrays(state):
        if value.size < 2 or path.endswith("weights") or ".size_field." in path:
            continue      # a histogram's bins, the adaptive mesh's windows: any length
        bad = tampered(state, path, change(value))
        try:
            checked = checked_state(bad, problem)
        except StateError as err:
            assert str(err).startswith(path) or why.startswith("has"), str(err)
            continue
        # a size no other member names: refused where the part restores it
        assert why.startswith("has"), path
        with pytest.raises(StateError, match="shape"):
            fresh = build_problem(problem.config)          # type: ignore[attr-defined]
            fresh.restore_state(checked.scenario)


def test_a_snapshot_name_that_leaves_the_fields_folder(
        run: tuple[Problem, SimulationState]) -> None:
    problem, state = run
    bad = tampered(state, "outputs.vtk_entries[0]", (0.0, "../../outside.vtu"))
    with pytest.raises(StateError, match=r"vtk_entries\[0\]\[1\] = '../../outside.vtu'"):
        checked_state(bad, problem)


def test_a_mesh_member_that_is_not_a_mesh(run: tuple[Problem, SimulationState]) -> None:
    problem, state = run
    if not isinstance(state.scenario.get("mesh"), ngs.Mesh):
        pytest.skip("a column's member")
    with pytest.raises(StateError, match="scenario.mesh = .* is not a mesh"):
        checked_state(tampered(state, "scenario.mesh", {"points": []}), problem)
