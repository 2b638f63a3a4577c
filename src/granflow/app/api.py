"""The Python API: run a case into a run directory, or open one, and read its results.

    import granflow
    run = granflow.run("trapezoid-rigid", overrides={"mesh.size": 0.03}, out="runs/t1")
    run.summary.stop_time_s, run.summary.runout_m
    run.diagnostics                   # pandas DataFrame, one row per accepted step
    run.surfaces                      # tidy DataFrame: t, kind, x, z
    run.fields(0.3)                   # velocity, pressure, strain rate... at an output time
    run.plot.free_surfaces()          # a matplotlib Axes
    again = granflow.load("runs/t1")  # the same object from the run directory
    cfg = granflow.Config.load("rectangle-rigid", {"geometry.height": 0.2})
    cfg.save("tall.toml")             # cfg.to_toml(): every key, as `granflow show` prints
    granflow.run(cfg)                 # out=None: a fresh folder under runs/, as the CLI does

Everything is read from the run directory's files (config.toml, summary.json,
diagnostics.csv, profiles/, fields/), so a run written by the command line, by a sweep or
by someone else opens the same way. The command line is a thin layer over ``run``.
"""

from __future__ import annotations

import re
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, fields
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any

from granflow.app.preflight import check_solver, note_cost, solver_label
from granflow.config import (
    CUSTOM,
    Config,
    ConfigError,
    apply_overrides,
    config_to_toml,
    load_config,
    toml_literal,
)
from granflow.io import profiles
from granflow.io.diagnostics import read_diagnostics
from granflow.io.report import display_path, final_lines
from granflow.io.run_dir import RunDir, RunDirError

if TYPE_CHECKING:
    import matplotlib.pyplot as plt
    import pandas as pd

    from granflow.io.vtk import Fields

RUNS_FOLDER = Path("runs")
OK_STATUSES = ("completed", "stopped")


@dataclass(frozen=True)
class Summary:
    """The headline results of a run (summary.json); every other key is in ``extra``."""

    scenario: str
    status: str                   # completed | stopped | interrupted | failed | running
    message: str
    t_final: float | None         # s, simulated time reached (stopped: the stop time plus
                                  # the rest window that confirmed it, time.rest_duration)
    stop_time_s: float | None     # s, the stop time: the mass at rest from then on (None:
                                  # still moving at t_end)
    runout_m: float | None        # m, front position at the end
    steps: int | None
    nonlinear_iterations: int | None
    wall_time_s: float | None
    linear_solver: str | None     # the sparse LU the run used
    volume_relative_error: float | None
    extra: dict[str, Any] = field(default_factory=dict, repr=False)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Summary:
        names = [f.name for f in fields(cls) if f.name != "extra"]
        known = {name: data.get(name) for name in names}
        known["scenario"] = known["scenario"] or ""
        known["status"] = known["status"] or "running"
        known["message"] = known["message"] or ""
        return cls(**known, extra={k: v for k, v in data.items() if k not in names})

    @property
    def ok(self) -> bool:
        """True when the run finished (reached t_end or came to rest)."""
        return self.status in OK_STATUSES

    @property
    def at_rest(self) -> bool:
        """True when the mass came to rest (``stop_time_s`` is its stop time)."""
        return self.stop_time_s is not None


