"""What makes judging many cases fast, each beside the plain judge (reasoner/judge/) and each
giving its answer: the court that reads what the case memo kept (kept_court.py), the run's
cases kept (kept_cases.py), the incidents of the judgement in force kept whole and by their
summaries (kept_verdicts.py, summaries.py), and what two investigations read of a run alike
(shared.py). The tests compare each with the plain judge to the byte."""
