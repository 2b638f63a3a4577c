"""The checkpoint is data only: a real run state survives the round trip exactly, and a
checkpoint from someone else cannot execute code when `granflow resume` reads it."""

from __future__ import annotations

import dataclasses
import io
import json
import pickle
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

import ngsolve as ngs
import numpy as np
import pytest

from granflow.config import config_to_toml, load_config
from granflow.io.checkpoint import (
    CHECKPOINT_FILE,
    LEGACY_CHECKPOINT_FILE,
    CheckpointError,
    read_checkpoint,
    write_checkpoint,
)
from granflow.io.run_dir import RunDir
from granflow.io.run_state import SimulationState
from granflow.runner import build_problem, checked_state
from granflow.state.spec import StateError

CONFIG = ["mesh.size=0.05", "time.t_end=0.01", "output.progress=false"]


def assert_same(a: Any, b: Any, where: str = "state") -> None:
    """Deep equality, exact: arrays bit for bit, meshes by vertices, cells and labels."""
    if isinstance(a, ngs.Mesh):
        assert isinstance(b, ngs.Mesh), where
        assert np.array_equal(a.ngmesh.Coordinates(), b.ngmesh.Coordinates()), where
        for vb in (ngs.VOL, ngs.BND):
            cells = [([v.nr for v in el.vertices], el.mat) for el in a.Elements(vb)]
            assert cells == [([v.nr for v in el.vertices], el.mat) for el in b.Elements(vb)]
        assert a.GetBoundaries() == b.GetBoundaries(), where
    elif isinstance(a, np.ndarray):
        assert isinstance(b, np.ndarray) and a.dtype == b.dtype, where
        assert np.array_equal(a, b, equal_nan=a.dtype.kind == "f"), where
    elif isinstance(a, dict):
        assert isinstance(b, dict) and a.keys() == b.keys(), where
        for k in a:
            assert_same(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, list | tuple):
        assert type(a) is type(b) and len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            assert_same(x, y, f"{where}[{i}]")
    elif dataclasses.is_dataclass(a):
        assert type(a) is type(b), where
        assert_same(dict(vars(a)), dict(vars(b)), f"{where}:{type(a).__name__}")
    elif isinstance(a, float) and np.isnan(a):
        assert isinstance(b, float) and np.isnan(b), where
    else:
        assert a == b and type(a) is type(b), f"{where}: {a!r} != {b!r}"


@pytest.fixture(scope="module")
def state() -> SimulationState:
    """The state of a coarse erodible collapse (surface tension and deposition on) after a
    few steps, as the runner checkpoints it."""
    problem = build_problem(load_config("trapezoid-erodible", CONFIG))
    problem.simulation.run()
    assert problem.simulation.step > 3
    return SimulationState(loop=problem.simulation.save_state(),
                           scenario=problem.save_state(),
                           outputs={"volume0": 0.0629, "pending_times": [0.18, 0.3],
                                    "vtk_entries": [(0.0, "fields_0000.vtu")],
                                    "animation_next": None})


def test_a_run_state_survives_the_round_trip_exactly(state: SimulationState,
                                                     tmp_path: Path) -> None:
    run_dir = RunDir.create(tmp_path / "run")
    path = write_checkpoint(run_dir, state)
    assert path == run_dir.path(CHECKPOINT_FILE)
    back = read_checkpoint(run_dir.root)
    assert back.version == state.version
    assert_same(state.loop, back.loop, "loop")
    assert_same(state.scenario, back.scenario, "scenario")
    assert_same(state.outputs, back.outputs, "outputs")
    with np.load(path, allow_pickle=False) as archive:   # loads without pickle at all
        assert all(archive[name].dtype != object for name in archive.files)


class _Payload:
    """A pickle that creates a file when unpickled: what a hostile checkpoint could do."""

    def __init__(self, marker: Path) -> None:
        self.marker = marker

    def __reduce__(self) -> tuple[Any, ...]:
        return (Path.write_text, (self.marker, "executed"))


