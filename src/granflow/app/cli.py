"""The ``granflow`` command line (also ``python -m granflow``).

    granflow scenarios
    granflow show [SCENARIO|FILE.toml] [--set key=value ...]
    granflow run [SCENARIO|FILE.toml] [--set key=value ...] [--out DIR] [--force] [--quiet]
    granflow resume RUN_DIR [--set key=value ...] [--quiet]
    granflow plot RUN_DIR [--format png|pdf|svg] [--dpi N]
    granflow sweep SWEEP.toml|STUDY [--scheduler ADDRESS] [--workers N] [--out DIR]
    granflow converge SCENARIO|FILE [--in time|space|both|tolerance|rest|margin] [--levels N]
                      [--set key=value ...]
                      [--tolerances NAME=VALUE,...] [--scheduler ADDRESS] [--workers N]
                      [--out DIR]
    granflow verify plug-flow [--table 1|2] [--cells quick|all] [--out DIR] [--quiet]

The configuration is loaded and validated before anything is created; an invalid one is
reported as one line on stderr with exit code 2. The simulation modules (and NGSolve) are
imported only by the command that needs them, so the CLI starts fast.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any, NoReturn

from granflow import __version__
from granflow.app.api import OK_STATUSES, RUNS_FOLDER, fresh_folder
from granflow.app.converge import (
    DEFAULT_TOLERANCES,
    MAX_LEVELS,
    MIN_LEVELS,
    MODES,
    OPTIONAL_TOLERANCES,
    TOLERANCE_MEANING,
    ConvergeError,
    parse_tolerances,
)
from granflow.app.preflight import check_solver
from granflow.app.sweep import SweepError
from granflow.config import (
    ConfigError,
    builtin_scenarios,
    config_to_toml,
    load_config,
)
from granflow.config.messages import notes_as_lines
from granflow.config.schema import FIGURE_FORMATS
from granflow.fem.mpi import world_rank, world_size
from granflow.io.checkpoint import CheckpointError
from granflow.io.run_dir import RunDir, RunDirError

DEFAULT_SCENARIO = "trapezoid-rigid"  # the scenario `granflow run` runs without an argument


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``granflow`` console script; returns the exit code. Under
    ``mpiexec`` rank 0 runs the command and the other ranks serve its flow solves
    (``fem/distributed_flow.py``)."""
    if world_size() > 1:
        from granflow.fem.distributed_flow import release, serve

        if world_rank() > 0:
            serve()
            return 0
        try:
            return _main(argv)
        finally:
            release()
    return _main(argv)


