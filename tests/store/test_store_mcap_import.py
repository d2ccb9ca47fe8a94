"""MCAP import: our own exports come back as the identical events and chain; files written by
other tools (schemaless JSON, unchunked, other encodings) import what is an event and say what
was skipped; files cut short or damaged import everything intact and say exactly what was not."""

from __future__ import annotations

import io
import json
from pathlib import Path

import pytest
from mcap.reader import make_reader
from mcap.records import Chunk
from mcap.stream_reader import breakup_chunk
from mcap.writer import Writer

from store import Store, canonical_json
from store.wire import key_for
from store.transfer import Skip, TransferError, export_run, import_file
from store.transfer.mcap_out import export_mcap
from tests.helpers.store_testkit import event

T0 = 1_732_184_100_000_000_000


def heads(store: Store) -> dict[str, str]:
    return {r.run: r.head for r in store.verify().runs}


def ingest_like_run(n: int = 3000, run: str = "busy") -> list[dict]:
    """Events of several sources interleaved the way an ingest receives them: not in time order."""
    out = []
    for i in range(n):
        src = ("vehicle/1", "vehicle/2", "pedestrian/p", "monitor/m")[i % 4]
        seq = i // 4
        t = T0 + seq * 100_000_000 + (7 - (i % 4)) * 1000  # each tick arrives in reverse source order
        if src == "monitor/m":
            out.append(event(seq, run=run, src=src, t=t, kind="monitor.observation",
                             body={"vehicle": "1", "facts": [f"1 has speed of {seq % 40}"]}))
        else:
            out.append(event(seq, run=run, src=src, t=t, kind="entity.state",
                             body={"x": seq * 0.5, "y": -1.0, "heading_deg": 0.0, "speed_mps": 5.0}))
    return out


@pytest.fixture
def source(tmp_path) -> Store:
    with Store(tmp_path / "source.db") as store:
        events = ingest_like_run()
        for start in range(0, len(events), 700):  # several appends: several checkpoints
            store.append(events[start:start + 700])
        yield store


def exported_file(store: Store, path: Path, chunk_size: int = 1 << 20) -> Path:
    export_mcap(store, store.runs()[0].run, path, chunk_size=chunk_size)
    return path


# --- round trip ---------------------------------------------------------------------------------


def test_round_trip_rebuilds_identical_events_and_chain(source, tmp_path):
    path = exported_file(source, tmp_path / "busy.mcap")
    with Store(tmp_path / "copy.db") as copy:
        report = import_file(copy, path)
        assert (report.stored, report.duplicates, report.rejected, report.truncated) == (3000, 0, 0, None)
        assert list(copy.events("busy")) == list(source.events("busy"))
        assert heads(copy) == heads(source) and copy.verify().ok
        (chain,) = report.chains
        assert chain.match is True
        assert chain.checkpoints_matched == chain.checkpoints == len(source.checkpoints("busy")) > 1
        assert chain.store_head == chain.exported_head == heads(source)["busy"]
        assert report.skipped > 0 and all(s["what"].startswith("channel /") for s in report.to_json()["skips"])
        reasons = {s["reason"] for s in report.to_json()["skips"]}  # said as what they are, not as an encoding
        assert "derived foxglove.SceneUpdate channel: rebuilt from the events on export" in reasons
        assert reasons <= {f"derived foxglove.{name} channel: rebuilt from the events on export"
                           for name in ("SceneUpdate", "Log")}
        again = import_file(copy, path)
        assert (again.stored, again.duplicates) == (0, 3000)


def test_round_trip_of_the_paper_run(tmp_path):
    from sim_replay.paper import paper_run
    with Store(tmp_path / "a.db") as a, Store(tmp_path / "b.db") as b:
        a.append(paper_run())
        run = a.runs()[0].run
        export_run(a, run, tmp_path / "paper.mcap")
        report = import_file(b, tmp_path / "paper.mcap")
        assert report.stored == a.count(run) and report.chains[0].match is True
        assert list(b.events(run)) == list(a.events(run)) and heads(b) == heads(a)


