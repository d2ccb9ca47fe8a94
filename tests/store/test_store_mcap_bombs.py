"""MCAP decompression bombs (issue 15, finding 6): chunks that decompress to gigabytes, declared
honestly or not, and zero-filled chunks, are refused by the bytes they actually produce, each
named by its offset; the good events before and after them are imported, in bounded memory and
time. The import runs in a child process so that its peak RSS is its own."""

from __future__ import annotations

import json
import resource
import subprocess
import sys
import time
from pathlib import Path

import pytest

from store import Store
from store.transfer import import_file
from store.transfer import mcap_chunks
from store.transfer.mcap_out import export_mcap
from tests.helpers.mcap_bombs import chunk_record, splice_after_first_chunk, write, zstd_rle
from tests.helpers.store_testkit import event

GIB = 1 << 30
ROOT = Path(__file__).resolve().parents[2]


def good_export(folder: Path, n: int = 20) -> bytes:
    """An export of `n` events in several small chunks."""
    with Store(folder / "good.db") as store:
        store.append([event(i, run="good", src="vehicle/1", kind="entity.state") for i in range(n)])
        export_mcap(store, "good", folder / "good.mcap", chunk_size=600)
    return (folder / "good.mcap").read_bytes()


def bombs() -> list[tuple[str, bytes]]:
    import lz4.frame
    return [
        ("zstd, 1 GiB declared honestly", chunk_record("zstd", zstd_rle(GIB, declared=GIB), GIB)),
        ("zstd, 1 GiB declared as 1000 bytes", chunk_record("zstd", zstd_rle(GIB), 1000)),
        ("lz4, 16 MiB declared as 1000 bytes", chunk_record("lz4", lz4.frame.compress(bytes(16 << 20)), 1000)),
        ("zstd, 48 MiB of zeros declared honestly", chunk_record("zstd", zstd_rle(48 << 20, declared=48 << 20),
                                                                 48 << 20)),
        ("uncompressed zeros", chunk_record("", bytes(4096), 4096)),
    ]


_CHILD = """
import json, resource, sys, time
from store import Store
from store.transfer import import_file
started = time.monotonic()
with Store(sys.argv[2]) as store:
    report = import_file(store, sys.argv[1])
    print(json.dumps({"stored": report.stored, "damaged": [d.to_json() for d in report.damaged], "count": store.count(),
                      "seconds": time.monotonic() - started,
                      "peak_rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def _limit_memory() -> None:
    """The child may not take the machine down if the bound is ever lost: 3 GiB of address space."""
    resource.setrlimit(resource.RLIMIT_AS, (3 * GIB, 3 * GIB))


def test_bombs_are_refused_by_what_they_produce_and_the_good_events_imported(tmp_path):
    good = good_export(tmp_path)
    named = bombs()
    data, offsets = splice_after_first_chunk(good, [record for _, record in named])
    path = write(tmp_path / "bombs.mcap", data)
    assert len(data) < 200_000  # a small file that would decompress to over 2 GiB
    started = time.monotonic()
    child = subprocess.run([sys.executable, "-c", _CHILD, str(path), str(tmp_path / "gaps.db")], cwd=ROOT,
                           env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"}, capture_output=True,
                           text=True, timeout=90, preexec_fn=_limit_memory)
    assert child.returncode == 0, child.stderr[-2000:]
    result = json.loads(child.stdout)
    assert result["stored"] == result["count"] == 20  # every good event, before and after the bombs
    refused = {d["offset"]: d["reason"] for d in result["damaged"]}
    assert set(refused) == set(offsets), refused
    reasons = [refused[o] for o in offsets]
    assert "over the 67108864-byte limit" in reasons[0] and "not decompressed" in reasons[0]
    assert "decompresses to more than the 1000 bytes it declares" in reasons[1]
    assert "decompresses to more than the 1000 bytes it declares" in reasons[2]
    assert "opcode 0x00" in reasons[3] and "opcode 0x00" in reasons[4]
    assert result["peak_rss_mib"] < 640, result  # gigabytes before (127 MiB alone; 415 MiB seen once in a full run)
    assert time.monotonic() - started < 30 and result["seconds"] < 15, result  # minutes before


def test_a_file_may_decompress_only_to_a_multiple_of_its_size(tmp_path, monkeypatch):
    """Chunks each within the per-chunk cap still cannot make a small file produce without end."""
    monkeypatch.setattr(mcap_chunks, "FILE_FLOOR", 1 << 20)
    monkeypatch.setattr(mcap_chunks, "FILE_RATIO", 1)
    good = good_export(tmp_path)
    zeros = chunk_record("zstd", zstd_rle(400_000, declared=400_000), 400_000)
    data, offsets = splice_after_first_chunk(good, [zeros, zeros, zeros])
    with Store(tmp_path / "gaps.db") as store:
        report = import_file(store, write(tmp_path / "many.mcap", data))
        assert report.stored == store.count() == 20
    refused = {d.offset: d.reason for d in report.damaged}
    assert "opcode 0x00" in refused[offsets[0]] and "opcode 0x00" in refused[offsets[1]]
    assert "the file's chunks may produce only" in refused[offsets[2]]


def test_a_record_running_past_its_chunk_gives_none_of_the_chunks_records(tmp_path):
    from store.transfer.mcap_chunks import ChunkRefused, chunk_records
    message = bytes.fromhex("05") + (22).to_bytes(8, "little") + bytes(22)  # a valid empty Message
    assert len(list(chunk_records(message * 3))) == 3
    with pytest.raises(ChunkRefused, match="runs past"):
        list(chunk_records(message * 3 + bytes.fromhex("05") + (100).to_bytes(8, "little") + bytes(10)))