def _run_dir_for_resume(root: Path) -> None:
    """A run directory that `granflow resume` accepts up to reading its checkpoint."""
    run_dir = RunDir.create(root)
    run_dir.write_text("config.toml", config_to_toml(load_config("rectangle-rigid")))
    run_dir.write_json("summary.json", {"status": "interrupted"})
    (root / "checkpoint").mkdir(exist_ok=True)


@pytest.mark.parametrize("flag", [[], ["--allow-pickle"]])
def test_an_old_pickled_checkpoint_is_never_read(tmp_path: Path, flag: list[str]) -> None:
    root, marker = tmp_path / "received", tmp_path / "marker.txt"
    _run_dir_for_resume(root)
    (root / LEGACY_CHECKPOINT_FILE).write_bytes(pickle.dumps(_Payload(marker)))
    with pytest.raises(CheckpointError, match="no longer reads it"):
        read_checkpoint(root)
    done = subprocess.run([sys.executable, "-m", "granflow", "resume", str(root), "--quiet",
                           *flag], capture_output=True, text=True, timeout=300)
    assert done.returncode == 2 and "granflow run" in done.stderr
    assert "Traceback" not in done.stderr and len(done.stderr.strip().splitlines()) == 1
    assert not marker.exists()


def _tampered(tmp_path: Path, edit: Any) -> Path:
    """A copy of a real checkpoint with its JSON part changed by ``edit``."""
    root = tmp_path / "tampered"
    (root / "checkpoint").mkdir(parents=True)
    with np.load(tmp_path / "run" / CHECKPOINT_FILE, allow_pickle=False) as archive:
        arrays = {name: archive[name] for name in archive.files}
    tree = json.loads(arrays["__state__"].tobytes())
    edit(tree, arrays)
    arrays["__state__"] = np.frombuffer(json.dumps(tree).encode(), dtype=np.uint8)
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    (root / CHECKPOINT_FILE).write_bytes(buffer.getvalue())
    return root


@pytest.mark.parametrize("edit", [
    lambda tree, arrays: tree["loop"].update(
        steps_policy={"__dataclass__": "os:system", "fields": {}}),
    lambda tree, arrays: arrays.update(a0=np.array([object()], dtype=object)),
    lambda tree, arrays: tree.update(version=1),
    lambda tree, arrays: tree["scenario"].update(mesh={"__mesh__": ["a1", "a0"]}),
    lambda tree, arrays: tree["loop"].update(t="0.1"),
    lambda tree, arrays: tree["loop"].update(step=-3),
    lambda tree, arrays: tree["loop"]["steps_policy"]["fields"].update(extra=1),
    lambda tree, arrays: tree.update(loop=[1, 2]),
    lambda tree, arrays: tree.update(scenario={"a": [[[[]]]] * 1000}, loop="x" * 10),
], ids=["foreign-class", "object-array", "old-version", "broken-mesh", "time-text",
        "negative-step", "unknown-field", "loop-list", "wrong-types"])
def test_a_tampered_checkpoint_is_a_clear_error(state: SimulationState, tmp_path: Path,
                                                edit: Any) -> None:
    write_checkpoint(RunDir.create(tmp_path / "run"), state)
    root = _tampered(tmp_path, edit)
    with pytest.raises((CheckpointError, StateError), match="checkpoint|^loop"):
        checked_state(read_checkpoint(root),       # as `granflow resume` reads it
                      build_problem(load_config("trapezoid-erodible", CONFIG)))


def _mesh_entry(tree: dict[str, Any]) -> dict[str, Any]:
    return tree["scenario"]["mesh"]["__mesh__"]


