"""The figures and the last state of a run that comes to rest: a small coarse column
(10 x 10 cm, 4 cells across, at rest by t = 0.5 s, about 10 s), drawn as PDF, then again
as SVG and PNG from its files."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import granflow
from granflow.io.frames import read_frames
from granflow.scenarios.registry import plot_run

SMALL = {"geometry.width": 0.1, "geometry.height": 0.1, "mesh.size": 0.025,
         "time.rest_fraction": 0.02, "time.t_end": 1.0, "time.output_times": [0.1, 0.9],
         "output.figure_format": "pdf"}
FIGURES = ["free_surface", "front_and_energy", "interface", "velocity_sections"]


@pytest.fixture(scope="module")
def stopped(tmp_path_factory: pytest.TempPathFactory) -> granflow.Run:
    out = tmp_path_factory.mktemp("figures") / "run"
    run = granflow.run("rectangle-rigid", SMALL, out=out, progress=False)
    assert run.summary.status == "stopped", run.summary.message
    return run


def test_output_times_after_the_stop_are_not_written(stopped: granflow.Run) -> None:
    s = stopped.summary
    assert s.at_rest and s.stop_time_s < 0.9 < 1.0
    assert s.extra["outputs_at_rest"] == [0.9]          # named, not written
    assert not list((stopped.root / "profiles").glob("*_t0.900.csv"))
    assert all(abs(t - 0.9) > 1e-6 for t in stopped.output_times)
    assert sorted(set(stopped.surfaces["t"])) == [0.1, s.t_final]
    # the final state is drawn once, named by its stop time, not by t_final or 0.9 s
    ax = stopped.plot.free_surfaces()
    assert ax.get_legend_handles_labels()[1] == [
        "t = 0.1 s", f"at rest from t = {s.stop_time_s:.3f} s"]


def test_figures_are_written_in_the_configured_format(stopped: granflow.Run) -> None:
    plots = stopped.root / "plots"
    assert sorted(p.stem for p in plots.glob("*.pdf")) == FIGURES
    assert not list(plots.glob("*.png"))
    for name in FIGURES:
        assert (plots / f"{name}.pdf").read_bytes()[:5] == b"%PDF-"
    svg = plot_run(stopped.root, "svg")
    assert sorted(p.stem for p in svg if p.suffix == ".svg") == FIGURES
    for path in svg:
        if path.suffix == ".svg":
            assert ET.parse(path).getroot().tag.endswith("svg")


def test_dpi_sets_the_raster_size(stopped: granflow.Run) -> None:
    plot_run(stopped.root, "png", 60)
    with Image.open(stopped.root / "plots" / "free_surface.png") as image:
        small = image.size[0]
    plot_run(stopped.root, "png", 120)
    with Image.open(stopped.root / "plots" / "free_surface.png") as image:
        large = image.size[0]
    assert large / small == pytest.approx(2.0, rel=0.05)


def test_remeshes_and_depositions_are_recorded_for_the_energy_figure(
        stopped: granflow.Run) -> None:
    s = stopped.summary
    remeshes, landings = s.extra["remesh_times_s"], s.extra["deposition_times_s"]
    assert len(remeshes) == s.extra["remeshes"]
    assert len(landings) == s.extra["deposited_segments"] > 0
    assert all(0 < t < s.stop_time_s for t in [*remeshes, *landings])
    # a landing brakes the front cell at once: the energy drops at the next step
    diag = stopped.diagnostics
    t, energy = diag["t"].to_numpy(), diag["kinetic_energy"].to_numpy()
    drops = np.diff(energy) / energy[:-1]
    i = int(np.searchsorted(t, landings[0] - 1e-12))
    assert drops[i] < -0.05


def test_the_animation_is_smooth_and_cropped(stopped: granflow.Run) -> None:
    frames = read_frames(stopped.root)
    assert all(len(f["vertex_speed"]) == len(f["xy"]) for f in frames)
    with Image.open(stopped.root / "plots" / "speed.gif") as gif:
        width, height = gif.size
        assert gif.n_frames > 10
    runout = stopped.summary.runout_m
    # cropped to the deposit (0.23 m x 0.1 m): wider than high by about its ratio
    assert 1.2 < width / height < 2.2 * runout / 0.1


def test_the_run_reports_its_last_lines(stopped: granflow.Run) -> None:
    lines = stopped.report().splitlines()
    s = stopped.summary
    assert lines[0] == (f"stopped: at rest from t = {s.stop_time_s:.3f} s (run to "
                        f"t = {s.t_final:.3f} s, {s.steps} steps)")
    text = "\n".join(lines)
    assert f"runout              {s.runout_m:.4f} m" in text
    assert "height at the wall" in text and "volume error" in text
    assert str(Path(stopped.root) / "plots") in text or "plots" in lines[-2]


def test_the_fields_hold_the_stress_and_the_yield_ratio(stopped: granflow.Run) -> None:
    """Where the material flows (|Du| far above eps) it is at yield, |sigma'| >= kappa, as
    (2.13) makes it; the static side of the interface is below."""
    fields = stopped.fields(0.1)
    for name in ("stress_xx", "stress_zz", "stress_xz", "deviatoric_stress_norm"):
        assert fields[name].shape == (len(fields.triangles),)
    shearing = (fields["flowing"] > 0) & (fields["strain_rate_norm"] > 1e-3)
    assert shearing.any() and np.nanmin(fields["yield_ratio"][shearing]) > 0.99
    assert np.nanmedian(fields["yield_ratio"][fields["flowing"] == 0]) < 1.0
    assert np.all(fields["stress_zz"] < 0)                # compression everywhere
