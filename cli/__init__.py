"""The `gaps` command: argument parsing and output only; the rooms hold the logic."""
