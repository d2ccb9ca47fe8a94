"""How anything points at a recorded event: the reference that crosses every room.

An explanation cites its evidence, a finding the events it rests on, a proof node the event that
stated a fact; all of them say it the same way, so that a reader (or `gaps verify`) can find the
very event in the store: run, source and sequence number identify it, time and kind say what it
is without reading it.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping


@dataclass(frozen=True, slots=True)
class EventRef:
    """(run, src, seq) identifies the event; t and kind describe it."""

    run: str | None
    src: str
    seq: int
    t: int
    kind: str | None = None

    @classmethod
    def of(cls, event: Mapping[str, Any], run: str | None = None, kind: str | None = None) -> EventRef:
        """The reference of a whole event, or of a piece of folded state (which lacks the run
        and kind: give them)."""
        return cls(event.get("run", run), event["src"], event["seq"], event["t"], event.get("kind", kind))

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> EventRef:
        return cls(data.get("run"), data["src"], data["seq"], data["t"], data.get("kind"))

    @property
    def key(self) -> tuple[str, int]:
        """(src, seq): unique within a run."""
        return (self.src, self.seq)

    def to_json(self) -> dict[str, Any]:
        return {"run": self.run, "src": self.src, "seq": self.seq, "t": self.t, "kind": self.kind}