def _main(argv: Sequence[str] | None) -> int:
    args = _parser().parse_args(argv)
    try:
        with notes_as_lines():            # each note once, one line
            return args.command(args)
    except (ConfigError, RunDirError, CheckpointError, SweepError, ConvergeError) as err:
        print(f"granflow: error: {err}", file=sys.stderr)
        return 2
    except OSError as err:   # a full disk, a folder that went away: one line too
        where = f" ('{err.filename}')" if err.filename else ""
        print(f"granflow: error: {err.strerror or err}{where}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("granflow: interrupted", file=sys.stderr)
        return 130


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error (exit 2) instead of usage plus message."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"granflow: error: {message} (see `{self.prog} --help`)\n")


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="granflow",
        description="2D viscoplastic granular flows (regularised Drucker-Prager, ALE, NGSolve).")
    parser.add_argument("--version", action="version", version=f"granflow {__version__}")
    commands = parser.add_subparsers(title="commands", metavar="COMMAND", required=True,
                                     parser_class=_Parser)

    p = commands.add_parser("scenarios", help="list the built-in scenarios, one line each")
    p.set_defaults(command=_scenarios)

    p = commands.add_parser(
        "show", help="print a scenario's resolved configuration (every key, as TOML)",
        description="Print the configuration a run of SCENARIO|FILE.toml would use: the package "
                    "defaults, the scenario's settings and the --set overrides, validated. The "
                    "output is a TOML file that `granflow run` accepts.")
    p.add_argument("scenario", nargs="?", default=DEFAULT_SCENARIO, metavar="SCENARIO|FILE.toml")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="overrides",
                   type=_assignment,
                   help="override a configuration key (repeatable)")
    p.set_defaults(command=_show)

    p = commands.add_parser(
        "run", help="run a scenario into a run directory",
        description="Run a built-in scenario or a TOML file into a run directory.",
        epilog="built-in scenarios: " + ", ".join(builtin_scenarios()))
    p.add_argument("scenario", nargs="?", default=DEFAULT_SCENARIO, metavar="SCENARIO|FILE.toml",
                   help=f"built-in scenario name or path of a TOML file (default: "
                        f"{DEFAULT_SCENARIO})")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="overrides",
                   type=_assignment,
                   help="override a configuration key, e.g. --set numerics.eps=1e-4 (repeatable)")
    p.add_argument("--out", type=Path, help="run directory (default: runs/<scenario>-<time>)")
    p.add_argument("--force", action="store_true",
                   help="replace the run already in --out (its files are deleted first)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(command=_run)

    p = commands.add_parser(
        "resume", help="continue an interrupted, killed or failed run from its checkpoint, "
                       "or extend a finished one (--set time.t_end=T)",
        description="Continue the run in RUN_DIR from checkpoint/state.npz, with the "
                    "configuration in RUN_DIR/config.toml, or extend a finished run to a "
                    "later --set time.t_end=T. Only time.t_end, later time.output_times, "
                    "output.*, the stop at rest and the step and solver controls may change.")
    p.add_argument("run_dir", type=Path, metavar="RUN_DIR")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="overrides",
                   type=_assignment,
                   help="change a key before continuing, e.g. --set time.t_end=2 to extend a "
                        "finished run, --set time.dt_max=5e-4 after a failure (the step "
                        "policy then restarts from the new configuration)")
    p.add_argument("--allow-pickle", action="store_true", help=argparse.SUPPRESS)
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(command=_resume)

    p = commands.add_parser(
        "sweep", help="run a parameter sweep on Dask (one run directory per run)",
        description="Run the product of a sweep file's [vary] lists on a Dask LocalCluster "
                    "(or an existing scheduler) and gather sweep.csv. Rerunning skips "
                    "finished runs. SWEEP is a TOML file or a built-in study "
                    "(aspect-ratio).")
    p.add_argument("sweep", metavar="SWEEP.toml|STUDY")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="address of a running Dask scheduler (tcp://host:8786); default: "
                        "a LocalCluster on this machine")
    p.add_argument("--workers", type=_positive_int, default=2, metavar="N",
                   help="worker processes of the LocalCluster (one thread each; default 2)")
    p.add_argument("--out", type=Path, help="sweep folder (default: runs/sweep-<name>)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(command=_sweep)

    p = commands.add_parser(
        "converge", help="rerun a case at successive resolutions: has it converged?",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Run a case at levels k = 0..N-1, each refined by 2^k in time (the step\n"
                    "halves per level), space (mesh.size halves; an erodible layer gets twice\n"
                    "the mesh.layer_cells) or both, or with a tighter numerical parameter:\n"
                    "tolerance (numerics.tol / sqrt(10) per level) or rest (the rest rule's\n"
                    "time.rest_fraction halved, time.rest_duration doubled), on Dask: one run\n"
                    "directory per level, rerunning skips finished levels. Compare\n"
                    "consecutive levels (stop time, runout, free surfaces at the common output\n"
                    "times, an erodible layer's displaced and mobilised material), fit the\n"
                    "observed orders, write converge.csv, converge.json and converge.png; for\n"
                    "tolerance and rest, judge every level against the tightest and name the\n"
                    "loosest within the tolerances. Exit code 0 when the finest two levels\n"
                    "agree within the tolerances, 1 when not.",
        epilog="tolerances (--tolerances NAME=VALUE,..., any subset; defaults: the project's "
               "accuracy targets):\n" + "\n".join(
                   f"  {k:<14} {v:<6g} {TOLERANCE_MEANING[k]}" for k, v in
                   DEFAULT_TOLERANCES.items())
               + "\noptional (checked only when given): " + ", ".join(
                   f"{k} (e.g. {v:g}: {TOLERANCE_MEANING[k]})"
                   for k, v in OPTIONAL_TOLERANCES.items())
               + "\nexample: granflow converge rectangle-rigid --in space --levels 3 "
                 "--tolerances runout=0.01,surface_max=0.005")
    p.add_argument("scenario", metavar="SCENARIO|FILE",
                   help="built-in scenario name or path of a TOML file")
    p.add_argument("--in", dest="mode", choices=MODES, default="time",
                   help="what is refined per level (default: time)")
    p.add_argument("--levels", type=_levels, default=3, metavar="N",
                   help=f"number of levels, {MIN_LEVELS}..{MAX_LEVELS} (default 3; the order "
                        "needs 3)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="overrides",
                   type=_assignment,
                   help="override a key of the base case (level 0), repeatable")
    p.add_argument("--tolerances", type=_tolerances, default=dict(DEFAULT_TOLERANCES),
                   metavar="NAME=VALUE,...", help="tolerances of the verdict (see below)")
    p.add_argument("--out", type=Path, metavar="DIR",
                   help="study folder (default: runs/converge-<case>-<in>)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="address of a running Dask scheduler; default: a LocalCluster")
    p.add_argument("--workers", type=_positive_int, default=2, metavar="N",
                   help="worker processes of the LocalCluster (default 2)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(command=_converge)

    p = commands.add_parser(
        "plot", help="draw every figure and the animation of a run again, from its files",
        description="Regenerate RUN_DIR/plots from config.toml, profiles/, diagnostics.csv "
                    "and frames/ (also for a killed or running run).")
    p.add_argument("run_dir", type=Path, metavar="RUN_DIR")
    p.add_argument("--format", choices=FIGURE_FORMATS, dest="figure_format",
                   help="png, pdf or svg (default: the run's output.figure_format)")
    p.add_argument("--dpi", type=int, metavar="N",
                   help="resolution of raster figures, 50..1200 (default: the run's output.dpi)")
    p.set_defaults(command=_plot)

    p = commands.add_parser(
        "verify", help="recompute a verification case of the paper",
        description="Recompute the paper's plug-flow Table 1 (fixed mesh) or Table 2 "
                    "(vertically moving mesh) against the 1D reference solver.")
    p.add_argument("case", choices=["plug-flow"], help="verification case")
    p.add_argument("--table", type=int, choices=[1, 2], default=1, help="paper table (default 1)")
    p.add_argument("--cells", choices=["quick", "all"], default="quick",
                   help="'quick': a few coarse cells; 'all': every cell of the table")
    p.add_argument("--out", type=Path, help="output folder (default: runs/verify-...-<time>)")
    p.add_argument("--workers", type=_positive_int, default=1, metavar="N",
                   help="run the cells on a Dask LocalCluster of N processes (default 1: "
                        "in this process)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="run the cells on this Dask scheduler")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(command=_verify)
    return parser


def _show(args: argparse.Namespace) -> int:
    print(config_to_toml(load_config(args.scenario, args.overrides)), end="")
    return 0


def _scenarios(args: argparse.Namespace) -> int:
    scenarios = builtin_scenarios()
    width = max(map(len, scenarios))
    for name, description in scenarios.items():
        print(f"{name:<{width}}  {description}")
    return 0


def _run(args: argparse.Namespace) -> int:
    from granflow.app.api import run_case

    result = run_case(args.scenario, args.overrides, args.out, force=args.force,
                      progress=not args.quiet, log=None if args.quiet else print)
    return _report(RunDir.summary(result.root), RunDir(result.root), printed=not args.quiet)


def _resume(args: argparse.Namespace) -> int:
    from granflow.app.api import resume_case

    if args.allow_pickle:
        raise CheckpointError("--allow-pickle is no longer supported: granflow does not read "
                              "the pickled checkpoints of granflow 0.1, which can execute "
                              f"code; run the case again with `granflow run "
                              f"{args.run_dir / 'config.toml'} --out NEW_DIR`")

    result = resume_case(args.run_dir, args.overrides, progress=not args.quiet,
                         log=None if args.quiet else print)
    return _report(RunDir.summary(result.root), RunDir(result.root))


def _assignment(text: str) -> str:
    """A --set argument: section.key=value (the key and value are checked with the rest of
    the configuration)."""
    if "=" not in text or not text.partition("=")[0].strip():
        raise argparse.ArgumentTypeError(f"expects section.key=value, got {text!r}")
    return text


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, got {text!r}") from None
    if not 1 <= value <= 256:
        raise argparse.ArgumentTypeError(f"expected a whole number in [1, 256], got {value}")
    return value


def _sweep(args: argparse.Namespace) -> int:
    from granflow.app.sweep import Cluster, check_scheduler, load_sweep, run_sweep
    from granflow.io.folders import prepare_folder

    sweep = load_sweep(args.sweep)        # validated before any worker starts
    out = args.out if args.out is not None else RUNS_FOLDER / f"sweep-{sweep.name}"
    check_scheduler(args.scheduler)
    prepare_folder(out, "the sweep")
    with Cluster(args.scheduler, args.workers) as cluster:
        where = args.scheduler or f"a LocalCluster of {args.workers} worker processes"
        board = f"; dashboard {cluster.dashboard}" if cluster.dashboard else ""
        print(f"granflow: sweep {sweep.name}: {len(sweep.runs())} runs on {where}{board} "
              f"-> {out}")
        result = run_sweep(sweep, out, cluster.client, progress=not args.quiet)
    print(f"sweep {sweep.name}: {len(result.rows)} runs ({result.skipped} skipped), "
          f"{len(result.failed)} failed, wall time {result.wall_time_s:.1f} s -> "
          f"{result.csv_path}")
    for row in result.failed:
        print(f"granflow: run {row['run']} {row['status']}: {row.get('message', '')}",
              file=sys.stderr)
    return 1 if result.failed else 0


def _levels(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = None
    if value is None or not MIN_LEVELS <= value <= MAX_LEVELS:
        raise argparse.ArgumentTypeError(f"must be a whole number {MIN_LEVELS}..{MAX_LEVELS}, "
                                         f"got {text!r}")
    return value


def _tolerances(text: str) -> dict[str, float]:
    try:
        return parse_tolerances(text)
    except ConvergeError as err:
        raise argparse.ArgumentTypeError(str(err).removeprefix("--tolerances: ")) from None


def _converge(args: argparse.Namespace) -> int:
    from granflow.app.converge import Study, format_table, run_study
    from granflow.app.sweep import Cluster, check_scheduler
    from granflow.io.folders import check_folder, prepare_folder

    study = Study(args.scenario, args.mode, args.levels, tuple(args.overrides), args.tolerances)
    out = args.out if args.out is not None else RUNS_FOLDER / f"converge-{study.label}-{args.mode}"
    check_scheduler(args.scheduler)
    check_folder(out, "the study")
    study.runs(out)                         # every level validated before any worker starts
    check_solver(load_config(args.scenario, args.overrides))
    prepare_folder(out, "the study")
    with Cluster(args.scheduler, args.workers) as cluster:
        where = args.scheduler or f"a LocalCluster of {args.workers} worker processes"
        print(f"granflow: converge {study.label} in {args.mode}: {args.levels} levels on "
              f"{where} -> {out}")
        report = run_study(study, out, cluster.client, progress=not args.quiet)
    print(format_table(report))
    print(f"granflow: converge.csv, converge.json, converge.png in {out}")
    return 0 if report.converged else 1


def _plot(args: argparse.Namespace) -> int:
    from granflow.scenarios.registry import plot_run

    try:
        written = plot_run(args.run_dir, args.figure_format, args.dpi)
    except (ConfigError, RunDirError):
        raise
    except Exception as exc:   # files someone else wrote that no figure can show: one line
        raise RunDirError(f"cannot draw the figures of '{args.run_dir}': "
                          f"{type(exc).__name__}: {str(exc)[:200]}") from None
    print(f"granflow: {len(written)} figures in {args.run_dir / 'plots'}: "
          f"{', '.join(p.name for p in written)}")
    return 0


def _report(summary: dict[str, Any], run_dir: RunDir, printed: bool = False) -> int:
    """The run's last lines (unless the run printed them already), its message on stderr if
    it did not finish, and the exit code."""
    from granflow.io.report import final_lines

    if not summary:       # what a run writes last could not be read back
        print(f"granflow: error: '{run_dir.root / 'summary.json'}' is missing or cannot be "
              "read (not JSON, or larger than 16 MB); the run's other files are beside it",
              file=sys.stderr)
        return 1
    status = summary.get("status", "failed")
    if not printed:
        print("\n".join(final_lines(summary, run_dir.root)))
    if status not in OK_STATUSES and summary.get("message"):
        print(f"granflow: {summary['message']}", file=sys.stderr)
    return 0 if status in OK_STATUSES else 130 if status == "interrupted" else 1


def _verify(args: argparse.Namespace) -> int:
    from granflow.app.verify import BOUND, VOLUME_BOUND, verify_plug_flow
    from granflow.io.folders import check_folder

    if args.out is not None:
        check_folder(args.out, "the verification")
    out = args.out or fresh_folder(f"verify-{args.case}-table{args.table}")
    if args.workers > 1 or args.scheduler:
        from granflow.app.sweep import Cluster

        with Cluster(args.scheduler, args.workers) as cluster:
            outcome = verify_plug_flow(table=args.table, cells=args.cells, out=out,
                                       progress=not args.quiet, client=cluster.client)
    else:
        outcome = verify_plug_flow(table=args.table, cells=args.cells, out=out,
                                   progress=not args.quiet)
    total, failed = len(outcome.results), len(outcome.failed)
    print(f"verify {args.case}: table {args.table} ({args.cells} cells) -> {outcome.path}")
    print(f"{'FAIL' if failed else 'PASS'}: {total - failed} of {total} cells within "
          f"{BOUND:g} x the paper's error and a volume error under {VOLUME_BOUND:g}")
    for cell in outcome.failed:
        print(f"granflow: cell eps = {cell.eps:g}, dt = {cell.dt:g}, dZ = {cell.dZ:g} missed "
              f"its bound: error {cell.error:.3g} > {BOUND:g} x paper {cell.paper_error:.3g}"
              + (f" or volume error {cell.volume_error:.2g} > {VOLUME_BOUND:g}"
                 if cell.volume_error is not None else ""), file=sys.stderr)
    return 1 if outcome.failed else 0

