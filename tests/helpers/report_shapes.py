"""Reports whose JSON is pinned (tests/explain/test_report_json.py): the paper run with road
users around its second incident and a SUMO-like map with lanes, and a forcing (the road user
forced, its speed, the distance to the Stop line). `python -m tests.helpers.report_shapes OUT`
writes their JSON, as data/report_before_typed.json was written by the code that built the
report as dicts (commit db5f254, main before this branch)."""
from __future__ import annotations

import json
import sys
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

NOW = datetime(2026, 1, 2, 3, 4, 5, tzinfo=timezone.utc)
SECOND = 1_000_000_000


def _event(run: str, src: str, kind: str, seq: int, t: int, body: dict) -> dict:
    return {"v": 1, "run": run, "src": src, "seq": seq, "t": t, "kind": kind, "body": body}


def crowded_lanes_run() -> list[dict]:
    """The paper run on a SUMO-like map (lanes, stop lines, crossings, box), with a car there at
    its second incident (+40 s), one gone quiet, one despawned, and two pedestrians."""
    from sim_replay.paper import RUN, T0, paper_run
    from tests.helpers.scene_pictures import sumo_like_map
    events = paper_run()
    start = next(e for e in events if e["kind"] == "run.start")
    start["body"]["map"] = {**sumo_like_map(), "monitors": start["body"]["map"]["monitors"]}
    at = T0 + 40 * SECOND
    events += [
        _event(RUN, "vehicle/500", "entity.spawn", 0, T0, {"type": "car"}),
        _event(RUN, "vehicle/500", "entity.state", 1, at - 800_000_000, {"x": 3.0, "y": -1.0, "heading_deg": 90.0,
                                                                         "speed_mps": 2.0}),
        _event(RUN, "vehicle/501", "entity.spawn", 0, T0, {"type": "car"}),
        _event(RUN, "vehicle/501", "entity.state", 1, at - 2_500_000_000, {"x": -4.0, "y": 3.0, "speed_mps": 0.0}),
        _event(RUN, "vehicle/502", "entity.spawn", 0, T0, {"type": "bus"}),
        _event(RUN, "vehicle/502", "entity.state", 1, at - 400_000_000, {"x": 5.0, "y": 5.0, "speed_mps": 1.0}),
        _event(RUN, "vehicle/502", "entity.despawn", 2, at - 200_000_000, {"reason": "left the map"}),
        _event(RUN, "pedestrian/p1", "entity.spawn", 0, T0, {"type": "pedestrian"}),
        _event(RUN, "pedestrian/p1", "entity.state", 1, T0 + 10 * SECOND, {"x": -1.0, "y": 1.0, "speed_mps": 1.2}),
        _event(RUN, "pedestrian/p2", "entity.spawn", 0, T0, {"type": "pedestrian"}),
        _event(RUN, "pedestrian/p2", "entity.state", 1, at - 100_000_000, {"x": 6.0, "y": -6.0, "speed_mps": 1.2}),
    ]
    return sorted(events, key=lambda e: e["t"])


def forcing_run() -> tuple[str, list[dict]]:
    """Issue 35's control scenario, as tests/explain/test_report_pictures.py builds it."""
    from tests.helpers.foreign import Motion
    from tests.reasoner.test_foreign_scenarios import _SET_OFF, stop_then_go_run
    begins = _SET_OFF + 3.43
    c2 = Motion(-30.0 - 13.4 * begins, 13.4, [(begins, 0.0), (13.4 / 5.0, -5.0)])
    run = stop_then_go_run(("c2", c2, "north"))
    run.end((max(e["t"] for e in run.events) - run.events[0]["t"]) / 1e9 + 1)
    return run.run, run.events


def report_json(folder: Path) -> dict[str, Any]:
    """Each report's JSON as `gaps report -o r.json` writes it, without what names the store
    file (provenance) or repeats `gaps explain --json` (each incident's explanation)."""
    from explain import build_report, render_report
    from reasoner import Case
    from sim_replay.paper import RUN
    from store import Store
    out = {}
    for name, (run, events) in {"crowded-lanes": (RUN, crowded_lanes_run()), "forcing": forcing_run()}.items():
        with Store(folder / f"{name}.db") as store:
            assert not store.append(events).rejected
            data = json.loads(render_report(build_report(Case(store), run, now=NOW), "json"))
        data.pop("provenance")
        for entry in data["incidents"]:
            entry.pop("explanation")
        out[name] = data
    return out


if __name__ == "__main__":
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        Path(sys.argv[1]).write_text(json.dumps(report_json(Path(tmp)), indent=1) + "\n", encoding="utf-8")
