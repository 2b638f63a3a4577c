"""``granflow run`` as a user types it, in a new process timed from outside: wall time from
start to exit, and the operating system's account of the finished child (processor time,
peak memory, faults, context switches), with the load average before it."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path


def timed_run(scenario: str, sets: list[str], out: Path, env: dict[str, str] | None = None,
              src: Path | None = None) -> dict:
    """Run ``granflow run SCENARIO --set ...`` into ``out`` with ``env`` added to the
    environment (and ``src`` first on the path: an earlier checkout's code); its times and
    its summary."""
    environment = {**os.environ, **(env or {})}
    if src is not None:
        environment["PYTHONPATH"] = str(src)
    command = [sys.executable, "-m", "granflow", "run", scenario, "--out", str(out),
               "--force", "--quiet", *(arg for o in sets for arg in ("--set", o))]
    load = os.getloadavg()[0]
    start = time.perf_counter()
    child = subprocess.Popen(command, stdout=subprocess.DEVNULL, env=environment)
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - start
    if status != 0:
        raise RuntimeError(f"{' '.join(command)} exited with status {status}")
    return {"process_wall_time_s": wall,
            "process_cpu_time_s": usage.ru_utime + usage.ru_stime,
            "user_s": usage.ru_utime, "system_s": usage.ru_stime,
            "peak_memory_mb": usage.ru_maxrss / 1024, "minor_faults": usage.ru_minflt,
            "involuntary_switches": usage.ru_nivcsw, "voluntary_switches": usage.ru_nvcsw,
            "load_before": load,
            "summary": json.loads((out / "summary.json").read_text())}
