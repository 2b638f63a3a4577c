"""Independent reference solutions used to verify granflow (no dependency on the rest of it)."""

from granflow.reference.plug1d import Plug1DSolution, solve_plug1d, source_term

__all__ = ["Plug1DSolution", "solve_plug1d", "source_term"]
