"""An MCAP export as Foxglove and Lichtblick read it (issue 13, "Seen, not just stored").

Lichtblick's JSON Schema parser (packages/mcap-support/src/parseJsonSchema.ts) refuses a channel
whose schema it cannot type, and every message on it with it (the event channels are JSON; the
drawing is foxglove-sdk's protobuf, read here by protobuf's own decoder); the MCAP doctor warns at every
message whose log time goes back; a viewer that jumps to a time shows the latest message of each
topic. So: every channel schema passes a checker that refuses what that parser refuses, every
message validates against its channel's schema, log times never go back, each scene message holds
every road user alive then, and the official reader's summary and indexes agree with the messages.
The run drawn here has what broke them: nullable fields, a recursive proof, enums, a map with $refs,
sources that publish each at its own instant, and a chain order that is not time order.
"""

from __future__ import annotations

import json
from pathlib import Path

import fastjsonschema
import foxglove.messages as fm
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from mcap.reader import make_reader
from mcap.records import Channel, Message
from mcap.stream_reader import StreamReader

from store import Store
from store.transfer import import_file
from store.kinds import KINDS
from store.transfer import export_run
from store.transfer.foxglove import SCENE_PERIOD_NS
from store.transfer.foxglove_channels import ENTITIES_TOPIC, SIGNALS_TOPIC
from tests.helpers.foxglove_decoded import alive_at, decoder
from store.transfer.message_schema import envelope_schema, viewer_envelope_schema
from tests.helpers.store_testkit import heads
from tests.helpers.viewer_run import RUN, viewer_events

T0 = 1_732_184_100_000_000_000
S = 1_000_000_000


# --- Lichtblick's parser, as a checker ------------------------------------------------------------


def lichtblick_problems(schema: dict) -> list[str]:
    """What stops Lichtblick from decoding a channel with this schema: what its parser refuses as
    it walks `type`, `properties` and `items` (a field without one of its types, an object without
    properties, an array of arrays, a contentEncoding other than base64), and, anywhere in the
    text, a $ref, an enum without a type or a type array."""
    problems: list[str] = []

    def anywhere(node, path):
        if isinstance(node, dict):
            if "$ref" in node:
                problems.append(f"{path}: $ref")
            if isinstance(node.get("type"), list):
                problems.append(f"{path}: type array {node['type']}")
            if "enum" in node and "type" not in node:
                problems.append(f"{path}: enum without type")
            for key, value in node.items():
                if key not in ("enum", "const", "default", "examples"):
                    anywhere(value, f"{path}/{key}")
        elif isinstance(node, list):
            for i, value in enumerate(node):
                anywhere(value, f"{path}/{i}")

    def walk(node, path):  # addFieldsRecursive
        if not isinstance(node, dict) or node.get("type") != "object":
            problems.append(f'{path}: expected "type": "object"')
            return
        if not isinstance(node.get("properties"), dict):
            problems.append(f"{path}: an object without properties")
            return
        for name, field in node["properties"].items():
            where, kind = f"{path}.{name}", field.get("type") if isinstance(field, dict) else None
            if kind == "string":
                if field.get("contentEncoding") not in (None, "base64"):
                    problems.append(f"{where}: contentEncoding {field['contentEncoding']}")
            elif kind == "object":
                walk(field, where)
            elif kind == "array":
                items = field.get("items")
                item_kind = items.get("type") if isinstance(items, dict) else None
                if item_kind == "object":
                    walk(items, f"{where}[]")
                elif item_kind == "string" and items.get("contentEncoding") is not None:
                    problems.append(f"{where}[]: contentEncoding for an array item")
                elif item_kind not in ("boolean", "string", "number", "integer"):
                    problems.append(f"{where}: unsupported array item type {item_kind!r}")
            elif kind not in ("boolean", "number", "integer"):
                problems.append(f"{where}: unsupported field type {kind!r}")

    anywhere(schema, "#")
    walk(schema, "#")
    return problems


def test_the_checker_refuses_what_broke_the_viewers():
    """Without viewer-safe copies, these exact schemas are what Lichtblick refused."""
    refused = {kind for kind in KINDS if lichtblick_problems(envelope_schema(kind))}
    assert {"entity.state", "run.start", "signal.state", "entity.spawn", "ads.event", "vehicle.trace"} <= refused
    assert any("type array" in p for p in lichtblick_problems(envelope_schema("entity.state")))
    assert any("$ref" in p for p in lichtblick_problems(envelope_schema("run.start")))
    assert any("enum without type" in p for p in lichtblick_problems(envelope_schema("signal.state")))
    foxglove_style_enum = {"type": "object", "properties": {"level": {"oneOf": [{"title": "INFO", "const": 2}]}}}
    assert lichtblick_problems(foxglove_style_enum) == ["#.level: unsupported field type None"]


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_every_kinds_viewer_safe_schema_passes(kind):
    assert lichtblick_problems(viewer_envelope_schema(kind)) == []


