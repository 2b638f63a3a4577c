"""Checkpoint files: the run's ``SimulationState`` as data only, in ``checkpoint/state.npz``.

A checkpoint may come from someone else's run directory, so reading one must not execute
code nor crash the process. The state's nested dicts and lists go to JSON (stored inside the
NumPy archive), its arrays to archive entries, read back by ``io/untrusted.py`` (each member
checked before it is read, never pickle); the few dataclasses of the state are rebuilt by
name from a fixed list (``_DATACLASSES``) with their own field names only; a mesh is stored
as arrays (vertices, triangles, labelled boundary segments), checked, and rebuilt with
``geometry/mesh.build_mesh``. Checkpoints of version 2 stored the mesh in Netgen's text
format: it is parsed strictly (``io/netgen_text.py``), never given to Netgen's reader.
Written atomically (temporary file, fsync, rename), so a run killed while writing leaves
the previous checkpoint intact.

Checkpoints of granflow 0.1 were pickles (``checkpoint/state.pkl``): they are not read (a
pickle can execute any code); such a run is run again.
"""

from __future__ import annotations

import dataclasses
import importlib
import io
import json
import zipfile
from pathlib import Path
from typing import Any

import ngsolve as ngs
import numpy as np

from granflow.geometry.mesh import LABELS, build_mesh
from granflow.io.netgen_text import MeshArrays, parse_vol
from granflow.io.run_dir import RunDir
from granflow.io.run_state import STATE_VERSION, SimulationState
from granflow.io.untrusted import MB, RunDirError, load_npz, read_bytes

CHECKPOINT_FILE = "checkpoint/state.npz"
LEGACY_CHECKPOINT_FILE = "checkpoint/state.pkl"
# what reading a checkpoint may decode, in all: its state's JSON and the members the state
# names, together (the largest mesh allowed, 100,000 triangles, needs ~100 MB); members it
# does not name are never read
CHECKPOINT_LIMIT = 512 * MB
# the state's own JSON (its counts, times and lists; the arrays are members): about 50 kB
# for a thousand steps, and it grows with the run's events only
STATE_JSON_LIMIT = 32 * MB
READABLE_VERSIONS = (2, STATE_VERSION)
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


def read_checkpoint(root: Path) -> SimulationState:
    """The state saved in RUN_DIR's checkpoint (data only); ``CheckpointError`` with one
    line if there is none or it is not one granflow wrote."""
    path = Path(root) / CHECKPOINT_FILE
    legacy = Path(root) / LEGACY_CHECKPOINT_FILE
    if not path.exists() and legacy.exists():
        raise CheckpointError(pickle_refusal(root))
    if not path.exists() and not path.is_symlink():
        raise CheckpointError(f"'{root}' holds no checkpoint ({CHECKPOINT_FILE}); a run "
                              "checkpoints every output.checkpoint_every steps, when it is "
                              "interrupted, when it fails and when it ends")
    try:
        data = read_bytes(path, CHECKPOINT_LIMIT)
        declared = _declared_size(data, _STATE_ENTRY)
        if declared > STATE_JSON_LIMIT:
            raise CheckpointError(f"the checkpoint '{path}' declares a state of {declared} "
                                  f"bytes (at most {STATE_JSON_LIMIT // MB} MB; a run's is "
                                  "tens of kB)")
        state = load_npz(data, path, STATE_JSON_LIMIT, names=[_STATE_ENTRY])[_STATE_ENTRY]
        if state.dtype != np.uint8 or state.ndim != 1:
            raise ValueError(f"it has no {_STATE_ENTRY} entry")
        tree = json.loads(state.tobytes().decode("utf-8"))
        if not isinstance(tree, dict) or tree.get("version") not in READABLE_VERSIONS:
            raise CheckpointError(f"the checkpoint '{path}' was written by another version "
                                  "of granflow; rerun the case")
        arrays = load_npz(data, path, CHECKPOINT_LIMIT, names=sorted(_named_members(tree)),
                          spent=state.nbytes)        # the cap is on the state and them
        parts = [_decode(tree.get(part), arrays) for part in ("loop", "scenario", "outputs")]
        if not all(isinstance(part, dict) for part in parts):
            raise ValueError("its state is not made of the loop's, the scenario's and the "
                             "outputs' parts")
        return SimulationState(loop=parts[0], scenario=parts[1], outputs=parts[2])
    except CheckpointError:
        raise
    except RunDirError as err:
        raise CheckpointError(f"cannot read the checkpoint: {err}") from None
    except Exception as exc:  # a truncated, foreign or tampered file; too deep a nesting
        raise CheckpointError(f"cannot read the checkpoint '{path}': "
                              f"{type(exc).__name__}: {str(exc)[:300]}") from None


def _declared_size(data: bytes, name: str) -> int:
    """The size the archive ``data`` declares for its member ``name`` (0 if it has none, or
    is no archive: ``load_npz`` then says what it is)."""
    try:
        with zipfile.ZipFile(io.BytesIO(data)) as archive:
            found = [i for i in archive.infolist() if i.filename == f"{name}.npy"]
    except (zipfile.BadZipFile, zipfile.LargeZipFile, OSError, ValueError, EOFError):
        return 0
    return found[0].file_size if found else 0


