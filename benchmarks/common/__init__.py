"""Helpers shared by the benchmark scripts, imported as the package ``common`` (a script's
own folder, ``benchmarks/``, is first on its import path): the cases several scripts run
(``cases``) and running a case into a run directory and comparing two runs (``runs``).
Scripts import this package, never each other."""
