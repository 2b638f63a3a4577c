"""The inertial numbers a mu(I) run reaches in its flowing cells.

Incompressible mu(I) is ill-posed at low and at high I (Barker, Schaeffer, Bohorquez and
Gray 2015, J. Fluid Mech. 779, 794-818); granflow does not regularise it (physics/mu_i.py),
so a run reports where it sat and how much of it sat in the law's well-posed window
(``physics/well_posedness.py``; fraction 0 when the law has no window): the distribution
of I = sqrt(2) |Du| d / sqrt([p]_+ / rho_s) over the flowing cells (mean |u| > 1 mm/s),
cell means weighted by area x dt, summed over the accepted steps. Kept as a histogram of 20
log-spaced bins per decade (quantiles good to 12 %), from 1e-8 to 1e2; values outside land
in the end bins.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from granflow.physics import MuI
from granflow.physics.well_posedness import well_posed_window

EDGES = np.logspace(-8.0, 2.0, 201)


@dataclass
class InertialNumbers:
    """Area x time spent by the flowing cells in each bin of I."""

    weights: np.ndarray = field(default_factory=lambda: np.zeros(len(EDGES) + 1))
    largest: float = 0.0
    well_posed: tuple[float, float] | None = None   # (I_N1, I_N2) of the law, or None

    @classmethod
    def of(cls, law: object) -> InertialNumbers | None:
        """The record of a mu(I) run, with its law's well-posed window (with a hysteretic
        friction, those of its flow law); None for another law."""
        law = getattr(law, "flow", law)
        if not isinstance(law, MuI):
            return None
        return cls(well_posed=well_posed_window(law))

    def add(self, values: np.ndarray, weights: np.ndarray) -> None:
        """Cell means of I and their weights (area x dt) of one step."""
        if len(values) == 0:
            return
        np.add.at(self.weights, np.searchsorted(EDGES, values), weights)
        self.largest = max(self.largest, float(np.max(values)))

    def quantile(self, q: float) -> float | None:
        """The upper edge of the bin where the cumulative weight reaches ``q``."""
        total = self.weights.sum()
        if total <= 0:
            return None
        k = int(np.searchsorted(np.cumsum(self.weights) / total, q))
        return float(EDGES[min(k, len(EDGES) - 1)])

    def fraction_between(self, low: float, high: float) -> float:
        """Weight fraction of the bins that lie inside [low, high] (to the bin width)."""
        total = self.weights.sum()
        lower = np.concatenate([[0.0], EDGES])          # bin k holds EDGES[k-1] < I <= EDGES[k]
        upper = np.concatenate([EDGES, [np.inf]])
        inside = (lower >= low) & (upper <= high)
        return float(self.weights[inside].sum() / total) if total > 0 else 0.0

    def summary(self) -> dict[str, Any] | None:
        """Quantiles 5, 50, 95, 99 % and the largest cell mean (a cell at the free surface,
        where p -> 0 sends I to infinity: the quantiles are the measure), the well-posed
        window and the fraction of the flowing area x time inside it, or None without
        flowing cells."""
        if self.weights.sum() <= 0:
            return None
        window = self.well_posed
        return {"p05": self.quantile(0.05), "p50": self.quantile(0.5),
                "p95": self.quantile(0.95), "p99": self.quantile(0.99), "max": self.largest,
                "well_posed_window": list(window) if window else None,
                "well_posed_fraction": self.fraction_between(*window) if window else 0.0}
