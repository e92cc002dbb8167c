"""``python -m csl_cli``: the ``csl`` command, for a checkout without the console script."""

from csl_cli.main import main

raise SystemExit(main())
