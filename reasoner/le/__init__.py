"""The Logical English compiler (the walking skeleton\x27s subset; issue 4 completes it)."""
