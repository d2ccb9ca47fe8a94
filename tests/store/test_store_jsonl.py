"""JSONL in and out: every line accounted for (stored, duplicate, quarantined with its exact
bytes, or a skipped blank line), streamed in bounded reads and batches, and exports that
re-import to the same events (and, in chain order, the same chain)."""

from __future__ import annotations

import io
import json
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from store import MAX_EVENT_BYTES, EventError, Store, canonical_json, decode_event
from store.transfer import Skip, TransferError, export_run, import_file
from store.transfer.feed import BATCH
from store.transfer.jsonl import KEEP_BYTES, read_lines
from tests.helpers.store_testkit import event


def write_lines(path: Path, lines: list[bytes], newline: bytes = b"\n") -> Path:
    path.write_bytes(b"".join(line + newline for line in lines))
    return path


def line_of(ev: dict) -> bytes:
    return json.dumps(ev).encode()


def exported_files(folder: Path) -> list[str]:
    """What an export left in the folder, besides the store's own files."""
    return sorted(p.name for p in folder.iterdir() if not p.name.startswith("gaps.db"))


def heads(store: Store) -> dict[str, str]:
    return {r.run: r.head for r in store.verify().runs}


# --- import: every kind of bad line is quarantined, the rest imported ------------------------------

BAD_LINES = {
    "malformed JSON": b'{"v": 1, "run": ',
    "wrong type": json.dumps({**event(1), "seq": "1"}).encode(),
    "unknown kind": json.dumps({**event(2), "kind": "vehicle.teleport"}).encode(),
    "bad run id": json.dumps({**event(3), "run": "no spaces allowed"}).encode(),
    "bad src": json.dumps({**event(4), "src": "drone/7"}).encode(),
    "invalid UTF-8": json.dumps(event(5)).encode().replace(b"173 has red", b"173 has \xff\xfe red"),
    "not an object": b"[1, 2, 3]",
}
EXPECTED_REASON = {
    "malformed JSON": "malformed JSON",
    "wrong type": "seq must be an integer",
    "unknown kind": "kind 'vehicle.teleport' is unknown",
    "bad run id": "run must be 1-64 characters",
    "bad src": "src role 'drone'",
    "invalid UTF-8": "not valid UTF-8",
    "not an object": "must be a JSON object",
}


def test_each_bad_line_is_quarantined_with_its_bytes_line_and_reason(store, tmp_path):
    good = [line_of(event(i, src="vehicle/9")) for i in range(3)]
    lines = [good[0], *BAD_LINES.values(), good[1], b"", b"  \t", good[2]]
    path = write_lines(tmp_path / "mixed.jsonl", lines)

    report = import_file(store, path)

    assert (report.stored, report.duplicates, report.rejected, report.skipped) == (3, 0, len(BAD_LINES), 2)
    assert report.skips == {"blank lines": Skip("blank lines", 2, "a blank line holds no event")}
    quarantined = store.quarantined()
    assert [q["raw"] for q in quarantined] == list(BAD_LINES.values())
    for number, (name, q) in enumerate(zip(BAD_LINES, quarantined), start=2):
        assert q["origin"] == f"{path}:{number}"
        assert EXPECTED_REASON[name] in q["reason"], (name, q["reason"])
    assert [d.origin for d in report.details] == [q["origin"] for q in quarantined]
    assert [e["seq"] for e in store.events("r1", srcs=["vehicle/9"])] == [0, 1, 2]


def test_duplicates_are_counted_and_conflicts_refused(store, tmp_path):
    original = event(0)
    conflicting = {**original, "body": {"facts": ["173 has green light"]}}
    path = write_lines(tmp_path / "dups.jsonl", [line_of(original), line_of(original), line_of(conflicting)])
    report = import_file(store, path)
    assert (report.stored, report.duplicates, report.rejected) == (1, 1, 1)
    assert "conflicting duplicate of r1/vehicle/173/0" in report.details[0].reason
    assert report.details[0].origin == f"{path}:3"


def test_over_size_line_is_quarantined_whole_and_the_next_line_imported(store, tmp_path):
    big = line_of(event(0, body={"facts": ["x" * (MAX_EVENT_BYTES + 10)]}))
    path = write_lines(tmp_path / "big.jsonl", [big, line_of(event(1))])
    report = import_file(store, path)
    assert (report.stored, report.rejected) == (1, 1)
    (q,) = store.quarantined()
    assert q["raw"] == big and q["origin"] == f"{path}:1"
    assert f"over the {MAX_EVENT_BYTES}-byte limit" in q["reason"]


def test_a_huge_line_keeps_its_first_bytes_and_says_how_long_it_was(store, tmp_path):
    huge = b"{" + b"9" * (KEEP_BYTES + 5000)
    path = write_lines(tmp_path / "huge.jsonl", [line_of(event(0)), huge, line_of(event(1))])
    report = import_file(store, path)
    assert (report.stored, report.rejected) == (2, 1)
    (q,) = store.quarantined()
    assert q["origin"] == f"{path}:2"
    assert q["raw"] == huge[:KEEP_BYTES]
    offset = len(line_of(event(0))) + 1
    assert f"line is {len(huge)} bytes" in q["reason"] and f"starts at byte {offset}" in q["reason"]


