"""The processor time of one call, as the median of repeated calls (a shared machine's
load moves wall time far more than processor time)."""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable


def processor_ms(call: Callable[[], object], repeat: int) -> float:
    """Processor time of one call of ``call`` (ms), median of ``repeat`` calls."""
    times = []
    for _ in range(repeat):
        start = time.process_time()
        call()
        times.append(time.process_time() - start)
    return 1e3 * statistics.median(times)
