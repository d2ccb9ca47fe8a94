"""Plain-English explanations of verdicts, rendered from proof trees with the rulebook's templates."""
from .text import explain_incident, render_tree, sentence

__all__ = ["explain_incident", "render_tree", "sentence"]