@pytest.mark.parametrize("name, values", [
    ("triangles", lambda a: np.where(a == a.max(), 10**6, a)),     # out of range
    ("triangles", lambda a: a - a.min() - 1),                      # negative (0 -> -1)
    ("triangles", lambda a: np.column_stack([a[:, 0], a[:, 0], a[:, 2]])),  # repeated
    ("triangles", lambda a: a[:, :2]),                             # not triangles
    ("segments", lambda a: a + 10**9),
    ("labels", lambda a: a + 7),
    ("points", lambda a: np.full_like(a, np.nan)),
    ("points", lambda a: a.astype(np.complex128)),
], ids=["index-out-of-range", "index-negative", "vertex-repeated", "two-columns",
        "segment-out-of-range", "unknown-label", "nan-points", "complex-points"])
def test_a_checkpoint_mesh_is_checked_before_it_is_built(state: SimulationState, tmp_path: Path,
                                                         name: str, values: Any) -> None:
    write_checkpoint(RunDir.create(tmp_path / "run"), state)

    def edit(tree: dict[str, Any], arrays: dict[str, np.ndarray]) -> None:
        key = _mesh_entry(tree)[name]["__array__"]
        arrays[key] = values(arrays[key])

    with pytest.raises(CheckpointError, match="mesh"):
        read_checkpoint(_tampered(tmp_path, edit))


@pytest.mark.parametrize("edit, why", [
    (lambda m: m.update(triangles=np.concatenate([m["triangles"]] * 2)), "a triangle twice"),
    (lambda m: m.update(triangles=np.concatenate([m["triangles"],
                                                  m["triangles"][:1, [1, 2, 0]]])),
     "a triangle twice"),
    (lambda m: m.update(triangles=m["triangles"][:, ::-1]), "inverted or of no area"),
    (lambda m: m.update(points=np.zeros_like(m["points"])), "inverted or of no area"),
    (lambda m: m.update(points=m["points"] * 1e300), "farther than"),
    (lambda m: m.update(points=m["points"][np.random.default_rng(1).permutation(
        len(m["points"]))]), "inverted or of no area|overlap"),
    (lambda m: m.update(segments=m["segments"][1:], labels=m["labels"][1:]),
     "do not close its domain"),
    (lambda m: m.update(triangles=m["triangles"][1:]), "do not close its domain"),
    (lambda m: m.update(segments=np.concatenate([m["segments"], m["segments"][:1]]),
                        labels=np.concatenate([m["labels"], m["labels"][:1]])),
     "a boundary segment twice"),
], ids=["every-triangle-twice", "one-triangle-twice", "clockwise", "collapsed",
        "scaled-1e300", "permuted", "segment-missing", "triangle-missing", "segment-twice"])
def test_a_checkpoint_mesh_must_be_one_a_run_could_have(state: SimulationState,
                                                        tmp_path: Path, edit: Any,
                                                        why: str) -> None:
    """Index ranges are not enough: each of these resumed (or ran and failed later)."""
    write_checkpoint(RunDir.create(tmp_path / "run"), state)

    def change(tree: dict[str, Any], arrays: dict[str, np.ndarray]) -> None:
        keys = {name: ref["__array__"] for name, ref in _mesh_entry(tree).items()}
        mesh = {name: arrays[key] for name, key in keys.items()}
        edit(mesh)
        arrays.update({keys[name]: value for name, value in mesh.items()})

    with pytest.raises(CheckpointError, match=why) as err:
        read_checkpoint(_tampered(tmp_path, change))
    assert "\n" not in str(err.value)


def _vol_text(mesh: ngs.Mesh) -> str:
    """The mesh in Netgen's text format, as checkpoints of version 2 stored it."""
    with tempfile.TemporaryDirectory() as folder:
        mesh.ngmesh.Save(str(Path(folder) / "mesh.vol"))
        return (Path(folder) / "mesh.vol").read_text()


