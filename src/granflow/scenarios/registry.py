"""The problem kinds (``geometry.kind``): each registers its builder and its figures here,
``register("column", build_column, figures=...)`` at the end of its module, and the runner,
``granflow resume`` and ``granflow plot`` find them by name; none asks which kind a run is.

A builder returns a ``Problem``: its mesh, its flow solver and its time loop, whose named
callbacks (``simulation/outputs.py``) declare every output. A figure is drawn from the run
directory's files alone (``granflow plot`` builds no problem) and draws nothing when the
files it reads are not there (a layer's figure in a run without a layer).

A new kind: its modules under ``scenarios/`` (the builder and the parts that measure it,
with its ``register`` call; its ``KindRules`` for the configuration, ``config/kinds.py``)
and its line of ``BUILT_IN`` (``scenarios/__init__.py``); new configuration keys go to
``config/`` as any parameter's.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

from granflow.config import Config
from granflow.io.replot import figure_config, figure_files
from granflow.io.run_dir import RunDir, RunDirError
from granflow.scenarios import BUILT_IN
from granflow.simulation.outputs import Figure
from granflow.simulation.simulation import Simulation
from granflow.state.spec import Share

if TYPE_CHECKING:
    import ngsolve as ngs

    from granflow.fem.flow import FlowSolver


class Problem(Protocol):
    """What a builder hands to the runner; its outputs are its simulation's callbacks."""

    mesh: ngs.Mesh
    solver: FlowSolver
    simulation: Simulation

    def save_state(self) -> dict[str, Any]: ...
    def share(self) -> Share: ...          # what the members of save_state may be
    def restore_state(self, state: dict[str, Any]) -> None: ...


Builder = Callable[[Config], Problem]


@dataclass(frozen=True)
class ProblemKind:
    """A kind of problem: its name (``geometry.kind``), its builder and its figures."""

    name: str
    build: Builder
    figures: tuple[Figure, ...] = ()


KINDS: dict[str, ProblemKind] = {}
# the kinds in three dimensions (``geometry.dimension = 3``), each in its own modules
KINDS_3D: dict[str, ProblemKind] = {}


def register(name: str, build: Builder, figures: Sequence[Figure] = (),
             dimension: int = 2) -> ProblemKind:
    """Make ``build`` the builder of ``geometry.kind = name`` (in ``dimension``) and
    ``figures`` its figures."""
    kind = ProblemKind(name, build, tuple(figures))
    (KINDS_3D if dimension == 3 else KINDS)[name] = kind
    return kind


def _load_built_in() -> None:
    """Import the built-in kinds' builders: each registers its own."""
    for _, builder in BUILT_IN:
        importlib.import_module(builder)


def problem_kind(name: str, dimension: int = 2) -> ProblemKind:
    """The registered kind ``name`` (in ``dimension``)."""
    _load_built_in()
    kinds = KINDS_3D if dimension == 3 else KINDS
    if name not in kinds:
        raise ValueError(f"geometry.kind = {name!r} is not a registered problem kind"
                         f"{' in 3D' if dimension == 3 else ''}; "
                         f"known: {', '.join(sorted(kinds))}")
    return kinds[name]


def kind_of(config: Config) -> ProblemKind:
    """The registered kind of ``config`` (its geometry.kind, in its geometry.dimension)."""
    return problem_kind(config.geometry.kind, config.geometry.dimension)


def build_problem(config: Config) -> Problem:
    """The problem of ``config``, built by its kind's builder."""
    return kind_of(config).build(config)


def draw_figures(run_dir: RunDir, config: Config) -> None:
    """Every figure of the run in ``run_dir`` into plots/, in ``output.figure_format`` at
    ``output.dpi``: its kind's figures, each from the files."""
    for figure in kind_of(config).figures:
        figure(run_dir, config)


def plot_run(root: Path, figure_format: str | None = None, dpi: int | None = None) -> list[Path]:
    """Regenerate the figures of the run in ``root`` (``granflow plot``), in its
    configuration's format or in ``figure_format`` (png, pdf, svg) at ``dpi``; return the
    files written. Works on a run that was killed or is still running (what is written so
    far) and after a figure was deleted."""
    if not RunDir.is_run_dir(root):
        raise RunDirError(f"'{root}' is not a granflow run directory (no config.toml)")
    config = figure_config(root, figure_format, dpi)
    draw_figures(RunDir(Path(root)), config)
    return figure_files(root, config)
