"""``python -m granflow``: the same as the ``granflow`` command."""

from granflow.app.cli import main

raise SystemExit(main())
