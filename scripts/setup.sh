#!/usr/bin/env bash
# Everything `make demo` and `make test` need: SWI-Prolog >= 9.1.12 (found or built once into a
# shared cache), then .venv with the pinned dependencies and janus-swi built against that Prolog.
# Idempotent: the Makefile runs it only when its inputs change.
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=.venv

pick_python() {
  local p
  for p in "${PYTHON:-}" python3.13 python3.12 python3.11 python3; do
    [ -n "$p" ] && command -v "$p" >/dev/null 2>&1 || continue
    if "$p" -c 'import sys; sys.exit(sys.version_info < (3, 11))' 2>/dev/null; then echo "$p"; return 0; fi
  done
  echo "setup: Python 3.11 or newer is needed" >&2; return 1
}

SWIPL=$(bash scripts/ensure-swipl.sh)
HOME_DIR=$("$SWIPL" --dump-runtime-variables | sed -n 's/^PLBASE="\(.*\)";$/\1/p')
echo "setup: SWI-Prolog $("$SWIPL" --version | awk '{print $3}') at $HOME_DIR" >&2

if [ ! -x "$VENV/bin/python" ]; then
  "$(pick_python)" -m venv "$VENV"
fi
export SWIPL   # janus-swi's build finds Prolog through it
"$VENV/bin/python" -m pip install -q --disable-pip-version-check -c requirements.lock pip
"$VENV/bin/python" -m pip install -q --disable-pip-version-check -c requirements.lock \
  --no-cache-dir --force-reinstall --no-deps janus-swi
"$VENV/bin/python" -m pip install -q --disable-pip-version-check -c requirements.lock -e '.[test,net]'
echo "$HOME_DIR" > "$VENV/gaps-swipl-home"
"$VENV/bin/python" -c 'from reasoner.prolog_home import import_janus; import_janus()' \
  || { echo "setup: janus_swi cannot start SWI-Prolog from $HOME_DIR" >&2; exit 1; }
touch "$VENV/.ready"
echo "setup: ready" >&2
