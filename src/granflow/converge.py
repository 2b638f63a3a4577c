"""`granflow converge`: one case at successive resolutions, and whether it has converged.

Level k = 0..N-1 refines the base configuration (the scenario with the user's ``--set``)
by 2^k in time, in space or in both (:func:`level_overrides`). Every level is an explicit
set of overrides, run as one sweep run (:func:`granflow.sweep.run_all`) into its own run
directory ``level-K`` of the output folder, so a rerun skips the finished levels and
resumes interrupted ones as ``granflow sweep`` does.

The comparison reads the run directories only (summary.json and the free surfaces in
profiles/): per level the stop time, runout, steps and wall time; between consecutive
levels the change of stop time and runout and the distance between the free surfaces at
each common output time; the observed order p = log2(|q1 - q0| / |q2 - q1|) of each
quantity from each consecutive triple of levels (the resolution doubles per level); and
the verdict: converged when the finest two levels agree within the tolerances (by default
the project's accuracy targets, :data:`DEFAULT_TOLERANCES`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from granflow.config import Config, ConfigError, builtin_scenarios, config_to_toml, load_config
from granflow.diagnostics.compare import surface_distance
from granflow.io import profiles
from granflow.io.run_dir import RunDir
from granflow.sweep import FINISHED, SweepRun, run_all

MODES = ("time", "space", "both")
MIN_LEVELS, MAX_LEVELS = 2, 6
DEFAULT_TOLERANCES = {"surface_mean": 1e-3, "surface_max": 3e-3, "stop_time_rel": 0.02,
                      "runout": 5e-3}     # the project's accuracy targets
TOLERANCE_MEANING = {
    "surface_mean": "m, mean free-surface distance at every common output time",
    "surface_max": "m, largest free-surface distance at every common output time",
    "stop_time_rel": "stop times, relative to the finer level's",
    "runout": "m, runouts"}
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
        if key not in DEFAULT_TOLERANCES or not sep:
            raise ConvergeError(f"--tolerances: unknown entry {item!r} (expected NAME=VALUE "
                                f"with NAME in {', '.join(DEFAULT_TOLERANCES)})")
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
    per level, so the steps halve (``time.dt_init`` is capped at the new ``dt_max``); the
    paper's ramp halves ``time.dt_max`` and ``time.dt_init``.
    space: ``mesh.size`` is halved (or ``mesh.cells_across`` / ``mesh.cells_x`` doubled where
    they set the resolution), and an erodible layer gets twice the ``mesh.layer_cells``.
    """
    if mode not in MODES:
        raise ConvergeError(f"--in = {mode!r}: expected one of {', '.join(MODES)}")
    factor = 2**level
    out: dict[str, Any] = {}
    t, m, g = config.time, config.mesh, config.geometry
    if mode in ("time", "both"):
        if t.dt is not None:
            out["time.dt"] = t.dt / factor
        elif t.adaptive:
            out["time.error_tol"] = t.error_tol / factor ** (time_order(config) + 1)
            out["time.dt_max"] = t.dt_max / factor
            out["time.dt_init"] = min(t.dt_init, out["time.dt_max"])
        else:
            out["time.dt_max"] = t.dt_max / factor
            out["time.dt_init"] = t.dt_init / factor
    if mode in ("space", "both"):
        if g.kind == "column" and m.cells_across is not None:
            out["mesh.cells_across"] = m.cells_across * factor
        else:
            out["mesh.size"] = m.size / factor
            if g.kind == "periodic-layer" and m.cells_x is not None:
                out["mesh.cells_x"] = m.cells_x * factor
        if g.kind == "column" and g.erodible_thickness > 0:
            out["mesh.layer_cells"] = m.layer_cells * factor
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
    # finest (longest) level first: the coarse ones fill the other workers meanwhile
    run_all(runs[::-1], out, client, key=f"granflow-converge-{study.label}-{study.mode}",
            report=report, progress=progress, desc="converge")
    result = analyse(study, out, runs)
    write_report(out, result)
    return result


