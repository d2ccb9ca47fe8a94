"""The store most command-line tests read: two runs, a gap in r1's seqs and two refusals, one hostile."""
import pytest

from store import Store
from tests.helpers.cli import HOSTILE_ORIGIN, HOSTILE_RAW
from tests.helpers.store_testkit import T0, event


@pytest.fixture
def db(tmp_path):
    path = tmp_path / "gaps.db"
    with Store(path) as store:
        store.append([event(i) for i in (0, 1, 2, 5, 6, 9)] + [event(0, kind="run.start")])
        store.append([event(1, kind="run.end", t=T0 + 3_723_500_000_000)])
        store.append([event(0, run="r2", kind="monitor.observation")])
        store.append_raw([(HOSTILE_RAW, HOSTILE_ORIGIN), (b"nonsense", "file.jsonl:3")])
    return path
