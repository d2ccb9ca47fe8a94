"""MCAP export as other tools see it: the official `mcap` reader finds the channels, schemas,
messages, statistics and metadata DESIGN promises, and the Foxglove channels hold scene updates
and log lines that protobuf's own decoder reads with the schemas the file carries."""

from __future__ import annotations

import json
import math
from pathlib import Path

import fastjsonschema
import foxglove.messages as fm
import pytest
from google.protobuf.unknown_fields import UnknownFieldSet
from mcap.reader import make_reader

from store import Store, canonical_json
from store.wire import key_for
from store.transfer import TransferError, export_run
from store.transfer.foxglove import SceneBuilder
from store.transfer.foxglove_channels import ENTITIES_TOPIC, LOG_TOPIC, MAP_TOPIC, SIGNALS_TOPIC
from tests.helpers.foxglove_decoded import decoded, decoder
from tests.helpers.store_testkit import event

RUN = "junction-7"
T0 = 1_732_184_100_000_000_000
S = 1_000_000_000
MAP = {"roads": [{"id": "r1", "from": [-100.0, 0.0], "to": [100.0, 0.0]},
                 {"id": "r2", "from": [0.0, -100.0], "to": [0.0, 100.0]}],
       "junctions": [{"id": "j1", "x": 5.0, "y": 2.0, "control": "lights"}],
       "monitors": [{"id": "m1", "junction": "j1", "x": -15.0, "y": 10.0, "heading_deg": 0.0,
                     "range_m": 60.0, "fov_deg": 90.0}]}


def scene_events() -> list[dict]:
    """A small run with one of everything that is drawn, appended in publication order."""
    seqs: dict[str, int] = {}

    def ev(src: str, t: int, kind: str, body: dict) -> dict:
        seqs[src] = seqs.get(src, -1) + 1
        return event(seqs[src], run=RUN, src=src, t=t, kind=kind, body=body)

    out = [ev("sim/world", T0, "run.start", {"map": MAP, "seed": 1}),
           ev("vehicle/173", T0, "entity.spawn", {"type": "car", "driver": "autonomous"}),
           ev("vehicle/253", T0, "entity.spawn", {"type": "ambulance", "emergency": True}),
           ev("pedestrian/p1", T0, "entity.spawn", {"type": "pedestrian"})]
    for tick in range(5):
        t = T0 + tick * S
        out.append(ev("signal/j1-west", t, "signal.state",
                      {"junction": "j1", "approach": "west", "colour": "red" if tick else "amber"}))
        for src, heading in (("vehicle/173", 90.0), ("vehicle/253", 0.0), ("pedestrian/p1", 180.0)):
            out.append(ev(src, t, "entity.state", {"x": -30.0 + 5 * tick, "y": 1.0, "heading_deg": heading,
                                                   "speed_mps": 5.0, "road": "r1", "junction": None}))
    out += [ev("vehicle/173", T0 + 2 * S, "vehicle.perception", {"facts": ["173 has red light"]}),
            ev("vehicle/173", T0 + 2 * S, "vehicle.decision", {"goal": "173 can enter the junction",
                                                                "action": "enter the junction",
                                                                "permitted": False, "proceeds": True}),
            ev("monitor/m1", T0 + 3 * S, "monitor.potential_violation",
               {"vehicle": "173", "action": "enter the junction", "facts": ["173 has red light"]}),
            ev("sim/world", T0 + 4 * S, "collision", {"entities": ["173", "p1"]}),
            ev("pedestrian/p1", T0 + 4 * S, "entity.despawn", {"reason": "collision"}),
            ev("sim/world", T0 + 5 * S, "run.end", {"reason": "done"})]
    return out


@pytest.fixture
def exported(tmp_path) -> tuple[Path, list[dict], Store]:
    events = scene_events()
    with Store(tmp_path / "gaps.db") as store:
        store.append(events[:10])  # two appends: two checkpoints
        store.append(events[10:])
        export_run(store, RUN, tmp_path / "run.mcap")
        yield tmp_path / "run.mcap", events, store