class Run:
    """A run directory opened for reading (see the module docstring)."""

    def __init__(self, root: str | Path) -> None:
        self.root = Path(root)
        if not RunDir.is_run_dir(self.root):
            raise RunDirError(f"'{self.root}' is not a granflow run directory "
                              "(no config.toml)")

    def __repr__(self) -> str:
        return f"granflow.Run('{self.root}', status={self.summary.status!r})"

    def report(self) -> str:
        """The lines a run prints when it ends: status, stop time (or still moving at
        t_end), runout, final height at the wall or on the axis, volume error, wall time,
        where the figures are."""
        return "\n".join(final_lines(RunDir.summary(self.root), self.root))

    @cached_property
    def config(self) -> Config:
        """The resolved configuration the run used."""
        return load_config(str(self.root / "config.toml"))

    @property
    def summary(self) -> Summary:
        """The run's summary (re-read each time: a running run updates it at its end)."""
        return Summary.from_dict(RunDir.summary(self.root))

    @property
    def diagnostics(self) -> pd.DataFrame:
        """diagnostics.csv: one row per accepted step (t, dt, iterations, front, energy...)."""
        return read_diagnostics(self.root)

    @property
    def surfaces(self) -> pd.DataFrame:
        """Free surface and static/flowing interface at every output time the run reached,
        tidy: columns t (s), kind ("free_surface" | "interface"), x (m), z (m). The last
        accepted state (profiles/*_final.csv) has the time summary.json records for it (for
        a mass at rest: its stop time plus the rest window); output times after the stop
        have no rows: the state at rest stands for them."""
        import pandas as pd

        final_t = self.summary.extra.get("final_profiles_t")
        frames = []
        for kind in ("free_surface", "interface"):
            for found in profiles.list_profiles(self.root, kind):
                t = found.t if found.t is not None else final_t
                if t is None:
                    continue
                data = pd.DataFrame({k: found.read().get(k, []) for k in ("x", "z")})
                frames.append(data.assign(t=float(t), kind=kind)[["t", "kind", "x", "z"]])
        if not frames:
            return pd.DataFrame(columns=["t", "kind", "x", "z"])
        table = pd.concat(frames, ignore_index=True)
        return table.drop_duplicates().sort_values(["kind", "t"], kind="stable",
                                                   ignore_index=True)

    def profile(self, kind: str, t: float | None = None) -> pd.DataFrame:
        """profiles/KIND at output time ``t`` (None: the last accepted state), e.g.
        "free_surface" (x, z) or, over an erodible layer, "layer_markers" (x, z, x0, z0,
        travel, speed: the layer material now and where it started), "layer_line" (x, z)
        and "erosion_depth" (x0, depth); lengths in m, speed in m/s."""
        import pandas as pd

        found = (profiles.final_profile(self.root, kind) if t is None
                 else profiles.profile_at(self.root, kind, t))
        if found is None:
            when = "the last state" if t is None else f"t = {t:g} s"
            raise KeyError(f"no '{kind}' profile at {when} in '{self.root}' (the files are "
                           f"{profiles.FOLDER}/KIND_tT.TTT.csv and KIND_final.csv)")
        return pd.DataFrame(found)

    @property
    def erosion(self) -> pd.DataFrame:
        """Over an erodible layer: the erosion depth along the bed at every output time and
        the last state, tidy: columns t (s), x0 (m, original position), depth (m). The
        entrainment history (eroded areas, erosion and column fronts) is in
        ``diagnostics``."""
        import pandas as pd

        final_t = self.summary.extra.get("final_profiles_t")
        frames = []
        for found in profiles.list_profiles(self.root, "erosion_depth"):
            t = found.t if found.t is not None else final_t
            if t is not None:
                data = pd.DataFrame(found.read())[["x0", "depth"]]
                frames.append(data.assign(t=float(t))[["t", "x0", "depth"]])
        if not frames:
            return pd.DataFrame(columns=["t", "x0", "depth"])
        return pd.concat(frames, ignore_index=True).drop_duplicates(ignore_index=True)

    @property
    def output_times(self) -> list[float]:
        """The times of the VTU snapshots in fields/ (fields.pvd)."""
        from granflow.io.vtk import snapshots

        return [t for t, _ in snapshots(self.root)]

    def fields(self, t: float) -> Fields:
        """The snapshot at time ``t`` (the nearest one within 1e-6 s)."""
        from granflow.io.vtk import read_snapshot

        return read_snapshot(self.root, t)

    @cached_property
    def plot(self) -> RunPlots:
        """Figures of this run: ``run.plot.free_surfaces()``, ``run.plot.all()``."""
        return RunPlots(self)


