"""Continuing a run from its checkpoint (``granflow resume``, ``granflow.resume``): an
interrupted, killed or failed run to its end, or a finished one to a later ``time.t_end``.

Only keys that leave the checkpointed state a state of the same problem may change: the
end time and later output times, the outputs, the stop at rest, and the step and solver
controls (``RESUMABLE``); the others (geometry, material, mesh, the model's numerics) are
refused with one line naming the key. Everything is checked before the run directory is
touched: the checkpoint is read, every member of its state checked against what its part
declares (``runner.checked_state``) and restored into a freshly built problem first, so a
checkpoint that does not fit its configuration is a ``CheckpointError``, not a failed run.
The temporary files a killed run left are removed.
Extending keeps the step policy where it was (only its end and stops change); changing a
step control rebuilds it from the configuration.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from granflow.config import Config, ConfigError, config_to_toml, load_config
from granflow.config.messages import fmt_value
from granflow.io.checkpoint import CHECKPOINT_FILE, CheckpointError, read_checkpoint
from granflow.io.profiles import label_of
from granflow.io.run_dir import RUN_FILES, RunDir, RunDirError
from granflow.io.run_state import SimulationState
from granflow.state.spec import StateError

FINISHED = ("completed", "stopped")
# keys whose change the step policy must follow (it is then rebuilt from the configuration)
POLICY_KEYS = frozenset({"time.dt", "time.dt_init", "time.dt_max", "time.dt_growth",
                         "time.adaptive", "time.error_tol", "time.error_floor",
                         "numerics.tol", "numerics.tol_init"})
RESUMABLE = POLICY_KEYS | frozenset({
    "time.t_end", "time.output_times", "time.stop_at_rest", "time.rest_fraction",
    "time.rest_duration", "numerics.max_iterations", "numerics.linearization",
    "numerics.linear_solver", "numerics.initial_guess", "numerics.velocity_floor",
    "mesh.remesh_quality", "mesh.failure_remesh_quality"})
RESUMABLE_SECTIONS = ("output",)


def resume_run(path: str | Path, overrides: Sequence[str], *, progress: bool,
               log: Callable[[str], None] | None,
               check_solver: Callable[[Config], None]) -> Path:
    """Continue the run in ``path`` (module docstring); returns its folder."""
    from granflow.app.run import build_problem, checked_state, run_simulation

    root = Path(path)
    if not RunDir.is_run_dir(root):
        raise RunDirError(f"'{root}' is not a granflow run directory (no config.toml)")
    saved = load_config(root / "config.toml")
    config = load_config(root / "config.toml", overrides) if overrides else saved
    changed = changed_keys(saved, config)
    _check_keys(root, changed)
    check_solver(config)
    run_dir = RunDir(root)
    with run_dir.lock():   # before reading: the run may still be writing it
        run_dir.check_layout()
        status = RunDir.status(root)
        state = _checkpoint(root, status, saved)
        try:
            problem = build_problem(config)
        except Exception:   # reported by run_simulation as for a new run: a failed run
            problem = None
        try:                # every member, before any is read
            state = checked_state(state, problem)
        except StateError as err:
            raise CheckpointError(f"the checkpoint of '{root}' was not written by granflow "
                                  f"or was changed since: {err}") from None
        _check_times(root, status, saved, config, state)
        _adapt(state, config, changed)
        if problem is not None:
            _fit_stop_criteria(state, len(problem.simulation.stop_criteria))
            try:
                problem.restore_state(state.scenario)
                problem.simulation.restore_state(state.loop)
            except Exception as exc:   # a tampered or foreign state: nothing is written
                raise CheckpointError(f"the checkpoint of '{root}' does not fit its "
                                      f"configuration: {type(exc).__name__}: "
                                      f"{str(exc)[:300]}") from None
        if not run_dir.has_manifest():          # a run of an earlier granflow: its files
            run_dir.adopt_layout(earlier_files(saved, state, problem))
        run_dir.remove_temporary_files()        # left by a killed run
        if changed:
            run_dir.write_text("config.toml", config_to_toml(config))
        if log is not None:
            what = "extending" if status in FINISHED else "resuming"
            log(f"granflow: {what} {root} from t = {state.t:.6g} s (step {state.step}) "
                f"to t_end = {config.time.t_end:g} s")
        run_simulation(config, run_dir, resume=state, problem=problem,
                       progress=progress and config.output.progress)
    return root


def earlier_files(config: Config, state: SimulationState, problem: Any) -> list[str]:
    """The files the run being resumed wrote, as far as its own records name them: the
    run's files, its checkpoint, the snapshots its state lists, its index, the frames it
    counts, the profiles of its output times so far (of the kinds its problem declares)
    and their units (``RunDir.adopt_layout``)."""
    names = [*RUN_FILES, CHECKPOINT_FILE, "fields/fields.pvd", "profiles/units.json"]
    names += [f"fields/{name}" for _, name in state.outputs.get("vtk_entries", [])]
    names += [f"frames/frame_{i:05d}.npz" for i in range(state.outputs.get("frames_written",
                                                                            0))]
    if problem is not None:
        times = [t for t in config.time.output_times if t <= state.t + 1e-9 * max(1.0, t)]
        kinds = problem.simulation.callbacks.profiles(state.t) if times else {}
        names += [f"profiles/{kind}_{label_of(t)}.csv" for kind in kinds for t in times]
    return names


def changed_keys(before: Config, after: Config) -> list[str]:
    """The "section.key" names whose values differ between two configurations."""
    a, b = before.model_dump(), after.model_dump()
    keys = [] if a["scenario"] == b["scenario"] else ["scenario"]
    return keys + [f"{section}.{key}" for section, values in a.items()
                   if isinstance(values, dict) for key in values
                   if values[key] != b[section][key]]


def _check_keys(root: Path, changed: list[str]) -> None:
    for key in changed:
        if key not in RESUMABLE and key.split(".")[0] not in RESUMABLE_SECTIONS:
            raise ConfigError(
                f"{key} cannot change when a run is resumed: the checkpoint is a state of the "
                "problem as it was; resume may change time.t_end, later time.output_times, "
                "output.*, the stop at rest and the step and solver controls (time.dt_max, "
                f"numerics.tol, ...); to change {key}, run the case again: `granflow run "
                f"{root / 'config.toml'} --set {key}=... --out NEW_DIR`")


def _checkpoint(root: Path, status: str | None, config: Config) -> SimulationState:
    """The run's checkpoint; without one, a message that says what happened and what to
    do."""
    if not (root / CHECKPOINT_FILE).exists() and not (root / CHECKPOINT_FILE).is_symlink() \
            and status in (None, "running"):
        raise CheckpointError(
            f"the run in '{root}' was stopped (killed?) before its first checkpoint, which "
            f"comes after output.checkpoint_every = {config.output.checkpoint_every} steps "
            f"(its status is still '{status}'): there is nothing to continue from; start it "
            f"again with `granflow run {root / 'config.toml'} --out {root} --force`")
    return read_checkpoint(root)


def _check_times(root: Path, status: str | None, saved: Config, config: Config,
                 state: SimulationState) -> None:
    """A later t_end (a finished run must be given one), output times added only after
    the checkpoint's time, and a run at rest told how to go on."""
    t, t_end = state.t, config.time.t_end
    if status in FINISHED and t_end <= saved.time.t_end and (
            status == "completed" or config.time.stop_at_rest):
        raise RunDirError(
            f"the run in '{root}' has already finished (status = '{status}' at t = {t:.6g} s);"
            f" to extend it, resume with --set time.t_end=T, T later than {t:.6g} s"
            + (" and --set time.stop_at_rest=false" if status == "stopped" else ""))
    if t_end <= t * (1 + 1e-12):
        raise ConfigError(f"time.t_end = {t_end!r} must be later than the run's time "
                          f"t = {t:.6g} s at its checkpoint")
    if status == "stopped" and config.time.stop_at_rest:
        raise ConfigError(
            f"the run in '{root}' came to rest, so with time.stop_at_rest = true it would stop "
            "again at once; add --set time.stop_at_rest=false to continue it to time.t_end")
    done = [x for x in saved.time.output_times if x <= t]
    now = [x for x in config.time.output_times if x <= t]
    if now != done:
        raise ConfigError(
            f"time.output_times may only add times after the run's time t = {t:.6g} s "
            f"(the earlier ones, {fmt_value(done) if done else 'none'}, are written and stay "
            "as they are)")


def _adapt(state: SimulationState, config: Config, changed: list[str]) -> None:
    """The step policy of the changed configuration: a new one if a step control changed,
    else the saved one with the new end and stops (an extension continues its steps)."""
    from granflow.simulation.timestep import step_policy

    if not changed:
        return
    policy: Any = state.loop.get("steps_policy")
    fresh = step_policy(config)
    if POLICY_KEYS.intersection(changed) or type(policy) is not type(fresh):
        state.loop["steps_policy"] = None          # the loop keeps the fresh one it was built with
        return
    policy.t_end, policy.stops = fresh.t_end, fresh.stops


def _fit_stop_criteria(state: SimulationState, count: int) -> None:
    """The saved criteria's states for the loop's ``count`` criteria (time.stop_at_rest may
    have changed: a new criterion starts afresh)."""
    saved = list(state.loop.get("stop_criteria") or [])
    state.loop["stop_criteria"] = (saved + [None] * count)[:count]
