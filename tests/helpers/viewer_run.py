"""A run with everything that broke the viewers: nullable fields, a recursive proof, enums, a map
with $refs, road users that each publish at their own instant, a despawn, two signals."""

from __future__ import annotations

from tests.helpers.store_testkit import event

RUN = "viewers"
T0 = 1_732_184_100_000_000_000
MS, S = 1_000_000, 1_000_000_000
SHA = "a" * 64
MAP = {"roads": [{"id": "r1", "from": [-100.0, 0.0], "to": [100.0, 0.0]}],
       "junctions": [{"id": "j1", "x": 0.0, "y": 0.0, "control": "lights"}],
       "monitors": [{"id": "m1", "junction": None, "x": -15.0, "y": 10.0, "heading_deg": 0.0,
                     "range_m": 60.0, "fov_deg": 90.0}]}
PROOF = {"sentence": "1 can enter the junction", "status": "failed", "rule": None, "source": None,
         "evidence": [], "children": [{"sentence": "1 has green light", "status": "failed", "rule": "HC 176",
                                       "source": {"file": "paper.le", "line": 32}, "children": []}]}


def viewer_events() -> list[dict]:
    """Three road users at 10 Hz, each at its own instant (1 µs slots, one 50 ms late), two signals,
    every kind with its awkward fields, a despawn; appended in arrival order, not time order."""
    seqs: dict[str, int] = {}

    def ev(src: str, t: int, kind: str, body: dict) -> dict:
        seqs[src] = seqs.get(src, -1) + 1
        return event(seqs[src], run=RUN, src=src, t=t, kind=kind, body=body)

    out = [ev("sim/world", T0, "run.start", {"map": MAP, "seed": 1, "config": {"any": [1, "x"]},
                                             "rulebooks": [{"name": "paper.le", "sha256": SHA, "text": "..."}]})]
    movers = {"vehicle/1": 0, "vehicle/2": 1000, "pedestrian/p": 50 * MS}
    for src in movers:
        out.append(ev(src, T0, "entity.spawn", {"type": "pedestrian" if "pedestrian" in src else "car",
                                                "driver": "human", "emergency": False}))
    out.append(ev("vehicle/1", T0 + 1, "ads.event", {"event": "activated", "software": {"ads": "1.0"}}))
    for tick in range(30):
        t = T0 + tick * 100 * MS
        if tick % 10 == 0:
            for signal in ("signal/j1-west", "signal/j1-north"):
                out.append(ev(signal, t, "signal.state", {"junction": "j1", "approach": signal[-5:].strip("-"),
                                                          "colour": ("red", "green", "amber")[tick // 10]}))
        for src, offset in movers.items():
            if src == "pedestrian/p" and tick >= 20:
                continue
            out.append(ev(src, t + offset, "entity.state",
                          {"x": -50.0 + tick, "y": 1.0, "heading_deg": 0.0, "speed_mps": 10.0,
                           "road": None if tick % 2 else "r1", "junction": "j1" if 10 <= tick < 15 else None}))
    out += [ev("pedestrian/p", T0 + 1950 * MS, "entity.despawn", {"reason": "left"}),
            ev("vehicle/1", T0 + 1200 * MS, "vehicle.perception", {"facts": ["1 has red light"]}),
            ev("vehicle/1", T0 + 1200 * MS, "vehicle.trace",
               {"query": "1 can enter the junction", "answer": ["1 can enter the junction"], "proof": PROOF}),
            ev("vehicle/1", T0 + 1200 * MS, "vehicle.decision",
               {"goal": "1 can enter the junction", "action": "enter the junction", "permitted": False,
                "proceeds": True, "rulebook": SHA, "trace": 1}),
            ev("monitor/m1", T0 + 1300 * MS, "monitor.observation",
               {"vehicle": "1", "facts": ["1 has red light"], "speed_mps": 10.0, "x": -38.0, "y": 1.0}),
            ev("monitor/m1", T0 + 1300 * MS, "monitor.potential_violation",
               {"vehicle": "1", "action": "enter the junction", "proof": PROOF}),
            ev("sim/world", T0 + 2500 * MS, "collision", {"entities": ["1", "2"]}),
            ev("sim/world", T0 + 3 * S, "run.end", {"reason": "done"})]
    return out
