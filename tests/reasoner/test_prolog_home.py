"""The embedded engine is pinned to the SWI-Prolog the set-up recorded, whatever `swipl` is on PATH."""
import os
import shutil
import subprocess
import sys

import pytest

from reasoner.prolog_home import swipl_home

PROBE = ("from reasoner.prolog_home import import_janus\n"
         "j = import_janus()\n"
         "print(j.query_once('current_prolog_flag(home, H)')['H'])")


def test_engine_runs_from_the_recorded_home_even_with_another_swipl_first_on_path():
    system = shutil.which("swipl", path="/usr/bin:/usr/local/bin")
    if not system:
        pytest.skip("no system swipl to shadow the recorded one")
    env = {k: v for k, v in os.environ.items() if k != "SWI_HOME_DIR"}
    env["PATH"] = os.path.dirname(system) + os.pathsep + env.get("PATH", "")
    r = subprocess.run([sys.executable, "-c", PROBE], env=env, capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert os.path.realpath(r.stdout.strip()) == os.path.realpath(swipl_home())


def test_missing_home_is_a_clear_error(tmp_path):
    env = dict(os.environ, GAPS_SWIPL_HOME=str(tmp_path))
    r = subprocess.run([sys.executable, "-c", PROBE], env=env, capture_output=True, text=True, timeout=60)
    assert r.returncode != 0 and "run `make setup`" in r.stderr
