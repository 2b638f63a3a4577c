"""A 3D column killed after its first remesh and resumed from its checkpoint is the
uninterrupted run, to the digit as in 2D (``tests/test_resume_extend.py``): the checkpoint
holds the lofted mesh as arrays, element for element, and the factorisations start afresh
after a checkpoint in both runs."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pandas as pd
import pytest

import granflow
import granflow.app.run as runner
from granflow.io.checkpoint import write_checkpoint
from granflow.io.run_dir import RunDir
from granflow.io.run_state import SimulationState

# half a 10 cm channel, the coarsest mesh: the first remesh comes near t = 0.12 s (step
# ~127), checkpoints every 5 steps, the run goes on to 0.135 s (about 20 steps more)
T_END = 0.135
CASE = {"geometry.dimension": 3, "boundary.channel_width": 0.1, "mesh.size": 0.04,
        "time.t_end": T_END, "time.output_times": [0.1, T_END],
        "output.checkpoint_every": 5}


def summary(root: Path) -> dict:
    return json.loads((root / "summary.json").read_text())


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """The uninterrupted run, and a copy of its folder taken right after its first
    checkpoint that follows a remesh: what kill -9 at that moment leaves."""
    folder = tmp_path_factory.mktemp("channel_resume")
    with pytest.MonkeyPatch.context() as patch:
        def copy_at(run_dir: RunDir, state: SimulationState) -> Path:
            path = write_checkpoint(run_dir, state)
            if state.scenario["remeshes"] >= 1 and not (folder / "killed").exists():
                shutil.copytree(run_dir.root, folder / "killed",
                                ignore=shutil.ignore_patterns(".granflow.lock"))
            return path
        patch.setattr(runner, "write_checkpoint", copy_at)
        granflow.run("rectangle-rigid", CASE, folder / "uninterrupted", progress=False)
    assert (folder / "killed").exists(), "no checkpoint came after a remesh"
    return folder / "uninterrupted", folder / "killed"


def test_a_3d_run_killed_after_a_remesh_resumes_to_the_same_run(runs: tuple[Path, Path],
                                                                tmp_path: Path) -> None:
    reference, killed = runs
    killed = Path(shutil.copytree(killed, tmp_path / "killed"))
    assert summary(killed)["status"] == "running"
    resumed = granflow.resume(killed, progress=False)
    first, again = summary(reference), summary(killed)
    assert first["status"] == again["status"] == "completed" and again["resumed"] is True
    assert first["remeshes"] >= 1 and again["steps"] == first["steps"]
    own = {"wall_time_s", "resumed"}
    assert {k: v for k, v in again.items() if k not in own} == {
        k: v for k, v in first.items() if k not in own}
    pd.testing.assert_frame_equal(pd.read_csv(reference / "diagnostics.csv"),
                                  resumed.diagnostics, rtol=0, atol=0)
    for kind in ("free_surface", "free_surface_wall"):
        surface = Path("profiles") / f"{kind}_final.csv"
        assert (killed / surface).read_bytes() == (reference / surface).read_bytes()
