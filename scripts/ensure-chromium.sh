#!/usr/bin/env bash
# Make sure a headless Chromium is there for the report's browser test (tests/explain/
# test_report_browser.py) and `gaps report --pdf`. `make test` runs this before pytest.
#
# Quick when it is already installed (one file test). Otherwise, where apt works (root, or
# sudo without a password), installs Debian's `chromium` package from the mirrors apt is
# configured with. Never fatal: without Chromium the browser test is skipped with the reason.
set -uo pipefail

log() { echo "ensure-chromium: $*" >&2; }

for cand in "${GAPS_CHROMIUM:-}" /usr/bin/chromium; do
  if [ -n "$cand" ] && command -v "$cand" >/dev/null 2>&1; then exit 0; fi
done
for name in chromium chromium-browser google-chrome google-chrome-stable; do
  if command -v "$name" >/dev/null 2>&1; then exit 0; fi
done

command -v apt-get >/dev/null 2>&1 || { log "no apt-get here: the browser test will be skipped"; exit 0; }
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then sudo="sudo -n"; else
    log "not root and no password-less sudo: the browser test will be skipped"; exit 0
  fi
fi

CACHE="${GAPS_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/mind-the-gaps}"
mkdir -p "$CACHE"
aptlog="$CACHE/apt-chromium.log"
log "installing Debian's chromium for the report's browser test (once)"
exec 9>"$CACHE/apt.lock"
flock 9   # another clone may be running apt right now
if command -v /usr/bin/chromium >/dev/null 2>&1; then exit 0; fi
if ! DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq chromium >"$aptlog" 2>&1; then
  # the package lists may be missing or stale on a fresh machine: refresh them once and retry
  { $sudo apt-get update -qq &&
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq chromium; } >>"$aptlog" 2>&1 \
    || { tail -n 5 "$aptlog" >&2; log "apt-get failed (log: $aptlog): the browser test will be skipped"; exit 0; }
fi
log "installed $(/usr/bin/chromium --version 2>/dev/null | head -n 1)"
