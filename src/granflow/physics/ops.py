"""A tiny operations shim so one law serves numpy arrays and FE coefficient functions.

The laws in this package only need a square root, a positive part and the larger of two
values; an FE layer provides its own ``Ops`` (e.g. NGSolve's ``sqrt`` and ``IfPos``)
without the laws importing that engine.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Ops:
    """The elementary functions a constitutive law may use."""

    sqrt: Callable[[Any], Any]
    positive_part: Callable[[Any], Any]
    maximum: Callable[[Any, Any], Any] = np.maximum   # a where a > b, else b exactly


NUMPY_OPS = Ops(sqrt=np.sqrt, positive_part=lambda a: np.maximum(a, 0.0))
