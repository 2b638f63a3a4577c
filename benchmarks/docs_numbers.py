"""The numbers the documentation quotes from runs a user can repeat, from fresh runs.

Each case is a command the pages show (``granflow run ...``), run as a user runs it: a new
process in an empty folder, its printed lines captured (the run folder's time stamp written
as the pages' example, 20261204-101500), its summary's figures and its processor time
recorded in ``benchmarks/results/docs_numbers/docs_numbers.json``. The pages quote the record
through ``CLAIMS`` (a number: the page, the text around it with ``{}`` where it stands, where
it is in the record, its format), ``RANGES`` (a processor time as a range: half to twice the
recorded one, rounded out) and ``BLOCKS`` (a printed block, line for line).
tests/unit/test_docs_numbers.py checks every one against the record, and (slow) a fresh run
of each case against the record within ``TOLERANCES``.

After a change to the numerics, regenerating them is one command:

    python benchmarks/docs_numbers.py --update-docs

which runs every case (about 7 minutes of processor time), writes the record and rewrites each
claimed number, range and printed block in the pages. ``--cases`` runs some of them only
(the record keeps the others); ``--update-docs`` alone with ``--no-run`` rewrites the pages
from the record as it is.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import re
import resource
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "benchmarks" / "results" / "docs_numbers" / "docs_numbers.json"
STAMP = "20261204-101500"          # the run folder's time stamp as the pages write it

# --- the cases: the commands the pages show -----------------------------------------------
CASES: dict[str, list[str]] = {
    # getting started, the user guide's printed lines, the README's default run
    "default": ["run"],
    "rectangle": ["run", "rectangle-rigid"],
    # the user guide's quick erodible run, against the scenario's defaults
    "erodible-quick": ["run", "trapezoid-erodible", "--set", "mesh.layer_cells=1",
                       "--set", "mesh.layer_ahead=0.1"],
    "erodible": ["run", "trapezoid-erodible"],
    # the nonlocal law with the glass beads: the collapse and the incline's stopping height
    "nonlocal-collapse": ["run", "rectangle-rigid", "--set", "material.rheology=nonlocal",
                          "--set", "material.preset=glass-beads"],
    "nonlocal-incline": ["run", "incline-nonlocal"],
    "nonlocal-incline-thin": ["run", "incline-nonlocal", "--set", "geometry.height=0.001"],
}
SUMMARY_KEYS = ["status", "t_final", "steps", "stop_time_s", "runout_m", "wall_height_m",
                "volume_relative_error", "area_correction_total", "area_correction_net",
                "n_triangles", "wall_time_s", "velocity_relative_error_l2", "reference_note"]

# --- what the pages quote -------------------------------------------------------------------
Path_ = str | Callable[[dict[str, Any]], float]
CLAIMS: list[tuple[str, str, Path_, str]] = [
    # page, text ({} where the number stands), where it is in the record, format
    ("README.md", "default fast path at {} s and {*} m", "default.summary.stop_time_s", ".3f"),
    ("README.md", "default fast path at {*} s and {} m", "default.summary.runout_m", ".3f"),
    ("docs/getting_started.md", "The mass is at rest from {} s, its stop time",
     "default.summary.stop_time_s", ".3f"),
    ("docs/getting_started.md", "so it ends at {} s.", "default.summary.t_final", ".3f"),
    ("docs/user_guide.md", "the fast path: {} s and {*} m", "default.summary.stop_time_s",
     ".4f"),
    ("docs/user_guide.md", "the fast path: {*} s and {} m", "default.summary.runout_m", ".4f"),
    ("docs/user_guide.md", "m, {} s and {*} m). Adding", "rectangle.summary.stop_time_s",
     ".4f"),
    ("docs/user_guide.md", "s and {} m). Adding", "rectangle.summary.runout_m", ".4f"),
    # the quick erodible run against the defaults
    ("docs/user_guide.md", "ran to rest ({} triangles at the end;",
     "erodible-quick.summary.n_triangles", ",d"),
    ("docs/user_guide.md", "at the end; stop time {} s,", "erodible-quick.summary.stop_time_s",
     ".3f"),
    ("docs/user_guide.md", "s, runout {} m) in", "erodible-quick.summary.runout_m", ".3f"),
    ("docs/user_guide.md", "against the defaults' run ({} triangles;",
     "erodible.summary.n_triangles", ",d"),
    ("docs/user_guide.md", "triangles; at rest from {} s, its front",
     "erodible.summary.stop_time_s", ".3f"),
    ("docs/user_guide.md", "its front at {} m) in", "erodible.summary.runout_m", ".3f"),
    # the nonlocal law: the collapse and the incline
    ("docs/user_guide.md", "comes to rest at {} s with a runout of",
     "nonlocal-collapse.summary.stop_time_s", ".3f"),
    ("docs/user_guide.md", "with a runout of {} m (the Drucker",
     "nonlocal-collapse.summary.runout_m", ".3f"),
    ("docs/user_guide.md", "Drucker–Prager rectangle: {} m)", "rectangle.summary.runout_m",
     ".3f"),
    ("docs/user_guide.md", "flows and tends to its steady profile ({} % from it",
     "nonlocal-incline.summary.velocity_relative_error_l2", ".2f"),
    ("docs/user_guide.md", "its largest speed falls to {} m/s",
     "nonlocal-incline-thin.max_speed_end", ".1e"),
    ("docs/user_guide.md", "not thicker than its stopping height {} mm",
     lambda record: 1e3 * float(re.search(
         r"stopping height ([\d.e-]+) m", record["cases"]["nonlocal-incline-thin"]["summary"]
         ["reference_note"])[1]), ".3f"),
    ("docs/getting_started.md", "comes to rest at {} s,", "nonlocal-collapse.summary.stop_time_s",
     ".3f"),
    ("docs/getting_started.md", "s, {} m from the wall", "nonlocal-collapse.summary.runout_m",
     ".3f"),
    ("docs/python_api.md", "run.summary.runout_m      # {} m", "nonlocal-collapse.summary.runout_m",
     ".3f"),
]
SCALES = {"nonlocal-incline.summary.velocity_relative_error_l2": 100.0}
RANGES: list[tuple[str, str, str]] = [
    # page, text ({lo} and {hi} where the range stands), the recorded processor time (s)
    ("docs/getting_started.md", "about {lo} to {hi} s of processor time on one core",
     "default.cpu_s"),
    ("docs/user_guide.md", "m) in {lo} to {hi} s of processor time, against",
     "erodible-quick.cpu_s"),
    ("docs/user_guide.md", "m) in {lo} to {hi} s (`python benchmarks/docs_numbers.py`)",
     "erodible.cpu_s"),
    ("docs/user_guide.md", "(about {lo} to {hi} s of processor time)",
     "nonlocal-collapse.cpu_s"),
]
BLOCKS: list[tuple[str, str, str]] = [
    # page, case, the printed line that opens the block (its start)
    ("docs/getting_started.md", "default", "granflow: running"),
    ("docs/user_guide.md", "default", "stopped: at rest from"),
]
# a fresh run against the record: (relative, absolute) tolerance of each summary figure
TOLERANCES = {"t_final": (0.03, 0.0), "stop_time_s": (0.03, 0.0), "runout_m": (0.01, 0.0),
              "wall_height_m": (0.01, 0.0), "steps": (0.1, 0), "n_triangles": (0.2, 0),
              "volume_relative_error": (0.0, 1e-12),
              "velocity_relative_error_l2": (0.1, 5e-4), "max_speed_end": (1.0, 0.0)}


def lookup(record: dict[str, Any], path: Path_) -> Any:
    """The value at ``case.member.key`` of the record (or a function of it)."""
    if callable(path):
        return path(record)
    case, *keys = path.split(".")
    value: Any = record["cases"][case]
    for key in keys:
        value = value[key]
    return value


def formatted(value: float, spec: str, scale: float = 1.0) -> str:
    """As the pages write it: 2.1e-5 (no exponent padding), 1,004."""
    if spec == ",d":
        return f"{round(value * scale):,d}"
    text = format(value * scale, spec)
    return re.sub(r"e([+-])0*(\d)", lambda m: f"e{'-' if m[1] == '-' else ''}{m[2]}", text)


NUMBER = r"[-+]?(?:\d[\d,]*)?\.?\d+(?:e[-+]?\d+)?"


ANY = "{*}"        # in a claim's text: any number (another claim's, or another record's)


def pattern(text: str, slots: tuple[str, ...] = ("{}",)) -> re.Pattern[str]:
    """``text`` as a regular expression: any whitespace for a space or line break, a number
    (a group) where each slot stands, any number where ``{*}`` does."""
    parts = re.split("(" + "|".join(map(re.escape, (*slots, ANY))) + ")", text)
    out = []
    for part in parts:
        if part == ANY:
            out.append(f"(?:{NUMBER})")
        elif part in slots:
            out.append(f"({NUMBER})")
        else:
            out.append(r"\s+".join(map(re.escape, part.split())) if part.strip() else
                       (r"\s+" if part else ""))
            if part[:1].isspace() and part.strip():
                out[-1] = r"\s+" + out[-1]
            if part[-1:].isspace() and part.strip():
                out[-1] += r"\s+"
    return re.compile("".join(out))


def nice_range(seconds: float) -> tuple[int, int]:
    """A processor time's range as the pages give it: half to twice it, rounded out."""
    def round_to(x: float, up: bool) -> int:
        step = 10 ** max(int(math.log10(max(x, 1.0))) - 0, 0) / (2 if x < 100 else 1)
        step = max(step, 1)
        return int((math.ceil if up else math.floor)(x / step) * step)
    return max(round_to(seconds / 2, False), 1), round_to(2 * seconds, True)


