"""`granflow sweep`: parameter sweeps as Dask tasks, one run directory per run.

A sweep file (docs/user_guide.md) names a base scenario, fixed overrides and the parameters to vary;
the runs are the product of the ``[vary]`` lists::

    base = "rectangle-rigid"
    [set]
    "mesh.size" = 0.02
    [vary]
    "geometry.height" = [0.05, 0.1, 0.2]
    "geometry.slope_deg" = [0, 10]

Every run is one Dask task that writes its own run directory under the output folder;
``sweep.csv`` gathers one row per run (the varied values, status, message and the summary
figures) and is rewritten as runs finish. Rerunning a sweep skips the runs that finished
(completed or stopped), resumes those that were interrupted or killed from their
checkpoint, and runs the failed ones again. A run that fails (or whose combination of
values is invalid) is a row with its message; the others go on.
"""

from __future__ import annotations

import csv
import io
import itertools
import json
import re
import time
import tomllib
from collections.abc import Callable
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

from granflow.config import ConfigError, load_config, read_toml_file
from granflow.config.messages import notes_as_lines
from granflow.io.run_dir import RunDir, RunDirError, atomic_write_text, prepare_folder

FINISHED = ("completed", "stopped")
MAX_RUNS = 10_000   # runs of one sweep: at a minute each, a week of one core
_SCHEDULER = re.compile(r"(?:tcp://)?(?P<host>\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9._-]+):(?P<port>\d{1,5})")
FIGURES = ["t_final", "steps", "wall_time_s", "stop_time_s", "runout_m", "wall_height_m",
           "initial_area_m2", "volume_relative_error", "n_triangles", "remeshes",
           "initial_volume_m3", "axis_height_m"]   # the last two: axisymmetric runs only


class SweepError(ValueError):
    """The sweep file is invalid (one line naming what and where)."""


@dataclass(frozen=True)
class Sweep:
    """A parsed sweep: base scenario, fixed overrides, varied keys and their values."""

    name: str
    base: str
    fixed: list[str]
    vary: dict[str, list[Any]]
    extra: dict[str, Any] = field(default_factory=dict)   # study-specific tables ([study])

    def runs(self) -> list[SweepRun]:
        keys = list(self.vary)
        out = []
        for i, values in enumerate(itertools.product(*self.vary.values())):
            varied = dict(zip(keys, values, strict=True))
            label = "_".join(f"{k.split('.')[-1]}-{_compact(v)}" for k, v in varied.items())
            out.append(SweepRun(f"{i:03d}_{label}" if label else f"{i:03d}", self.base,
                                [*self.fixed, *(f"{k}={_literal(v)}" for k, v in
                                                varied.items())], varied))
        return out


@dataclass(frozen=True)
class SweepRun:
    name: str                 # run directory name inside the sweep's folder
    base: str
    overrides: list[str]
    varied: dict[str, Any]


def studies_folder() -> Any:
    """The built-in sweep files' folder (``granflow/app/studies/``)."""
    return resources.files("granflow.app").joinpath("studies")


def builtin_studies() -> list[str]:
    folder = studies_folder()
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def load_sweep(source: str) -> Sweep:
    """A sweep from a TOML file or a built-in study name (``granflow/app/studies/NAME.toml``)."""
    if source in builtin_studies():
        text = studies_folder().joinpath(f"{source}.toml").read_text()
        data, name = tomllib.loads(text), source
    else:
        path = Path(source)
        if not path.exists():
            raise SweepError(f"sweep file '{source}' not found (built-in studies: "
                             f"{', '.join(builtin_studies())})")
        try:
            data, name = read_toml_file(path, "sweep file"), path.stem
        except ConfigError as err:
            raise SweepError(str(err)) from None
    unknown = set(data) - {"base", "set", "vary", "study"}
    if unknown:
        raise SweepError(f"sweep file '{source}': unknown entries {sorted(unknown)} "
                         "(allowed: base, [set], [vary], [study])")
    base = data.get("base")
    if not isinstance(base, str):
        raise SweepError(f"sweep file '{source}': 'base' must name a scenario")
    fixed, vary = data.get("set", {}), data.get("vary", {})
    if not isinstance(fixed, dict) or not isinstance(vary, dict):
        raise SweepError(f"sweep file '{source}': [set] and [vary] must be tables")
    for key, values in vary.items():
        if not isinstance(values, list) or not values:
            raise SweepError(f"sweep file '{source}': vary '{key}' must be a non-empty list")
    count = 1
    for values in vary.values():
        count *= len(values)
    if count > MAX_RUNS:
        raise SweepError(f"sweep file '{source}': its [vary] lists make {count:.3g} runs (at "
                         f"most {MAX_RUNS} allowed); vary fewer values or split the sweep")
    sweep = Sweep(name, base, [f"{k}={_literal(v)}" for k, v in fixed.items()],
                  {k: list(v) for k, v in vary.items()}, data.get("study", {}))
    try:   # the keys must exist and the base must load; single combinations may still fail
        load_config(base, sweep.fixed)
        for key, values in vary.items():
            load_config(base, [*sweep.fixed, f"{key}={_literal(values[0])}"])
    except ConfigError as err:
        raise SweepError(f"sweep file '{source}': {err}") from None
    return sweep


