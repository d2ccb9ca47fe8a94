"""An export re-imports to the same chain heads: JSONL and MCAP are written in chain order by
default, so a store whose events arrived out of time order across sources comes back identical."""
import pytest
from tests.helpers.store_testkit import T0, event
from typer.testing import CliRunner

from cli.main import app
from store import Store, export_run, import_file

MS = 1_000_000


def heads(store):
    return {r["run"]: r["head"] for r in store.verify().runs}


@pytest.fixture
def out_of_order(tmp_path):
    """Two runs; each source's batches arrive after the other's, so chain order is not time order."""
    path = tmp_path / "a.db"
    with Store(path) as store:
        for run in ("r1", "r2"):
            late = [event(seq, run=run, src="vehicle/2", kind="entity.state", t=T0 + seq * 10 * MS,
                          body={"x": 1.0, "y": 2.0, "speed_mps": 3.0}) for seq in range(30)]
            early = [event(seq, run=run, src="vehicle/1", t=T0 + seq * 10 * MS + 5 * MS) for seq in range(30)]
            store.append(late[15:] + early[:20])
            store.append(late[:15] + early[20:])
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


@pytest.mark.parametrize("suffix", ["jsonl", "mcap"])
def test_gaps_export_then_import_gives_the_same_chain_heads(out_of_order, tmp_path, suffix):
    runner = CliRunner()
    for run in ("r1", "r2"):
        exported = runner.invoke(app, ["export", "--run", run, "-o", str(tmp_path / f"{run}.{suffix}"),
                                       "--db", str(out_of_order)])
        assert exported.exit_code == 0 and "in chain order" in exported.output, exported.output
        imported = runner.invoke(app, ["import", str(tmp_path / f"{run}.{suffix}"), "--db", str(tmp_path / "b.db")])
        assert imported.exit_code == 0, imported.output
    with Store.open_read_only(out_of_order) as a, Store.open_read_only(tmp_path / "b.db") as b:
        assert heads(a) == heads(b)


def test_a_time_ordered_jsonl_export_would_not(out_of_order, tmp_path):
    """Why the default is chain order: the same events in time order chain to another head."""
    with Store.open_read_only(out_of_order) as source, Store(tmp_path / "b.db") as copy:
        export_run(source, "r1", tmp_path / "r1.jsonl", order="time")
        import_file(copy, tmp_path / "r1.jsonl")
        assert heads(copy)["r1"] != heads(source)["r1"]
