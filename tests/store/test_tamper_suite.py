"""The tamper suite (issue 15, "Done when"): every table and every index of a store, and every
table of its cache file, changed one row at a time, and no change alters a verdict, an export or a
report without `gaps verify` failing.

The store holds the paper's run (sim_replay/paper.py: an ambulance's mitigated crossing and a
car's punishable one, judged by the bundled rulebooks), the paper's rulebook stored as `gaps rules
put` stores it (its version is the one a report shows: the run's `run.start` records none),
liveliness changes and a lost sample as the ingest records them, a quarantined line, and a cache
with state snapshots, boxes of where road users were and a recorded verification. Each attack works on a fresh copy of store and cache:
a column of a row set to another value (moved further where the value first drawn collides with
another row's under a UNIQUE constraint), a row deleted, a forged row inserted (a row's copy with
one column changed), or an index entry made to disagree with its row (the split view,
tests/helpers/split_view.py, for any table; for an automatic index of a UNIQUE or PRIMARY KEY
constraint, which has no definition to hide, the entry's bytes rewritten in its b-tree page,
tests/helpers/index_pages.py). Then, as an investigator would: `gaps verify`; if it
passes, the outputs (`gaps incidents --json`, `gaps report` as JSON, `gaps export`, `gaps runs
--json --live --gaps`, the scene at a few moments and who came near the junction) are compared
with the untouched store's. Each attack ends in one of:

- detected: verify exits 1 (or the store is refused at opening, exit 2, with a message);
- no effect: verify passes and every output is the untouched store's (a cache entry forged is
  dropped and rebuilt; verify then warns of it, counted apart);
- refused: verify passes and a read stops with a clear message (exit 1), never a wrong answer;
- undetected: verify passes and an output differs. Must not happen;
- crash: a traceback. Must not happen.

CI samples ROWS rows per table with a fixed seed (a few seconds); `GAPS_TAMPER_ROWS=0` (all rows)
and `GAPS_TAMPER_SEED` run the long mode (`make fuzz`). The counts are printed (pytest -s) and
written to GAPS_TAMPER_COUNTS if set.
"""
from __future__ import annotations

import json
import os
import random
import shutil
import sqlite3
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

import pytest

from reasoner.bundled import PAPER, bundled
from sim_replay.paper import paper_run
from store import Store, state_at
from store.cache import sources_near
from store.wire import LivelinessChange, WireMiss
from store.state import build_snapshots
from tests.helpers.cli import gaps
from tests.helpers.index_pages import forge_entry

ROWS = int(os.environ.get("GAPS_TAMPER_ROWS", "1"))   # rows per table and attack; 0: every row
SEED = int(os.environ.get("GAPS_TAMPER_SEED", "15"))
RUN = "paper-junctions"


@dataclass(frozen=True)
class Attack:
    name: str
    file: str            # "store" or "cache"
    apply: Callable[[Path], bool]  # False: the change could not be made (e.g. a constraint), not tried


# --- the store ----------------------------------------------------------------------------------


def build(path: Path) -> None:
    events = paper_run()
    with Store(path) as store:
        store.put_rulebook(PAPER, "2024.1", bundled(PAPER))  # the report's version of the run's rulebook
        store.append(events)
        store.append([{"junk": "not an event"}])  # a quarantined line
        t_end = max(e["t"] for e in events)
        store.record_wire([LivelinessChange(RUN, "vehicle/173", True, 10, None),
                           LivelinessChange(RUN, "vehicle/253", True, 11, None),
                           LivelinessChange(RUN, "vehicle/173", False, 20, 3)],
                          [WireMiss(RUN, "vehicle/253", "entity.state", 2, 15, 1)])
        build_snapshots(store, RUN, every=3)
        sources_near(store, RUN, 0.0, 0.0, 1e6, 0, t_end)
        store.verified(RUN)


def outputs(path: Path) -> dict[str, Any]:
    """What an investigator reads: exit code and output of each read command, and the scene."""
    found: dict[str, Any] = {}
    for name, args in (("incidents", ("incidents", "--json")),
                       ("report", ("report", "--run", RUN, "-o", "-", "--format", "json")),
                       ("export", ("export", "--run", RUN, "-o", "-")),
                       ("runs", ("runs", "--json", "--live", "--gaps"))):
        result = gaps(*args, db=path)
        text = result.stdout.replace(str(path.parent), "<folder>") if result.exit_code == 0 else ""
        if name == "report" and text:
            report = json.loads(text)
            report.pop("generated")  # the time it was written
            report["provenance"]["store"].pop("sha256")  # the file's own hash: any byte changes it, rightly
            text = json.dumps(report)
        found[name] = (result.exit_code, text)
    found["scene"] = scene(path)
    return found


