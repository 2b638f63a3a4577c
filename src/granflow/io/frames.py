"""Animation frames on disk: ``frames/frame_NNNNN.npz`` (mesh, cell speeds, interface).

Written as the run goes (every 0.02 s of simulated time), so that the animation can be
made again from the files alone (``granflow plot``), also for a killed run, and no frame
has to stay in memory or in a checkpoint.
"""

from __future__ import annotations

import io
import math
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from granflow.io.run_dir import RunDir
from granflow.io.untrusted import MB, RunDirError, load_npz, read_bytes
from granflow.state.spec import COUNT, Share, may_lack

FRAMES = "frames"
INTERVAL_S = 0.02   # simulated time between frames
FRAME_LIMIT = 64 * MB   # a frame of the largest mesh allowed is ~10 MB


class AnimationFrames:
    """The frames of a run; ``written`` is what a checkpoint remembers (the schedule's next
    time is the runner's)."""

    name = "frames"
    share: ClassVar[Share] = {"frames_written": may_lack(COUNT)}    # of a checkpoint

    def __init__(self, run_dir: RunDir, frame: Callable[[Any], dict[str, Any]],
                 resume: Mapping[str, Any] | None = None) -> None:
        self.run_dir, self.frame = run_dir, frame
        self.written = int(resume.get("frames_written", 0)) if resume else 0

    def write(self, sim: Any) -> None:
        """The frame of the current state of ``sim`` (its ``t``)."""
        write_frame(self.run_dir, self.written, self.frame(sim))
        self.written += 1

    def save_state(self) -> dict[str, Any]:
        return {"frames_written": self.written}


def write_frame(run_dir: RunDir, index: int, frame: dict[str, Any]) -> None:
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **{k: np.asarray(v) for k, v in frame.items()})
    run_dir.write_bytes(f"{FRAMES}/frame_{index:05d}.npz", buffer.getvalue())


def read_frames(root: Path) -> list[dict[str, Any]]:
    """Every readable frame of the run in ``root``, in time order; a file that is not a
    frame (cut short, not a regular file, an archive of something else) is left out."""
    frames = []
    for path in sorted((Path(root) / FRAMES).glob("frame_*.npz")):
        try:
            frame = load_npz(read_bytes(path, FRAME_LIMIT), path, FRAME_LIMIT)
        except RunDirError:
            continue
        if _valid(frame):
            frames.append(frame)
    frames.sort(key=lambda f: float(f["t"]))
    return frames


def _valid(frame: dict[str, np.ndarray]) -> bool:
    """A finite time; numbers only; a mesh whose triangles index its vertices."""
    t = frame.get("t")
    if t is None or t.shape != () or t.dtype.kind not in "iuf" or not math.isfinite(t):
        return False
    if any(v.dtype.kind not in "biuf" for v in frame.values()):
        return False
    xy, tri = frame.get("xy"), frame.get("tri")
    if xy is None or tri is None:
        return True
    return (xy.ndim == 2 and xy.shape[1] == 2 and bool(np.isfinite(xy).all())
            and tri.ndim == 2 and tri.shape[1] == 3 and tri.dtype.kind in "iu"
            and (tri.size == 0 or (tri.min() >= 0 and tri.max() < len(xy))))
