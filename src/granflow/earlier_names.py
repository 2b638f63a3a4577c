"""The modules that moved, under the names they had before: the application's modules
(``granflow.runner``, ``granflow.cli``, ...) now gathered in ``granflow.app``, the
checkpoint's schema (``granflow.simulation.state_spec``, now ``granflow.state.spec``, on
the ground floor) and the distances between polylines (now in ``granflow.geometry``).
Scripts and plug-ins that import an earlier name get the very module it became (so that
patching one of its names patches it), through a finder that Python asks after its own
(``install``, done when granflow is imported)."""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys
from collections.abc import Sequence
from importlib.machinery import ModuleSpec
from types import ModuleType

EARLIER = {
    "granflow.api": "granflow.app.api",
    "granflow.cli": "granflow.app.cli",
    "granflow.converge": "granflow.app.converge",
    "granflow.convergence_report": "granflow.app.convergence_report",
    "granflow.resuming": "granflow.app.resume",
    "granflow.runner": "granflow.app.run",
    "granflow.sweep": "granflow.app.sweep",
    "granflow.verify": "granflow.app.verify",
    "granflow.simulation.state_spec": "granflow.state.spec",
    "granflow.diagnostics.compare": "granflow.geometry.polylines",
}


class _Same(importlib.abc.Loader):
    """Loads an earlier name as the module it became."""

    def __init__(self, target: str) -> None:
        self.target = target

    def create_module(self, spec: ModuleSpec) -> ModuleType:
        module = importlib.import_module(self.target)
        self.own = module.__spec__       # Python sets the earlier name's spec on it
        return module

    def exec_module(self, module: ModuleType) -> None:
        """Nothing to run (the module it became is imported): its own spec back."""
        module.__spec__ = self.own


class EarlierNames(importlib.abc.MetaPathFinder):
    """Finds the earlier names of ``EARLIER``."""

    def find_spec(self, fullname: str, path: Sequence[str] | None,
                  target: ModuleType | None = None) -> ModuleSpec | None:
        if fullname not in EARLIER:
            return None
        return importlib.util.spec_from_loader(fullname, _Same(EARLIER[fullname]))


def install() -> None:
    """Ask this finder after Python's own (once)."""
    if not any(isinstance(finder, EarlierNames) for finder in sys.meta_path):
        sys.meta_path.append(EarlierNames())
