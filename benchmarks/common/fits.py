"""Power-law fits of the aspect-ratio studies."""

from __future__ import annotations

import numpy as np


def power_fit(a: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """(k, n) of the least-squares line log y = log k + n log a."""
    n, log_k = np.polyfit(np.log(a), np.log(y), 1)
    return float(np.exp(log_k)), float(n)