def pickle_refusal(root: Path) -> str:
    """Why a checkpoint of granflow 0.1 (a pickle) is not read, and what to do instead."""
    return (f"'{Path(root) / LEGACY_CHECKPOINT_FILE}' is a checkpoint of granflow 0.1, a "
            "pickle, which can execute code when read: granflow no longer reads it; run the "
            f"case again with `granflow run {Path(root) / 'config.toml'} --out NEW_DIR`")


def _named_members(tree: Any) -> set[str]:
    """The archive members the state's JSON refers to (its arrays, bytes and meshes)."""
    names: set[str] = set()
    stack = [tree]
    while stack:
        value = stack.pop()
        if isinstance(value, dict):
            for tag in ("__array__", "__bytes__"):
                if tag in value:
                    names.add(_member(value[tag]))
            mesh = value.get("__mesh__")
            if isinstance(mesh, list):                 # version 2: text and coordinates
                names.update(map(_member, mesh))
            stack.extend(value.values())
        elif isinstance(value, list):
            stack.extend(value)
    return names


def _member(name: Any) -> str:
    if not isinstance(name, str):
        raise ValueError(f"its state names an array by {str(name)[:40]!r}")
    return name


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
        return {"__mesh__": {name: _encode(part, arrays)
                             for name, part in _mesh_arrays(value).items()}}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        name = f"{type(value).__module__}:{type(value).__qualname__}"
        if name not in _DATACLASSES:
            raise TypeError(f"checkpoint: {name} is not in the list of state dataclasses")
        return {"__dataclass__": name, "fields": _encode(
            {f.name: getattr(value, f.name) for f in dataclasses.fields(value)}, arrays)}
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
        return _mesh(value["__mesh__"], arrays)
    if "__dataclass__" in value:
        return _dataclass(value["__dataclass__"], _decode(value["fields"], arrays))
    return {k: _decode(v, arrays) for k, v in value.items()}


def _dataclass(name: Any, fields: Any) -> Any:
    """An instance of a listed state dataclass with its own fields only, each given or
    with a default (earlier checkpoints left out a field never set after its default)."""
    if name not in _DATACLASSES:
        raise ValueError(f"unknown state class {str(name)[:60]!r}")
    module, qualname = name.split(":")
    cls = getattr(importlib.import_module(module), qualname)
    defaults = {f.name: f.default for f in dataclasses.fields(cls)
                if f.default is not dataclasses.MISSING}
    names = {f.name for f in dataclasses.fields(cls)}
    if not isinstance(fields, dict) or not set(defaults) | set(fields) >= names or \
            not set(fields) <= names:
        raise ValueError(f"the state of {qualname} does not have its fields {sorted(names)}")
    obj = cls.__new__(cls)
    obj.__dict__.update(defaults | fields)
    return obj


def _mesh_arrays(mesh: ngs.Mesh) -> dict[str, np.ndarray]:
    """Vertices, triangles and boundary segments (0-based) with their label numbers (in
    ``LABELS``): what ``build_mesh`` rebuilds the same mesh from, element for element."""
    ngmesh = mesh.ngmesh
    segments = ngmesh.Elements1D().NumPy()
    labels = [LABELS.index(ngmesh.GetBCName(int(i) - 1)) for i in segments["index"]]
    return {"points": ngmesh.Coordinates().copy(),
            "triangles": ngmesh.Elements2D().NumPy()["nodes"][:, :3].astype(np.int64) - 1,
            "segments": segments["nodes"][:, :2].astype(np.int64) - 1,
            "labels": np.array(labels, dtype=np.int64)}


def _mesh(stored: Any, arrays: dict[str, np.ndarray]) -> ngs.Mesh:
    """The mesh of ``_mesh_arrays`` (version 3) or of Netgen's text and the exact vertex
    coordinates (version 2), checked before it is built."""
    if isinstance(stored, list) and len(stored) == 2:          # version 2
        text, coordinates = (arrays[key] for key in stored)
        mesh = parse_vol(text.tobytes().decode("utf-8"))
        if coordinates.shape != mesh.points.shape:
            raise ValueError("the stored mesh and its coordinates disagree")
        mesh = MeshArrays(coordinates, mesh.triangles, mesh.segments, mesh.labels)
    else:
        parts = {name: _decode(stored[name], arrays)
                 for name in ("points", "triangles", "segments", "labels")}
        codes = np.asarray(parts["labels"])
        if codes.dtype.kind not in "iu" or codes.ndim != 1 or (
                codes.size and (codes.min() < 0 or codes.max() >= len(LABELS))):
            raise ValueError("the stored mesh's boundary labels are not label numbers")
        mesh = MeshArrays(np.asarray(parts["points"]), np.asarray(parts["triangles"]),
                          np.asarray(parts["segments"]), [LABELS[i] for i in codes])
    mesh.check()
    return build_mesh(mesh.points, mesh.triangles, mesh.segments, mesh.labels)
