"""`gaps import` on a full disk: one line, exit 2, and the batches committed before it kept, verified
(SQLite's own full disk: PRAGMA max_page_count, from the second batch on)."""
import json

import store
from store import Store
from tests.helpers.cli import gaps
from tests.helpers.store_testkit import event


def test_import_on_a_full_disk_is_one_line_and_keeps_what_was_committed(tmp_path, monkeypatch):
    class FullAfterOneBatch(Store):
        """SQLite's own full disk (max_page_count) from the second append on."""
        def _append(self, feed):
            if getattr(self, "_appended", False):
                pages = self.connection.execute("PRAGMA page_count").fetchone()[0]
                self.connection.execute(f"PRAGMA max_page_count = {pages}")
            self._appended = True
            return super()._append(feed)

    source = tmp_path / "run.jsonl"
    source.write_text("".join(json.dumps(event(seq)) + "\n" for seq in range(7_000)))
    monkeypatch.setattr(store, "Store", FullAfterOneBatch)
    result = gaps("import", source, db=tmp_path / "gaps.db")
    assert result.exit_code == 2 and "database or disk is full" in result.output
    assert result.output.count("\n") == 1
    with Store.open_read_only(tmp_path / "gaps.db") as kept:
        assert kept.count() == 5_000 and kept.verify().ok