# ------------------------------------------------------------------ reading the levels


@dataclass
class Level:
    """What the comparison needs from one level's run directory."""

    level: int
    run: str
    status: str | None
    message: str
    stop_time_s: float | None
    runout_m: float | None
    steps: int | None
    wall_time_s: float | None
    surfaces: dict[float, np.ndarray] = field(default_factory=dict, repr=False)

    @property
    def finished(self) -> bool:
        return self.status in FINISHED


def read_level(folder: Path, level: int) -> Level:
    """A level from its run directory: summary.json and profiles/free_surface_t*.csv."""
    s = RunDir.summary(folder)
    surfaces = {}
    for found in profiles.list_profiles(folder, "free_surface"):
        if not found.final and found.t is not None:
            data = found.read()
            surfaces[found.t] = np.column_stack([data["x"], data["z"]]) if data else (
                np.empty((0, 2)))
    return Level(level, folder.name, s.get("status"), s.get("message", "") or "",
                 s.get("stop_time_s"), s.get("runout_m"), s.get("steps"), s.get("wall_time_s"),
                 surfaces)


# ------------------------------------------------------------------ the comparison


def _diff(fine: float | None, coarse: float | None) -> float | None:
    return None if fine is None or coarse is None else fine - coarse


def difference(coarse: Level, fine: Level) -> dict[str, Any]:
    """Changes from one level to the next: stop time, runout, and the (mean, max) distance
    between the free surfaces at each output time both have."""
    times = sorted(set(coarse.surfaces) & set(fine.surfaces))
    return {"levels": [coarse.level, fine.level],
            "stop_time_s": _diff(fine.stop_time_s, coarse.stop_time_s),
            "runout_m": _diff(fine.runout_m, coarse.runout_m),
            "surfaces": {t: dict(zip(("mean_m", "max_m"), surface_distance(
                coarse.surfaces[t], fine.surfaces[t]), strict=True)) for t in times}}


def observed_order(first: float | None, second: float | None,
                   signed: bool = True) -> tuple[float, str]:
    """p = log2(|first| / |second|) of two successive differences, with a note when it
    cannot be fitted (NaN): a missing value, a zero difference, or (``signed``) a sign that
    alternates, i.e. not yet monotone convergence."""
    if first is None or second is None or not (math.isfinite(first) and math.isfinite(second)):
        return math.nan, "a value is missing"
    if first == 0 or second == 0:
        return math.nan, "a difference is 0"
    if signed and (first > 0) != (second > 0):
        return math.nan, "the sign alternates (not in the asymptotic range)"
    return math.log2(abs(first) / abs(second)), ""


