"""An export re-imports to the same chain heads: JSONL and MCAP are written in chain order by
default, so a store whose events arrived out of time order across sources comes back identical."""
import pytest
from tests.helpers.store_testkit import heads, out_of_order_store

from store import Store
from store.transfer import export_run, import_file


@pytest.fixture
def out_of_order(tmp_path):
    path = out_of_order_store(tmp_path / "a.db")
    with Store.open_read_only(path) as store:
        assert [e["t"] for e in store.events("r1")] != [e["t"] for e in _chain_order(store, "r1")]
    return path


def _chain_order(store, run):
    return sorted(store.events(run), key=lambda e: store.chain_positions(run, [(e["src"], e["seq"])])[(e["src"], e["seq"])])


@pytest.mark.parametrize("suffix", ["jsonl", "mcap"])
def test_an_export_reimports_to_the_same_chain_heads(out_of_order, tmp_path, suffix):
    with Store.open_read_only(out_of_order) as source:
        for run in ("r1", "r2"):
            assert export_run(source, run, tmp_path / f"{run}.{suffix}").order == "chain"
        expected = heads(source)
    with Store(tmp_path / "b.db") as copy:
        for run in ("r1", "r2"):
            import_file(copy, tmp_path / f"{run}.{suffix}")
        assert heads(copy) == expected and None not in expected.values()


def test_a_time_ordered_jsonl_export_would_not(out_of_order, tmp_path):
    """Why the default is chain order: the same events in time order chain to another head."""
    with Store.open_read_only(out_of_order) as source, Store(tmp_path / "b.db") as copy:
        export_run(source, "r1", tmp_path / "r1.jsonl", order="time")
        import_file(copy, tmp_path / "r1.jsonl")
        assert heads(copy)["r1"] != heads(source)["r1"]
