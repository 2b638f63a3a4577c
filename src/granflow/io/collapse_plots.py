"""Figures of a collapse run, like the paper's (Figures 7-9, 12-15), and its animation, drawn
from the run directory's files through their readers (profiles, fields, diagnostics,
frames): free surfaces, the static and flowing zones, velocity sections with where they
are, the front and the kinetic energy (remeshes and the stop marked) and ``speed.gif``
(``io/animation.py``); an erodible layer draws its own (``io/erosion_plots.py``).

Only output times the run reached are drawn; the last accepted state is drawn once, named
for what it is ("at rest from t = ..." for a mass at rest, the status of a run that failed).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from granflow.geometry.section import Section  # noqa: E402
from granflow.io import profiles  # noqa: E402
from granflow.io.animation import animate  # noqa: E402
from granflow.io.diagnostics import read_diagnostics  # noqa: E402
from granflow.io.frames import read_frames  # noqa: E402
from granflow.io.plots import FigureFormat  # noqa: E402
from granflow.io.run_dir import RunDir, RunDirError  # noqa: E402
from granflow.simulation.rest import FLOWING_SPEED  # noqa: E402

STATIC, FLOWING = "0.62", "#bcd7ee"        # fills of the static and flowing zones
MARKED = 100      # events marked a line each on the time axis; more are counted only
CURVES = 40       # output times drawn (evenly chosen among more, the first and last kept)


@dataclass(frozen=True)
class Final:
    """The last accepted state: its time, its legend label and its free surface."""

    t: float
    label: str
    surface: dict[str, np.ndarray]


@dataclass(frozen=True)
class Drawn:
    """What the figures draw of the run's set-up: the plane or r-z section, the initial
    domain as a closed polyline (dashed, for reference) and the bed profile (None: the
    paper's level bed z = 0, the figures' lower edge)."""

    section: Section
    outline: np.ndarray
    bed_line: np.ndarray | None = None


@dataclass
class View:
    """What every figure of one run shares: labels, outline, times and their colours."""

    run_dir: RunDir
    config: Any
    summary: dict[str, Any]
    fmt: FigureFormat
    drawn: Drawn

    def __post_init__(self) -> None:
        self.section = self.drawn.section
        self.x = self.section.coordinate                  # the radius of a cylinder
        self.bed = _bed_note(self.config.geometry.slope_deg, self.section)
        self.outline = self.drawn.outline
        self.bed_line = self.drawn.bed_line
        self.final = final_state(self.run_dir, self.summary)
        rest = self.summary.get("outputs_at_rest") or [] if self.final is not None else []
        reached = [t for t in self.config.time.output_times
                 if profiles.profile_at(self.run_dir.root, "free_surface", t) is not None
                 and not any(abs(t - x) < 1e-9 for x in rest)]
        # an output time at the last state (t_end) is the last state's curve, drawn once
        times = [t for t in reached if self.final is None or abs(t - self.final.t) > 1e-6]
        keep = np.unique(np.linspace(0, len(times) - 1, min(len(times), CURVES)).round())
        self.times = [times[int(i)] for i in keep]
        cmap = plt.get_cmap("viridis")
        n = max(len(self.times), 1)
        self.colours = {t: cmap(0.9 * i / max(n - 1, 1)) for i, t in enumerate(self.times)}

    def label(self, t: float) -> str:
        return f"t = {t:.2f} s"

    def aspect(self, xmax: float) -> str:
        """True proportions, unless the flow ran out over more than 8 column heights (a
        slope): then a stretched z, or the deposit would be a line."""
        return "equal" if xmax <= 8 * self.config.geometry.height else "auto"


def final_state(run_dir: RunDir, summary: dict[str, Any]) -> Final | None:
    """The last state's free surface (profiles/free_surface_final.csv) and its label."""
    surface = profiles.final_profile(run_dir.root, "free_surface")
    t = summary.get("final_profiles_t")
    if surface is None or t is None:
        return None
    status, stop = summary.get("status", "end"), summary.get("stop_time_s")
    if status in ("stopped", "completed") and stop is not None:
        label = f"at rest from t = {stop:.3f} s"
    elif status == "completed":
        label = f"t_end = {t:.2f} s, still moving"
    else:
        label = f"{status} at t = {t:.3f} s"
    return Final(float(t), label, surface)


