"""What `gaps verify` finds about signatures: how many events are signed, and, given the public
keys an investigator trusts, how many signatures verify and which is the first that does not.

A signature is judged on its own event's text, independently of the hash chain: a signed event
stays proven to come from its source even where the chain is broken, and a chain that verifies
says nothing about who wrote its events. Both verdicts are reported side by side.
"""

from __future__ import annotations

from typing import Any

from .signatures import SIG_FIELD, sig_problem


class SignatureTally:
    """Counts fed one stored event at a time (in chain order, run after run)."""

    def __init__(self, keys: Any = None) -> None:
        self.keys = keys  # store.TrustedKeys, or None: count only
        self.signed = 0
        self.unsigned = 0
        self.valid = 0
        self.invalid = 0
        self.first_invalid: dict[str, Any] | None = None

    def see(self, run: str, chain_pos: Any, src: Any, seq: Any, event: dict) -> int:
        """Count (and check) one event; returns 1 if it is signed, else 0."""
        if SIG_FIELD not in event:
            self.unsigned += 1
            return 0
        self.signed += 1
        if self.keys is not None:
            what = self._problem(event)
            if what is None:
                self.valid += 1
            else:
                self.invalid += 1
                if self.first_invalid is None:
                    self.first_invalid = {"run": run, "src": src, "seq": seq, "chain_pos": chain_pos, "what": what}
        return 1

    def _problem(self, event: dict) -> str | None:
        shape = sig_problem(event[SIG_FIELD])
        if shape is not None:
            return shape
        try:
            return self.keys.problem(event)
        except (KeyError, TypeError, AttributeError):  # a row altered into something that is no event
            return "the stored event is not a valid envelope, so its signature cannot be checked"

    @staticmethod
    def counted(signed: int, unsigned: int) -> dict[str, Any]:
        """The to_json of a tally that only counted (no keys): what a run's cached result keeps."""
        tally = SignatureTally()
        tally.signed, tally.unsigned = signed, unsigned
        return tally.to_json()

    def to_json(self) -> dict[str, Any]:
        """{signed, unsigned, checked, keys, valid, invalid, first_invalid}: valid, invalid and
        first_invalid are null when no keys were given (checked false)."""
        checked = self.keys is not None
        return {
            "signed": self.signed,
            "unsigned": self.unsigned,
            "checked": checked,
            "keys": self.keys.origin if checked else None,
            "valid": self.valid if checked else None,
            "invalid": self.invalid if checked else None,
            "first_invalid": self.first_invalid,
        }