def test_a_huge_last_line_without_newline(store, tmp_path):
    path = tmp_path / "tail.jsonl"
    path.write_bytes(line_of(event(0)) + b"\n" + b"x" * (KEEP_BYTES + 1))
    report = import_file(store, path)
    assert (report.stored, report.rejected) == (1, 1)
    assert f"line is {KEEP_BYTES + 1} bytes" in store.quarantined()[0]["reason"]


def test_crlf_bom_and_no_final_newline(store, tmp_path):
    path = tmp_path / "windows.jsonl"
    path.write_bytes(b"\xef\xbb\xbf" + line_of(event(0)) + b"\r\n" + line_of(event(1)) + b"\r\n" + line_of(event(2)))
    report = import_file(store, path)
    assert (report.stored, report.rejected, report.skipped) == (3, 0, 0)


def test_lines_are_read_with_bounded_reads():
    """Streaming: no read asks for more than one event's worth of bytes (or a 1 MiB piece)."""
    class Recording(io.BytesIO):
        asked: list[int] = []

        def readline(self, size=-1):
            self.asked.append(size)
            return super().readline(size)

        def read(self, size=-1):
            raise AssertionError("whole-file read")

    data = b"\n".join([b"a" * 10, b"b" * (3 * MAX_EVENT_BYTES), b"c"]) + b"\n"
    stream = Recording(data)
    lines = list(read_lines(stream))
    assert [(line.number, line.length) for line in lines] == [(1, 10), (2, 3 * MAX_EVENT_BYTES), (3, 1)]
    assert all(0 < size <= MAX_EVENT_BYTES + 2 for size in stream.asked)


def test_import_appends_in_batches(store, tmp_path):
    class Counting:
        def __init__(self, inner: Store) -> None:
            self.inner, self.sizes = inner, []

        def append_candidates(self, candidates):
            candidates = list(candidates)
            self.sizes.append(len(candidates))
            return self.inner.append_candidates(candidates)

        def __getattr__(self, name):        # what an import asks besides (the runs held, conflicts)
            return getattr(self.inner, name)

    n = 2 * BATCH + 123
    path = write_lines(tmp_path / "many.jsonl", [line_of(event(i)) for i in range(n)])
    counting = Counting(store)
    report = import_file(counting, path)
    assert report.stored == n
    assert counting.sizes == [BATCH, BATCH, 123]


def test_missing_file_and_unknown_extension_are_clear_errors(store, tmp_path):
    with pytest.raises(TransferError, match="no such file"):
        import_file(store, tmp_path / "absent.jsonl")
    (tmp_path / "events.csv").write_text("x")
    with pytest.raises(TransferError, match="cannot tell the format"):
        import_file(store, tmp_path / "events.csv")
    assert import_file(store, tmp_path / "events.csv", "jsonl").rejected == 1


def test_ndjson_extension(store, tmp_path):
    path = write_lines(tmp_path / "e.ndjson", [line_of(event(0))])
    assert import_file(store, path).stored == 1


# --- export and round trip ---------------------------------------------------------------------------


def shuffled_run() -> list[dict]:
    """Events of three sources, appended out of time order (as an ingest interleaves them)."""
    events = [event(seq, src=src, t=1_000 + 10 * seq + offset, kind="entity.state",
                    body={"x": float(seq), "y": 0.5, "speed_mps": 3.0, "note": "é"})
              for offset, src in enumerate(["vehicle/1", "pedestrian/p", "vehicle/2"]) for seq in range(40)]
    return events


def test_export_writes_canonical_lines_in_time_order(store, tmp_path):
    store.append(shuffled_run())
    report = export_run(store, "r1", tmp_path / "out.jsonl", order="time")
    lines = (tmp_path / "out.jsonl").read_bytes().split(b"\n")
    assert lines[-1] == b"" and report.events == len(lines) - 1 == 120
    expected = [canonical_json(ev) for ev in store.events("r1")]
    assert lines[:-1] == expected
    decoded = [json.loads(line) for line in lines[:-1]]
    assert decoded == sorted(decoded, key=lambda e: (e["t"], e["seq"], e["src"]))
    assert report.order == "time" and report.bytes == (tmp_path / "out.jsonl").stat().st_size


def test_round_trip_in_time_order_gives_identical_events_and_heads_for_a_time_ordered_run(tmp_path):
    events = sorted(shuffled_run(), key=lambda e: (e["t"], e["seq"], e["src"]))
    with Store(tmp_path / "a.db") as a:
        a.append(events)
        export_run(a, "r1", tmp_path / "r1.jsonl", order="time")
        with Store(tmp_path / "b.db") as b:
            report = import_file(b, tmp_path / "r1.jsonl")
            assert report.stored == len(events)
            assert list(b.events("r1")) == list(a.events("r1"))
            assert heads(b) == heads(a) and b.verify().ok


