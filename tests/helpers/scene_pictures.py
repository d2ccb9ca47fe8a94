"""Scene pictures (report_data.scene_picture's shape) built by hand, for the label tests of
test_report_print.py and of the browser test."""
from __future__ import annotations


def crowded_picture() -> dict:
    """Seven vehicles within 4 m of one another at a junction, a monitor and a signal beside them."""
    cars = [("1", 0.0, 0.0, True), ("22", 1.5, 0.5, False), ("333", -1.0, 1.2, False), ("4444", 0.8, -1.5, False),
            ("55", 2.5, 2.0, False), ("ambulance-6", -2.0, -1.0, False), ("7", 3.0, -2.5, False)]
    return {"t": 0, "offset": "+0s", "vehicle": "1", "note": None,
            "roads": [{"id": "r", "from": [-50.0, 0.0], "to": [50.0, 0.0]}],
            "junctions": [{"id": "j1", "x": 1.0, "y": 0.0, "control": "lights"}],
            "signals": [{"junction": "j1", "approach": "west", "colour": "red", "since_t": 0, "evidence": None}],
            "monitors": [{"id": "monitor/m1", "junction": "j1", "x": -1.0, "y": 3.0, "heading_deg": 0.0,
                          "fov_deg": 90.0, "range_m": 30.0, "observed": ["1"], "watching": True}],
            "vehicles": [{"id": i, "type": "car", "x": x, "y": y, "heading_deg": 0.0, "speed_mps": 5.0,
                          "junction": "j1", "incident": me, "evidence": None, "present": True, "age_s": 0.0}
                         for i, x, y, me in cars],
            "road_users": [{"id": "pedestrian/p", "type": "pedestrian", "x": 0.5, "y": 0.5, "heading_deg": None,
                            "present": True, "age_s": 0.0}]}
