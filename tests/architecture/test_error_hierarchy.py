"""One error hierarchy: every error raised on purpose anywhere is a GapsError with an exit code,
so `gaps` turns it into one message and a script catches them all with one `except`."""
from __future__ import annotations

import pytest

from explain.pdf import PdfError, ToolMissing
from explain.report import ReportError
from reasoner.counterfactuals import QuestionUnreadable
from reasoner.engine import QuestionError
from reasoner.le.errors import LEError
from reasoner.le.expectations import ExpectationError
from reasoner.prolog_home import PrologUnavailable
from reasoner.when import TimeError, parse_time
from sim_replay.monitors import MonitorsError
from sim_replay.sumo_world import WorldError
from store import GapsError, NoSuchRun, StoreError
from store.envelope import EventError
from store.transfer.errors import TransferError

USER_MISTAKES = [StoreError, NoSuchRun, EventError, TransferError, TimeError, LEError,
                 ExpectationError, QuestionError, QuestionUnreadable, ReportError, PdfError, MonitorsError, WorldError]
SET_UP = [PrologUnavailable, ToolMissing]


@pytest.mark.parametrize("cls", USER_MISTAKES + SET_UP, ids=lambda c: c.__name__)
def test_every_error_is_a_gaps_error(cls):
    assert issubclass(cls, GapsError)


@pytest.mark.parametrize("cls", USER_MISTAKES, ids=lambda c: c.__name__)
def test_user_mistakes_exit_2(cls):
    assert cls.exit_code == 2


@pytest.mark.parametrize("cls", SET_UP, ids=lambda c: c.__name__)
def test_set_up_problems_exit_3(cls):
    assert cls.exit_code == 3


def test_old_bases_still_catch_them():
    """Callers that caught ValueError before keep working: the hierarchy was added, not swapped."""
    with pytest.raises(ValueError):
        parse_time("half past never", 0)
    with pytest.raises(GapsError, match="cannot read the time"):
        parse_time("half past never", 0)


def test_no_such_run_lists_the_runs():
    err = NoSuchRun("typo", ["run-a", "run-b"])
    assert str(err) == "no run 'typo'; runs: run-a, run-b"
    assert str(NoSuchRun("x", [])) == "no run 'x'; runs: none"


def test_a_fleet_of_runs_is_not_listed_in_full():
    runs = [f"run-{i:04d}" for i in range(1000)]
    message = str(NoSuchRun("typo", runs))
    assert message.endswith("run-0019 and 980 more") and "run-0020" not in message
