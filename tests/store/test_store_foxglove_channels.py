"""The Foxglove channels of an export are foxglove-sdk's own: the schemas are the FileDescriptorSets
the SDK publishes, the messages are protobuf, and protobuf's own decoder (through the MCAP reader's
protobuf support) reads back, field for field, the positions, times, ids and levels the events say."""

from __future__ import annotations

import math
from pathlib import Path

import foxglove.messages as fm
import pytest
from mcap.reader import make_reader

from store import Store
from store.transfer import export_run
from store.transfer.foxglove import SceneBuilder
from store.transfer.foxglove_channels import ENTITIES_TOPIC, LOG_TOPIC, MAP_TOPIC, SIGNALS_TOPIC
from tests.helpers.foxglove_decoded import alive_at, decoded, decoder
from tests.helpers.viewer_run import RUN, viewer_events

S = 1_000_000_000
SDK_SCHEMAS = {"foxglove.SceneUpdate": fm.SceneUpdate.get_schema(), "foxglove.Log": fm.Log.get_schema()}


@pytest.fixture(scope="module")
def exported(tmp_path_factory) -> tuple[Path, list[dict]]:
    folder = tmp_path_factory.mktemp("foxglove")
    events = viewer_events()
    with Store(folder / "gaps.db") as store:
        store.append(events)
        export_run(store, RUN, folder / "run.mcap")
    return folder / "run.mcap", sorted(events, key=lambda e: (e["t"], e["seq"], e["src"]))


def test_the_channels_carry_the_sdks_schemas_in_protobuf(exported):
    path, _ = exported
    with open(path, "rb") as f:
        summary = make_reader(f).get_summary()
    drawn = {c.topic: c for c in summary.channels.values() if not c.topic.startswith("gaps/")}
    assert set(drawn) == {MAP_TOPIC, ENTITIES_TOPIC, SIGNALS_TOPIC, LOG_TOPIC}
    for channel in drawn.values():
        schema = summary.schemas[channel.schema_id]
        sdk = SDK_SCHEMAS[schema.name]
        assert channel.message_encoding == "protobuf"
        assert (schema.encoding, schema.data) == (sdk.encoding, bytes(sdk.data)) == ("protobuf", schema.data)
    assert summary.schemas[drawn[LOG_TOPIC].schema_id].name == "foxglove.Log"


def test_every_scene_decodes_to_the_road_users_positions_and_times(exported):
    path, events = exported
    scenes = decoded(path, ENTITIES_TOPIC)
    assert len(scenes) > 3
    for log_time, scene in scenes:
        (deletion,) = scene.deletions
        assert deletion.type == fm.SceneEntityDeletionType.All.value
        assert deletion.timestamp.seconds * S + deletion.timestamp.nanos == log_time
        states = alive_at(events, log_time)
        assert {e.id for e in scene.entities} == set(states)
        for entity in scene.entities:
            body = states[entity.id]
            position = entity.cubes[0].pose.position
            assert (position.x, position.y) == (body["x"], body["y"])
            q = entity.cubes[0].pose.orientation
            assert math.degrees(2 * math.atan2(q.z, q.w)) == pytest.approx(body.get("heading_deg", 0.0))
            assert entity.frame_id == "map" and entity.timestamp.seconds * S + entity.timestamp.nanos <= log_time
            assert {kv.key: kv.value for kv in entity.metadata}["src"] == entity.id


def test_signals_and_the_map_decode(exported):
    path, events = exported
    ((t, world),) = decoded(path, MAP_TOPIC)
    (start,) = [ev for ev in events if ev["kind"] == "run.start"]
    assert t == start["t"] and [e.id for e in world.entities] == ["map"] and not world.deletions
    (lines,) = world.entities[0].lines
    assert lines.type == fm.LinePrimitiveLineType.LineList.value and len(lines.points) % 2 == 0 and lines.points
    junctions = start["body"]["map"]["junctions"]
    assert [(c.pose.position.x, c.pose.position.y) for c in world.entities[0].cylinders] == \
        [(j["x"], j["y"]) for j in junctions]
    signals = decoded(path, SIGNALS_TOPIC)
    colours = {ev["src"]: ev["body"]["colour"] for ev in events if ev["kind"] == "signal.state" and ev["t"] <= signals[-1][0]}
    last = {e.id: {kv.key: kv.value for kv in e.metadata}["colour"] for e in signals[-1][1].entities}
    assert last == colours


def test_log_lines_decode_to_their_events_level_key_and_seq(exported):
    path, events = exported
    logged = [ev for ev in events if ev["kind"] in ("vehicle.decision", "monitor.potential_violation", "collision")]
    lines = decoded(path, LOG_TOPIC)
    assert len(lines) == len(logged) > 0
    for (t, line), ev in zip(lines, logged):
        assert t == ev["t"] == line.timestamp.seconds * S + line.timestamp.nanos
        assert (line.name, line.file, line.line) == (ev["src"], f"gaps/{RUN}/{ev['src']}/{ev['kind']}", ev["seq"])
        want = {"collision": fm.LogLevel.Error, "monitor.potential_violation": fm.LogLevel.Warning}.get(ev["kind"])
        if want is not None:
            assert line.level == want.value


def test_a_scene_of_many_road_users_is_one_update(tmp_path):
    """Forty road users moving at one instant are one scene: protobuf's decoder reads one
    SceneUpdate with one deletion and every one of them, in the order they moved."""
    from tests.helpers.store_testkit import event
    events = [event(0, run="many", src=f"vehicle/{i}", t=S, kind="entity.state",
                    body={"x": float(i), "y": -float(i), "speed_mps": 1.0, "junction": None}) for i in range(40)]
    scene = SceneBuilder()
    drawn = [d for ev in events for d in scene.add(ev)] + scene.finish()
    (only,) = drawn
    update = decoder("foxglove.SceneUpdate", "protobuf", bytes(fm.SceneUpdate.get_schema().data))(only.data)
    assert len(update.deletions) == 1 and [e.id for e in update.entities] == [f"vehicle/{i}" for i in range(40)]
    assert [e.cubes[0].pose.position.y for e in update.entities] == [-float(i) for i in range(40)]


def test_times_beyond_foxglove_s_range_are_drawn_at_its_ends():
    from tests.helpers.store_testkit import event
    scene = SceneBuilder()
    far = event(0, run="far", src="sim/c", t=2**62, kind="collision", body={"entities": ["a", "b"]})
    before = event(1, run="far", src="sim/c", t=-5, kind="collision", body={"entities": ["a", "b"]})
    log = decoder("foxglove.Log", "protobuf", bytes(fm.Log.get_schema().data))
    (late,), (early,) = scene.add(far), scene.add(before)
    assert log(late.data).timestamp.seconds == 2**32 - 1 and log(early.data).timestamp.seconds == 0
