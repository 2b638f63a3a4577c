"""Checkpoint files: the run's ``SimulationState`` as data only, in ``checkpoint/state.npz``.

A checkpoint may come from someone else's run directory, so reading one must not execute
code. The state's nested dicts and lists go to JSON (stored inside the NumPy archive), its
arrays to archive entries, read back with ``allow_pickle=False``; the few dataclasses of the
state are rebuilt by name from a fixed list (``_DATACLASSES``), never from a name the file
chooses; a mesh is stored as Netgen's own text format (``.vol``) plus its exact vertex
coordinates. Written atomically (temporary file, fsync, rename), so a run killed while
writing leaves the previous checkpoint intact.

Checkpoints of earlier granflow versions were pickles (``checkpoint/state.pkl``); they are
read only when the caller says it trusts the file (``granflow resume --allow-pickle``).
"""

from __future__ import annotations

import dataclasses
import importlib
import io
import json
import tempfile
from pathlib import Path
from typing import Any

import ngsolve as ngs
import numpy as np

from granflow.io.run_dir import RunDir
from granflow.io.run_state import STATE_VERSION, SimulationState

CHECKPOINT_FILE = "checkpoint/state.npz"
LEGACY_CHECKPOINT_FILE = "checkpoint/state.pkl"
_STATE_ENTRY = "__state__"
# the dataclasses a run state holds, by "module:name"; nothing else is ever constructed
_DATACLASSES = frozenset({
    "granflow.simulation.timestep:AdaptiveStep",
    "granflow.simulation.timestep:RampedStep",
    "granflow.ale.surface_tension:TensionState",
    "granflow.diagnostics.inertial:InertialNumbers",
})


class CheckpointError(Exception):
    """The run directory holds no usable checkpoint (the message says why)."""


def write_checkpoint(run_dir: RunDir, state: SimulationState) -> Path:
    """Write ``state`` to RUN_DIR/checkpoint/state.npz (atomically) and return the path."""
    arrays: dict[str, np.ndarray] = {}
    tree = {"version": state.version, "loop": _encode(state.loop, arrays),
            "scenario": _encode(state.scenario, arrays),
            "outputs": _encode(state.outputs, arrays)}
    arrays[_STATE_ENTRY] = np.frombuffer(json.dumps(tree).encode("utf-8"), dtype=np.uint8)
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    return run_dir.write_bytes(CHECKPOINT_FILE, buffer.getvalue())


def read_checkpoint(root: Path, allow_pickle: bool = False) -> SimulationState:
    """The state saved in RUN_DIR's checkpoint. Data only; an old pickled checkpoint is
    read only with ``allow_pickle`` (pickle can run any code the file's author chose)."""
    path = Path(root) / CHECKPOINT_FILE
    legacy = Path(root) / LEGACY_CHECKPOINT_FILE
    if not path.is_file() and legacy.is_file():
        if not allow_pickle:
            raise CheckpointError(
                f"'{legacy}' is a checkpoint of an earlier granflow in pickle format, which "
                "can execute code when read; if you wrote it yourself, resume with "
                "--allow-pickle, else rerun the case")
        return _read_pickle(legacy)
    if not path.is_file():
        raise CheckpointError(f"'{root}' holds no checkpoint ({CHECKPOINT_FILE}); a run "
                              "checkpoints every output.checkpoint_every steps, when it is "
                              "interrupted and when it fails")
    try:
        with np.load(path, allow_pickle=False) as archive:
            arrays = {name: archive[name] for name in archive.files}
        tree = json.loads(arrays.pop(_STATE_ENTRY).tobytes().decode("utf-8"))
        if not isinstance(tree, dict) or tree.get("version") != STATE_VERSION:
            raise CheckpointError(f"the checkpoint '{path}' was written by another version "
                                  "of granflow; rerun the case")
        return SimulationState(loop=_decode(tree["loop"], arrays),
                               scenario=_decode(tree["scenario"], arrays),
                               outputs=_decode(tree["outputs"], arrays))
    except CheckpointError:
        raise
    except Exception as exc:  # a truncated, foreign or tampered file
        raise CheckpointError(f"cannot read the checkpoint '{path}': "
                              f"{type(exc).__name__}: {exc}") from None