def test_a_time_ordered_export_rebuilds_the_events_and_says_the_chain_is_not_compared(source, tmp_path):
    export_run(source, "busy", tmp_path / "t.mcap", order="time")
    with Store(tmp_path / "copy.db") as copy:
        report = import_file(copy, tmp_path / "t.mcap")
        assert list(copy.events("busy")) == list(source.events("busy"))
        assert report.chains[0].match is None and report.chains[0].order == "time"


def test_an_altered_message_is_caught_by_the_exported_checkpoints(source, tmp_path):
    """Rewrite the file with one message changed, keeping its metadata: the import stores the
    altered (valid) event but the chain check names the first checkpoint after it."""
    original = exported_file(source, tmp_path / "busy.mcap")
    altered = tmp_path / "altered.mcap"
    keys = [(e["src"], e["seq"]) for e in source.events("busy")]
    (target,) = [key for key, pos in source.chain_positions("busy", keys).items() if pos == 1000]
    assert target[0] != "monitor/m"  # an entity.state (every fourth event is a monitor's)
    with open(original, "rb") as f, open(altered, "wb") as out:
        reader = make_reader(f)
        writer = Writer(out)
        writer.start()
        for m in reader.iter_metadata():
            writer.add_metadata(m.name, m.metadata)
        for a in reader.iter_attachments():  # the chain order: the file is in time order
            writer.add_attachment(a.create_time, a.log_time, a.name, a.media_type, a.data)
        ids = {}
        for schema, channel, message in reader.iter_messages(log_time_order=False):
            if schema.id not in ids.setdefault("s", {}):
                ids["s"][schema.id] = writer.register_schema(schema.name, schema.encoding, schema.data)
            if channel.id not in ids.setdefault("c", {}):
                ids["c"][channel.id] = writer.register_channel(channel.topic, channel.message_encoding,
                                                               ids["s"][schema.id], channel.metadata)
            data = message.data
            if channel.topic.startswith("gaps/") and (json.loads(data)["src"], json.loads(data)["seq"]) == target:
                data = data.replace(b'"speed_mps":5.0', b'"speed_mps":4.0')
                assert data != message.data
            writer.add_message(ids["c"][channel.id], message.log_time, data, message.publish_time, message.sequence)
        writer.finish()
    with Store(tmp_path / "copy.db") as copy:
        report = import_file(copy, altered)
        assert report.stored == 3000
        (chain,) = report.chains
        assert chain.match is False
        counts = [c["count"] for c in source.checkpoints("busy")]
        assert chain.first_mismatch.count == min(c for c in counts if c >= 1001)
        assert chain.checkpoints_matched == sum(1 for c in counts if c < 1001)


# --- files from other tools ----------------------------------------------------------------------


def foreign_file(path: Path, *, chunked: bool = True) -> Path:
    """What another recorder might write: schemaless JSON, a JSON channel with its own schema, a
    ros1 channel, and JSON that is not an event."""
    events = [event(i, run="foreign", src="vehicle/9", kind="entity.state",
                    body={"x": float(i), "y": 2.0, "speed_mps": 1.5}) for i in range(4)]
    with open(path, "wb") as out:
        writer = Writer(out, use_chunking=chunked)
        writer.start(profile="", library="some other recorder")
        plain = writer.register_channel("/events", "json", schema_id=0)
        schema = writer.register_schema("Event", "jsonschema", b'{"type": "object"}')
        typed = writer.register_channel("/typed", "json", schema_id=schema)
        ros_schema = writer.register_schema("std_msgs/String", "ros1msg", b"string data")
        ros = writer.register_channel("/chatter", "ros1", schema_id=ros_schema)
        for i, ev in enumerate(events):
            pretty = json.dumps(dict(reversed(list(ev.items()))), indent=2).encode()  # not canonical
            writer.add_message(plain if i % 2 else typed, ev["t"], pretty, ev["t"], sequence=i)
            writer.add_message(ros, ev["t"], b"\x05\x00\x00\x00hello", ev["t"])
        writer.add_message(plain, T0, b'{"temperature": 21.5}', T0)
        writer.add_message(plain, T0, b"\xff not json", T0)
        writer.finish()
    return path