# --- a run with everything that broke the viewers (tests/helpers/viewer_run.py) -------------------


@pytest.fixture(scope="module")
def exported(tmp_path_factory) -> tuple[Path, list[dict], Path]:
    folder = tmp_path_factory.mktemp("viewers")
    events = viewer_events()
    with Store(folder / "gaps.db") as store:
        store.append(events[len(events) // 2:])  # the second half arrives first: chain order is not time order
        store.append(events[:len(events) // 2])
        report = export_run(store, RUN, folder / "run.mcap")
    assert report.chain_order
    return folder / "run.mcap", events, folder / "gaps.db"


def in_file_order(path: Path) -> list[tuple[Message, str]]:
    """Every message with its topic, in the order the records lie in the file."""
    topics, out = {}, []
    with open(path, "rb") as f:
        for record in StreamReader(f, emit_chunks=False).records:
            if isinstance(record, Channel):
                topics[record.id] = record.topic
            elif isinstance(record, Message):
                out.append((record, topics[record.channel_id]))
    return out


def test_every_channel_schema_passes_the_checker(exported):
    path, _, _ = exported
    with open(path, "rb") as f:
        summary = make_reader(f).get_summary()
    assert {s.name for s in summary.schemas.values()} >= {"foxglove.SceneUpdate", "foxglove.Log", "entity.state",
                                                          "run.start", "vehicle.trace", "signal.state"}
    for schema in summary.schemas.values():
        if schema.name.startswith("foxglove."):  # foxglove-sdk's own, in protobuf
            assert schema.encoding == "protobuf"
            continue
        assert schema.encoding == "jsonschema"
        assert lichtblick_problems(json.loads(schema.data)) == [], schema.name


def test_every_message_validates_against_its_channel_schema(exported):
    path, events, _ = exported
    validators, checked = {}, 0
    with open(path, "rb") as f:
        for schema, channel, message in make_reader(f).iter_messages():
            if schema.id not in validators:
                validators[schema.id] = (decoder(schema.name, schema.encoding, schema.data)
                                         if schema.encoding == "protobuf"
                                         else fastjsonschema.compile(json.loads(schema.data)))
            validators[schema.id](message.data if schema.encoding == "protobuf" else json.loads(message.data))
            checked += 1
    assert checked > len(events)


def test_viewer_safe_schemas_accept_what_the_exact_ones_accept():
    """Nullable fields are left untyped rather than narrowed: a null junction still validates."""
    for ev in viewer_events():
        exact = fastjsonschema.compile(envelope_schema(ev["kind"]))
        viewer = fastjsonschema.compile(viewer_envelope_schema(ev["kind"]))
        assert exact(ev) == viewer(ev)
    state = viewer_envelope_schema("entity.state")["properties"]["body"]
    assert "junction" not in state["properties"] and "junction" in state["description"]


def test_log_times_never_go_back_in_the_file(exported):
    """What the MCAP doctor checks: no message is logged before one written ahead of it."""
    path, _, _ = exported
    messages = in_file_order(path)
    latest, back = 0, 0
    for message, _ in messages:
        back += message.log_time < latest
        latest = max(latest, message.log_time)
    assert back == 0 and len(messages) > 100
    for topic in {topic for _, topic in messages}:
        times = [m.log_time for m, t in messages if t == topic]
        assert times == sorted(times), topic


def scene_update(data: bytes):
    """A foxglove.SceneUpdate as protobuf's decoder reads it with foxglove-sdk's schema."""
    sdk = fm.SceneUpdate.get_schema()
    return decoder(sdk.name, sdk.encoding, bytes(sdk.data))(data)


def test_each_scene_holds_every_road_user_alive_then(exported):
    path, events, _ = exported
    scenes = [(m.log_time, scene_update(m.data)) for m, topic in in_file_order(path) if topic == ENTITIES_TOPIC]
    duration = max(ev["t"] for ev in events if ev["kind"] == "entity.state") - T0
    assert len(scenes) <= duration // SCENE_PERIOD_NS + 2  # per tick, not per source and instant
    for t, scene in scenes:
        assert [d.type for d in scene.deletions] == [fm.SceneEntityDeletionType.All.value]  # the previous scene goes
        drawn = {e.id: e.cubes[0].pose.position.x for e in scene.entities}
        assert drawn == {src: body["x"] for src, body in alive_at(events, t).items()}, t
    assert {e.id for e in scenes[0][1].entities} == {"vehicle/1", "vehicle/2", "pedestrian/p"}
    assert "pedestrian/p" not in {e.id for e in scenes[-1][1].entities}


def test_each_signal_scene_holds_every_signal(exported):
    path, _, _ = exported
    scenes = [scene_update(m.data) for m, topic in in_file_order(path) if topic == SIGNALS_TOPIC]
    assert len(scenes) == 3  # one per change of the lights, both signals in each
    assert all({e.id for e in s.entities} == {"signal/j1-west", "signal/j1-north"} for s in scenes)


def test_the_official_reader_reads_it_and_its_summary_matches(exported):
    path, _, _ = exported
    in_file = in_file_order(path)
    with open(path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        indexed = list(reader.iter_messages())
        window = list(reader.iter_messages(starting_at=T0 + S, ending_before=T0 + 2 * S))
    stats = summary.statistics
    assert stats.message_count == len(indexed) == len(in_file)
    assert [(m.channel_id, m.log_time, m.data) for _, _, m in indexed] == [(m.channel_id, m.log_time, m.data)
                                                                          for m, _ in in_file]
    counted: dict[int, int] = {}
    for m, _ in in_file:
        counted[m.channel_id] = counted.get(m.channel_id, 0) + 1
    assert stats.channel_message_counts == counted
    assert (stats.message_start_time, stats.message_end_time) == (in_file[0][0].log_time, in_file[-1][0].log_time)
    assert stats.channel_count == len(summary.channels) and stats.schema_count == len(summary.schemas)
    chunks = sorted(summary.chunk_indexes, key=lambda c: c.chunk_start_offset)
    assert chunks and stats.chunk_count == len(chunks)
    assert all(a.message_end_time <= b.message_start_time for a, b in zip(chunks, chunks[1:]))
    assert [m.log_time for _, _, m in window] == [m.log_time for m, _ in in_file if T0 + S <= m.log_time < T0 + 2 * S]


def test_it_imports_back_to_the_same_events_and_chain(exported, tmp_path):
    path, _, source_path = exported
    with Store.open_read_only(source_path) as source, Store(tmp_path / "copy.db") as copy:
        report = import_file(copy, path)
        assert report.stored == source.count(RUN) and report.rejected == 0
        assert list(copy.events(RUN)) == list(source.events(RUN))
        assert heads(copy) == heads(source) and report.chains[0].match is True


# --- any run: random times, kinds and arrival order -----------------------------------------------

_KINDS = ["entity.state", "entity.state", "entity.state", "signal.state", "vehicle.decision", "entity.despawn",
          "monitor.potential_violation", "vehicle.perception"]


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.lists(st.tuples(st.sampled_from(["vehicle/1", "vehicle/2", "pedestrian/3", "signal/s"]),
                          st.integers(0, 3 * S), st.sampled_from(_KINDS)), min_size=1, max_size=60),
       st.randoms(use_true_random=False))
def test_any_run_is_written_in_log_time_order_with_whole_scenes(tmp_path, drawn_events, shuffle):
    from tests.helpers.store_testkit import event
    seqs: dict[str, int] = {}
    events = []
    for src, dt, kind in sorted(drawn_events, key=lambda d: d[1]):  # a source's seq rises with its t
        if src == "signal/s":
            kind, body = "signal.state", {"junction": "j1", "approach": "west", "colour": "red"}
        elif kind in ("signal.state", "monitor.potential_violation"):
            kind, body = "entity.state", {"x": dt / S, "y": 0.0, "speed_mps": 1.0, "junction": None}
        elif kind == "entity.state":
            body = {"x": dt / S, "y": 0.0, "speed_mps": 1.0, "junction": None}
        elif kind == "vehicle.decision":
            body = {"goal": "1 can enter the junction", "action": "enter the junction", "proceeds": True}
        else:
            body = {"facts": ["1 has red light"]} if kind == "vehicle.perception" else {}
        if src.startswith("pedestrian") and kind in ("vehicle.decision", "vehicle.perception"):
            continue
        seqs[src] = seqs.get(src, -1) + 1
        events.append(event(seqs[src], run="any", src=src, t=T0 + dt, kind=kind, body=body))
    assume(events)
    arrival = list(events)
    shuffle.shuffle(arrival)
    path = tmp_path / f"any-{len(list(tmp_path.iterdir()))}"
    path.mkdir()
    with Store(path / "gaps.db") as store:
        store.append(arrival)
        export_run(store, "any", path / "any.mcap")
        source_heads = heads(store)
    messages = in_file_order(path / "any.mcap")
    times = [m.log_time for m, _ in messages]
    assert times == sorted(times)
    for m, topic in messages:
        if topic == ENTITIES_TOPIC:
            drawn = {e.id for e in scene_update(m.data).entities}
            assert drawn == set(alive_at(events, m.log_time))
    with Store(path / "copy.db") as copy:
        import_file(copy, path / "any.mcap")
        assert heads(copy) == source_heads
