"""A parsed LE document: its templates by functor, its knowledge base, scenarios and queries.

The sentences in it are terms.py's plain data; the templates are templates.py's, and the matcher
built from them (sentences.py's `Vocabulary`) is cached on the template table. Kept apart from
terms.py, which the sentence matcher imports: the document names the matcher, the terms do not.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

if TYPE_CHECKING:   # for the annotations only
    from .sentences import Vocabulary
    from .templates import Template


class TemplateTable(dict[str, "Template"]):
    """Templates by functor (a second template with the same functor and another arity is
    filed under `functor/arity`); it also caches the matcher built from it."""

    _vocabulary: Vocabulary | None = None


@dataclass
class Document:
    """A parsed LE document: templates by functor, the knowledge base, scenarios and queries."""

    file: str
    templates: TemplateTable = field(default_factory=TemplateTable)    # functor (or functor/arity) -> Template
    rules: list = field(default_factory=list)
    scenarios: dict = field(default_factory=dict)    # name -> Scenario
    queries: dict = field(default_factory=dict)      # name -> Query
    target: str | None = None
    kb_names: list = field(default_factory=list)
    warnings: list = field(default_factory=list)     # LEWarning
    unreadable_queries: dict = field(default_factory=dict)   # name -> LEError (asking it raises that)

    def template_for(self, functor: str, arity: int):
        """The declared (or built-in) template that compiles to functor/arity, if any."""
        t = self.templates.get(functor)
        if t is not None and t.arity == arity:
            return t
        t = self.templates.get(f"{functor}/{arity}")
        if t is not None:
            return t
        return _builtin(functor, arity)


_BUILTINS: dict | None = None


def _builtin(functor: str, arity: int):
    """The built-in template of functor/arity (builtins.py imports templates, loaded on first use)."""
    global _BUILTINS
    if _BUILTINS is None:
        from .builtins import BUILTIN_BY_KEY
        _BUILTINS = BUILTIN_BY_KEY
    return _BUILTINS.get((functor, arity))