@pytest.mark.parametrize("chunked", [True, False])
def test_foreign_schemaless_json_imports_and_other_encodings_are_skipped(tmp_path, chunked):
    path = foreign_file(tmp_path / f"foreign-{chunked}.mcap", chunked=chunked)
    with Store(tmp_path / "gaps.db") as store:
        report = import_file(store, path)
        assert (report.stored, report.rejected, report.skipped) == (4, 2, 4)
        assert report.skips == {"channel /chatter": Skip("channel /chatter", 4, "message encoding 'ros1' is not json")}
        stored = list(store.events("foreign"))
        assert [e["seq"] for e in stored] == [0, 1, 2, 3]
        assert store.count("foreign") == 4 and report.chains == []
        quarantined = store.quarantined()
        assert [q["raw"] for q in quarantined] == [b'{"temperature": 21.5}', b"\xff not json"]
        assert quarantined[0]["origin"].startswith(f"{path}:channel /events:message 3 (log_time {T0}, ")
        assert "missing envelope field" in quarantined[0]["reason"]
        assert "not valid UTF-8" in quarantined[1]["reason"]


def test_an_event_on_another_events_topic_is_refused(tmp_path):
    ev = event(0, run="r", src="vehicle/1")
    path = tmp_path / "misrouted.mcap"
    with open(path, "wb") as out:
        writer = Writer(out)
        writer.start()
        wrong = writer.register_channel("gaps/r/vehicle/2/vehicle.perception", "json", 0)
        right = writer.register_channel(key_for(ev), "json", 0)
        writer.add_message(wrong, 1, canonical_json(ev), 1)
        writer.add_message(right, 2, canonical_json(ev), 2)
        writer.finish()
    with Store(tmp_path / "gaps.db") as store:
        report = import_file(store, path)
        assert (report.stored, report.rejected) == (1, 1)
        assert "does not match the event's own key gaps/r/vehicle/1/vehicle.perception" in report.details[0].reason


def test_a_message_on_an_undefined_channel_is_quarantined(tmp_path):
    """Hand-framed: a Message record whose channel no Channel record defined."""
    import struct
    from store.transfer.mcap_records import MAGIC
    ev = canonical_json(event(0))
    body = struct.pack("<HIQQ", 42, 0, 5, 5) + ev
    data = MAGIC + struct.pack("<BQ", 0x01, 8) + struct.pack("<I", 0) + struct.pack("<I", 0)
    data += struct.pack("<BQ", 0x05, len(body)) + body
    path = tmp_path / "orphan.mcap"
    path.write_bytes(data)
    with Store(tmp_path / "gaps.db") as store:
        report = import_file(store, path)
        assert (report.stored, report.rejected) == (0, 1)
        (q,) = store.quarantined()
        assert q["raw"] == ev and "channel id 42" in q["reason"]
        assert report.truncated.cut.reason == "the file ends after a complete record, without a footer"


def test_not_an_mcap_file(tmp_path):
    for name, data in (("empty.mcap", b""), ("text.mcap", b"hello world, not mcap"), ("short.mcap", b"\x89MCA")):
        (tmp_path / name).write_bytes(data)
        with Store(tmp_path / "gaps.db") as store, pytest.raises(TransferError, match=f"{name}: not an MCAP file"):
            import_file(store, tmp_path / name)


# --- cut and damaged files -------------------------------------------------------------------------