class RunPlots:
    """Figures drawn from a run's files (the same files ``granflow plot`` reads)."""

    def __init__(self, run: Run) -> None:
        self._run = run

    def free_surfaces(self, ax: plt.Axes | None = None) -> plt.Axes:
        """The free surface at every output time the run reached and its last state, once,
        labelled "at rest from t = ..." for a mass at rest (x and z in m, equal scales)."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(8, 3))
        summary = self._run.summary
        final_t = summary.extra.get("final_profiles_t")
        surfaces = self._run.surfaces
        surfaces = surfaces[surfaces["kind"] == "free_surface"]
        for t, rows in surfaces.groupby("t"):
            last = final_t is not None and abs(t - final_t) < 1e-9
            if last and summary.at_rest:
                label = f"at rest from t = {summary.stop_time_s:.3f} s"
            else:
                label = f"t = {t:.3g} s" + (f" ({summary.status})" if last and not
                                            summary.ok else "")
            ax.plot(rows["x"], rows["z"], label=label, **({"color": "k"} if last else {}))
        from granflow.fem.measure import coordinates_of

        ax.set_xlabel(f"{coordinates_of(self._run.config.geometry).coordinate} (m)")
        ax.set_ylabel("z (m)")
        ax.set_aspect("equal")
        ax.set_title(f"{summary.scenario}: free surface")
        if len(ax.lines):
            ax.legend(fontsize="small")
        return ax

    def all(self, figure_format: str | None = None, dpi: int | None = None) -> list[Path]:
        """Every figure of the run again, into RUN_DIR/plots, in the run's format or in
        ``figure_format`` ("png", "pdf", "svg") at ``dpi``; returns the files."""
        from granflow.scenarios.registry import plot_run

        return plot_run(self._run.root, figure_format, dpi)


def run(case: str | Path | Config, overrides: Mapping[str, Any] | Sequence[str] | None = None,
        out: str | Path | None = None, *, force: bool = False, progress: bool | None = None,
        log: Callable[[str], None] | None = None) -> Run:
    """Run ``case`` (a built-in scenario, a TOML file or a ``Config``) to its end.

    ``overrides``: {"section.key": value} or ["section.key=value", ...], checked as the
    command line checks ``--set``. ``out``: the run directory (None: runs/<scenario>-<time>);
    ``force=True`` replaces a run already there. ``progress``: a progress bar and the run's
    last lines (status, stop time, runout, where the figures are); None (default) shows them
    where someone watches: a terminal or a notebook. ``log`` receives those lines and the
    first one (where the run goes, with which solver); ``print`` when progress is shown.
    A run that fails still returns: its ``summary.status`` and ``message`` say why.
    """
    try:
        return run_case(case, overrides, out, force=force, progress=progress, log=log)
    except RunDirError as err:
        raise RunDirError(python_wording(str(err))) from None


def run_case(case: str | Path | Config,
             overrides: Mapping[str, Any] | Sequence[str] | None = None,
             out: str | Path | None = None, *, force: bool = False,
             progress: bool | None = None, log: Callable[[str], None] | None = None) -> Run:
    """``run`` as the command line calls it: its messages name the command's options."""
    config, label = _resolve(case, overrides)
    check_solver(config)
    note_cost(config)
    from granflow.app.run import run_simulation

    progress = watched() if progress is None else progress
    log = print if log is None and progress else log
    run_dir = RunDir.create(Path(out) if out is not None else fresh_folder(label), force=force)
    with run_dir.lock():
        run_dir.write_text("config.toml", config_to_toml(config))
        if log is not None:
            log(f"granflow: running {label} into {display_path(run_dir.root)} "
                f"(sparse LU: {solver_label(config)})")
        summary = run_simulation(config, run_dir, progress=progress and config.output.progress)
    if log is not None:
        for line in final_lines(summary, run_dir.root):
            log(line)
    return Run(run_dir.root)