# --- running a case --------------------------------------------------------------------------
def run_case(name: str, folder: Path) -> dict[str, Any]:
    """The case ``name`` as a user runs it in ``folder``: printed lines, summary figures,
    processor and wall time."""
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1",
           "MPLBACKEND": "Agg"}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "granflow", *CASES[name]], cwd=folder,
                          capture_output=True, text=True, env=env, check=False)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise RuntimeError(f"{name}: exit code {done.returncode}: {done.stderr[-2000:]}")
    runs = sorted((folder / "runs").iterdir())
    summary = json.loads((runs[-1] / "summary.json").read_text(encoding="utf-8"))
    diagnostics = (runs[-1] / "diagnostics.csv").read_text(encoding="utf-8").splitlines()
    header = diagnostics[0].split(",")
    last = dict(zip(header, diagnostics[-1].split(","), strict=True))
    stamp = re.compile(r"\d{8}-\d{6}")
    bar = [part for part in re.split(r"[\r\n]+", done.stderr) if part.strip()]
    return {
        "command": "granflow " + " ".join(CASES[name]),
        "printed": [stamp.sub(STAMP, line) for line in done.stdout.splitlines()],
        "progress_bar_end": stamp.sub(STAMP, bar[-1]) if bar else None,
        "summary": {k: summary.get(k) for k in SUMMARY_KEYS},
        "max_speed_end": float(last["max_speed"]),
        "cpu_s": (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime),
        "wall_s": wall,
    }