def read_all(path: Path):
    with open(path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        messages = list(reader.iter_messages())
        metadata = list(reader.iter_metadata())
    return summary, messages, metadata


def test_event_channels_topics_sequence_and_log_time(exported):
    path, events, _ = exported
    summary, messages, _ = read_all(path)
    by_topic: dict[str, list] = {}
    for schema, channel, message in messages:
        by_topic.setdefault(channel.topic, []).append((schema, channel, message))
    expected_topics = {key_for(ev) for ev in events}
    assert expected_topics | {MAP_TOPIC, ENTITIES_TOPIC, SIGNALS_TOPIC, LOG_TOPIC} == set(by_topic)
    event_messages = [m for topic, ms in by_topic.items() if topic.startswith("gaps/") for m in ms]
    assert len(event_messages) == len(events)
    payloads = {(ev["src"], ev["seq"]): ev for ev in events}
    for schema, channel, message in event_messages:
        ev = json.loads(message.data)
        assert message.data == canonical_json(payloads[(ev["src"], ev["seq"])])
        assert channel.topic == f"gaps/{RUN}/{ev['src']}/{ev['kind']}"
        assert channel.message_encoding == "json"
        assert (schema.encoding, schema.name) == ("jsonschema", ev["kind"])
        assert message.log_time == message.publish_time == ev["t"]
        assert message.sequence == ev["seq"]
    log_times = [m.log_time for _, _, m in messages]
    assert log_times == sorted(log_times)  # make_reader orders by log time itself


def test_summary_has_statistics_chunk_indexes_and_metadata_index(exported):
    path, events, _ = exported
    summary, messages, _ = read_all(path)
    stats = summary.statistics
    assert stats.message_count == len(messages) > len(events)
    assert stats.channel_count == len(summary.channels)
    assert stats.message_start_time == min(ev["t"] for ev in events)
    assert stats.message_end_time == max(ev["t"] for ev in events)
    assert summary.chunk_indexes and all(c.compression == "zstd" for c in summary.chunk_indexes)
    assert {m.name for m in summary.metadata_indexes} == {"gaps.run", "gaps.checkpoint"}
    events_channels = [c for c in summary.channels.values() if c.topic.startswith("gaps/")]
    drawn = [c for c in summary.channels.values() if not c.topic.startswith("gaps/")]
    assert all(c.message_encoding == "json" for c in events_channels)
    assert {summary.schemas[c.schema_id].encoding for c in events_channels} == {"jsonschema"}
    assert {(c.message_encoding, summary.schemas[c.schema_id].encoding, summary.schemas[c.schema_id].name)
            for c in drawn} == {("protobuf", "protobuf", "foxglove.SceneUpdate"), ("protobuf", "protobuf", "foxglove.Log")}


def test_run_and_checkpoint_metadata_as_strings(exported):
    path, events, store = exported
    _, _, metadata = read_all(path)
    (run,) = [m.metadata for m in metadata if m.name == "gaps.run"]
    assert run["run"] == RUN and run["events"] == str(len(events)) and run["order"] == "chain"
    assert run["head"] == store.verify(RUN).runs[0].head
    assert run["first_t"] == str(T0) and run["sources"].split(",") == sorted({ev["src"] for ev in events})
    checkpoints = [m.metadata for m in metadata if m.name == "gaps.checkpoint"]
    stored = store.checkpoints(RUN)
    assert len(checkpoints) == len(stored) == 2
    for written, original in zip(checkpoints, stored):
        assert all(isinstance(v, str) for v in written.values())
        assert written == {k: "" if v is None else str(v) for k, v in original.items()}
    assert checkpoints[-1]["count"] == str(len(events)) and checkpoints[-1]["head"] == run["head"]


def test_every_message_matches_its_channel_schema(exported):
    """The schemas in the file describe the messages: the event envelopes (with the kind's body
    schema) validate, and the Foxglove SceneUpdate and Log messages we draw decode, each with
    nothing left over that its schema does not define."""
    path, _, _ = exported
    _, messages, _ = read_all(path)
    check, decoded_count = {}, 0
    for schema, _, message in messages:
        if schema.id not in check:
            check[schema.id] = (fastjsonschema.compile(json.loads(schema.data)) if schema.encoding == "jsonschema"
                                else decoder(schema.name, schema.encoding, schema.data))
        if schema.encoding == "jsonschema":
            check[schema.id](json.loads(message.data))
        else:
            proto = check[schema.id](message.data)
            assert not _unknown(proto) and proto.SerializeToString() == message.data
            decoded_count += 1
    assert decoded_count > 0


def derived(path: Path, topic: str) -> list:
    return decoded(path, topic)


def nanoseconds(stamp) -> int:
    return stamp.seconds * S + stamp.nanos


def test_scene_draws_every_live_road_user_at_its_position_once_per_tick(exported):
    """Each message is the whole live scene: a deletion of everything drawn before on the topic,
    then every road user alive then; the pedestrian, despawned at the last tick, is not in it."""
    path, _, _ = exported
    updates = derived(path, ENTITIES_TOPIC)
    assert [t for t, _ in updates] == [T0 + tick * S for tick in range(5)]
    for t, update in updates:
        (deletion,) = update.deletions
        assert (nanoseconds(deletion.timestamp), deletion.type, deletion.id) == (t, fm.SceneEntityDeletionType.All.value, "")
    t, first = updates[0]
    by_id = {e.id: e for e in first.entities}
    assert set(by_id) == {"vehicle/173", "vehicle/253", "pedestrian/p1"}
    car = by_id["vehicle/173"]
    cube = car.cubes[0]
    assert (cube.pose.position.x, cube.pose.position.y) == (-30.0, 1.0)
    q = cube.pose.orientation
    assert q.z == pytest.approx(2 ** -0.5) and q.w == pytest.approx(2 ** -0.5)  # heading 90°
    assert car.frame_id == "map" and nanoseconds(car.timestamp) == T0
    assert by_id["vehicle/253"].spheres, "an ambulance on an emergency call shows a blue light"
    assert by_id["pedestrian/p1"].cubes[0].size.x < 1.0
    assert [{e.id for e in u.entities} for _, u in updates[1:]] == [set(by_id)] * 3 + [{"vehicle/173", "vehicle/253"}]


def test_signals_are_coloured_spheres_beside_their_junction(exported):
    path, _, _ = exported
    signals = derived(path, SIGNALS_TOPIC)
    colours = [u.entities[0].spheres[0].color for _, u in signals]
    assert (colours[0].r, colours[0].g) == (1.0, 0.65)  # amber
    assert (colours[1].r, colours[1].g) == (1.0, 0.0)  # red
    position = signals[0][1].entities[0].spheres[0].pose.position
    assert (position.x, position.y) == (5.0 - 10.0, 2.0)  # west of j1


def test_map_draws_roads_junctions_and_monitors(exported):
    path, _, _ = exported
    ((t, update),) = derived(path, MAP_TOPIC)
    (entity,) = update.entities
    (roads,) = entity.lines
    assert t == T0 and roads.type == fm.LinePrimitiveLineType.LineList.value == 2 and len(roads.points) == 4
    assert [(p.x, p.y) for p in roads.points] == [(-100.0, 0.0), (100.0, 0.0), (0.0, -100.0), (0.0, 100.0)]
    assert entity.cylinders[0].pose.position.x == 5.0
    assert len(entity.arrows) == 1


def test_log_lines_for_decisions_violations_and_collisions(exported):
    path, _, _ = exported
    logs = [m for _, m in derived(path, LOG_TOPIC)]
    assert [(m.level, m.name) for m in logs] == [(3, "vehicle/173"), (3, "monitor/m1"), (4, "sim/world")]
    assert (fm.LogLevel.Warning.value, fm.LogLevel.Error.value) == (3, 4)
    assert "173 proceeds to enter the junction (not permitted" in logs[0].message
    assert "potential violation by vehicle 173" in logs[1].message
    assert logs[2].message == "collision between 173, p1"
    assert logs[0].file == f"gaps/{RUN}/vehicle/173/vehicle.decision" and logs[0].line == 7
    assert nanoseconds(logs[0].timestamp) == T0 + 2 * S


def test_hostile_bodies_do_not_break_the_drawing():
    """The store validates bodies now, but a drawing must not fail on a store written before
    it did, or on fields a schema leaves open."""
    weird = [event(0, run="w", src="sim/world", kind="run.start",
                   body={"map": {"roads": [1, {"id": 2, "from": "x", "to": [1]}], "junctions": [{"x": "?"}],
                                 "monitors": "none"}}),
             event(0, run="w", src="signal/s", kind="signal.state",
                   body={"junction": ["j"], "colour": {"r": 1}, "approach": 7}),
             event(0, run="w", src="vehicle/1", kind="entity.spawn", body={"type": ["car"], "emergency": "yes"}),
             event(1, run="w", src="vehicle/1", kind="entity.state", body={"x": "1", "y": 10**400, "speed_mps": 1}),
             event(2, run="w", src="vehicle/1", kind="vehicle.decision", body={"permitted": [], "proceeds": {}}),
             event(0, run="w", src="monitor/m", kind="monitor.potential_violation",
                   body={"vehicle": {}, "action": None, "facts": "a"}),
             event(0, run="w", src="sim/c", kind="collision", body={"entities": "everyone"})]
    scene = SceneBuilder()
    drawn = [item for ev in weird for item in scene.add(ev)] + scene.finish()
    assert {item.topic for item in drawn} == {MAP_TOPIC, SIGNALS_TOPIC, ENTITIES_TOPIC, LOG_TOPIC}
    schemas = {"/log": fm.Log.get_schema()}
    for item in drawn:
        sdk = schemas.get(item.topic, fm.SceneUpdate.get_schema())
        message = decoder(sdk.name, sdk.encoding, bytes(sdk.data))(item.data)
        numbers = [v for _, v in _fields(message) if isinstance(v, float)]
        assert all(math.isfinite(v) for v in numbers)


def _unknown(message) -> int:
    """How many fields a decoded message and those within it hold that their schema does not define."""
    count = len(UnknownFieldSet(message))
    for field, value in message.ListFields():
        if field.message_type is not None:
            count += sum(_unknown(item) for item in (value if field.is_repeated else [value]))
    return count


def _fields(message):
    """Every (field, value) of a decoded protobuf message, nested ones included."""
    for field, value in message.ListFields():
        for item in value if field.is_repeated else [value]:
            if hasattr(item, "ListFields"):
                yield from _fields(item)
            else:
                yield field.name, item


def test_times_before_1970_and_huge_seqs_fit_mcap_fields(tmp_path):
    events = [event(0, run="edge", t=-5), event(2**40, run="edge", t=7)]
    with Store(tmp_path / "gaps.db") as store:
        store.append(events)
        export_run(store, "edge", tmp_path / "edge.mcap")
    _, messages, _ = read_all(tmp_path / "edge.mcap")
    written = {json.loads(m.data)["seq"]: m for _, _, m in messages}
    assert (written[0].log_time, written[0].sequence) == (0, 0)
    assert (written[2**40].log_time, written[2**40].sequence) == (7, (2**40) % 2**32)
    assert [json.loads(m.data)["t"] for _, _, m in messages] == [-5, 7]


def test_lz4_and_uncompressed_exports_are_readable(tmp_path):
    from store.transfer.mcap_out import export_mcap
    with Store(tmp_path / "gaps.db") as store:
        store.append(scene_events())
        for compression in ("lz4", "none"):
            export_mcap(store, RUN, tmp_path / f"{compression}.mcap", compression=compression)
            summary, messages, _ = read_all(tmp_path / f"{compression}.mcap")
            assert {c.compression for c in summary.chunk_indexes} == {"" if compression == "none" else "lz4"}
            assert summary.statistics.message_count == len(messages)


def test_unknown_run_is_an_error_and_no_file_is_written(tmp_path):
    with Store(tmp_path / "gaps.db") as store:
        store.append([event(0)])
        with pytest.raises(TransferError, match="no run 'nope'"):
            export_run(store, "nope", tmp_path / "x.mcap")
    assert not any(p.name.endswith((".mcap", ".partial")) for p in tmp_path.iterdir())


def test_without_the_scene_only_events_and_metadata_are_written(tmp_path):
    with Store(tmp_path / "gaps.db") as store:
        store.append(scene_events())
        report = export_run(store, RUN, tmp_path / "plain.mcap", scene=False)
    summary, messages, metadata = read_all(tmp_path / "plain.mcap")
    assert report.derived == 0 and len(messages) == report.events == len(scene_events())
    assert all(c.topic.startswith("gaps/") for c in summary.channels.values())
    assert {m.name for m in metadata} == {"gaps.run", "gaps.checkpoint"}