def watched() -> bool:
    """True where someone watches the run: a Jupyter kernel or a terminal on stderr."""
    if "ipykernel" in sys.modules:
        return True
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


# The command line's options in a message, and what a Python caller writes instead.
_PYTHON_WORDS = [(re.compile(r"`granflow resume ([^`]+)`"), r"granflow.resume('\1')"),
                 (re.compile(r"use --force"), "pass force=True"),
                 (re.compile(r"--force"), "force=True"),
                 (re.compile(r"--out"), "out"),
                 (re.compile(r"--set "), "overrides "),
                 (re.compile(r"--allow-pickle"), "allow_pickle=True")]


def python_wording(message: str) -> str:
    """A message worded for the command line, reworded for a Python caller."""
    for pattern, words in _PYTHON_WORDS:
        message = pattern.sub(words, message)
    return message


def resume(path: str | Path, overrides: Mapping[str, Any] | Sequence[str] | None = None, *,
           allow_pickle: bool = False, progress: bool = False,
           log: Callable[[str], None] | None = None) -> Run:
    """Continue the interrupted, killed or failed run in ``path`` from its checkpoint to its
    end, or extend a finished one: ``overrides={"time.t_end": 2.0}``.

    ``overrides`` may change only the end time, later output times, ``output.*``, the stop
    at rest and the step and solver controls (``granflow.app.resume``); others are refused.
    ``allow_pickle`` is no longer supported (granflow 0.1's pickled checkpoints are not
    read): True raises ``CheckpointError``.
    """
    from granflow.io.checkpoint import CheckpointError, pickle_refusal

    if allow_pickle:
        raise CheckpointError("allow_pickle is no longer supported: "
                              + pickle_refusal(Path(path)))
    try:
        return resume_case(path, overrides, progress=progress, log=log)
    except (RunDirError, ConfigError, CheckpointError) as err:   # worded for Python
        raise type(err)(python_wording(str(err))) from None


def resume_case(path: str | Path,
                overrides: Mapping[str, Any] | Sequence[str] | None = None, *,
                progress: bool = False, log: Callable[[str], None] | None = None) -> Run:
    """``resume`` as the command line calls it: its messages name the command's options."""
    from granflow.app.resume import resume_run

    return Run(resume_run(path, _override_texts(overrides), progress=progress, log=log,
                          check_solver=check_solver))


def load(path: str | Path) -> Run:
    """Open the run directory ``path`` (finished, failed, interrupted or still running)."""
    return Run(path)


def fresh_folder(label: str) -> Path:
    """``runs/<label>-<YYYYmmdd-HHMMSS>``, with a suffix if two runs start in the same second."""
    base = RUNS_FOLDER / f"{label}-{time.strftime('%Y%m%d-%H%M%S')}"
    path, n = base, 1
    while path.exists():
        n += 1
        path = base.with_name(f"{base.name}-{n}")
    return path


def _override_texts(overrides: Mapping[str, Any] | Sequence[str] | None) -> list[str]:
    """["section.key=value", ...] from a mapping or a sequence of such texts."""
    if isinstance(overrides, Mapping):
        return [f"{key}={toml_literal(value)}" for key, value in overrides.items()]
    return list(overrides or ())


def _resolve(case: str | Path | Config,
             overrides: Mapping[str, Any] | Sequence[str] | None) -> tuple[Config, str]:
    """The validated configuration of ``case`` with ``overrides``, and its label (the same
    checks as the command line's, ``config/loading.py``)."""
    overrides = overrides or ()
    if isinstance(case, Config):
        config = apply_overrides(case, overrides) if overrides else case
        return config, "custom" if config.scenario == CUSTOM else config.scenario
    config = load_config(case, overrides)
    return config, Path(str(case)).stem if config.scenario == CUSTOM else config.scenario
