"""Regression of a new rulebook over logged runs (`gaps regress`): which verdicts and decisions it
changes, and why. This is the regression's face: cli/ and bench/ import from here
(`from reasoner.regress import X`), never from a module inside.

    regression  one store's runs judged under two rulebooks, and the result
    books       the rulebooks compared, and which stage each answers
    decisions   the vehicles' recorded decisions, asked again under two rulebooks
    diff        what changed between two versions of a rulebook, rule by rule
    reasons     the changed rules two proofs went through
    match       which incident of one judgement is which of the other
    cluster     many runs at once, on Dask
    recording   regression straight from recordings
    golden      golden runs and their approved verdicts
    text        a regression in words
    junit       a regression as JUnit XML

It is the judge's caller, never its callee: of the rest of the reasoner only its API (reasoner/api.py,
`reasoner.regression`) imports it.
"""
from .books import RegressError
from .cluster import Cluster, ClusterLost, regress_recordings, regress_store
from .golden import check_golden
from .junit import junit_xml
from .regression import CaseResult, Change, Regression, Regressor, RunResult, assemble, regress
from .text import lines

__all__ = ["CaseResult", "Change", "Cluster", "ClusterLost", "RegressError", "Regression", "Regressor", "RunResult",
           "assemble", "check_golden", "junit_xml", "lines", "regress", "regress_recordings", "regress_store"]
