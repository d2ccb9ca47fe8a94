# The two commands of the README. Both set everything up on first use and reuse it after.
SHELL := /bin/bash
VENV := .venv
READY := $(VENV)/.ready
# pytest-xdist workers for `make test`: CI has two cores; TEST_WORKERS=0 runs the suite in one process
TEST_WORKERS ?= 2

.PHONY: demo test setup clean bench bench-quick fuzz

demo: $(READY)
	$(VENV)/bin/gaps demo

test: $(READY)
	@bash scripts/ensure-chromium.sh
	$(VENV)/bin/python -m pytest -n $(TEST_WORKERS)

setup: $(READY)

# The fuzzers (tests/fuzz: envelope decoding, JSONL and MCAP import, the LE parser and engine, the
# command line's arguments, hostile output paths that must never touch the evidence, checkpoint rows
# edited under a rewritten run) with ten times the examples `make test` gives them, round after round
# with fresh seeds until FUZZ_SECONDS (default 600) have passed; the round in progress finishes.
# A failure stops at once; Hypothesis keeps the failing example in .hypothesis/ and tries it first.
FUZZ_SECONDS ?= 600

fuzz: $(READY)
	@end=$$(( $$(date +%s) + $(FUZZ_SECONDS) )); round=0; \
	while [ $$(date +%s) -lt $$end ]; do \
		round=$$((round + 1)); seed=$$(od -An -N4 -tu4 /dev/urandom | tr -d ' '); \
		echo "== fuzz round $$round (seed $$seed)"; \
		GAPS_FUZZ=long PYTHONPATH=$(CURDIR) $(VENV)/bin/python -m pytest -q -p no:cacheprovider \
			--hypothesis-seed=$$seed tests/fuzz tests/reasoner/test_le_fuzz.py || exit 1; \
	done; \
	echo "== the tamper suite, every row of every table and index"; \
	GAPS_TAMPER_ROWS=0 GAPS_TAMPER_COUNTS=$(CURDIR)/tests/artifacts/tamper-counts.json PYTHONPATH=$(CURDIR) \
		$(VENV)/bin/python -m pytest -q -p no:cacheprovider tests/store/test_tamper_suite.py && \
		cat tests/artifacts/tamper-counts.json

# Every benchmark, one after another (a shared machine: never two at once), each recording its figures
# in bench/results.json; then docs/performance.md is regenerated from it. The full sizes take an hour
# or more (the 10-million-event files are generated once under /tmp/gaps-bench); bench-quick runs
# reduced sizes in a few minutes and records them apart from the full ones.
BENCHES := rules append transfer ingest_throughput ingest_cost signatures scene_at_t incidents history scene explanations sumo_step sim kill9 injection regress replay conflict_agreement ingest_fleet run_release dask_kill

bench: $(READY)
	@for b in $(BENCHES); do echo "== bench/$$b.py"; PYTHONPATH=$(CURDIR) $(VENV)/bin/python bench/$$b.py || exit 1; done
	PYTHONPATH=$(CURDIR) $(VENV)/bin/python bench/performance_md.py

bench-quick:
	@BENCH_QUICK=1 $(MAKE) --no-print-directory bench

$(READY): pyproject.toml requirements.lock scripts/setup.sh scripts/ensure-swipl.sh
	@bash scripts/setup.sh

clean:
	rm -rf $(VENV) gaps.db gaps.db-wal gaps.db-shm gaps.db.serve.lock gaps-report.html out