def _draw_bed(view: View, ax: plt.Axes) -> None:
    if view.bed_line is not None:
        ax.plot(*view.bed_line.T, color="0.25", lw=1.4, zorder=1)


def plot_collapse(run_dir: RunDir, config: Any, drawn: Drawn) -> None:
    """Every figure of a collapse into plots/ (``output.figure_format``) and speed.gif."""
    view = View(run_dir, config, RunDir.summary(run_dir.root), FigureFormat.of(config),
                drawn)
    _free_surfaces(view)
    _zones(view)
    _sections(view)
    _history(view)
    frames = read_frames(run_dir.root)
    if frames:
        animate(run_dir.path("plots/speed.gif"), frames, view.outline,
                config.geometry.erodible_thickness, view.bed, view.x, view.fmt.dpi)


def _free_surfaces(view: View) -> None:
    fig, ax = plt.subplots(figsize=(9.5, 3.2), layout="constrained")
    _draw_bed(view, ax)
    ax.plot(*view.outline.T, "--", color="0.6", lw=0.8, label="t = 0")
    for t in view.times:
        prof = profiles.profile_at(view.run_dir.root, "free_surface", t)
        ax.plot(prof["x"], prof["z"], color=view.colours[t], label=view.label(t))
    if view.final is not None:      # dashed: an output time at rest shows through it
        ax.plot(view.final.surface["x"], view.final.surface["z"], color="k", lw=1.3,
                ls=(0, (4, 2)), label=view.final.label)
    ax.set(xlabel=f"{view.x} (m)", ylabel="z (m)", title=f"Free surface{view.bed}",
           aspect=view.aspect(ax.dataLim.intervalx[1]))
    _legend(ax)
    view.fmt.save(fig, view.run_dir, "free_surface")