def test_round_trip_of_the_paper_run_in_chain_order_rebuilds_the_same_chain(tmp_path):
    from sim_replay.paper import paper_run
    with Store(tmp_path / "a.db") as a:
        a.append(paper_run())
        run = a.runs()[0].run
        export_run(a, run, tmp_path / "chain.jsonl", order="chain")
        export_run(a, run, tmp_path / "time.jsonl", order="time")
        with Store(tmp_path / "b.db") as b, Store(tmp_path / "c.db") as c:
            import_file(b, tmp_path / "chain.jsonl")
            import_file(c, tmp_path / "time.jsonl")
            assert list(b.events(run)) == list(c.events(run)) == list(a.events(run))
            assert heads(b) == heads(a)
            # the paper run is published out of time order, so a time-ordered file chains differently
            assert heads(c) != heads(a) and c.verify().ok


def test_export_of_an_unknown_run_names_the_runs_and_writes_nothing(store, tmp_path):
    store.append([event(0)])
    with pytest.raises(TransferError, match=r"no run 'r9' .*runs: r1"):
        export_run(store, "r9", tmp_path / "x.jsonl")
    assert exported_files(tmp_path) == []


def test_a_failed_export_leaves_no_partial_file(store, tmp_path, monkeypatch):
    store.append([event(i) for i in range(10)])
    import store.transfer.jsonl as jsonl

    real = jsonl.stored_rows

    def broken(*args):
        yield from list(real(*args))[:3]
        raise OSError("disk full")

    monkeypatch.setattr(jsonl, "stored_rows", broken)
    with pytest.raises(OSError):
        export_run(store, "r1", tmp_path / "x.jsonl")
    assert exported_files(tmp_path) == []


# --- hostile input: hypothesis-generated garbage between valid events --------------------------------

_JSON_SPACE = b" \t\r"
json_values = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False) | st.text(max_size=8),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=5), inner, max_size=3),
    max_leaves=8,
)
mangled_events = st.builds(
    lambda field, value: json.dumps({**event(0, run="hostile"), field: value}).encode(),
    st.sampled_from(["v", "run", "src", "seq", "t", "kind", "body"]),
    json_values,
)


def is_event(raw: bytes) -> bool:
    try:
        decode_event(raw)
    except EventError:
        return False
    return True


# garbage is whatever the store would not take as an event (a mangled field may happen to be valid)
garbage = st.one_of(
    st.binary(max_size=60),
    st.text(max_size=40).map(lambda s: s.encode("utf-8", "surrogatepass")),
    mangled_events,
    json_values.map(lambda v: json.dumps(v).encode()),
).map(lambda raw: raw.replace(b"\n", b"")).filter(lambda raw: not is_event(raw))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.one_of(st.none(), garbage), min_size=1, max_size=30))
def test_garbage_lines_never_crash_and_are_each_quarantined_exactly(plan):
    """None in the plan is a valid event; bytes are garbage (which may happen to be blank)."""
    lines, valid, bad = [], 0, []
    for number, item in enumerate(plan, start=1):
        if item is None:
            lines.append(line_of(event(valid, run="good", src="vehicle/1")))
            valid += 1
            continue
        lines.append(item)
        kept = item[3:] if number == 1 and item.startswith(b"\xef\xbb\xbf") else item
        if kept.strip(_JSON_SPACE):
            bad.append((number, kept))
    with tempfile.TemporaryDirectory() as folder:
        path = write_lines(Path(folder) / "hostile.jsonl", lines)
        with Store(Path(folder) / "gaps.db") as store:
            report = import_file(store, path)
            quarantined = store.quarantined()
            assert report.stored == valid == store.count("good")
            assert report.rejected == len(bad)
            assert report.offered + report.skipped == len(lines)
            rows: dict[bytes, list] = {}  # identical lines of a file are one row: first line, last line, count
            for n, raw in bad:
                row = rows.setdefault(raw, [f"{path}:{n}", raw, None, 0])
                row[2:] = [f"{path}:{n}", row[3] + 1]
            assert [[q["origin"], q["raw"], q["last_origin"], q["count"]] for q in quarantined] == list(rows.values())
            assert all(q["reason"] for q in quarantined)
            assert store.verify().ok


def test_progress_is_reported_per_batch_in_bytes(store, tmp_path):
    path = write_lines(tmp_path / "many.jsonl", [line_of(event(i)) for i in range(BATCH + 10)])
    seen: list[int] = []
    import_file(store, path, progress=seen.append)
    assert len(seen) == 2 and seen[-1] == path.stat().st_size
    exported: list[int] = []
    export_run(store, "r1", tmp_path / "out.jsonl", progress=exported.append)
    assert exported[-1] == BATCH + 10
