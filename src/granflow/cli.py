"""The ``granflow`` command line (also ``python -m granflow``).

    granflow scenarios
    granflow run [SCENARIO|FILE.toml] [--set key=value ...] [--out DIR] [--quiet]
    granflow verify plug-flow [--table 1|2] [--cells quick|all] [--out DIR] [--quiet]

The configuration is loaded and validated before anything is created; an invalid one is
reported as one line on stderr with exit code 2. The simulation modules (and NGSolve) are
imported only by the command that needs them, so the CLI starts fast.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from pathlib import Path

from granflow import __version__
from granflow.config import CUSTOM, ConfigError, config_to_toml, load_config
from granflow.io.run_dir import RunDir, RunDirError
from granflow.scenarios.registry import builtin_scenarios

DEFAULT_SCENARIO = "trapezoid-rigid"  # the scenario `granflow run` runs without an argument
RUNS_FOLDER = Path("runs")
OK_STATUSES = ("completed", "stopped")


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``granflow`` console script; returns the exit code."""
    args = _parser().parse_args(argv)
    try:
        return args.command(args)
    except (ConfigError, RunDirError) as err:
        print(f"granflow: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("granflow: interrupted", file=sys.stderr)
        return 130


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="granflow",
        description="2D viscoplastic granular flows (regularised Drucker-Prager, ALE, NGSolve).")
    parser.add_argument("--version", action="version", version=f"granflow {__version__}")
    commands = parser.add_subparsers(title="commands", metavar="COMMAND", required=True)

    p = commands.add_parser("scenarios", help="list the built-in scenarios, one line each")
    p.set_defaults(command=_scenarios)

    p = commands.add_parser(
        "run", help="run a scenario into a run directory",
        description="Run a built-in scenario or a TOML file into a run directory.",
        epilog="built-in scenarios: " + ", ".join(builtin_scenarios()))
    p.add_argument("scenario", nargs="?", default=DEFAULT_SCENARIO, metavar="SCENARIO|FILE.toml",
                   help=f"built-in scenario name or path of a TOML file (default: "
                        f"{DEFAULT_SCENARIO})")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="overrides",
                   help="override a configuration key, e.g. --set numerics.eps=1e-4 (repeatable)")
    p.add_argument("--out", type=Path, help="run directory (default: runs/<scenario>-<time>)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(command=_run)

    p = commands.add_parser(
        "verify", help="recompute a verification case of the paper",
        description="Recompute the paper's plug-flow Table 1 (fixed mesh) or Table 2 "
                    "(vertically moving mesh) against the 1D reference solver.")
    p.add_argument("case", choices=["plug-flow"], help="verification case")
    p.add_argument("--table", type=int, choices=[1, 2], default=1, help="paper table (default 1)")
    p.add_argument("--cells", choices=["quick", "all"], default="quick",
                   help="'quick': a few coarse cells; 'all': every cell of the table")
    p.add_argument("--out", type=Path, help="output folder (default: runs/verify-...-<time>)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(command=_verify)
    return parser


def _scenarios(args: argparse.Namespace) -> int:
    scenarios = builtin_scenarios()
    width = max(map(len, scenarios))
    for name, description in scenarios.items():
        print(f"{name:<{width}}  {description}")
    return 0


def _run(args: argparse.Namespace) -> int:
    config = load_config(args.scenario, args.overrides)  # validate before creating anything
    from granflow.simulation.runner import run_simulation

    label = Path(args.scenario).stem if config.scenario == CUSTOM else config.scenario
    run_dir = RunDir.create(args.out or _fresh_folder(label))
    run_dir.write_text("config.toml", config_to_toml(config))
    if not args.quiet:
        print(f"granflow: running {label} into {run_dir.root}")
    summary = run_simulation(config, run_dir, progress=config.output.progress and not args.quiet)
    status = summary.get("status", "failed")
    print(f"{status}: t_final = {_num(summary.get('t_final'), '.6g')} s, "
          f"{summary.get('steps')} steps, wall time {_num(summary.get('wall_time_s'), '.1f')} s"
          f" -> {run_dir.root}")
    if status not in OK_STATUSES and summary.get("message"):
        print(f"granflow: {summary['message']}", file=sys.stderr)
    return 0 if status in OK_STATUSES else 1


def _verify(args: argparse.Namespace) -> int:
    from granflow.verify import verify_plug_flow

    out = args.out or _fresh_folder(f"verify-{args.case}-table{args.table}")
    path = verify_plug_flow(table=args.table, cells=args.cells, out=out, progress=not args.quiet)
    print(f"verify {args.case}: table {args.table} ({args.cells} cells) -> {path}")
    return 0


def _num(value: object, spec: str) -> str:
    return format(value, spec) if isinstance(value, int | float) else str(value)


def _fresh_folder(label: str) -> Path:
    """``runs/<label>-<YYYYmmdd-HHMMSS>``, with a suffix if two runs start in the same second."""
    base = RUNS_FOLDER / f"{label}-{time.strftime('%Y%m%d-%H%M%S')}"
    path, n = base, 1
    while path.exists():
        n += 1
        path = base.with_name(f"{base.name}-{n}")
    return path