def chunk_layout(path: Path) -> list[tuple[int, int, int]]:
    """(start, end, event messages) of each chunk, from the file's own index (the mcap package's
    reading, not ours)."""
    data = path.read_bytes()
    event_channels = None
    layout = []
    with open(path, "rb") as f:
        summary = make_reader(f).get_summary()
    event_channels = {cid for cid, c in summary.channels.items() if c.topic.startswith("gaps/")}
    for index in summary.chunk_indexes:
        from mcap.data_stream import ReadDataStream
        start, length = index.chunk_start_offset, index.chunk_length
        chunk = Chunk.read(ReadDataStream(io.BytesIO(data[start + 9:start + length])))
        n = sum(1 for r in breakup_chunk(chunk) if getattr(r, "channel_id", None) in event_channels)
        layout.append((start, start + length, n))
    return layout


def test_a_cut_file_imports_everything_before_the_cut_and_says_where(source, tmp_path):
    full = exported_file(source, tmp_path / "busy.mcap", chunk_size=16 * 1024)
    data = full.read_bytes()
    layout = chunk_layout(full)
    assert len(layout) > 5
    time_order = list(source.events("busy"))  # the file's order
    first_chunk, last_end = layout[0][0], layout[-1][1]
    data_end = data.index(b"\x0f" + (4).to_bytes(8, "little"), last_end) + 13  # after the DataEnd record
    cuts = [20, first_chunk + 5, layout[2][0] + 100, layout[3][1] + 3, (layout[4][0] + layout[4][1]) // 2,
            last_end - 1, last_end + 40, data_end + 10, len(data) - 3]
    for cut in cuts:
        path = tmp_path / f"cut-{cut}.mcap"
        path.write_bytes(data[:cut])
        with Store(tmp_path / f"cut-{cut}.db") as store:
            report = import_file(store, path)
            complete = [(start, end, n) for start, end, n in layout if end <= cut]
            expected = sum(n for _, _, n in complete)
            assert report.stored == expected, cut
            # what was imported is exactly the events of the complete chunks: the first in time
            assert sorted(store.events("busy"), key=lambda e: (e["src"], e["seq"])) == \
                sorted(time_order[:expected], key=lambda e: (e["src"], e["seq"]))
            assert report.truncated is not None and report.truncated.cut.file_size == cut
            cut_info = report.truncated.cut
            assert (complete[-1][1] if complete else 0) <= cut_info.offset <= cut
            assert cut_info.unreadable_bytes == cut - cut_info.offset
            assert report.truncated.stored == expected
            assert cut_info.data_complete == (cut >= data_end)
            if cut_info.record is not None:
                assert cut_info.declared is not None and cut_info.declared > cut - cut_info.offset - 9
            if cut < first_chunk:  # cut inside the metadata: the run is not declared yet
                continue
            (chain,) = report.chains  # the metadata precede the messages, so a cut file declares its run
            assert chain.exported_events == 3000 and chain.file_events == expected
            assert chain.match is (expected == 3000)


def test_a_damaged_chunk_is_skipped_and_reported_and_the_rest_imported(source, tmp_path):
    full = exported_file(source, tmp_path / "busy.mcap", chunk_size=16 * 1024)
    layout = chunk_layout(full)
    start, end, lost = layout[2]
    data = bytearray(full.read_bytes())
    data[end - 50] ^= 0xFF  # inside the compressed records of the third chunk
    damaged = tmp_path / "damaged.mcap"
    damaged.write_bytes(bytes(data))
    with Store(tmp_path / "gaps.db") as store:
        report = import_file(store, damaged)
        assert report.stored == 3000 - lost and report.truncated is None
        (damage,) = report.damaged
        assert damage.offset == start and damage.record == "Chunk"
        assert report.chains[0].match is False


def test_progress_is_reported_in_bytes_up_to_the_file_size(source, tmp_path):
    path = exported_file(source, tmp_path / "busy.mcap")
    seen: list[int] = []
    with Store(tmp_path / "copy.db") as copy:
        import_file(copy, path, progress=seen.append)
    assert seen and seen == sorted(seen) and seen[-1] == path.stat().st_size


# --- hostile files: random damage never crashes an import ------------------------------------------

from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402


