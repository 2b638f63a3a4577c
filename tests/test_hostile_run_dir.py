"""A run directory from someone else is data: one hostile directory per class, each read by
`granflow plot`, `granflow resume` and `granflow.load`, gives one line (a typed error from
the API), never a hang, a crash or a write outside the directory.

The classes: a link planted at a temporary or a final file name, or in a folder's place;
a FIFO, a folder or a /dev/zero link where a file belongs; a CSV that is not UTF-8; XML
with entities; a VTU or a checkpoint that inflates without bound or is cut short; a
damaged VTU (meshio would exit); a checkpoint whose mesh indexes vertices that do not exist
(Netgen's reader crashed on it). All from one coarse run (about 2 s).
"""

from __future__ import annotations

import base64
import contextlib
import io
import json
import os
import re
import shutil
import zipfile
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

import granflow
import granflow.runner as runner
from granflow.cli import main
from granflow.config import ConfigError
from granflow.io.checkpoint import CHECKPOINT_FILE, CheckpointError, write_checkpoint
from granflow.io.run_dir import SUMMARY_LIST_LIMIT, RunDir, RunDirError
from granflow.io.run_state import SimulationState

COARSE = {"geometry.width": 0.1, "geometry.height": 0.1, "mesh.size": 0.025,
          "time.t_end": 0.03, "time.output_times": [0.01, 0.02], "output.checkpoint_every": 10}
OUTSIDE = "outside, must stay\n"
pytestmark = pytest.mark.timeout(120)     # a hang is a failure, not a stuck suite


