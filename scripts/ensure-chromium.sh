#!/usr/bin/env bash
# Make sure a headless Chromium (the report's browser test, tests/explain/test_report_browser.py,
# and `gaps report --pdf`) and poppler's pdftotext (the tests that read the printed PDF back) are
# there. `make test` runs this before pytest.
#
# Quick when both are already installed (two lookups). Otherwise, where apt works (root, or sudo
# without a password), installs Debian's `chromium` and `poppler-utils` packages from the mirrors
# apt is configured with. Never fatal: without them those tests are skipped with the reason.
set -uo pipefail

log() { echo "ensure-chromium: $*" >&2; }

have_chromium() {
  local cand
  for cand in "${GAPS_CHROMIUM:-}" /usr/bin/chromium chromium chromium-browser google-chrome google-chrome-stable; do
    if [ -n "$cand" ] && command -v "$cand" >/dev/null 2>&1; then return 0; fi
  done
  return 1
}

missing=()
have_chromium || missing+=(chromium)
command -v pdftotext >/dev/null 2>&1 || missing+=(poppler-utils)
[ ${#missing[@]} -eq 0 ] && exit 0

command -v apt-get >/dev/null 2>&1 || { log "no apt-get here: the tests that need ${missing[*]} will be skipped"; exit 0; }
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then sudo="sudo -n"; else
    log "not root and no password-less sudo: the tests that need ${missing[*]} will be skipped"; exit 0
  fi
fi

CACHE="${GAPS_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/mind-the-gaps}"
mkdir -p "$CACHE"
aptlog="$CACHE/apt-chromium.log"
log "installing Debian's ${missing[*]} for the report's browser and PDF tests (once)"
exec 9>"$CACHE/apt.lock"
flock 9   # another clone may be running apt right now
missing=()
have_chromium || missing+=(chromium)
command -v pdftotext >/dev/null 2>&1 || missing+=(poppler-utils)
[ ${#missing[@]} -eq 0 ] && exit 0   # the other clone installed them
if ! DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >"$aptlog" 2>&1; then
  # the package lists may be missing or stale on a fresh machine: refresh them once and retry
  { $sudo apt-get update -qq &&
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}"; } >>"$aptlog" 2>&1 \
    || { tail -n 5 "$aptlog" >&2; log "apt-get failed (log: $aptlog): the browser and PDF tests will be skipped"; exit 0; }
fi
log "installed ${missing[*]}: $(/usr/bin/chromium --version 2>/dev/null | head -n 1), $(pdftotext -v 2>&1 | head -n 1)"
