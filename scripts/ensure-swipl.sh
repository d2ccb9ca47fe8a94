#!/usr/bin/env bash
# Find or build an SWI-Prolog new enough for janus_swi (>= 9.1.12, with libswipl),
# and print the path of its `swipl` executable on stdout. Everything else goes to stderr.
#
# Order: $GAPS_SWIPL, a `swipl` on PATH, the shared cache prefix, else build 9.2.9 from
# Debian's source tarball into the cache prefix (shared by every clone on this machine).
set -euo pipefail

MIN_VERSION=90112
VERSION=9.2.9
TARBALL="swi-prolog_${VERSION}+dfsg.orig.tar.gz"
SHA256=6d6f2dd6e4558bccb7c87cc7a5cbcf582503384a5fa890efba0ae91a0aaf2258
CACHE="${GAPS_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/mind-the-gaps}"
PREFIX="$CACHE/swipl-$VERSION"

log() { echo "ensure-swipl: $*" >&2; }

# usable SWIPL: prints nothing, succeeds when SWIPL is >= MIN_VERSION and has a shared libswipl.
usable() {
  local swipl="$1" vars version shared
  [ -x "$swipl" ] || return 1
  vars=$("$swipl" --dump-runtime-variables 2>/dev/null) || return 1
  version=$(sed -n 's/^PLVERSION="\([0-9]*\)";$/\1/p' <<<"$vars")
  shared=$(sed -n 's/^PLSHARED="\(.*\)";$/\1/p' <<<"$vars")
  [ -n "$version" ] && [ "$version" -ge "$MIN_VERSION" ] && [ "$shared" = yes ]
}

# debian_mirror: the first Debian archive apt is configured with (never a hard-coded host).
debian_mirror() {
  {
    grep -hs '^URIs:' /etc/apt/sources.list.d/*.sources | awk '{print $2}' || true
    grep -hs '^deb ' /etc/apt/sources.list /etc/apt/sources.list.d/*.list | awk '{print $2}' || true
  } | grep -v -e security -e '^$' | grep '/debian/*$' | head -n 1 | sed 's:/*$::' || true
}

install_build_deps() {
  local deps=(cmake ninja-build gcc g++ make pkg-config libgmp-dev libssl-dev zlib1g-dev
              libpcre2-dev libyaml-dev libarchive-dev libreadline-dev libncurses-dev libffi-dev)
  local missing=()
  for d in "${deps[@]}"; do
    dpkg-query -W -f='${Status}' "$d" 2>/dev/null | grep -q 'install ok installed' || missing+=("$d")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  log "installing build dependencies: ${missing[*]}"
  local sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
  local aptlog="$CACHE/apt.log"
  { $sudo apt-get update -qq &&
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
  } >"$aptlog" 2>&1 || { tail -n 20 "$aptlog" >&2; log "apt-get failed (log: $aptlog)"; exit 1; }
}

build() {
  local mirror src
  mirror=$(debian_mirror)
  [ -n "$mirror" ] || { log "no Debian mirror found in the apt sources"; exit 1; }
  mkdir -p "$CACHE"
  src="$CACHE/$TARBALL"
  if [ ! -f "$src" ] || ! echo "$SHA256  $src" | sha256sum -c --status; then
    log "downloading $TARBALL from the apt mirror"
    curl -fsSL --retry 3 -o "$src.part" "$mirror/pool/main/s/swi-prolog/$TARBALL"
    mv "$src.part" "$src"
  fi
  echo "$SHA256  $src" | sha256sum -c --status || { log "sha256 mismatch for $src"; rm -f "$src"; exit 1; }
  install_build_deps
  work=$(mktemp -d "$CACHE/build.XXXXXX")   # global: the EXIT trap needs it
  trap 'rm -rf "$work"' EXIT
  tar -xzf "$src" -C "$work"
  local top; top=$(find "$work" -mindepth 1 -maxdepth 1 -type d | head -n 1)
  log "building SWI-Prolog $VERSION into $PREFIX (about 2 minutes on 2 cores)"
  cmake -S "$top" -B "$work/build" -G Ninja \
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$PREFIX" \
    -DSWIPL_PACKAGES_X=OFF -DSWIPL_PACKAGES_JAVA=OFF -DSWIPL_PACKAGES_ODBC=OFF \
    -DSWIPL_PACKAGES_QT=OFF -DSWIPL_PACKAGES_BDB=OFF -DBUILD_TESTING=OFF \
    -DINSTALL_DOCUMENTATION=OFF >"$work/cmake.log" 2>&1 \
    || { tail -n 40 "$work/cmake.log" >&2; exit 1; }
  ninja -C "$work/build" >"$work/ninja.log" 2>&1 || { tail -n 40 "$work/ninja.log" >&2; exit 1; }
  rm -rf "$PREFIX"
  ninja -C "$work/build" install >"$work/install.log" 2>&1 || { tail -n 40 "$work/install.log" >&2; exit 1; }
  touch "$PREFIX/.complete"
}

main() {
  local cand
  for cand in "${GAPS_SWIPL:-}" "$(command -v swipl || true)"; do
    if [ -n "$cand" ] && usable "$cand"; then echo "$cand"; return 0; fi
  done
  if [ -f "$PREFIX/.complete" ] && usable "$PREFIX/bin/swipl"; then echo "$PREFIX/bin/swipl"; return 0; fi
  mkdir -p "$CACHE"
  exec 9>"$CACHE/swipl.lock"
  flock 9   # another clone may be building the same prefix right now
  if ! { [ -f "$PREFIX/.complete" ] && usable "$PREFIX/bin/swipl"; }; then build; fi
  usable "$PREFIX/bin/swipl" || { log "built SWI-Prolog is not usable"; exit 1; }
  echo "$PREFIX/bin/swipl"
}

main "$@"
