"""Command-line shell: parses arguments, shows progress, calls the core. No computing here."""
