"""The seal's framing is a format: cache files sealed by an earlier version must still open, so
the bytes a tuple frames to are fixed (this vector was framed by the first version of _framed)."""
from store.cache.seal import _framed

VECTOR = ("73000000000000000161690000000000000001316e00000000000000044e6f6e656e0000000000000004547275"
          "656600000000000000143078312e34303030303030303030303030702b316200000000000000027879730000"
          "000000000002c3a9")


def test_a_tuple_frames_to_the_bytes_it_always_did() -> None:
    assert _framed(("a", 1, None, True, 2.5, b"xy", "é")).hex() == VECTOR


def test_a_str_subclass_frames_as_its_text() -> None:
    class Name(str):
        pass
    assert _framed((Name("a"),)) == _framed(("a",))
