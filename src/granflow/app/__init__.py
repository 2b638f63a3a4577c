"""The application: what a user can ask of granflow, one module each. ``cli.py``, the
``granflow`` command (also ``python -m granflow``); ``api.py``, the Python API
(``granflow.run``, ``granflow.load``, ``granflow.resume``); ``run.py``, a configured problem
run into a run directory; ``resume.py``, a run continued from its checkpoint; ``sweep.py``,
parameter sweeps (the built-in ones in ``studies/``); ``converge.py`` and
``convergence_report.py``, a convergence study and its comparison; ``verify.py``, the paper's
plug-flow tables recomputed. Their earlier names keep working
(``granflow/earlier_names.py``)."""
