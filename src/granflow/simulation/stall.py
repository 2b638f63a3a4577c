"""The stall test: a run whose accepted steps no longer advance time ends with advice.

Steps accepted only because they are tiny (an iteration or a move that succeeds only at
dt ~ 1e-9 s) would otherwise crawl forever. The test looks at windows of ``stall_steps``
accepted steps: a window that advanced t by less than one dt_max while at least a tenth as
many attempts were rejected for another reason than the step error (the solve or the move
failed) is a stall. Small steps the policy chose (a slow ramp, an error controller far
below dt_max) are left alone.
"""

from __future__ import annotations

STALL_STEPS = 1000   # accepted steps that must advance t by at least one dt_max
STALL_ADVICE = {     # by the most frequent failure while the run stalled (Rejection names)
    "not_converged": "Try a larger numerics.max_iterations or numerics.linearization = "
                     "'hybrid' or 'newton'",
    "non_finite": "Try numerics.linearization = 'hybrid' or 'newton', or a larger numerics.eps",
    "move": "Try a smaller mesh.size or a larger mesh.remesh_quality",
    "exception": "See the rejections in summary.json",
}

# where the current window started: its step, its time, the rejections counted by then
Window = tuple[int, float, dict[str, int]]


def stall_check(window: Window | None, stall_steps: int, step: int, t: float, dt: float,
                rejections: dict[str, int], dt_max: float,
                t_end: float) -> tuple[Window | None, str | None]:
    """The window after this accepted step, and a failure message if the window that just
    closed stalled (None otherwise)."""
    if window is None:
        return (step, t, dict(rejections)), None
    step0, t0, rejected0 = window
    if step - step0 < stall_steps:
        return window, None
    window = (step, t, dict(rejections))
    dt_max = min(dt_max, t_end - t0)
    failed = {k: n - rejected0.get(k, 0) for k, n in rejections.items()
              if k != "error" and n > rejected0.get(k, 0)}
    if t - t0 >= dt_max or 10 * sum(failed.values()) < step - step0:
        return window, None
    worst = max(failed, key=failed.__getitem__)
    return window, (f"stalled at t = {t:.6g} s (step {step}): the last {step - step0} "
                    f"accepted steps advanced t by {t - t0:.3g} s, less than one dt_max "
                    f"({dt_max:g} s), last dt = {dt:.3g} s, while attempts were rejected: "
                    f"{failed}. {STALL_ADVICE[worst]}")