def _encode(value: Any, arrays: dict[str, np.ndarray]) -> Any:
    """``value`` as JSON data; arrays (and meshes) are moved into ``arrays``."""
    if value is None or isinstance(value, bool | int | float | str):
        return value
    if isinstance(value, np.bool_ | np.integer | np.floating):
        return value.item()
    if isinstance(value, dict):
        if not all(isinstance(k, str) for k in value):
            raise TypeError(f"checkpoint: dict keys must be strings, got {list(value)[:3]}")
        return {k: _encode(v, arrays) for k, v in value.items()}
    if isinstance(value, list):
        return [_encode(v, arrays) for v in value]
    if isinstance(value, tuple):
        return {"__tuple__": [_encode(v, arrays) for v in value]}
    if isinstance(value, np.ndarray | bytes):
        key = f"a{len(arrays)}"
        arrays[key] = (np.frombuffer(value, dtype=np.uint8) if isinstance(value, bytes)
                       else np.asarray(value))
        return {"__bytes__" if isinstance(value, bytes) else "__array__": key}
    if isinstance(value, ngs.Mesh):
        vol, coordinates = f"a{len(arrays)}", f"a{len(arrays) + 1}"
        arrays[vol] = np.frombuffer(_vol_text(value), dtype=np.uint8)
        arrays[coordinates] = value.ngmesh.Coordinates().copy()
        return {"__mesh__": [vol, coordinates]}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        name = f"{type(value).__module__}:{type(value).__qualname__}"
        if name not in _DATACLASSES:
            raise TypeError(f"checkpoint: {name} is not in the list of state dataclasses")
        return {"__dataclass__": name, "fields": _encode(dict(vars(value)), arrays)}
    raise TypeError(f"checkpoint: cannot store a {type(value).__name__}")


def _decode(value: Any, arrays: dict[str, np.ndarray]) -> Any:
    """Inverse of ``_encode``."""
    if isinstance(value, list):
        return [_decode(v, arrays) for v in value]
    if not isinstance(value, dict):
        return value
    if "__array__" in value:
        return arrays[value["__array__"]].copy()
    if "__bytes__" in value:
        return arrays[value["__bytes__"]].tobytes()
    if "__tuple__" in value:
        return tuple(_decode(v, arrays) for v in value["__tuple__"])
    if "__mesh__" in value:
        vol, coordinates = value["__mesh__"]
        return _mesh(arrays[vol].tobytes(), arrays[coordinates])
    if "__dataclass__" in value:
        name = value["__dataclass__"]
        if name not in _DATACLASSES:
            raise ValueError(f"unknown state class {name!r}")
        module, qualname = name.split(":")
        cls = getattr(importlib.import_module(module), qualname)
        obj = cls.__new__(cls)
        obj.__dict__.update(_decode(value["fields"], arrays))
        return obj
    return {k: _decode(v, arrays) for k, v in value.items()}


def _vol_text(mesh: ngs.Mesh) -> bytes:
    """The mesh in Netgen's text format: vertices, triangles, boundary segments and the
    boundary names that deposition changes."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "mesh.vol"
        mesh.ngmesh.Save(str(path))
        return path.read_bytes()


def _mesh(vol: bytes, coordinates: np.ndarray) -> ngs.Mesh:
    """The mesh from ``_vol_text``, with its exact vertex coordinates."""
    from netgen.meshing import Mesh as NetgenMesh

    if b"\nmesh3d" not in vol[:4096]:
        raise ValueError("the stored mesh is not in Netgen's .vol format")
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "mesh.vol"
        path.write_bytes(vol)
        ngmesh = NetgenMesh(dim=2)
        ngmesh.Load(str(path))
    if ngmesh.Coordinates().shape != coordinates.shape:
        raise ValueError("the stored mesh and its coordinates disagree")
    ngmesh.Coordinates()[:] = coordinates
    return ngs.Mesh(ngmesh)


def _read_pickle(path: Path) -> SimulationState:
    """An earlier granflow's pickled checkpoint (trusted by the caller)."""
    import pickle

    try:
        state = pickle.loads(path.read_bytes())  # noqa: S301 - the user said they trust it
    except Exception as exc:  # a truncated or foreign file
        raise CheckpointError(f"cannot read the checkpoint '{path}': {exc}") from None
    if not isinstance(state, SimulationState) or state.version != 1:
        raise CheckpointError(f"the checkpoint '{path}' was written by another version of "
                              "granflow; rerun the case")
    if isinstance(state.scenario.get("mesh"), bytes):   # then pickled on its own
        state.scenario["mesh"] = pickle.loads(state.scenario["mesh"])  # noqa: S301
    state.version = STATE_VERSION
    return state
