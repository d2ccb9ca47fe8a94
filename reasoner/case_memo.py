"""What an investigation measured of a run's cases, kept for the next one (store/derived_cache.py).

Judging a case is measuring it (the vehicle's passage, what it shows at the act, the state at
the act) and then asking the rulebooks. The measuring reads and reconstructs from the record and
is most of the cost; it depends on the events and on this code, never on a rulebook. So what it
found is kept in the store's cache file, sealed, under the run's chain and a digest of the code
that measured it; the next investigation of the same chain, under the same or other rulebooks,
re-runs the law on every case from it. The list of cases is kept as well, under the monitor
rulebook that found them (re-deriving potential violations from every observation is a rulebook
question), and so are the cases nobody recorded that this rulebook does not raise (no incident,
whatever the other stages' rulebooks say).

Kept values are encoded as JSON through a closed list of this code's own value types
(`_TYPES`): nothing read back can name a type outside it, and nothing executes.
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
from functools import lru_cache
from pathlib import Path
from typing import Any, Callable

from store import EventRef, Store, parse_json
from store.cache import derived as derived_cache

from .derived import Contradiction
from .measurement import Measurement
from .model import (Act, AdsEvent, Cited, Control, Decision, DerivedFact, Finding, Incident, Liability, Margin,
                    Penalty, Proofs, RulebookChoice, Scenarios, Source, StageProof)
from .unforced import Unforced

_ROOT = Path(__file__).resolve().parent.parent
_CODE = ("reasoner", "store")           # the packages whose code measures


# The kinds read for a few of their entries: each read by its key when asked for (a regression
# reads the whole incidents of the changed ones alone, beside every one's summary).
_BY_KEY = frozenset({"incident"})
_PIECES = "#pieces "       # an entry kept in pieces holds this, its count and digest: no JSON starts so


class Uncacheable(TypeError):
    """A value of a type the codec does not keep: the case is measured again next time."""


@lru_cache(maxsize=1)
def code_version() -> str:
    """A digest of every Python and Prolog file of the measuring packages: a kept value is only used
    by the very code that made it (any change, even a comment, starts afresh). The Prolog engine is
    in it because which cases the monitor rulebook does not raise is kept too."""
    digest = hashlib.sha256()
    for package in _CODE:
        for path in sorted([*(_ROOT / package).rglob("*.py"), *(_ROOT / package).rglob("*.pl")]):
            digest.update(str(path.relative_to(_ROOT)).encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()[:32]


def key_of(*parts: Any) -> str:
    """A key for what names an entry (times, ids, the stated facts and their refs): the digest of
    the parts' repr, made in C but for an event reference's. Of the values a question is made of
    (None, bools, numbers, text, lists, tuples and dicts of them, event references) the repr
    is a literal that reads back as the very value, so no two that differ share it: a tuple
    and a list, 1, 1.0 and True, NaN or -0.0 and any other number, a big int and its float,
    an event reference and its fields (the repr names its type) all stay apart (JSON, the
    key's earlier form, made one array of a tuple and a list). A key is only compared under
    the code version that made it (code_version), so its form need only be stable within
    one: a dict is named in its order, which the code that builds a question keeps."""
    return hashlib.sha256(repr(parts).encode("utf-8", "surrogatepass")).hexdigest()


class CaseMemo:
    """One run's kept entries, per kind, loaded on first use; new ones are written by `save`."""

    def __init__(self, store: Store, run: str, *, enabled: bool = True) -> None:
        self.store, self.run, self.enabled = store, run, enabled
        self.chain = derived_cache.current_chain(store, run) if enabled else (0, "")
        self._kept: dict[str, derived_cache.Sealed] = {}
        self._fresh: dict[str, dict[str, str]] = {}
        self.hits = self.misses = 0

    def get(self, kind: str, key: str, *, plain: bool = False, counted: bool = True) -> Any:
        """The kept value, or None (never kept, kept for another chain or code, or its seal failed).
        `plain`: the value was kept as plain JSON data, not through the codec. `counted` False:
        not counted in hits and misses (what is measured again): a stage's answer, not a measurement."""
        value = self._value(kind, key, plain)
        if counted:
            if value is None:
                self.misses += 1
            else:
                self.hits += 1
        return value

    def text(self, kind: str, key: str) -> str | None:
        """The kept entry's JSON text, its seal checked, not parsed (a caller that may not need it
        parses it later), or None. Not counted in hits and misses."""
        if not self.enabled:
            return None
        if kind not in self._kept:
            self._kept[kind] = derived_cache.load(self.store, self.run, kind, code_version(), self.chain,
                                                  by_key=kind in _BY_KEY)
        text = self._kept[kind].get(key)
        if text is not None and text.startswith(_PIECES):
            return self._joined(kind, key, text)
        return text

    def _joined(self, kind: str, key: str, head: str) -> str | None:
        """The value kept in pieces, each under its own seal: None unless every piece is there
        and together they are the value the head names by its digest (pieces of two writes of
        the entry, each sealed, are not one value)."""
        try:
            count, digest = head[len(_PIECES):].split(" ")
            pieces = [self._kept[kind].get(_piece_key(key, n)) for n in range(int(count))]
        except ValueError:
            return None
        present = [piece for piece in pieces if piece is not None]
        if len(present) < len(pieces):
            return None
        text = "".join(present)
        return text if _digest(text) == digest else None

    def _value(self, kind: str, key: str, plain: bool) -> Any:
        text = self.text(kind, key)
        if text is None:
            return None
        try:
            return parse_json(text) if plain else decode(parse_json(text))
        except (ValueError, KeyError, TypeError, IndexError):
            return None         # written by this code under this seal, so never expected: measured again

    def put(self, kind: str, key: str, value: Any, *, plain: bool = False) -> None:
        if not self.enabled:
            return
        try:
            text = plain_text(value) if plain else json.dumps(encode(value), separators=(",", ":"), allow_nan=True)
        except (Uncacheable, TypeError, ValueError):
            return
        if text is None:
            return              # not plain after all (a tuple, a key that is not text): not kept
        fresh, size = self._fresh.setdefault(kind, {}), _piece_size()
        if len(text) <= size:
            fresh[key] = text
            return
        pieces = range(0, len(text), size)
        for n, i in enumerate(pieces):
            fresh[_piece_key(key, n)] = text[i:i + size]
        fresh[key] = f"{_PIECES}{len(pieces)} {_digest(text)}"

    def remember(self, kind: str, key: str, compute: Callable[[], Any], *, plain: bool = False) -> Any:
        """The kept value, else computed now and kept (at `save`); a None computed is not kept."""
        found = self.get(kind, key, plain=plain)
        if found is None:
            found = compute()
            if found is not None:
                self.put(kind, key, found, plain=plain)
        return found

    def save(self) -> None:
        """Write what was measured afresh, if the run's chain is still the one it was read from."""
        for kind, entries in self._fresh.items():
            if entries:
                derived_cache.save(self.store, self.run, kind, code_version(), self.chain, entries)
        self._fresh.clear()


def plain_text(value: Any) -> str | None:
    """The value's JSON text, or None where it is no plain JSON data: it does not read back as
    the very value (a tuple, a key that is not text), or JSON has no form for it."""
    try:
        text = json.dumps(value, separators=(",", ":"), allow_nan=True)
    except (TypeError, ValueError):
        return None
    return text if json.loads(text) == value else None


def _piece_size() -> int:
    """The most characters one kept entry holds: a longer value is kept in pieces of a quarter
    of the cache's largest entry (store/derived_cache.py keeps none over it), so that a run
    three times the hour keeps its cases and its decisions' forms as the hour does (its forms
    are 1.5 MB, its cases 2.4 MB)."""
    return max(1, derived_cache.MAX_PAYLOAD // 4)


def _piece_key(key: str, n: int) -> str:
    return f"{key} piece {n}"


def _digest(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest()


# --- the codec ---------------------------------------------------------------------------------

# The measurements' types, and an incident's (a judgement under the rulebooks in force is kept too:
# reasoner/speedups/kept_verdicts.py).
_TYPES: dict[str, type] = {cls.__name__: cls for cls in (
    EventRef, DerivedFact, Contradiction, Margin, Measurement, Incident, RulebookChoice, Finding, Penalty, Liability,
    AdsEvent, Cited, Control, Decision, Scenarios, StageProof, Proofs, Act, Source, Unforced)}


def encode(value: Any) -> Any:
    """Plain JSON data for a value: tuples, dicts and this code's value types tagged."""
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    if isinstance(value, list):
        return [encode(v) for v in value]
    if isinstance(value, tuple):
        return {"()": [encode(v) for v in value]}
    if isinstance(value, dict):
        if _pure(value):            # a proof tree: kept as it is, read back by the parser alone
            return {"j": value}
        if all(type(k) is str for k in value):
            return {"s": {k: encode(v) for k, v in value.items()}}
        return {"{}": [[encode(k), encode(v)] for k, v in value.items()]}
    if type(value) is EventRef:         # the most common value by far: kept short
        return {"r": [value.run, value.src, value.seq, value.t, value.kind]}
    name = type(value).__name__
    if _TYPES.get(name) is type(value) and dataclasses.is_dataclass(value):
        return {"@": name, "f": [encode(getattr(value, f.name)) for f in dataclasses.fields(value)]}
    raise Uncacheable(f"{name} is not kept")


_SCALARS = frozenset({str, int, float, bool, type(None)})


def decode(data: Any) -> Any:
    """The value `encode` was given. (Scalars, most of a kept measurement, are passed over
    without a call each: a judgement from kept measurements decodes half a million values.)"""
    kind = type(data)
    if kind is list:
        return _decoded(data)
    if kind is not dict:
        return data
    ref = data.get("r")
    if ref is not None:
        return EventRef(*ref)
    if "j" in data:
        return data["j"]
    if "()" in data:
        return tuple(_decoded(data["()"]))
    plain = data.get("s")
    if plain is not None:
        scalars = _SCALARS
        return {k: v if type(v) in scalars else decode(v) for k, v in plain.items()}
    if "{}" in data:
        return {_hashable(decode(k)): decode(v) for k, v in data["{}"]}
    return _TYPES[data["@"]](*_decoded(data["f"]))


def _pure(value: Any) -> bool:
    """Whether the value is JSON's own data (objects with text keys, arrays, scalars), which JSON
    gives back exactly as it was: no tuple, no value type, nothing the codec must tag."""
    kind = type(value)
    if kind in _SCALARS:
        return kind is not float or value == value          # NaN is not itself: tagged, never equal
    if kind is list:
        return all(_pure(v) for v in value)
    if kind is dict:
        return all(type(k) is str and _pure(v) for k, v in value.items())
    return False


def _decoded(items: list) -> list:
    scalars = _SCALARS
    return [v if type(v) in scalars else decode(v) for v in items]


def _hashable(key: Any) -> Any:
    return tuple(key) if isinstance(key, list) else key