def machine() -> dict[str, Any]:
    """Where the record was made: the processor, the load, the packages, MKL's mode."""
    from importlib.metadata import version

    cpu = next((line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text()
                .splitlines() if line.startswith("model name")), platform.processor()) \
        if Path("/proc/cpuinfo").exists() else platform.processor()
    packages = {}
    for name in ("granflow", "ngsolve", "mkl", "numpy", "scipy"):
        try:
            packages[name] = version(name)
        except Exception:     # not installed (mkl off x86-64)
            packages[name] = None
    return {"cpu": cpu, "load_average": os.getloadavg(), "python": platform.python_version(),
            "packages": packages, "MKL_CBWR": os.environ.get("MKL_CBWR")}


# --- the pages ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class Found:
    """A claim's place on its page: the match, and the number's group(s)."""

    page: Path
    match: re.Match[str]


def find_claim(page: str, text: str, slots: tuple[str, ...] = ("{}",)) -> Found | None:
    path = ROOT / page
    match = pattern(text, slots).search(path.read_text(encoding="utf-8"))
    return Found(path, match) if match else None


def find_block(page: str, opening: str) -> tuple[int, int, list[str]] | None:
    """The fenced code block of ``page`` whose first line starts with ``opening``: its
    first and last line numbers (inside the fence) and its lines."""
    lines = (ROOT / page).read_text(encoding="utf-8").splitlines()
    for i, line in enumerate(lines):
        if line.startswith("```") and i + 1 < len(lines) and lines[i + 1].startswith(opening):
            end = next(j for j in range(i + 1, len(lines)) if lines[j].startswith("```"))
            return i + 1, end, lines[i + 1:end]
    return None