def _small_export() -> bytes:
    import tempfile
    with tempfile.TemporaryDirectory() as folder:
        with Store(Path(folder) / "gaps.db") as store:
            store.append(ingest_like_run(200, run="small"))
            return exported_file(store, Path(folder) / "small.mcap", chunk_size=2048).read_bytes()


_SMALL = _small_export()


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(flips=st.lists(st.tuples(st.integers(8, len(_SMALL) - 1), st.integers(1, 255)), min_size=1, max_size=6),
       keep=st.integers(8, len(_SMALL)))
def test_damaged_files_never_crash_an_import(flips, keep):
    """Flip bytes anywhere after the magic and cut the file anywhere: the import reports what
    it could not read and accounts for every message it did read."""
    import tempfile
    data = bytearray(_SMALL)
    for position, mask in flips:
        data[position] ^= mask
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "damaged.mcap"
        path.write_bytes(bytes(data[:keep]))
        with Store(Path(folder) / "gaps.db") as store:
            report = import_file(store, path)
            assert report.stored == store.count()
            assert report.rejected == len(store.quarantined())
            assert store.verify().ok
            originals = {(e["src"], e["seq"]): e for e in ingest_like_run(200, run="small")}
            for event in store.events("small"):  # chunk CRCs: a damaged payload is never stored
                assert originals[(event["src"], event["seq"])] == event


def test_a_chunk_claiming_a_huge_size_is_damaged_not_allocated(tmp_path):
    import struct
    from store.transfer.mcap_records import MAGIC, MAX_CHUNK_BYTES
    chunk = struct.pack("<QQQI", 0, 0, MAX_CHUNK_BYTES + 1, 0) + struct.pack("<I", 4) + b"zstd" + struct.pack("<Q", 3) + b"abc"
    data = MAGIC + struct.pack("<BQ", 0x06, len(chunk)) + chunk
    (tmp_path / "huge.mcap").write_bytes(data)
    with Store(tmp_path / "gaps.db") as store:
        report = import_file(store, tmp_path / "huge.mcap")
    (damage,) = report.damaged
    assert damage.offset == 8 and "over the" in damage.reason


# --- files written before the export was in log-time order ---------------------------------------


def older_export(store: Store, run: str, path: Path) -> Path:
    """What exports wrote before issue 13: messages in chain order (log times going back), the
    exact schemas ($ref, untyped enums, type arrays), no chain-order attachment."""
    from store.transfer.message_schema import envelope_schema
    with open(path, "wb") as f:
        writer = Writer(f)
        writer.start(profile="", library="mind-the-gaps store.transfer")
        summary = {r.run: r for r in store.runs()}[run]
        writer.add_metadata("gaps.run", {"run": run, "events": str(summary.events), "order": "chain",
                                         "head": heads(store)[run]})
        schemas, channels = {}, {}
        for (text,) in store.connection.execute("SELECT event FROM events WHERE run = ? ORDER BY chain_pos", (run,)):
            ev = json.loads(text)
            if ev["kind"] not in schemas:
                schemas[ev["kind"]] = writer.register_schema(ev["kind"], "jsonschema",
                                                             json.dumps(envelope_schema(ev["kind"])).encode())
            topic = key_for(ev)
            if topic not in channels:
                channels[topic] = writer.register_channel(topic, "json", schemas[ev["kind"]])
            writer.add_message(channels[topic], max(ev["t"], 0), text.encode(), max(ev["t"], 0), ev["seq"])
        writer.finish()
    return path


def test_an_older_export_still_imports_to_the_same_events_and_chain(source, tmp_path):
    path = older_export(source, "busy", tmp_path / "old.mcap")
    with open(path, "rb") as f:
        times = [m.log_time for _, _, m in make_reader(f).iter_messages(log_time_order=False)]
    assert times != sorted(times)  # chain order: what the doctor warned about
    with Store(tmp_path / "copy.db") as copy:
        report = import_file(copy, path)
        assert (report.stored, report.rejected) == (3000, 0)
        assert list(copy.events("busy")) == list(source.events("busy")) and heads(copy) == heads(source)
        assert report.chains[0].match is True
