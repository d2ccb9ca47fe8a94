"""JSONL and MCAP import fuzzed: lines of junk and mutated events, and MCAP files with hostile chunks
(any compression, declared size, CRC and content, bombs among them) spliced between good ones,
import every good event, account for every other, leave a store that verifies, and raise nothing
but TransferError (a file that is not MCAP at all)."""
from __future__ import annotations

import json
import tempfile
from pathlib import Path

from hypothesis import given
from hypothesis import strategies as st

from store import Store
from store.transfer import TransferError, import_file
from store.transfer.mcap_out import export_mcap
from tests.fuzz.budget import fuzz
from tests.helpers.mcap_bombs import chunk_record, splice_after_first_chunk, zstd_rle
from tests.helpers.store_testkit import event

GOOD = [event(i, run="good", src="vehicle/1", kind="entity.state") for i in range(12)]
LINES = [json.dumps(e).encode() for e in GOOD]


def _good_mcap() -> bytes:
    with tempfile.TemporaryDirectory() as folder:
        with Store(Path(folder) / "g.db") as store:
            store.append(GOOD)
            export_mcap(store, "good", Path(folder) / "g.mcap", chunk_size=500)
        return (Path(folder) / "g.mcap").read_bytes()


GOOD_MCAP = _good_mcap()


def import_checked(data: bytes, suffix: str) -> tuple[Store, object] | None:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / f"fuzz{suffix}"
        path.write_bytes(data)
        with Store(Path(folder) / "gaps.db") as store:
            try:
                report = import_file(store, path)
            except TransferError:
                return None
            assert report.stored == store.count()
            assert report.rejected == sum(row["count"] for row in store.quarantined())  # repeats are one row
            assert store.verify().ok
            return {(e["src"], e["seq"]) for e in store.events("good")} if store.runs() else set()


junk_line = st.one_of(st.binary(max_size=120).filter(lambda b: b"\n" not in b),
                      st.sampled_from(LINES).map(lambda b: b[: len(b) // 2]),
                      st.sampled_from(LINES).map(lambda b: b.replace(b'"seq"', b'"seq ', 1)))


@fuzz(15)
@given(st.lists(st.one_of(st.sampled_from(range(len(LINES))), junk_line), max_size=30))
def test_jsonl_lines_of_events_and_junk(items):
    lines = [LINES[i] if isinstance(i, int) else i for i in items]
    stored = import_checked(b"\n".join(lines) + b"\n", ".jsonl")
    wanted = {(GOOD[i]["src"], GOOD[i]["seq"]) for i in items if isinstance(i, int)}
    assert stored is not None and wanted <= stored


hostile_chunk = st.builds(
    lambda compression, declared, crc, payload: chunk_record(compression, payload, declared, crc),
    st.sampled_from(["", "zstd", "lz4", "bogus"]),
    st.one_of(st.integers(0, 1 << 20), st.sampled_from([0, 1000, 64 << 20, (64 << 20) + 1, 1 << 30, (1 << 64) - 1])),
    st.integers(0, (1 << 32) - 1),
    st.one_of(st.binary(max_size=300),
              st.integers(1, 1 << 30).map(lambda n: zstd_rle(n, declared=None)),
              st.integers(1, 1 << 26).map(lambda n: zstd_rle(n, declared=n)),
              st.integers(1, 1 << 26).map(lambda n: zstd_rle(n, declared=n, byte=5))),
)


@fuzz(12)
@given(st.lists(hostile_chunk, min_size=1, max_size=4))
def test_mcap_with_hostile_chunks_keeps_its_good_events(chunks):
    data, _ = splice_after_first_chunk(GOOD_MCAP, chunks)
    stored = import_checked(data, ".mcap")
    assert stored == {(e["src"], e["seq"]) for e in GOOD}


@fuzz(12)
@given(st.lists(st.tuples(st.integers(8, len(GOOD_MCAP) - 1), st.integers(1, 255)), min_size=1, max_size=8),
       st.integers(0, len(GOOD_MCAP)))
def test_mcap_with_bytes_changed_and_cut(edits, keep):
    data = bytearray(GOOD_MCAP)
    for position, mask in edits:
        data[position] ^= mask
    stored = import_checked(bytes(data[:keep]), ".mcap")
    assert stored is None or stored <= {(e["src"], e["seq"]) for e in GOOD}
