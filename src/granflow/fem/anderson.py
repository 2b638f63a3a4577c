"""Anderson acceleration of the fixed-point iteration (3.2).

The fixed point x = G(x) of (3.2) contracts linearly, slowly where the flow changes
between rest and motion (rates of 0.6-0.8 per iteration after a remesh or where the
surface tension (3.8)-(3.11) switches on). Anderson's mixing (Walker & Ni 2011, SIAM J.
Numer. Anal. 49; for Picard iterations of flows, Pollock, Rebholz & Xiao 2019, SIAM J.
Numer. Anal. 57) takes as the next iterate the combination of the last ``depth`` + 1
images G(x_j) whose residuals f_j = G(x_j) - x_j combine to the smallest norm:

    gamma = argmin || f_k - sum_j gamma_j (f_{j+1} - f_j) ||,
    x_{k+1} = G(x_k) - sum_j gamma_j (G(x_{j+1}) - G(x_j)).

Only the iterate changes: each iteration is still one solve of (3.2) at x_k, and the
convergence test is the plain fixed-point change ||G(x_k) - x_k||, so an accepted state
passes the test of section 3.1 exactly as a plain iteration's does. The norm is the
velocity's L2 norm (the one of the test). A mixed iterate whose residual has grown
restarts the history.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

Weighted = Callable[[np.ndarray], np.ndarray]   # v -> M v for the inner product v . M w


class Anderson:
    """The mixing history of one step's fixed-point iterations (numpy vectors)."""

    def __init__(self, depth: int, weight: Weighted, rcond: float = 1e-10) -> None:
        self.depth = depth
        self.weight = weight
        self.rcond = rcond
        self._images: list[np.ndarray] = []      # G(x_j)
        self._residuals: list[np.ndarray] = []   # f_j = G(x_j) - x_j
        self._weighted: list[np.ndarray] = []    # M f_j
        self.restarts = 0

    def reset(self) -> None:
        """Forget the history (a new step, or the iteration changed its map)."""
        self._images.clear()
        self._residuals.clear()
        self._weighted.clear()

    def mix(self, iterate: np.ndarray, image: np.ndarray) -> np.ndarray:
        """The next iterate from x_k (``iterate``) and G(x_k) (``image``)."""
        residual = image - iterate
        weighted = self.weight(residual)
        if self._residuals:
            last = float(self._residuals[-1] @ self._weighted[-1])
            if float(residual @ weighted) > last:      # the mixing did not pay: restart
                self.reset()
                self.restarts += 1
        self._images.append(image.copy())
        self._residuals.append(residual)
        self._weighted.append(weighted)
        if len(self._residuals) > self.depth + 1:
            for history in (self._images, self._residuals, self._weighted):
                history.pop(0)
        if len(self._residuals) < 2 or self.depth == 0:
            return image.copy()
        d_f = np.diff(np.array(self._residuals), axis=0)         # (m, n)
        d_mf = np.diff(np.array(self._weighted), axis=0)
        gram = d_f @ d_mf.T                                      # (df_i, M df_j)
        rhs = d_mf @ residual
        gamma = np.linalg.lstsq(gram, rhs, rcond=self.rcond)[0]
        d_g = np.diff(np.array(self._images), axis=0)
        return image - gamma @ d_g