def _literal(value: Any) -> str:
    """A TOML literal for ``--set`` (strings quoted)."""
    return json.dumps(value) if isinstance(value, str) else repr(value).lower() if isinstance(
        value, bool) else repr(value)


def _compact(value: Any) -> str:
    text = format(value, "g") if isinstance(value, float) else str(value)
    return re.sub(r"[^A-Za-z0-9.+-]", "", text)


# ------------------------------------------------------------------- one run (a Dask task)


def run_one(run: SweepRun, root: str) -> dict[str, Any]:
    """Run (or resume) one sweep run into ROOT/NAME and return its sweep.csv row.

    Executes in a Dask worker process. Never raises: an invalid combination or a failure
    is a row with status "failed" and the message.
    """
    with notes_as_lines():     # the worker's notes as the command line prints them
        return _run_one(run, root)


def _run_one(run: SweepRun, root: str) -> dict[str, Any]:
    folder = Path(root) / run.name
    row: dict[str, Any] = {"run": run.name, **run.varied}
    try:
        config = load_config(run.base, run.overrides)
    except ConfigError as err:
        return row | {"status": "failed", "message": f"invalid configuration: {err}"}
    from granflow.app.api import resume
    from granflow.app.api import run as run_case
    from granflow.io.checkpoint import CheckpointError

    try:
        status = RunDir.status(folder)
        if status in ("running", "interrupted") and (folder / "checkpoint").is_dir():
            summary = RunDir.summary(resume(folder).root)
        else:
            summary = RunDir.summary(run_case(config, out=folder, force=True).root)
    except (RunDirError, CheckpointError) as err:
        return row | {"status": "failed", "message": str(err)}
    except Exception as err:  # noqa: BLE001 - a worker must report, not die
        return row | {"status": "failed", "message": f"{type(err).__name__}: {err}"}
    return row | _figures(summary)


def _figures(summary: dict[str, Any]) -> dict[str, Any]:
    return {"status": summary.get("status", "failed"), "message": summary.get("message", ""),
            **{k: summary.get(k) for k in FIGURES}}


def finished_row(run: SweepRun, root: Path) -> dict[str, Any] | None:
    """The row of a run that already finished in ROOT (skipped by a rerun), else None."""
    folder = root / run.name
    if RunDir.status(folder) not in FINISHED:
        return None
    summary = json.loads((folder / "summary.json").read_text())
    return {"run": run.name, **run.varied} | _figures(summary)


# ------------------------------------------------------------------- the sweep


@dataclass
class SweepResult:
    rows: list[dict[str, Any]]
    csv_path: Path
    skipped: int
    wall_time_s: float

    @property
    def failed(self) -> list[dict[str, Any]]:
        return [r for r in self.rows if r.get("status") not in FINISHED]


def write_csv(path: Path, sweep: Sweep, rows: list[dict[str, Any]]) -> None:
    columns = ["run", *sweep.vary, "status", "message", *FIGURES]
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, columns, extrasaction="ignore", lineterminator="\n")
    writer.writeheader()
    for row in sorted(rows, key=lambda r: r["run"]):
        writer.writerow({k: ("" if row.get(k) is None else row.get(k)) for k in columns})
    atomic_write_text(path, buffer.getvalue())


def run_sweep(sweep: Sweep, out: Path, client: Any,
              report: Callable[[str], None] = print, progress: bool = True) -> SweepResult:
    """Submit every unfinished run to the Dask ``client``; gather sweep.csv in ``out``."""
    start = time.perf_counter()
    prepare_folder(out, "the sweep")
    atomic_write_text(out / "sweep.toml", _describe(sweep))
    csv_path = out / "sweep.csv"
    rows, skipped = run_all(sweep.runs(), out, client, key=f"granflow-{sweep.name}",
                            on_rows=lambda rows: write_csv(csv_path, sweep, rows),
                            report=report, progress=progress)
    return SweepResult(rows, csv_path, skipped, time.perf_counter() - start)


