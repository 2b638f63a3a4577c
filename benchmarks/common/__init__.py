"""Helpers shared by the benchmark scripts, imported as the package ``common`` (a script's
own folder, ``benchmarks/``, is first on its import path): writing the results
(``results``), the cases several scripts run (``cases``), running a case into a run
directory and comparing two runs (``runs``), a built-in study on Dask (``studies``) and
power-law fits (``fits``). Scripts import this package rather than each other."""
