"""``python -m insrail`` runs the command-line interface."""

from insrail.cli.main import console

console()
