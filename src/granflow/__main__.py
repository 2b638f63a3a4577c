"""``python -m granflow``: the same as the ``granflow`` command."""

from granflow.cli import main

raise SystemExit(main())