@pytest.fixture(scope="module")
def base(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A coarse run as a kill leaves it: every file written, status "running", and a
    checkpoint a few steps before the end (so that a resume reads every file, computes
    and writes them again)."""
    root = tmp_path_factory.mktemp("base") / "run"
    saved: dict[int, bytes] = {}
    with pytest.MonkeyPatch.context() as patch:
        def keep(run_dir: RunDir, state: SimulationState) -> Path:
            path = write_checkpoint(run_dir, state)
            saved[state.step] = path.read_bytes()
            return path
        patch.setattr(runner, "write_checkpoint", keep)
        granflow.run("rectangle-rigid", COARSE, root)
    (root / CHECKPOINT_FILE).write_bytes(saved[sorted(saved)[-2]])
    summary = json.loads((root / "summary.json").read_text())
    (root / "summary.json").write_text(json.dumps(summary | {"status": "running"}))
    return root


@pytest.fixture
def hostile(base: Path, tmp_path: Path) -> Callable[[str, Callable[[Path], object]], Path]:
    """A copy of ``base`` with ``edit`` applied to one of its paths; an outside file and an
    outside folder beside it, for links to point at."""
    (tmp_path / "outside.txt").write_text(OUTSIDE)
    (tmp_path / "outside").mkdir()

    def make(relpath: str, edit: Callable[[Path], object]) -> Path:
        root = tmp_path / "run"
        shutil.copytree(base, root)
        edit(root / relpath)
        return root

    return make


def outside_untouched(root: Path) -> bool:
    return ((root.parent / "outside.txt").read_text() == OUTSIDE
            and not any((root.parent / "outside").iterdir()))


def cli(*args: str | Path) -> tuple[int, list[str]]:
    """Exit code and the error lines of ``granflow ARGS`` (notes left out)."""
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main([str(a) for a in args])
    lines = [line for line in err.getvalue().splitlines() if "granflow: note:" not in line]
    assert "Traceback" not in err.getvalue()
    return code, lines


def load_everything(root: Path) -> None:
    """What a user reads from a run directory through the API."""
    run = granflow.load(root)
    run.summary, run.config, run.diagnostics, run.surfaces  # noqa: B018
    for t in run.output_times:
        run.fields(t)


def link_outside(path: Path) -> None:
    """``path`` becomes a link to the outside file beside the run directory."""
    outside = next(p / "outside.txt" for p in path.parents if (p / "outside.txt").exists())
    path.parent.mkdir(exist_ok=True)
    path.unlink(missing_ok=True)
    path.symlink_to(outside)


def replace_with(kind: str) -> Callable[[Path], None]:
    def edit(path: Path) -> None:
        if path.is_dir():
            shutil.rmtree(path)
        path.unlink(missing_ok=True)
        if kind == "fifo":
            os.mkfifo(path)
        elif kind == "folder":
            path.mkdir()
        elif kind == "dev-zero":
            path.symlink_to("/dev/zero")
    return edit


# ---------------------------------------------------------------- links: nothing outside


@pytest.mark.parametrize("relpath", [
    "fields/.fields.pvd.tmp", "fields/.fields_00003.vtu.tmp", "plots/.speed.tmp.gif",
    "plots/.free_surface.tmp.png", "fields/fields.pvd", "diagnostics.csv", "summary.json"])
def test_a_planted_link_never_makes_resume_or_plot_write_outside(hostile, relpath: str) -> None:
    root = hostile(relpath, link_outside)
    code, lines = cli("resume", root, "--quiet")     # computes, writes and plots
    assert code == 0 and lines == [], lines
    assert json.loads((root / "summary.json").read_text())["status"] == "completed"
    assert outside_untouched(root)


@pytest.mark.parametrize("folder", ["plots", "fields", "profiles"])
def test_a_linked_folder_is_refused(hostile, folder: str) -> None:
    root = hostile(folder, lambda p: (shutil.rmtree(p), p.symlink_to(p.parents[1] /
                                                                      "outside")))
    code, lines = cli("resume", root, "--quiet")
    assert code == 2 and len(lines) == 1 and "not a folder of the run directory" in lines[0]
    code, lines = cli("plot", root)
    assert code in (0, 2) and len(lines) <= 1
    assert outside_untouched(root)


# ---------------------------------------------------------------- special files: no hang


@pytest.mark.parametrize("kind, relpath", [
    ("fifo", "summary.json"), ("fifo", "diagnostics.csv"),
    ("fifo", "profiles/free_surface_t0.010.csv"), ("fifo", "fields/fields.pvd"),
    ("fifo", CHECKPOINT_FILE), ("folder", "diagnostics.csv"), ("folder", "fields/fields.pvd"),
    ("folder", CHECKPOINT_FILE), ("dev-zero", "summary.json"),
    ("dev-zero", "fields/fields_00001.vtu"), ("dev-zero", "frames/frame_00000.npz"),
    ("dev-zero", "profiles/free_surface_final.csv")])
def test_a_special_file_where_a_file_belongs_is_one_line(hostile, kind: str,
                                                         relpath: str) -> None:
    root = hostile(relpath, replace_with(kind))
    command = ["resume", root, "--quiet"] if relpath == CHECKPOINT_FILE else ["plot", root]
    code, lines = cli(*command)
    assert code in (0, 2) and len(lines) <= 1, (command, lines)
    with contextlib.suppress(RunDirError, ConfigError, CheckpointError):
        load_everything(root)


def test_a_fifo_config_is_not_a_run_directory(hostile) -> None:
    root = hostile("config.toml", replace_with("fifo"))
    code, lines = cli("resume", root)
    assert code == 2 and lines == [f"granflow: error: '{root}' is not a granflow run "
                                   "directory (no config.toml)"]
    with pytest.raises(RunDirError, match="not a granflow run directory"):
        granflow.load(root)


# ---------------------------------------------------------------- contents


def not_utf8(path: Path) -> None:
    data = path.read_bytes()
    path.write_bytes(data[:20] + b"\xff\xfe\x80" + data[20:])


@pytest.mark.parametrize("relpath", ["diagnostics.csv", "profiles/free_surface_t0.010.csv"])
def test_a_csv_that_is_not_utf8_is_one_line(hostile, relpath: str) -> None:
    root = hostile(relpath, not_utf8)
    code, lines = cli("plot", root)
    assert code == 2 and len(lines) == 1 and "is not UTF-8 text" in lines[0]
    with pytest.raises(RunDirError, match="not UTF-8"):
        load_everything(root)


LAUGHS = ('<?xml version="1.0"?><!DOCTYPE l [<!ENTITY a "aaaaaaaaaa">'
          '<!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;"><!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;">]>'
          '<VTKFile type="Collection"><Collection><DataSet timestep="&c;" file="f.vtu"/>'
          '</Collection></VTKFile>')
EXTERNAL = ('<?xml version="1.0"?><!DOCTYPE x [<!ENTITY e SYSTEM "file:///etc/passwd">]>'
            '<VTKFile type="Collection"><Collection><DataSet timestep="0" file="&e;"/>'
            '</Collection></VTKFile>')
TRAVERSAL = ('<?xml version="1.0"?><VTKFile type="Collection"><Collection>'
             '<DataSet timestep="0" file="../../outside.txt"/></Collection></VTKFile>')


@pytest.mark.parametrize("text, why", [(LAUGHS, "refused"), (EXTERNAL, "refused"),
                                       (TRAVERSAL, "not a snapshot file")],
                         ids=["entity-expansion", "external-entity", "path-traversal"])
def test_an_index_with_entities_or_paths_is_refused(hostile, text: str, why: str) -> None:
    root = hostile("fields/fields.pvd", lambda p: p.write_text(text))
    with pytest.raises(RunDirError, match=why):
        granflow.load(root).output_times  # noqa: B018


def vtu_bomb(path: Path) -> None:
    """The first compressed array's data as one block declared 16 bytes that inflates to
    64 MB."""
    text = path.read_text()
    block = __import__("zlib").compress(b"\0" * 2**26, 9)
    header = np.array([1, 16, 16, len(block)], dtype="<u4").tobytes()
    payload = base64.b64encode(header).decode() + base64.b64encode(block).decode()
    match = re.search(r'(<DataArray[^>]*format="binary"[^>]*>)([^<]*)(</DataArray>)', text)
    assert match is not None
    path.write_text(text[:match.start(2)] + payload + text[match.end(2):])


def vtu_damaged(path: Path) -> None:
    """Valid XML that meshio cannot read (meshio.read would print and call sys.exit)."""
    path.write_text('<?xml version="1.0"?><VTKFile type="UnstructuredGrid"><UnstructuredGrid>'
                    '<Piece NumberOfPoints="3" NumberOfCells="1"></Piece></UnstructuredGrid>'
                    '</VTKFile>')


@pytest.mark.parametrize("edit, why", [
    (vtu_bomb, "does not inflate to its declared size"),
    (vtu_damaged, "cannot read the snapshot"),
    (lambda p: p.write_bytes(p.read_bytes()[:len(p.read_bytes()) // 2]), "not valid XML")],
    ids=["bomb", "damaged", "cut"])
def test_run_fields_raises_one_error_and_never_exits(hostile, edit, why: str) -> None:
    root = hostile("fields/fields_00001.vtu", edit)
    run = granflow.load(root)
    with pytest.raises(RunDirError, match=why):
        run.fields(run.output_times[1])


def checkpoint_bomb(path: Path) -> None:
    """A small archive whose one member inflates to 64 MB of zeros (the limit is lowered to
    16 MB below: the same as 2 GiB against the real limit, in a fraction of the time)."""
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
        archive.writestr("__state__.npy", np.lib.format.magic(1, 0) + b"\0" * 2**26)
    path.write_bytes(buffer.getvalue())
    assert len(buffer.getvalue()) < 2**20


@pytest.mark.parametrize("edit, why", [
    (checkpoint_bomb, "declare"),
    (lambda p: p.write_bytes(p.read_bytes()[:len(p.read_bytes()) // 2]),
     "not a readable NumPy archive")], ids=["bomb", "cut"])
def test_a_bad_checkpoint_is_one_line_before_anything_runs(hostile, edit, why: str,
                                                         monkeypatch: pytest.MonkeyPatch
                                                         ) -> None:
    monkeypatch.setattr("granflow.io.checkpoint.CHECKPOINT_LIMIT", 2**24)
    root = hostile(CHECKPOINT_FILE, edit)
    before = (root / "diagnostics.csv").read_bytes()
    code, lines = cli("resume", root, "--quiet")
    assert code == 2 and len(lines) == 1 and why in lines[0], lines
    assert (root / "diagnostics.csv").read_bytes() == before      # nothing was written


def state_member(path: str, value: object) -> Callable[[Path], None]:
    """An edit of the checkpoint: its state's member at ``path`` (dotted) set to ``value``."""
    def edit(checkpoint: Path) -> None:
        with np.load(checkpoint, allow_pickle=False) as archive:
            arrays = {name: archive[name] for name in archive.files}
        tree = json.loads(arrays["__state__"].tobytes())
        *parents, last = path.split(".")
        node = tree
        for key in parents:
            node = node[key]
        node[last] = value
        arrays["__state__"] = np.frombuffer(json.dumps(tree).encode(), dtype=np.uint8)
        buffer = io.BytesIO()
        np.savez(buffer, **arrays)
        checkpoint.write_bytes(buffer.getvalue())
    return edit


@pytest.mark.parametrize("path, value", [
    ("scenario.mover.initial_area", "x"), ("scenario.history", "abc"),
    ("scenario.history.t", "abc"), ("scenario.remeshes", "x"), ("loop.t", "abc"),
    ("outputs.vtk_entries", [[0.0, "../../outside.txt"]])])
def test_a_tampered_state_member_is_one_line_before_anything_runs(hostile, path: str,
                                                                 value: object) -> None:
    """Each of the first four ended in a traceback once the run had started."""
    root = hostile(CHECKPOINT_FILE, state_member(path, value))
    before = (root / "diagnostics.csv").read_bytes()
    code, lines = cli("resume", root, "--quiet")
    assert code == 2 and len(lines) == 1 and f"{path}" in lines[0], lines
    assert (root / "diagnostics.csv").read_bytes() == before      # nothing was written
    assert outside_untouched(root)


def unnamed_bombs(checkpoint: Path) -> None:
    """Two members nothing in the state names, each 64 MB of deflated zeros (the limit is
    lowered to 16 MB below: as 2 x 512 MiB against the real one)."""
    with zipfile.ZipFile(checkpoint, "a", zipfile.ZIP_DEFLATED) as archive:
        for name in ("extra1.npy", "extra2.npy"):
            with archive.open(name, "w", force_zip64=True) as member:
                member.write(np.lib.format.magic(1, 0))
                for _ in range(64):
                    member.write(b"\0" * 2**20)


def test_members_the_state_does_not_name_are_never_read(hostile, monkeypatch:
                                                         pytest.MonkeyPatch) -> None:
    import granflow.io.untrusted as untrusted

    monkeypatch.setattr("granflow.io.checkpoint.CHECKPOINT_LIMIT", 2**24)
    read: list[str] = []
    member = untrusted._read_member
    monkeypatch.setattr(untrusted, "_read_member", lambda archive, info, path: (
        read.append(info.filename), member(archive, info, path))[1])
    root = hostile(CHECKPOINT_FILE, unnamed_bombs)
    assert (root / CHECKPOINT_FILE).stat().st_size < 2**21
    code, lines = cli("resume", root, "--quiet")
    assert code == 0 and lines == [], lines
    assert read and not {"extra1.npy", "extra2.npy"} & set(read)


def test_the_members_a_state_names_are_capped_together(hostile, monkeypatch:
                                                        pytest.MonkeyPatch) -> None:
    """Two fields of 10 MB each, each within the per-member limit, together over it."""
    monkeypatch.setattr("granflow.io.checkpoint.CHECKPOINT_LIMIT", 2**24)

    def grow(checkpoint: Path) -> None:
        with np.load(checkpoint, allow_pickle=False) as archive:
            arrays = {name: archive[name] for name in archive.files}
        tree = json.loads(arrays["__state__"].tobytes())
        fields = tree["scenario"]["fields"]
        for name in ("previous", "before_previous"):
            arrays[fields[name]["__array__"]] = np.zeros(10 * 2**17)
        buffer = io.BytesIO()
        np.savez_compressed(buffer, **arrays)
        checkpoint.write_bytes(buffer.getvalue())

    root = hostile(CHECKPOINT_FILE, grow)
    code, lines = cli("resume", root, "--quiet")
    assert code == 2 and len(lines) == 1 and "together (at most 16 MB)" in lines[0], lines


PLANTED = ["plots/holiday.png", "profiles/my_final.csv", "fields/fields_99999.vtu",
           "frames/frame_99999.npz", "notes.txt"]


def test_force_keeps_the_users_files_named_as_the_runs(hostile) -> None:
    """--force deletes what the run's manifest lists: a user's files, even named as a run
    names its own, stay; the old run's files are gone (none of its 3 VTUs is left)."""
    root = hostile("notes.txt", lambda p: p.write_text("mine\n"))
    for name in PLANTED:
        (root / name).write_text("mine\n")
    overrides = [f"--set={key}={value}" for key, value in (COARSE | {"time.t_end": 0.005,
                                                                     "time.output_times": []
                                                                     }).items()]
    code, lines = cli("run", "rectangle-rigid", *overrides, "--out", root, "--force", "--quiet")
    assert code == 0 and lines == [], lines
    assert all((root / name).read_text() == "mine\n" for name in PLANTED)
    assert sorted(p.name for p in (root / "fields").glob("fields_0*.vtu")) == [
        "fields_00000.vtu", "fields_00001.vtu"]               # the new run's only
    assert not list((root / "profiles").glob("*_t0.0[12]0.csv"))   # the old output times'


@pytest.mark.parametrize("count", [10**6, 500])
def test_a_summary_of_many_events_is_bounded_and_so_is_its_figure(
        hostile, count: int, monkeypatch: pytest.MonkeyPatch) -> None:
    """10^6 remesh times drew one line each, for minutes and with no word: a list longer
    than the summary allows is left out (as a member of the wrong type); 500 are counted in
    the figure's legend, not drawn."""
    from matplotlib.axes import Axes

    def edit(path: Path) -> None:
        summary = json.loads(path.read_text())
        path.write_text(json.dumps(summary | {"remesh_times_s": [1e-6 * i
                                                                 for i in range(count)]}))

    root = hostile("summary.json", edit)
    marks: list[float] = []
    axvline = Axes.axvline
    monkeypatch.setattr(Axes, "axvline", lambda self, x=0, *a, **k: (
        marks.append(x), axvline(self, x, *a, **k))[1])
    code, lines = cli("plot", root)
    assert code == 0 and lines == [], lines
    assert ("remesh_times_s" in RunDir.summary(root)) == (count <= SUMMARY_LIST_LIMIT)
    assert len(marks) < 10 and (root / "plots" / "front_and_energy.png").is_file()


WIDE = ",".join(f"c{i}" for i in range(10**5)) + "\n"


@pytest.mark.parametrize("command", ["plot", "resume"])
def test_an_error_line_stays_short(hostile, command: str) -> None:
    """A diagnostics file 100k columns wide put them all in its one error line."""
    root = hostile("diagnostics.csv", lambda p: p.write_text(WIDE + ",".join(["x"] * 10**5)))
    code, lines = cli(command, root, *(["--quiet"] if command == "resume" else []))
    assert code == 2 and len(lines) == 1 and len(lines[0]) < 500, lines


def test_a_column_of_mixed_types_is_one_line_and_no_warning(hostile, recwarn) -> None:
    """A word among 400k numbers: pandas warned (DtypeWarning) before granflow's line."""
    rows = [f"{i * 1e-6},1" for i in range(2 * 10**5)]
    root = hostile("diagnostics.csv", lambda p: p.write_text(
        "\n".join(["t,dt", *rows, "x,1", *rows]) + "\n"))
    code, lines = cli("plot", root)
    assert code == 2 and len(lines) == 1 and "column 't' is not numbers" in lines[0], lines
    assert not [w for w in recwarn if "DtypeWarning" in w.category.__name__]


def test_a_snapshot_error_stays_short(hostile) -> None:
    """An index of 100k snapshots put their 100k times in one error."""
    rows = "".join(f'<DataSet timestep="{i}" file="fields_00000.vtu"/>' for i in range(10**5))
    root = hostile("fields/fields.pvd", lambda p: p.write_text(
        f'<?xml version="1.0"?><VTKFile type="Collection"><Collection>{rows}'
        "</Collection></VTKFile>"))
    with pytest.raises(ValueError, match="no snapshot at t = 0.5 s") as err:
        granflow.load(root).fields(0.5)
    assert len(str(err.value)) < 300


def test_a_full_disk_ends_with_one_line(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The disk fills while the figures are drawn: every write from then on fails with
    ENOSPC (the figures', then the error report's)."""
    import errno

    import granflow.io.atomic as atomic_module

    full = []
    atomic = atomic_module._atomic

    def no_space(target: Path, data: bytes | None = None):  # type: ignore[no-untyped-def]
        if full or "plots" in Path(target).parts:
            full.append(target)
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(target))
        return atomic(target, data)

    monkeypatch.setattr(atomic_module, "_atomic", no_space)
    overrides = [f"--set={key}={value}" for key, value in COARSE.items()]
    code, lines = cli("run", "rectangle-rigid", *overrides, "--out", tmp_path / "run", "--quiet")
    assert full and code == 2 and len(lines) == 1
    assert "No space left on device" in lines[0]


def padded_state(path: Path) -> None:
    """The state's JSON padded with 64 MB of spaces: 64 KB on disk once deflated (as 500
    MiB of spaces, which resumed at 1.7 GB of memory, against the real limit)."""
    with np.load(path, allow_pickle=False) as archive:
        arrays = {name: archive[name] for name in archive.files}
    text = arrays["__state__"].tobytes() + b" " * 2**26
    arrays["__state__"] = np.frombuffer(text, dtype=np.uint8)
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **arrays)
    path.write_bytes(buffer.getvalue())


def test_a_padded_state_is_one_line_before_anything_is_read(hostile) -> None:
    root = hostile(CHECKPOINT_FILE, padded_state)
    assert (root / CHECKPOINT_FILE).stat().st_size < 2**20
    before = (root / "diagnostics.csv").read_bytes()
    code, lines = cli("resume", root, "--quiet")
    assert code == 2 and len(lines) == 1 and "declares a state of" in lines[0], lines
    assert (root / "diagnostics.csv").read_bytes() == before


def test_the_state_and_the_members_it_names_are_capped_together(
        hostile, monkeypatch: pytest.MonkeyPatch) -> None:
    """A state of 10 MB (within its own limit) and fields of 8 MB: 18 MB together, over the
    16 MB the test allows a checkpoint in all."""
    monkeypatch.setattr("granflow.io.checkpoint.CHECKPOINT_LIMIT", 2**24)

    def grow(checkpoint: Path) -> None:
        with np.load(checkpoint, allow_pickle=False) as archive:
            arrays = {name: archive[name] for name in archive.files}
        tree = json.loads(arrays["__state__"].tobytes())
        fields = tree["scenario"]["fields"]
        arrays[fields["previous"]["__array__"]] = np.zeros(2**20)
        text = json.dumps(tree).encode() + b" " * (10 * 2**20)
        arrays["__state__"] = np.frombuffer(text, dtype=np.uint8)
        buffer = io.BytesIO()
        np.savez_compressed(buffer, **arrays)
        checkpoint.write_bytes(buffer.getvalue())

    root = hostile(CHECKPOINT_FILE, grow)
    code, lines = cli("resume", root, "--quiet")
    assert code == 2 and len(lines) == 1 and "together (at most" in lines[0], lines


@pytest.mark.parametrize("path, value, member", [
    ("outputs.remesh_times", [1e-9 * i for i in range(10**6)], "outputs.remesh_times"),
    ("outputs.deposition_times", [1e-9 * i for i in range(10**6)],
     "outputs.deposition_times"),
    ("loop.steps_policy.fields.dt", float("nan"), "loop.steps_policy.dt"),
    ("loop.steps_policy.fields.dt_max", -1.0, "loop.steps_policy.dt_max"),
    ("loop.steps_policy.fields.tol", float("nan"), "loop.steps_policy.tol"),
    ("loop.steps_policy.fields.stops", [-1.0, 0.03], "loop.steps_policy.stops[0]"),
], ids=["remesh-times", "deposition-times", "dt-nan", "dt-max-negative", "tol-nan",
        "stop-negative"])
def test_a_state_that_would_run_wrong_is_one_line_before_anything_runs(
        hostile, path: str, value: object, member: str) -> None:
    """10^6 remesh times resumed and wrote a summary its own reader refused (the command
    said "failed" and no more); a NaN or negative step, tolerance or stop resumed and ran,
    or failed later."""
    root = hostile(CHECKPOINT_FILE, state_member(path, value))
    before = (root / "diagnostics.csv").read_bytes()
    code, lines = cli("resume", root, "--quiet")
    assert code == 2 and len(lines) == 1 and member in lines[0], lines
    assert (root / "diagnostics.csv").read_bytes() == before


def test_an_unreadable_summary_says_why(base: Path,
                                        capsys: pytest.CaptureFixture[str]) -> None:
    """When what a run writes last cannot be read back (RunDir.summary gives {}), the
    command says so in one line, not only "failed"."""
    from granflow.app.cli import _report

    assert _report({}, RunDir(base), printed=True) == 1
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 1 and "summary.json' is missing or cannot be read" in lines[0], lines


def test_resuming_an_earlier_granflows_run_lists_only_its_own_files(hostile) -> None:
    """A run directory from before the manifest: resumed, it lists the files its own
    records name; a later --force deletes those and the resumed session's, and leaves a
    user's files of layout-like names and temporary-like names."""
    from granflow.io.run_dir import MANIFEST

    planted = [*PLANTED, ".notes.tmp.txt", "fields/.mine.abcdefgh.tmp.txt",
               "plots/.holiday.tmp"]
    root = hostile(MANIFEST, lambda p: p.unlink())
    for name in planted:
        (root / name).write_text("mine\n")
    code, lines = cli("resume", root, "--quiet")
    assert code == 0 and lines == [], lines
    listed = (root / MANIFEST).read_text().splitlines()
    assert "fields/fields_00001.vtu" in listed and "checkpoint/state.npz" in listed
    assert not set(planted) & set(listed)
    overrides = [f"--set={key}={value}" for key, value in (COARSE | {"time.t_end": 0.005,
                                                                     "time.output_times": []
                                                                     }).items()]
    code, lines = cli("run", "rectangle-rigid", *overrides, "--out", root, "--force", "--quiet")
    assert code == 0 and lines == [], lines
    assert all((root / name).read_text() == "mine\n" for name in planted)
    assert not list((root / "profiles").glob("*_t0.0[12]0.csv"))   # the earlier run's
