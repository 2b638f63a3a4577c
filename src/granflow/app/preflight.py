"""What is checked and said before a run starts, beyond its configuration's own checks:
that the linear solver it names is installed (only NGSolve can detect MKL; PETSc's
fieldsplit needs petsc4py and ngspetsc), the solver's label the run logs, and a note
before a run of more than an hour."""

from __future__ import annotations

from granflow.config import Config, ConfigError


def check_solver(config: Config) -> None:
    """PARDISO needs MKL, which only NGSolve can detect, and the fieldsplit solve needs
    petsc4py and ngspetsc: checked before the run starts."""
    if config.numerics.linear_solver == "fieldsplit":
        from granflow.fem.fieldsplit import refusal

        if (message := refusal()) is not None:
            raise ConfigError(message)
    if config.numerics.linear_solver == "pardiso":
        from granflow.fem.linalg import pardiso_available

        if not pardiso_available():
            raise ConfigError("numerics.linear_solver = 'pardiso' needs Intel MKL (pip install "
                              "mkl, x86-64 only); use 'auto' or 'umfpack'")


def note_cost(config: Config) -> None:
    """A ``ConfigNote`` before a run of more than an hour (``config/cost.py``)."""
    from granflow.config.cost import cost_note
    from granflow.config.messages import note

    message = cost_note(config)
    if message is not None:
        note(message)


def solver_label(config: Config) -> str:
    """The direct solver the run will use, as logged once at its start."""
    from granflow.fem.linalg import direct_solver

    solver = direct_solver(config.numerics.linear_solver)
    if solver == "fieldsplit":
        return "PETSc fieldsplit GMRes (Schur LSC, GAMG)"
    if solver == "umfpack" and config.numerics.linear_solver == "auto":
        return "UMFPACK (Intel MKL not found: pip install mkl for PARDISO)"
    return solver.upper()
