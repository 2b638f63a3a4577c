"""`granflow converge`: one case at successive resolutions, and whether it has converged.

Level k = 0..N-1 refines the base configuration (the scenario with the user's ``--set``)
by 2^k in time, in space or in both, or tightens a numerical parameter: the nonlinear
iteration's tolerance (``tolerance``: ``numerics.tol`` divided by sqrt(10) per level) or the
rest rule's thresholds (``rest``) (:func:`level_overrides`). Every level is an explicit
set of overrides, run as one sweep run (:func:`granflow.app.sweep.run_all`) into its own run
directory ``level-K`` of the output folder, so a rerun skips the finished levels and
resumes interrupted ones as ``granflow sweep`` does.

The comparison reads the run directories only (summary.json and the free surfaces in
profiles/): per level the stop time, runout, steps and wall time; between consecutive
levels the change of stop time and runout and the distance between the free surfaces at
each common output time; the observed order p = log2(|q1 - q0| / |q2 - q1|) of each
quantity from each consecutive triple of levels (the resolution doubles per level); and
the verdict: converged when the finest two levels agree within the tolerances (by default
the project's accuracy targets, :data:`DEFAULT_TOLERANCES`). For a tightened parameter every
level is also compared with the tightest, the reference, and the loosest level whose results
stay within the tolerances of it is named (``convergence_report.py``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from granflow.app.convergence_report import (
    DEFAULT_TOLERANCES,
    OPTIONAL_TOLERANCES,
    TOLERANCE_MEANING,
    Report,
    compare_levels,
    format_table,
    observed_order,
    orders,
    write_report,
)
from granflow.app.sweep import SweepRun, run_all
from granflow.config import Config, ConfigError, builtin_scenarios, config_to_toml, load_config
from granflow.config.kinds import erodible_layer, rules_of
from granflow.io.run_dir import prepare_folder

__all__ = ["DEFAULT_TOLERANCES", "MAX_LEVELS", "MIN_LEVELS", "MODES", "OPTIONAL_TOLERANCES",
           "PARAMETER_MODES",
           "TOLERANCE_MEANING", "ConvergeError", "Report", "Study", "analyse", "format_table",
           "level_overrides", "observed_order", "orders", "parse_tolerances", "run_study",
           "write_report"]

MODES = ("time", "space", "both", "tolerance", "rest", "margin")
PARAMETER_MODES = ("tolerance", "rest", "margin")   # a numerical parameter, not a resolution
MIN_LEVELS, MAX_LEVELS = 2, 6
TOL_STEP = math.sqrt(10.0)   # numerics.tol is divided by this per level (two levels a decade)
SCHEME_ORDER = {"implicit-euler": 1, "bdf2": 2}   # order q of the time scheme


class ConvergeError(ValueError):
    """Invalid convergence study (one line naming the parameter and what is allowed)."""


# ------------------------------------------------------------------ input and levels


def parse_tolerances(text: str) -> dict[str, float]:
    """``surface_mean=0.001,runout=0.01`` -> the default tolerances with these replaced."""
    out = dict(DEFAULT_TOLERANCES)
    for item in filter(None, (part.strip() for part in text.split(","))):
        key, sep, raw = item.partition("=")
        key = key.strip()
        if key not in TOLERANCE_MEANING or not sep:
            raise ConvergeError(f"--tolerances: unknown entry {item!r} (expected NAME=VALUE "
                                f"with NAME in {', '.join(TOLERANCE_MEANING)})")
        try:
            value = float(raw)
        except ValueError:
            value = math.nan
        if not math.isfinite(value) or value <= 0:
            raise ConvergeError(f"--tolerances: {key} = {raw.strip()!r} must be a number > 0")
        out[key] = value
    return out


def time_order(config: Config) -> int:
    """Order q of the configured time scheme (1: implicit Euler, 2: BDF2)."""
    return SCHEME_ORDER[getattr(config.time, "scheme", "implicit-euler")]


def level_overrides(config: Config, mode: str, level: int) -> dict[str, Any]:
    """The keys level ``level`` sets, refined by 2^level from the resolved ``config``.

    time: a fixed ``time.dt`` is halved per level; adaptive steps (error per step ~ dt^(q+1)
    for a scheme of order q) divide ``time.error_tol`` by 2^(q+1) and ``time.dt_max`` by 2
    per level, so the steps halve (``time.dt_init`` is capped at the new ``dt_max``, and a
    slow flow's ``time.dt_max_slow`` halves with it); the paper's ramp halves
    ``time.dt_max`` and ``time.dt_init``.
    space: what the problem kind refines (``KindRules.refine_space``): a column halves
    ``mesh.size`` (or doubles ``mesh.cells_across`` where it sets the resolution) and doubles
    an erodible layer's ``mesh.layer_cells``; a periodic layer halves ``mesh.size`` (and
    doubles ``mesh.cells_x`` where it is set).
    tolerance: ``numerics.tol`` is divided by TOL_STEP per level (and the ramp's
    ``numerics.tol_init`` capped at it). rest: the rest rule's ``time.rest_fraction`` is
    halved and its ``time.rest_duration`` doubled per level. margin: the adaptive mesh's
    ``mesh.flow_margin`` is doubled and its ``mesh.layer_rest_coarsening`` halved (to 1) per
    level: its fine region grows towards the uniform mesh.
    """
    if mode not in MODES:
        raise ConvergeError(f"--in = {mode!r}: expected one of {', '.join(MODES)}")
    factor = 2**level
    out: dict[str, Any] = {}
    t, m = config.time, config.mesh
    if mode == "tolerance":
        num = config.numerics
        out["numerics.tol"] = float(f"{num.tol / TOL_STEP**level:.4g}")
        if not t.adaptive and t.dt is None:
            out["numerics.tol_init"] = min(num.tol_start, out["numerics.tol"])
    if mode == "rest":
        out["time.rest_fraction"] = t.rest_fraction / factor
        out["time.rest_duration"] = t.rest_duration * factor
    if mode == "margin":
        if not m.adaptive:
            raise ConvergeError("--in margin: the case has mesh.adaptive = false; its margin "
                                "changes nothing (set mesh.adaptive=true)")
        out["mesh.flow_margin"] = min(m.flow_margin * factor, 100.0)
        if erodible_layer(config):
            out["mesh.layer_rest_coarsening"] = max(m.layer_rest_coarsening / factor, 1.0)
    if mode in ("time", "both"):
        if t.dt is not None:
            out["time.dt"] = t.dt / factor
        elif t.adaptive:
            out["time.error_tol"] = t.error_tol / factor ** (time_order(config) + 1)
            out["time.dt_max"] = t.dt_max / factor
            out["time.dt_init"] = min(t.dt_init, out["time.dt_max"])
            if t.dt_max_slow is not None:    # the slow flow's cap halves too
                out["time.dt_max_slow"] = t.dt_max_slow / factor
        else:
            out["time.dt_max"] = t.dt_max / factor
            out["time.dt_init"] = t.dt_init / factor
    if mode in ("space", "both"):
        out |= rules_of(config).refine_space(config, factor)
    return out


@dataclass(frozen=True)
class Study:
    """A convergence study: the case (scenario or file and ``--set`` overrides), what is
    refined, how many levels, and the tolerances of the verdict."""

    source: str
    mode: str = "time"
    levels: int = 3
    overrides: tuple[str, ...] = ()
    tolerances: dict[str, float] = field(default_factory=lambda: dict(DEFAULT_TOLERANCES))

    @property
    def label(self) -> str:
        """The case's short name (scenario name or file stem), for folders and task keys."""
        return Path(self.source).stem

    def runs(self, out: Path | None = None) -> list[SweepRun]:
        """One sweep run per level, every configuration validated before anything runs.

        Raises ConfigError or ConvergeError (one line). With ``out``, a level directory
        that already holds a run of another configuration (another study) is refused.
        """
        if not MIN_LEVELS <= self.levels <= MAX_LEVELS:
            raise ConvergeError(f"--levels = {self.levels}: must be {MIN_LEVELS}..{MAX_LEVELS}")
        base_config = load_config(self.source, self.overrides)
        # a file by its absolute path: the workers may start elsewhere
        base = self.source if self.source in builtin_scenarios() else str(
            Path(self.source).resolve())
        runs = []
        for k in range(self.levels):
            keys = level_overrides(base_config, self.mode, k)
            run = SweepRun(f"level-{k}", base, [*self.overrides, *(
                f"{key}={value!r}" for key, value in keys.items())], {"level": k, **keys})
            try:
                config = load_config(run.base, run.overrides)
            except ConfigError as err:
                raise ConvergeError(f"level {k} of --levels {self.levels} (--in {self.mode}): "
                                    f"{err}; use fewer --levels or a coarser base") from None
            file = out / run.name / "config.toml" if out is not None else None
            if file is not None and file.is_file() and \
                    file.read_text(encoding="utf-8") != config_to_toml(config):
                raise ConvergeError(f"--out: '{file.parent}' holds a run of another "
                                    "configuration (another case, --in or --set); choose "
                                    "another --out")
            runs.append(run)
        return runs


def run_study(study: Study, out: Path, client: Any, progress: bool = True,
              report: Callable[[str], None] = print) -> Report:
    """Run the levels not yet finished in ``out`` on the Dask ``client`` (as sweep runs),
    then compare them and write converge.csv, converge.json and converge.png."""
    runs = study.runs(out)
    prepare_folder(out, "the study")
    # finest (longest) level first: the coarse ones fill the other workers meanwhile
    run_all(runs[::-1], out, client, key=f"granflow-converge-{study.label}-{study.mode}",
            report=report, progress=progress, desc="converge")
    result = analyse(study, out, runs)
    write_report(out, result)
    return result


def analyse(study: Study, out: Path, runs: list[SweepRun]) -> Report:
    """Compare the study's levels from their run directories in ``out``; a tightened
    parameter's levels are also judged against the tightest (``convergence_report.py``)."""
    return compare_levels(study.source, study.mode, study.overrides, study.tolerances, out,
                          runs, against_reference=study.mode in PARAMETER_MODES)
