"""``python -m insrail`` runs the command-line interface."""

from insrail.cli.main import main

raise SystemExit(main())