def run_all(runs: list[SweepRun], out: Path, client: Any, key: str,
            on_rows: Callable[[list[dict[str, Any]]], None] | None = None,
            report: Callable[[str], None] = print, progress: bool = True,
            desc: str = "sweep") -> tuple[list[dict[str, Any]], int]:
    """Run each of ``runs`` as one Dask task into ``out``/NAME; return (rows, skipped).

    Runs that already finished in ``out`` are skipped (their rows are read from their
    summaries); the others are submitted to ``client`` with :func:`run_one`, which resumes
    an interrupted run from its checkpoint. ``on_rows`` receives all rows so far, once
    before the first task and after each finished one (to rewrite a table as runs finish).
    Shared by ``granflow sweep`` and ``granflow converge``.
    """
    from distributed import as_completed
    from tqdm import tqdm

    out.mkdir(parents=True, exist_ok=True)
    rows: dict[str, dict[str, Any]] = {}
    todo = []
    for run in runs:
        done = finished_row(run, out)
        if done is not None:
            rows[run.name] = done
        else:
            todo.append(run)
    skipped = len(rows)
    if skipped:
        report(f"granflow: {skipped} of {len(runs)} runs already finished, skipped")
    if on_rows is not None:
        on_rows(list(rows.values()))
    futures = [client.submit(run_one, run, str(out), key=f"{key}-{run.name}", pure=False)
               for run in todo]
    failed = 0
    with tqdm(total=len(todo), disable=not progress, unit="run", desc=desc) as bar:
        for future in as_completed(futures):
            row = future.result()
            rows[row["run"]] = row
            failed += row["status"] not in FINISHED
            if on_rows is not None:
                on_rows(list(rows.values()))
            running = sum(not f.done() for f in futures)
            bar.set_postfix_str(f"done {bar.n + 1}, running {min(running, _workers(client))}, "
                                f"failed {failed}", refresh=False)
            bar.update(1)
    return sorted(rows.values(), key=lambda r: r["run"]), skipped


def _workers(client: Any) -> int:
    try:
        return max(1, len(client.scheduler_info().get("workers", {})))
    except Exception:  # noqa: BLE001
        return 1


def _describe(sweep: Sweep) -> str:
    """The sweep as it ran (a copy beside sweep.csv)."""
    lines = [f'base = "{sweep.base}"', "", "[set]"]
    lines += [f'"{o.split("=", 1)[0]}" = {o.split("=", 1)[1]}' for o in sweep.fixed]
    lines += ["", "[vary]"]
    lines += [f'"{k}" = [{", ".join(_literal(v) for v in vs)}]' for k, vs in sweep.vary.items()]
    return "\n".join(lines) + "\n"


@dataclass
class Cluster:
    """A Dask client on a new LocalCluster (N single-threaded process workers) or on an
    existing scheduler; closes what it opened."""

    scheduler: str | None
    workers: int
    client: Any = None
    _cluster: Any = None

    def __enter__(self) -> Cluster:
        from distributed import Client, LocalCluster

        check_scheduler(self.scheduler)
        if self.scheduler:
            try:
                self.client = Client(self.scheduler, timeout="20s")
            except (OSError, TimeoutError, ValueError) as err:
                raise SweepError(f"cannot reach the Dask scheduler at '{self.scheduler}': "
                                 f"{err} (an address is tcp://HOST:PORT)") from None
        else:
            self._cluster = LocalCluster(n_workers=self.workers, threads_per_worker=1,
                                         processes=True, dashboard_address=":0")
            self.client = Client(self._cluster)
        return self

    @property
    def dashboard(self) -> str:
        """The scheduler's dashboard address, or "" where it has none: no dashboard service,
        or no bokeh where the scheduler runs (Dask then serves a page that asks for it)."""
        try:
            if "dashboard" not in self.client.scheduler_info().get("services", {}):
                return ""
            if self._cluster is not None:          # the scheduler runs in this process
                has_bokeh = _has_bokeh()
            else:
                has_bokeh = bool(self.client.run_on_scheduler(_has_bokeh))
            return str(self.client.dashboard_link or "") if has_bokeh else ""
        except Exception:   # an old or odd scheduler: say nothing rather than something wrong
            return ""

    def __exit__(self, *exc: object) -> None:
        if self.client is not None:
            self.client.close()
        if self._cluster is not None:
            self._cluster.close()


def _has_bokeh() -> bool:
    """Whether Dask can serve its dashboard here (it needs bokeh)."""
    import importlib.util

    return importlib.util.find_spec("bokeh") is not None


def check_scheduler(address: str | None) -> None:
    """``--scheduler`` is tcp://HOST:PORT (or HOST:PORT) with a port in 1..65535: the
    protocol granflow connects with (ucx://, tls:// and the others need a Dask
    configuration of their own, which granflow does not set up)."""
    if address is None:
        return
    match = _SCHEDULER.fullmatch(address.strip())
    if match is None or not 1 <= int(match["port"]) <= 65535:
        raise SweepError(f"--scheduler {address[:80]!r} is not tcp://HOST:PORT with a port "
                         "in 1..65535 (granflow connects to a Dask scheduler over plain TCP)")