def block_lines(record: dict[str, Any], case: str, opening: str) -> list[str]:
    """What the case printed from the line that opens the block on: its first line, the
    progress bar's last state after it (getting started), the rest."""
    printed = record["cases"][case]["printed"]
    start = next(i for i, line in enumerate(printed) if line.startswith(opening))
    lines = [line for line in printed[start:] if line.strip()]
    bar = record["cases"][case].get("progress_bar_end")
    if opening == "granflow: running" and bar:
        lines.insert(1, bar)
    return lines


def update_docs(record: dict[str, Any]) -> list[str]:
    """Rewrite every claimed number, range and block in the pages from the record; returns
    what changed."""
    changed = []
    for page, text, path, spec in CLAIMS:
        if text.count("{}") != 1:
            continue
        found = find_claim(page, text)
        if found is None:
            changed.append(f"{page}: not found: {text!r}")
            continue
        value = formatted(lookup(record, path), spec,
                          SCALES.get(path, 1.0) if isinstance(path, str) else 1.0)
        _replace(found, [(1, value)], changed)
    for page, text, path in RANGES:
        found = find_claim(page, text, ("{lo}", "{hi}"))
        value = lookup(record, path)
        if found is None:
            changed.append(f"{page}: not found: {text!r}")
        elif (int(found.match[1]), int(found.match[2])) != nice_range(value):
            lo, hi = nice_range(value)
            _replace(found, [(1, str(lo)), (2, str(hi))], changed)
    for page, case, opening in BLOCKS:
        where = find_block(page, opening)
        if where is None:
            changed.append(f"{page}: no block opening with {opening!r}")
            continue
        first, end, old = where
        new = block_lines(record, case, opening)
        if new != old:
            lines = (ROOT / page).read_text(encoding="utf-8").splitlines(keepends=True)
            lines[first:end] = [line + "\n" for line in new]
            (ROOT / page).write_text("".join(lines), encoding="utf-8")
            changed.append(f"{page}: the block of {case} ({len(new)} lines)")
    return changed


def _replace(found: Found, groups: list[tuple[int, str]], changed: list[str]) -> None:
    text = found.page.read_text(encoding="utf-8")
    match = pattern_again(found, text)
    pieces, last = [], 0
    for group, value in groups:
        pieces += [text[last:match.start(group)], value]
        last = match.end(group)
    new = "".join(pieces) + text[last:]
    if new != text:
        found.page.write_text(new, encoding="utf-8")
        changed.append(f"{found.page.relative_to(ROOT)}: {match[0]!r} -> "
                       f"{', '.join(v for _, v in groups)}")


def pattern_again(found: Found, text: str) -> re.Match[str]:
    """The claim's match in the page as it is now (an earlier rewrite may have moved it)."""
    match = found.match.re.search(text)
    assert match is not None
    return match


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", nargs="+", choices=sorted(CASES), default=sorted(CASES))
    parser.add_argument("--update-docs", action="store_true",
                        help="rewrite the claimed numbers in the pages from the record")
    parser.add_argument("--no-run", action="store_true", help="use the record as it is")
    args = parser.parse_args(argv)
    record = json.loads(RECORD.read_text()) if RECORD.is_file() else {"cases": {}}
    if not args.no_run:
        from common.results import write_json

        for name in args.cases:
            with tempfile.TemporaryDirectory(prefix="docs-numbers-") as folder:
                record["cases"][name] = run_case(name, Path(folder))
            case = record["cases"][name]
            print(f"{name}: {case['summary']['status']}, stop {case['summary']['stop_time_s']}, "
                  f"runout {case['summary']['runout_m']}, {case['cpu_s']:.1f} s processor, "
                  f"{case['wall_s']:.1f} s wall", flush=True)
            record["machine"] = machine()
            write_json(RECORD, record)
    if args.update_docs:
        for line in update_docs(record):
            print(line)


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    main(sys.argv[1:])
