"""Reasoning over recorded runs: the LE rulebooks, the Prolog engine, scenarios and verdicts.

Importing this package does not start Prolog; the engine starts on first use.
"""
