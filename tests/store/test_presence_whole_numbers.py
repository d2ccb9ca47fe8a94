"""A box of where a road user was, when one of its positions is a JSON whole number (x 0, as a
producer writes a position on an axis) or -0.0: it is stored in the cache's REAL columns as 0.0,
and is sealed as such, so it is believed when read. Sealed over the integer (or -0.0), its seal
did not open over the 0.0 read back: verify called the cache tampered, and every read meeting the
box rebuilt the run's boxes from all its events (on the one-hour run, 3 boxes of 470,438: some
45% of its first judgement)."""
from store import Store
from store.cache import presence, sources_near
from store.cache.presence import tampered_presence
from tests.helpers.store_testkit import T0

SECOND = 1_000_000_000


def _states(src, points):
    return [{"v": 1, "run": "r1", "src": src, "seq": i, "t": T0 + i * SECOND // 10, "kind": "entity.state",
             "body": {"x": x, "y": y, "speed_mps": 5.0}} for i, (x, y) in enumerate(points)]


def test_a_box_with_a_whole_number_position_is_believed_and_built_once(db_path, monkeypatch):
    built = []
    real = presence._boxes

    def counted(*args):
        built.append(args[2:])
        return real(*args)
    monkeypatch.setattr(presence, "_boxes", counted)
    with Store(db_path) as store:
        store.append(_states("vehicle/1", [(0, -1.75 + 0.5 * i) for i in range(30)])     # along x = 0
                     + _states("vehicle/2", [(40.5 - i, 3) for i in range(30)])           # along y = 3
                     + _states("vehicle/3", [(-0.0, 20.5 - i) for i in range(30)]))       # along x = -0.0
        for _ in range(3):
            assert sources_near(store, "r1", 0.0, 0.0, 50.0, T0, T0 + 2 * SECOND) == [
                "vehicle/1", "vehicle/2", "vehicle/3"]
        assert tampered_presence(store, "r1") == []
        assert store.cache.sealer.tampered() == {}
    assert len(built) == 1