def orders(differences: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Observed order of each quantity from each consecutive triple of levels."""
    out = []
    for a, b in zip(differences, differences[1:], strict=False):
        triple = [*a["levels"], b["levels"][1]]
        rows = [("stop_time_s", *observed_order(a["stop_time_s"], b["stop_time_s"])),
                ("runout_m", *observed_order(a["runout_m"], b["runout_m"]))]
        for t in sorted(set(a["surfaces"]) & set(b["surfaces"])):
            for stat in ("mean", "max"):
                rows.append((f"surface_{stat}_t{t:.3f}", *observed_order(
                    a["surfaces"][t][f"{stat}_m"], b["surfaces"][t][f"{stat}_m"], False)))
        out += [{"levels": triple, "quantity": q, "p": p, "note": note} for q, p, note in rows]
    return out


def verdict(coarse: Level, fine: Level, diff: dict[str, Any],
            tolerances: dict[str, float]) -> dict[str, Any]:
    """Whether the finest two levels agree within ``tolerances``: one check per criterion
    (``ok`` None when it does not apply, with the reason) and ``converged``."""
    checks = []

    def check(name: str, value: float | None, tol: float, ok: bool | None, note: str = ""):
        checks.append({"criterion": name, "value": value, "tolerance": tol, "ok": ok,
                       "note": note})

    for lv in (coarse, fine):
        if not lv.finished:
            check(f"level {lv.level} status", None, math.nan, False,
                  f"{lv.status or 'no summary'}: {lv.message}".rstrip(": "))
    tol = tolerances["stop_time_rel"]
    if coarse.stop_time_s is None and fine.stop_time_s is None:
        check("stop_time_rel", None, tol, None, "the mass came to rest at neither level")
    elif coarse.stop_time_s is None or fine.stop_time_s is None:
        check("stop_time_rel", None, tol, False, "the mass came to rest at one level only")
    else:
        rel = abs(diff["stop_time_s"]) / abs(fine.stop_time_s) if fine.stop_time_s else math.inf
        check("stop_time_rel", rel, tol, rel <= tol)
    if diff["runout_m"] is None:
        check("runout", None, tolerances["runout"], False, "a runout is missing")
    else:
        value = abs(diff["runout_m"])
        check("runout", value, tolerances["runout"], value <= tolerances["runout"])
    if not diff["surfaces"]:
        check("surface", None, math.nan, None, "no common output time: surfaces not compared")
    for t, d in diff["surfaces"].items():
        for stat in ("mean", "max"):
            value, tol = d[f"{stat}_m"], tolerances[f"surface_{stat}"]
            check(f"surface_{stat} at t = {t:.3f} s", value, tol, value <= tol)
    return {"levels": [coarse.level, fine.level], "tolerances": tolerances,
            "converged": all(c["ok"] is not False for c in checks), "checks": checks}


# ------------------------------------------------------------------ the report


@dataclass
class Report:
    """The study's outcome, as written to converge.csv / converge.json / converge.png."""

    study: Study
    levels: list[Level]
    varied: list[dict[str, Any]]
    differences: list[dict[str, Any]]
    orders: list[dict[str, Any]]
    verdict: dict[str, Any]

    @property
    def converged(self) -> bool:
        return bool(self.verdict["converged"])


def analyse(study: Study, out: Path, runs: list[SweepRun]) -> Report:
    """Compare the levels from their run directories in ``out`` (no simulation state)."""
    levels = [read_level(out / run.name, k) for k, run in enumerate(runs)]
    diffs = [difference(a, b) for a, b in zip(levels, levels[1:], strict=False)]
    return Report(study, levels,
                  [{k: v for k, v in run.varied.items() if k != "level"} for run in runs],
                  diffs, orders(diffs), verdict(levels[-2], levels[-1], diffs[-1],
                                                  study.tolerances))


def _worst(diff: dict[str, Any] | None, stat: str) -> float | None:
    values = [d[f"{stat}_m"] for d in diff["surfaces"].values()] if diff else []
    return max(values) if values else None


CSV_COLUMNS = ["level", "run", "status", "stop_time_s", "runout_m", "steps", "wall_time_s",
               "stop_time_diff_s", "runout_diff_m", "surface_mean_max_m", "surface_max_max_m"]


def write_report(out: Path, report: Report) -> list[Path]:
    """converge.csv (one row per level; the differences are to the level before, the
    surface columns the worst over common output times), converge.json and converge.png."""
    from granflow.io.plots import plot_level_differences

    folder = RunDir(out)
    rows = []
    for lv, varied in zip(report.levels, report.varied, strict=True):
        d = report.differences[lv.level - 1] if lv.level > 0 else None
        values = [lv.level, lv.run, lv.status, lv.stop_time_s, lv.runout_m, lv.steps,
                  lv.wall_time_s, d and d["stop_time_s"], d and d["runout_m"],
                  _worst(d, "mean"), _worst(d, "max"), *varied.values()]
        rows.append(["" if v is None else v for v in values])
    keys = list(report.varied[0])
    written = [folder.write_csv("converge.csv", [*CSV_COLUMNS, *keys], rows)]
    written.append(folder.write_json("converge.json", {
        "source": report.study.source, "mode": report.study.mode,
        "overrides": list(report.study.overrides),
        "levels": [{"level": lv.level, "run": lv.run, "status": lv.status,
                    "message": lv.message, "overrides": varied, "stop_time_s": lv.stop_time_s,
                    "runout_m": lv.runout_m, "steps": lv.steps, "wall_time_s": lv.wall_time_s,
                    "output_times": sorted(lv.surfaces)}
                   for lv, varied in zip(report.levels, report.varied, strict=True)],
        "differences": [d | {"surfaces": {f"{t:.3f}": v for t, v in d["surfaces"].items()}}
                        for d in report.differences],
        "orders": report.orders, "verdict": report.verdict}))
    stop = [lv.stop_time_s for lv in report.levels]
    series = {
        "stop time (relative)": [abs(d["stop_time_s"]) / abs(s) if d["stop_time_s"] is not None
                                 and s else None for d, s in zip(report.differences, stop[1:],
                                                                 strict=True)],
        "runout (m)": [None if d["runout_m"] is None else abs(d["runout_m"])
                       for d in report.differences],
        "surface mean, worst time (m)": [_worst(d, "mean") for d in report.differences],
        "surface max, worst time (m)": [_worst(d, "max") for d in report.differences]}
    tol = report.verdict["tolerances"]
    limits = dict(zip(series, (tol["stop_time_rel"], tol["runout"], tol["surface_mean"],
                               tol["surface_max"]), strict=True))
    written.append(out / "converge.png")
    plot_level_differences(written[-1], series, limits,
                           f"{report.study.label}: convergence in {report.study.mode}")
    return written


def _fmt(value: Any, spec: str) -> str:
    return "-" if value is None else format(value, spec) if isinstance(value, int | float) \
        else str(value)


def format_table(report: Report) -> str:
    """The study as a short text table: levels, changes, orders and the verdict."""
    lines = [f"{'level':>5} {'status':<10} {'steps':>6} {'wall_s':>7} {'stop_s':>8} "
             f"{'runout_m':>9} {'d_stop_s':>9} {'d_runout_m':>10} {'surf_mean':>9} "
             f"{'surf_max':>9}"]
    for lv in report.levels:
        d = report.differences[lv.level - 1] if lv.level > 0 else None
        lines.append(f"{lv.level:>5} {_fmt(lv.status, ''):<10} {_fmt(lv.steps, 'd'):>6} "
                     f"{_fmt(lv.wall_time_s, '.1f'):>7} {_fmt(lv.stop_time_s, '.4f'):>8} "
                     f"{_fmt(lv.runout_m, '.5f'):>9} "
                     f"{_fmt(d and d['stop_time_s'], '.2e'):>9} "
                     f"{_fmt(d and d['runout_m'], '.2e'):>10} "
                     f"{_fmt(_worst(d, 'mean'), '.2e'):>9} {_fmt(_worst(d, 'max'), '.2e'):>9}")
    fitted = [o for o in report.orders if not o["quantity"].startswith("surface_")
              or o["quantity"].startswith("surface_mean")]
    for o in fitted:
        levels = "-".join(map(str, o["levels"]))
        lines.append(f"order p of {o['quantity']} (levels {levels}): "
                     + (f"{o['p']:.2f}" if math.isfinite(o["p"]) else f"n/a, {o['note']}"))
    v = report.verdict
    failed = [c for c in v["checks"] if c["ok"] is False]
    what = "converged" if v["converged"] else "NOT converged"
    lines.append(f"verdict: {what} (levels {v['levels'][0]} and {v['levels'][1]})" + (
        ": " + "; ".join(_describe(c) for c in failed) if failed else ""))
    lines += [f"note: {c['criterion']}: {c['note']}" for c in v["checks"] if c["ok"] is None]
    return "\n".join(lines)


def _describe(check: dict[str, Any]) -> str:
    if check["value"] is None:
        return f"{check['criterion']}: {check['note']}"
    return f"{check['criterion']} = {check['value']:.3g} > {check['tolerance']:g}"