def _as_version_2(text: str) -> Any:
    """An edit that stores the mesh as version 2 did: Netgen's text and the coordinates."""
    def edit(tree: dict[str, Any], arrays: dict[str, np.ndarray]) -> None:
        points = arrays[_mesh_entry(tree)["points"]["__array__"]]
        arrays["vol"] = np.frombuffer(text.encode(), dtype=np.uint8)
        arrays["xy"] = points
        tree["version"] = 2
        tree["scenario"]["mesh"] = {"__mesh__": ["vol", "xy"]}
    return edit


def test_a_version_2_checkpoint_is_still_read_exactly(state: SimulationState,
                                                      tmp_path: Path) -> None:
    write_checkpoint(RunDir.create(tmp_path / "run"), state)
    back = read_checkpoint(_tampered(tmp_path, _as_version_2(_vol_text(state.scenario["mesh"]))))
    assert_same(state.scenario, back.scenario, "scenario")


def _edit_section(text: str, section: str, edit: Any) -> str:
    """``text`` with the rows of a .vol section (after its count) passed through ``edit``."""
    lines = text.splitlines()
    at = lines.index(section)
    count = int(lines[at + 1])
    rows = edit(lines[at + 2:at + 2 + count])
    return "\n".join([*lines[:at + 1], str(len(rows)), *rows, *lines[at + 2 + count:]])


def _first_index(row: str, value: str) -> str:
    parts = row.split()
    parts[5] = value            # p1 of a surface element
    return " ".join(parts)


@pytest.mark.parametrize("edit", [
    lambda t: _edit_section(t, "surfaceelements", lambda r: [_first_index(r[0], "99999"),
                                                              *r[1:]]),
    lambda t: _edit_section(t, "surfaceelements", lambda r: [_first_index(r[0], "-4"), *r[1:]]),
    lambda t: _edit_section(t, "surfaceelements", lambda r: [_first_index(r[0], "0"), *r[1:]]),
    lambda t: t.replace("\nsurfaceelements\n", "\nsurfaceelements\n-5\n", 1),
    lambda t: t[:len(t) // 2],
    lambda t: _edit_section(t, "points", lambda r: r[:-3]),
    lambda t: t.replace("mesh3d", "mesh2d", 1),
], ids=["index-out-of-range", "index-negative", "index-zero", "negative-count", "cut-short",
        "fewer-points", "not-netgen"])
def test_a_bad_netgen_text_is_one_error_never_a_crash(state: SimulationState, tmp_path: Path,
                                                      edit: Any) -> None:
    """Netgen's own reader crashed the process on these (a signal, a double free)."""
    write_checkpoint(RunDir.create(tmp_path / "run"), state)
    text = edit(_vol_text(state.scenario["mesh"]))
    with pytest.raises(CheckpointError, match="mesh|checkpoint") as err:
        read_checkpoint(_tampered(tmp_path, _as_version_2(text)))
    assert "\n" not in str(err.value)


def test_a_fixed_step_policy_is_read_back_also_as_earlier_versions_wrote_it(
        tmp_path: Path) -> None:
    """A field left at its class default (RampedStep.recovering) was not written, and the
    checkpoint of every fixed-step run was refused on resume: it is written now, and read
    with its default where an earlier checkpoint lacks it."""
    problem = build_problem(load_config("plug-flow", ["time.t_end=0.01",
                                                      "output.progress=false"]))
    problem.simulation.run()
    state = SimulationState(loop=problem.simulation.save_state(), scenario=problem.save_state(),
                            outputs={})
    write_checkpoint(RunDir.create(tmp_path / "run"), state)

    def fields(policy: Any) -> dict[str, Any]:
        return {f.name: getattr(policy, f.name) for f in dataclasses.fields(policy)}

    policy = state.loop["steps_policy"]
    assert fields(read_checkpoint(tmp_path / "run").loop["steps_policy"]) == fields(policy)
    earlier = _tampered(tmp_path, lambda tree, arrays: tree["loop"]["steps_policy"][
        "fields"].pop("recovering"))
    assert fields(read_checkpoint(earlier).loop["steps_policy"]) == fields(policy)
