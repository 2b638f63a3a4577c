"""What the outputs read from a 3D column: the front (furthest point, and on the centre
line and at the side wall), the free surface along the centre line (``free_surface``, as a
section's) and at the side wall (``free_surface_wall``), the flowing fraction, the
diagnostics history, the summary and the figures (``io/channel_plots.py``), declared as
the collapse's callback (``simulation/outputs.py``). Read-only on the flow; its state is
the history of the rows it was given (checkpointed)."""

from __future__ import annotations

import copy
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from granflow.ale.channel_surface import front_of, plane_section
from granflow.config import Config
from granflow.diagnostics import front as front_diag
from granflow.diagnostics.state import flowing_cells
from granflow.geometry.mesh3d import ON_PLANE, tetrahedron_quality
from granflow.scenarios.channel_discretisation import ChannelDiscretisation
from granflow.scenarios.channel_remesher import ChannelRemesher
from granflow.scenarios.channel_setup import ChannelSetup
from granflow.simulation.outputs import Outputs, Table
from granflow.simulation.simulation import RunResult, Simulation
from granflow.state.spec import ANY_NUMBER, Share, list_of, record


def _history() -> dict[str, list[float]]:
    return {"t": [], "front_x": [], "flowing_fraction": []}


def channel_figures(run_dir: Any, config: Config) -> None:
    """The free surfaces on the centre line and at the side wall, and the histories
    (``io/channel_plots.py``)."""
    from granflow.io.channel_plots import plot_channel

    plot_channel(run_dir, config)


@dataclass
class ChannelMeasures(Outputs):
    """Measures of the current state of a 3D column (``current`` follows the remeshes)."""

    figures = (channel_figures,)
    columns: ClassVar[tuple[str, ...]] = ("front_x_centre", "front_x_side",
                                          "volume_correction", "remesh_volume_change")
    share: ClassVar[Share] = {"history": record({
        name: list_of(ANY_NUMBER, length="history steps") for name in _history()})}

    setup: ChannelSetup
    current: ChannelDiscretisation
    remesher: ChannelRemesher
    simulation: Simulation
    history: dict[str, list[float]] = field(default_factory=_history)

    def front(self) -> float:
        """The furthest point of the mass along the bed (the runout)."""
        return float(self.current.mesh.ngmesh.Coordinates()[:, 0].max())

    def wall_height(self) -> float:
        """The highest point of the mass on the back wall X = 0."""
        xyz = self.current.mesh.ngmesh.Coordinates()
        on_wall = np.abs(xyz[:, 0]) < ON_PLANE
        return float(xyz[on_wall, 2].max()) if on_wall.any() else 0.0

    def centre_line(self) -> np.ndarray:
        """The free surface along the channel's centre line (the slab's first plane)."""
        return plane_section(self.current.mesh, self.setup.span.centre)

    def side_wall(self) -> np.ndarray:
        """The free surface against the side wall (the slab's second plane)."""
        return plane_section(self.current.mesh, self.setup.span.high)

    def diagnostics(self, sim: Simulation, cell_speed: np.ndarray) -> dict[str, float]:
        return {"front_x": self.front(), "wall_height": self.wall_height(),
                "front_x_centre": front_of(self.centre_line()),
                "front_x_side": front_of(self.side_wall()),
                "volume_correction": self.current.mover.step_correction,
                "remesh_volume_change": self.remesher.unrecorded_change}

    def record(self, row: dict[str, float]) -> None:
        for key, values in self.history.items():
            values.append(row[key])
        self.remesher.recorded()

    def flowing_fraction(self) -> float:
        """Volume fraction of the tetrahedra faster than the flowing threshold (1 mm/s)."""
        flags, volumes = flowing_cells(self.current.mesh, self.current.solver.velocity)
        return float(volumes[flags].sum() / volumes.sum())

    def profiles(self, t: float | None = None) -> dict[str, Table]:
        """The free surface on the centre line and at the side wall, as ``io/profiles.py``
        writes them."""
        return {"free_surface": (["x", "z"], self.centre_line()),
                "free_surface_wall": (["x", "z"], self.side_wall())}

    def summary(self, result: RunResult) -> dict[str, Any]:
        mover, span = self.current.mover, self.setup.span
        h = {k: np.asarray(v) for k, v in self.history.items()}
        stop = front_diag.stop_time(h["t"], h["flowing_fraction"],
                                    self.setup.config.time.rest_fraction)
        return {
            "runout_m": self.front(),
            "runout_centre_m": front_of(self.centre_line()),
            "runout_wall_m": front_of(self.side_wall()),
            "stop_time_s": stop,
            "all_cells_static_s": front_diag.stop_time(h["t"], h["flowing_fraction"]),
            "runout_at_stop_m": float(np.interp(stop, h["t"], h["front_x"])) if stop else None,
            "front_settle_time_s": front_diag.settle_time(h["t"], h["front_x"]),
            "wall_height_m": self.wall_height(),
            "initial_volume_m3": mover.initial_volume,
            "channel_span_m": [span.low, span.high],
            "deposited_faces": mover.relabelled_segments,
            "dt_limited_steps": mover.limited_steps,
            "min_tetrahedron_quality": float(tetrahedron_quality(self.current.mesh).min()),
            **self.remesher.summary(),
            "volume_correction_total": mover.correction_abs,
            "volume_correction_net": mover.correction_net,
        }

    def save_state(self) -> dict[str, Any]:
        return {"history": copy.deepcopy(self.history)}

    def restore_state(self, state: dict[str, Any]) -> None:
        self.history = copy.deepcopy(state["history"])
