# The two commands of the README. Both set everything up on first use and reuse it after.
SHELL := /bin/bash
VENV := .venv
READY := $(VENV)/.ready

.PHONY: demo test setup clean

demo: $(READY)
	$(VENV)/bin/gaps demo

test: $(READY)
	@bash scripts/ensure-chromium.sh
	$(VENV)/bin/python -m pytest

setup: $(READY)

$(READY): pyproject.toml requirements.lock scripts/setup.sh scripts/ensure-swipl.sh
	@bash scripts/setup.sh

clean:
	rm -rf $(VENV) gaps.db gaps.db-wal gaps.db-shm gaps-report.html out
