"""Suite-wide settings: machines here are shared and their speed swings, so no property test may
fail for taking longer than Hypothesis's default 200 ms on one example (speed is measured in bench/)."""
import pytest
from hypothesis import settings

settings.register_profile("shared-machine", deadline=None)
settings.load_profile("shared-machine")


@pytest.fixture(scope="module")
def paper_db(tmp_path_factory):
    """The paper's run (sim_replay/paper.py) in a fresh store, one per test module: the readers'
    tests share it within a module and none of them writes to it."""
    from sim_replay.paper import paper_run
    from store import Store

    path = tmp_path_factory.mktemp("paper") / "gaps.db"
    with Store(path) as store:
        store.append(paper_run())
    return path


@pytest.fixture(autouse=True, scope="session")
def _cache_key_home(tmp_path_factory):
    """The cache key (store/cache_seal.py) is kept in the user's config home, and caches (a
    read-only store's, the kept recordings of store/kept_recording.py) in the cache home: tests keep
    theirs in folders of their own (subprocesses inherit them), never in the real home."""
    import os
    if "XDG_CONFIG_HOME" not in os.environ or not os.environ.get("GAPS_TEST_REAL_CONFIG"):
        os.environ["XDG_CONFIG_HOME"] = str(tmp_path_factory.mktemp("config"))
        os.environ["XDG_CACHE_HOME"] = str(tmp_path_factory.mktemp("cache"))
    yield
