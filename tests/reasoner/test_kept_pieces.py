"""A kept value longer than the cache keeps in one entry (store/derived_cache.py MAX_PAYLOAD) is
kept in pieces, each under its own seal, with a head naming their count and digest
(reasoner/case_memo.py): a run whose cases or decisions' forms outgrow one entry keeps them as
a smaller run does, and a forged piece, or pieces of two writes put together, are not believed."""
from __future__ import annotations

import json
import sqlite3

import pytest

from reasoner.regress import regression as regress_module
from reasoner.case_memo import CaseMemo
from store import Store
from store.cache import cache_tampering, derived as derived_cache

from tests.reasoner import regress_runs as R
from tests.reasoner.regress_runs import db, new_rules  # noqa: F401 (fixtures)

SMALL = 256         # the largest entry, in characters: every kept value of the small run outgrows it


def test_values_larger_than_an_entry_are_kept_in_pieces_and_read_back(db, new_rules, monkeypatch):
    """With entries of at most SMALL characters, the decisions' forms and the baseline's cases and
    incidents are still kept: the second regression shapes no decision, judges no baseline case,
    and gives the plain path's result."""
    monkeypatch.setattr(derived_cache, "MAX_PAYLOAD", SMALL)
    first = R.regressed(db, new_rules)
    with sqlite3.connect(f"{db}.cache") as cache:
        assert cache.execute("SELECT max(length(payload)) FROM derived").fetchone()[0] <= SMALL
        assert cache.execute("SELECT count(*) FROM derived WHERE kind = 'shapes' AND instr(key, ' piece ')"
                             ).fetchone()[0] > 1
    calls = R.shaping(monkeypatch)
    judged: list = []
    afresh = regress_module.Investigation._afresh
    monkeypatch.setattr(regress_module.Investigation, "_afresh",
                        lambda inv, *a: judged.append(inv.speedups.keeps_incidents) or afresh(inv, *a))
    assert R.regressed(db, new_rules) == first == R.plain(db, new_rules)
    assert calls == []
    assert True not in judged                   # the baseline's incidents read, not judged


def test_a_forged_piece_is_not_believed(db, new_rules, monkeypatch):
    """The first piece of each kept set of forms altered: its seal does not open, `gaps verify`'s
    check names it, and the decisions are shaped again, to the same result."""
    monkeypatch.setattr(derived_cache, "MAX_PAYLOAD", SMALL)
    first = R.regressed(db, new_rules)
    with sqlite3.connect(f"{db}.cache") as cache:
        forged = cache.execute("SELECT key, payload FROM derived WHERE kind = 'shapes' AND key LIKE '% piece 0'"
                               ).fetchall()
        assert forged
        for key, payload in forged:
            cache.execute("UPDATE derived SET payload = ? WHERE kind = 'shapes' AND key = ?",
                          (payload[:-1] + ("0" if payload[-1] != "0" else "1"), key))
    with Store.open_read_only(db) as store:
        named = cache_tampering(store, [R.RUN]).derived[R.RUN]
    assert sorted(named) == sorted(f"shapes {key}" for key, _ in forged)
    calls = R.shaping(monkeypatch)
    assert R.regressed(db, new_rules) == first
    assert calls


def test_pieces_of_two_writes_are_not_one_value(db, monkeypatch):
    """Each piece of an older write of the same entry opens its seal (this code wrote it under
    that key), but put among a newer write's pieces they are not the value the head names."""
    monkeypatch.setattr(derived_cache, "MAX_PAYLOAD", SMALL)
    older, newer = list(range(200)), list(range(1, 201))
    with Store.open_read_only(db) as store:
        for value in (older, newer):
            memo = CaseMemo(store, R.RUN)
            memo.put("test", "k", value, plain=True)
            memo.save()
            if value is older:
                kept = store.cache.connection.execute(
                    "SELECT key, payload, mac FROM derived WHERE kind = 'test' AND key = 'k piece 0'").fetchone()
        assert CaseMemo(store, R.RUN).get("test", "k", plain=True) == newer
        store.cache.connection.execute("UPDATE derived SET payload = ?, mac = ? WHERE kind = 'test' AND key = ?",
                                       (kept[1], kept[2], kept[0]))
        assert not cache_tampering(store, [R.RUN]).derived.get(R.RUN)      # every seal opens
        assert CaseMemo(store, R.RUN).get("test", "k", plain=True) is None
    assert json.dumps(older) != json.dumps(newer) and len(json.dumps(older)) > SMALL // 4