def _zones(view: View) -> None:
    """The static and flowing zones at each output time: the mass coloured by whether it
    moves faster than 1 mm/s (from the VTU snapshot's vertex velocities), the interface
    their 1 mm/s contour; without a snapshot, the profile's edge of the flowing cells."""
    from granflow.io.vtk import read_snapshot

    times = view.times
    if not times:
        return
    front = max(float(np.nanmax(profiles.profile_at(view.run_dir.root, "free_surface", t)["x"]))
                for t in times)
    xmax = 1.04 * max(front, float(view.outline[:, 0].max()))
    zmax = 1.06 * view.config.geometry.height
    zmin = 0.0
    if view.bed_line is not None:               # the mass over the drawn part of the bed
        zmax = float(view.outline[:, 1].max()) + 0.06 * view.config.geometry.height
        shown = view.bed_line[(view.bed_line[:, 0] <= xmax)]
        zmin = min(float(view.outline[:, 1].min()), float(shown[:, 1].min(initial=0.0)))
    ncols = 2 if len(times) > 2 else 1
    nrows = -(-len(times) // ncols)
    aspect = view.aspect(xmax)
    panel = (4.4 if ncols == 2 else 8.0) * (zmax - zmin) / xmax if aspect == "equal" else 1.4
    fig, axes = plt.subplots(nrows, ncols, figsize=(9.0 if ncols == 2 else 8.0,
                                                    0.9 + nrows * max(panel, 0.9)),
                             sharex=True, sharey=True, squeeze=False, layout="constrained")
    for ax, t in zip(axes.flat, times, strict=False):
        _draw_bed(view, ax)
        ax.plot(*view.outline.T, "--", color="0.6", lw=0.7)
        try:
            snap = read_snapshot(view.run_dir.root, t)
        except (RunDirError, ValueError, OSError, KeyError):   # no usable snapshot
            snap = None
        if snap is not None and "velocity" in snap.point_data:
            mesh = mtri.Triangulation(snap.points[:, 0], snap.points[:, 1], snap.triangles)
            speed = np.linalg.norm(snap["velocity"], axis=1)
            top = max(float(speed.max()), 2 * FLOWING_SPEED)
            ax.tricontourf(mesh, speed, levels=[0.0, FLOWING_SPEED, top],
                           colors=[STATIC, FLOWING])
            if speed.max() > FLOWING_SPEED > speed.min():
                ax.tricontour(mesh, speed, levels=[FLOWING_SPEED], colors="tab:red",
                              linewidths=1.1)
        else:
            line = profiles.profile_at(view.run_dir.root, "interface", t)
            if line:
                ax.plot(line["x"], line["z"], color="tab:red", lw=1.1)
        surface = profiles.profile_at(view.run_dir.root, "free_surface", t)
        ax.plot(surface["x"], surface["z"], color="k", lw=0.7)
        ax.text(0.99, 0.93, view.label(t), transform=ax.transAxes, ha="right", va="top",
                fontsize=9)
        ax.set(xlim=(min(0.0, float(view.outline[:, 0].min())), xmax), ylim=(zmin, zmax),
               aspect=aspect)
    for ax in axes.flat[len(times):]:
        ax.set_visible(False)
    for j in range(min(ncols, len(times))):   # each column's lowest panel: the x axis
        lowest = axes[(len(times) - 1 - j) // ncols, j]
        lowest.xaxis.set_tick_params(labelbottom=True)
        lowest.set_xlabel(f"{view.x} (m)")
    for ax in axes[:, 0]:
        ax.set_ylabel("z (m)")
    # the speed is resolved by the cells: its 1 mm/s level, read from the vertex values,
    # steps with the mesh (so does the finite-element field's own, sampled finely)
    cell = f"{100 * view.config.mesh.size:.2g} cm"
    handles = [Patch(color=STATIC, label="static, |u| < 1 mm/s"),
               Patch(color=FLOWING, label="flowing"),
               Line2D([], [], color="tab:red",
                      label=f"interface, |u| = 1 mm/s: resolved to a cell ({cell})"),
               Line2D([], [], color="0.6", ls="--", label="t = 0")]
    fig.legend(handles=handles, loc="outside lower center", ncols=4, fontsize=8,
               frameon=False)
    fig.suptitle(f"Static and flowing zones{view.bed}", fontsize=11)
    view.fmt.save(fig, view.run_dir, "interface")


def _sections(view: View) -> None:
    """Velocity profiles along the verticals of profiles/velocity_sections_*.csv, with a
    map of where they are (the initial front X_g at the bed, and 10 cm either side)."""
    root = view.run_dir.root
    found = [(t, p) for t in view.times
             if (p := profiles.profile_at(root, "velocity_sections", t))]
    if not found:
        return
    offsets = sorted({round(x, 6) for _, p in found for x in p["section_x"]})
    n = len(offsets)
    fig = plt.figure(figsize=(max(3.1 * n, 7.0), 8.2), layout="constrained")
    grid = fig.add_gridspec(3, n, height_ratios=[0.8, 1, 1])
    where = fig.add_subplot(grid[0, :])
    _draw_bed(view, where)
    where.plot(*view.outline.T, "--", color="0.6", lw=0.8, label="t = 0")
    for t, _ in found:
        surface = profiles.profile_at(root, "free_surface", t)
        where.plot(surface["x"], surface["z"], color=view.colours[t], lw=0.9,
                   label=view.label(t))
    front0 = view.config.geometry.width
    names = "ABCDEFGH"
    for j, xs in enumerate(offsets):
        where.axvline(xs, color="k", lw=0.8, ls=":")
        where.annotate(f" {names[j]}", (xs, 0.97), xycoords=("data", "axes fraction"),
                       ha="left", va="top", fontsize=9, weight="bold")
    where.set(xlabel=f"{view.x} (m)", ylabel="z (m)", aspect=view.aspect(
        where.dataLim.intervalx[1]), title=f"Where the sections are{view.bed}")
    _legend(where)
    first = None
    for j, xs in enumerate(offsets):
        top = fig.add_subplot(grid[1, j], sharey=first)
        bottom = fig.add_subplot(grid[2, j], sharey=top)
        first = first or top
        for t, p in found:
            m = np.isclose(p["section_x"], xs)
            top.plot(p["u_x"][m], p["z"][m], color=view.colours[t])
            bottom.plot(p["u_z"][m], p["z"][m], color=view.colours[t])
        shift = (xs - front0) * 100
        where_text = "X_g" if abs(shift) < 0.05 else f"X_g {shift:+.0f} cm".replace("-", "−")
        top.set_title(f"{names[j]}: {view.x} = {xs:.3f} m ({where_text})", fontsize=9)
        top.set_xlabel(f"u_{view.x} (m/s)")
        bottom.set_xlabel("u_z (m/s)")
        for a in (top, bottom):
            a.xaxis.set_major_locator(plt.MaxNLocator(4))
            a.axvline(0, color="0.8", lw=0.6)
        if j == 0:
            top.set_ylabel("z (m)")
            bottom.set_ylabel("z (m)")
    fig.suptitle(f"Velocity across vertical sections; X_g: the initial front at the bed "
                 f"({view.x} = {front0:g} m)", fontsize=10)
    view.fmt.save(fig, view.run_dir, "velocity_sections")


def _history(view: View) -> None:
    """Front and kinetic energy against time, with the stop time, the remeshes (the velocity
    carried to a new mesh) and the depositions (a free-surface edge that lands on the bed
    takes its friction, Figure 2 of the paper) marked: each changes the energy at once."""
    diag = read_diagnostics(view.run_dir.root)
    if not len(diag):
        return
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9.5, 3.4), layout="constrained")
    a1.plot(diag["t"], diag["front_x"], color="C0")
    a1.set(xlabel="t (s)", ylabel=f"front {view.x} (m)", title=f"Front position{view.bed}")
    a2.plot(diag["t"], diag["kinetic_energy"], color="C0")
    a2.set(xlabel="t (s)", ylabel=f"kinetic energy ({view.section.energy_unit})",
           title="Kinetic energy")
    handles = []
    for name, colour, style, words in (
            ("remesh", "0.5", ":", "velocity carried to a new mesh"),
            ("deposition", "tab:orange", "-.", "a surface edge lands on the bed")):
        times = [t for t in view.summary.get(f"{name}_times_s") or []
                 if isinstance(t, int | float)]
        for t in times if len(times) <= MARKED else []:
            for a in (a1, a2):
                a.axvline(t, color=colour, lw=0.6, ls=style)
        if times:
            unmarked = f", more than {MARKED}: not marked" if len(times) > MARKED else ""
            handles.append(Line2D([], [], color=colour, lw=0.6, ls=style,
                                  label=f"{name} ({len(times)}{unmarked}): {words}"))
    stop = view.summary.get("stop_time_s")
    if isinstance(stop, int | float):
        for a in (a1, a2):
            a.axvline(stop, color="k", lw=0.9, ls="--")
        handles.append(Line2D([], [], color="k", lw=0.9, ls="--",
                              label=f"at rest from t = {stop:.3f} s"))
    if handles:      # below the panels, off the curves
        fig.legend(handles=handles, loc="outside lower center", ncols=min(len(handles), 3),
                   fontsize=7, frameon=False)
    view.fmt.save(fig, view.run_dir, "front_and_energy")


def _bed_note(slope_deg: float, section: Section) -> str:
    """Words for a title: x runs along the bed, which is inclined on a slope; or the
    section of a cylinder, r from its axis."""
    if section.axisymmetric:
        return section.note
    return f" (x along the bed, inclined at {slope_deg:g}°)" if slope_deg else ""


def _legend(ax: plt.Axes) -> None:
    """The legend beside the axes, on the right: never over a curve."""
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