def scene(path: Path) -> Any:
    try:
        with Store.open_read_only(path) as store:
            ts = sorted(e["t"] for e in store.events(RUN))
            moments = [ts[len(ts) // 4], ts[len(ts) // 2], ts[-1]]
            return ([state_at(store, RUN, t).to_json() for t in moments],
                    sources_near(store, RUN, 0.0, 0.0, 1e6, ts[0], ts[-1]))
    except Exception as exc:  # a clear refusal is a GapsError; anything else is reported as a crash
        from store.errors import GapsError
        if isinstance(exc, GapsError):
            return ("refused", type(exc).__name__)
        raise


# --- the attacks ------------------------------------------------------------------------------


def _connect(path: Path) -> sqlite3.Connection:
    """The file opened as its holder would, the append-only triggers dropped."""
    conn = sqlite3.connect(path, isolation_level=None)
    conn.execute("PRAGMA synchronous=OFF")  # a test's file need not survive a power cut: no fsync
    for (name,) in conn.execute("SELECT name FROM sqlite_master WHERE type = 'trigger'").fetchall():
        conn.execute(f"DROP TRIGGER {name}")
    return conn


def _other(value: Any, rng: random.Random) -> Any:
    """A different value of the same kind."""
    if isinstance(value, bool) or value is None:
        return 1
    if isinstance(value, int):
        return value + rng.choice([1, -1, 1000])
    if isinstance(value, float):
        return value + rng.choice([0.5, -100.0])
    if isinstance(value, bytes):
        if not value:
            return b"\x00"
        i = rng.randrange(len(value))
        return value[:i] + bytes([value[i] ^ 0x01]) + value[i + 1:]
    text = str(value)
    if not text:
        return "x"
    i = rng.randrange(len(text))
    swapped = {"0": "1", "1": "0", "t": "f", "f": "t", "e": "a"}.get(text[i], "0" if text[i] != "0" else "1")
    return text[:i] + swapped + text[i + 1:]


def _moved(value: Any) -> Any:
    """The value moved far from every other row's: where the one first drawn collides with another
    row's under a UNIQUE constraint (a chain position, a seq one off), the attack is made with this."""
    if isinstance(value, int) and not isinstance(value, bool):
        return value + 1_000_003
    return value + "~" if isinstance(value, str) else value


def _tables(path: Path) -> list[str]:
    conn = sqlite3.connect(path)
    try:
        return [n for (n,) in conn.execute("SELECT name FROM sqlite_master WHERE type = 'table' "
                                           "AND name NOT LIKE 'sqlite_%' ORDER BY name")]
    finally:
        conn.close()


def _rows(path: Path, table: str) -> tuple[list[str], list[tuple]]:
    conn = sqlite3.connect(path)
    try:
        cursor = conn.execute(f"SELECT rowid, * FROM {table}" if not _without_rowid(conn, table)
                              else f"SELECT NULL, * FROM {table}")
        return [d[0] for d in cursor.description][1:], cursor.fetchall()
    finally:
        conn.close()


def _without_rowid(conn: sqlite3.Connection, table: str) -> bool:
    (sql,) = conn.execute("SELECT sql FROM sqlite_master WHERE name = ?", (table,)).fetchone()
    return "WITHOUT ROWID" in sql.upper()


def _where(columns: list[str], row: tuple) -> tuple[str, tuple]:
    if row[0] is not None:
        return "rowid = ?", (row[0],)
    return " AND ".join(f"{c} IS ?" for c in columns), tuple(row[1:])


def _changed(path: Path, sql: str, params: tuple) -> bool:
    conn = _connect(path)
    try:
        return conn.execute(sql, params).rowcount > 0
    except sqlite3.Error:
        return False
    finally:
        conn.close()


def _inserted(path: Path, table: str, n: int, forged: tuple, column: int) -> bool:
    """The forged row; where it collides with a row's key, the same with its other numbers moved
    on (a new chain position, seq, id), then with its other text changed too."""
    sql = f"INSERT INTO {table} VALUES ({', '.join('?' * n)})"
    moved = tuple(v + 1_000_003 if isinstance(v, int) and not isinstance(v, bool) and i != column else v
                  for i, v in enumerate(forged))
    renamed = tuple(v + "~" if isinstance(v, str) and i != column else v for i, v in enumerate(moved))
    return any(_changed(path, sql, attempt) for attempt in (forged, moved, renamed))


def row_attacks(path: Path, file: str, rng: random.Random) -> list[Attack]:
    found = []
    for table in _tables(path):
        columns, rows = _rows(path, table)
        picked = rows if ROWS == 0 or len(rows) <= ROWS else rng.sample(rows, ROWS)
        for row in picked:
            where, key = _where(columns, row)
            column = rng.randrange(len(columns))
            value = _other(row[column + 1], rng)
            found.append(Attack(f"{file}:{table}: {columns[column]} of a row changed", file,
                                lambda p, t=table, c=columns[column], v=value, w=where, k=key:
                                any(_changed(p, f"UPDATE {t} SET {c} = ? WHERE {w}", (attempt, *k))
                                    for attempt in (v, _moved(v)))))
            found.append(Attack(f"{file}:{table}: a row deleted", file,
                                lambda p, t=table, w=where, k=key: _changed(p, f"DELETE FROM {t} WHERE {w}", k)))
            forged = list(row[1:])
            forged[column] = value
            if "id" in columns:
                forged[columns.index("id")] = None if table not in ("cache_key",) else forged[columns.index("id")]
            found.append(Attack(f"{file}:{table}: a forged row inserted ({columns[column]} changed)", file,
                                lambda p, t=table, f=tuple(forged), n=len(columns), c=column:
                                _inserted(p, t, n, f, c)))
        if not rows and table not in ("cache_key",):
            found.append(Attack(f"{file}:{table}: a row inserted into the empty table", file,
                                lambda p, t=table, n=len(columns): _changed(
                                    p, f"INSERT INTO {t} VALUES ({', '.join('?' * n)})", (1,) * n)))
    return found


def _indexes(path: Path) -> list[tuple[str, str, list[str]]]:
    """(index, table, indexed columns) of every index of the store, automatic ones included."""
    conn = sqlite3.connect(path)
    try:
        found = []
        for name, table in conn.execute("SELECT name, tbl_name FROM sqlite_master WHERE type = 'index' ORDER BY name"):
            columns = [c for _, _, c in conn.execute(f"PRAGMA index_info('{name}')") if c is not None]
            found.append((name, table, columns))
        return found
    finally:
        conn.close()


def split_view(path: Path, index: str, table: str, rowid: int, column: str, value: Any, position: int) -> bool:
    """tests/helpers/split_view.py's technique for any table: the index entry follows a change,
    the index is hidden, the row is put back, the index shown again. An automatic index (UNIQUE,
    PRIMARY KEY) has no definition to hide it by: its entry's value `position` is changed in the
    page bytes instead (tests/helpers/index_pages.py)."""
    conn = _connect(path)
    try:
        (original,) = conn.execute(f"SELECT {column} FROM {table} WHERE rowid = ?", (rowid,)).fetchone()
        (sql,) = conn.execute("SELECT sql FROM sqlite_master WHERE type = 'index' AND name = ?", (index,)).fetchone()
        if sql is None:
            conn.close()
            return forge_entry(path, index, rowid, position)
        if not any(_updated(conn, table, column, attempt, rowid) for attempt in (value, _moved(value))):
            return False
        conn.execute("PRAGMA writable_schema = ON")
        conn.execute("UPDATE sqlite_master SET sql = ? WHERE name = ?",
                     (sql + (" AND 0" if " WHERE " in sql else " WHERE 0"), index))
        conn.close()
        conn = _connect(path)
        conn.execute(f"UPDATE {table} SET {column} = ? WHERE rowid = ?", (original, rowid))
        conn.execute("PRAGMA writable_schema = ON")
        conn.execute("UPDATE sqlite_master SET sql = ? WHERE name = ?", (sql, index))
        return True
    finally:
        conn.close()


def _updated(conn: sqlite3.Connection, table: str, column: str, value: Any, rowid: int) -> bool:
    try:
        conn.execute(f"UPDATE {table} SET {column} = ? WHERE rowid = ?", (value, rowid))
    except sqlite3.Error:  # a UNIQUE constraint: the caller moves the value further
        return False
    return True


def index_attacks(path: Path, rng: random.Random) -> list[Attack]:
    found = []
    for index, table, columns in _indexes(path):
        _, rows = _rows(path, table)
        usable = [r for r in rows if r[0] is not None]
        picked = usable if ROWS == 0 or len(usable) <= ROWS else rng.sample(usable, ROWS)
        conn = sqlite3.connect(path)
        names = [d[0] for d in conn.execute(f"SELECT * FROM {table} LIMIT 0").description]
        conn.close()
        for row in picked:
            column = rng.choice(columns)
            value = _other(row[1 + names.index(column)], rng)
            found.append(Attack(f"store:{index}: an entry made to disagree with its row ({column})", "store",
                                lambda p, i=index, t=table, r=row[0], c=column, v=value, k=columns.index(column):
                                split_view(p, i, t, r, c, v, k)))
    return found


# --- running them -----------------------------------------------------------------------------


@pytest.fixture(scope="module")
def pristine(tmp_path_factory) -> tuple[Path, dict[str, Any]]:
    path = tmp_path_factory.mktemp("tamper") / "gaps.db"
    build(path)
    baseline = outputs(path)
    assert baseline == outputs(path)  # the outputs are a function of the store
    verdicts = {i["verdict"] for i in json.loads(baseline["incidents"][1])}
    assert {"mitigated", "punishable"} <= verdicts, verdicts
    assert '"version": "2024.1"' in baseline["report"][1]  # the stored rulebook's row is read by the report
    return path, baseline


def _copy(pristine: Path, folder: Path) -> Path:
    folder.mkdir()
    for suffix in ("", ".cache"):
        shutil.copyfile(f"{pristine}{suffix}", folder / f"gaps.db{suffix}")
    return folder / "gaps.db"


def judge(attack: Attack, copy: Path, baseline: dict[str, Any]) -> str:
    target = copy if attack.file == "store" else Path(f"{copy}.cache")
    if not attack.apply(target):
        return "not applicable"
    checked = gaps("verify", "--json", db=copy)
    if checked.exit_code != 0:
        return "detected"
    warned = not json.loads(checked.stdout)["cache"]["ok"]
    now = outputs(copy)
    if now == baseline:
        return "no effect, cache warned" if warned else "no effect"
    differing = {k for k in now if now[k] != baseline[k]}
    if all(now[k][0] == 1 if isinstance(now[k], tuple) and isinstance(now[k][0], int) else now[k][0] == "refused"
           for k in differing):
        return "refused"
    return "UNDETECTED: " + ", ".join(sorted(differing))


def test_no_change_to_any_table_or_index_alters_an_output_without_verify_failing(pristine, tmp_path):
    path, baseline = pristine
    rng = random.Random(SEED)
    attacks = row_attacks(path, "store", rng) + index_attacks(path, rng) + row_attacks(Path(f"{path}.cache"), "cache", rng)
    tables = {a.name.split(":")[1] for a in attacks}
    assert {"events", "checkpoints", "rulebooks", "quarantine", "liveliness", "wire_misses", "events_by_kind",
            "events_by_time", "state_snapshots", "presence", "verifications", "sqlite_autoindex_events_1",
            "sqlite_autoindex_events_2", "rulebooks_by_name", "sqlite_autoindex_rulebooks_1"} <= tables
    outcomes: Counter[str] = Counter()
    undetected, crashes = [], []
    for i, attack in enumerate(attacks):
        try:
            outcome = judge(attack, _copy(path, tmp_path / f"a{i}"), baseline)
        except Exception as exc:  # noqa: BLE001: counted, and the test fails on it
            outcome = "crash"
            crashes.append(f"{attack.name}: {type(exc).__name__}: {exc}")
        outcomes[outcome.split(":")[0].split(",")[0]] += 1
        outcomes["cache entries warned of by verify"] += outcome.endswith("cache warned")
        if outcome.startswith("UNDETECTED"):
            undetected.append(f"{attack.name}: {outcome}")
        shutil.rmtree(tmp_path / f"a{i}")
    tried = sum(outcomes.values()) - outcomes["not applicable"] - outcomes["cache entries warned of by verify"]
    counts = {"attacks_tried": tried, **dict(outcomes), "undetected": len(undetected), "crashes": len(crashes),
              "not applicable": outcomes["not applicable"], "seed": SEED, "rows": ROWS}
    print("\ntamper suite:", json.dumps(counts))
    if os.environ.get("GAPS_TAMPER_COUNTS"):
        Path(os.environ["GAPS_TAMPER_COUNTS"]).write_text(
            json.dumps({**counts, "undetected_list": undetected, "crash_list": crashes}, indent=1) + "\n",
            encoding="utf-8")
    assert not crashes, crashes
    assert not undetected, undetected
    assert outcomes["detected"] > 0 and tried > 30
    assert outcomes["not applicable"] == 0  # every attack drawn was made (automatic indexes included)
