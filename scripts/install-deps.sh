#!/usr/bin/env bash
# Installs what skillcell needs on a fresh Debian 12 machine; safe to run again: it installs
# only what is missing.
#
#   scripts/install-deps.sh          everything: the main job's packages and the tests' (CI)
#   scripts/install-deps.sh --main   only what building and running `skillcell demo` needs
#
# The tests add: clang and its sanitizer runtime (the ASan + UBSan build, the fuzz targets),
# clang-format and clang-tidy (lint), stress-ng (the suite under load), Node.js with the
# pinned node-opcua interop peer (tests/interop/package.json), python3 (the netns harness,
# fuzz seeds), Avahi (mDNS interop, run only inside a test's network namespace), and
# Chromium with playwright-core (the dashboard's browser tests, tests/browser).
set -euo pipefail
cd "$(dirname "$0")/.."

scope=all
case "${1:-}" in
  --main) scope=main ;;
  "") ;;
  *) echo "usage: $0 [--main]" >&2; exit 2 ;;
esac

packages=(
  build-essential cmake ninja-build ccache lld  # lld: links in a fifth of GNU ld's time
  libasio-dev libspdlog-dev libfmt-dev libcli11-dev libpugixml-dev libmdnsd-dev libssl-dev
  libgtest-dev libgmock-dev  # CMake configures the tests' targets even when it builds one
  liborocos-kdl-dev libeigen3-dev libmodbus-dev pkg-config
  libtomlplusplus-dev  # cell files (src/cell)
  libcpp-httplib-dev  # HTTP(S): the knowledge base's SPARQL endpoint and its clients (src/http)
  nlohmann-json3-dev  # `cell up`'s control socket (src/apps/cell_supervisor)
  iproute2 util-linux procps
  # the knowledge base: Turtle (libserd), the triple store (Virtuoso), the reasoner (Konclude);
  # the MES's journal (SQLite; the sqlite3 shell to look into it)
  libserd-dev virtuoso-opensource konclude libsqlite3-dev sqlite3
)
if [ "$scope" = all ]; then
  packages+=(clang clang-format clang-tidy libclang-rt-14-dev stress-ng)
  # mDNS interop (tests/netns/avahi_interop.sh): Avahi runs only inside the test's namespace
  packages+=(avahi-daemon avahi-utils dbus)
  # the dashboard's browser tests (tests/browser): Debian's Chromium, and openssl for the pin
  # of the dashboard's key
  packages+=(chromium openssl)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "$scope" = all ]; then
  # Node.js may come from Debian or elsewhere (NodeSource ships npm inside nodejs): check the
  # commands, not the package names.
  command -v node >/dev/null || missing+=(nodejs)
  command -v npm >/dev/null || missing+=(npm)
  command -v python3 >/dev/null || missing+=(python3)
fi
if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get update -q
  # No package may start its service here (avahi-daemon would speak mDNS on the machine's own
  # network): a policy-rc.d that refuses, for the time of the install, unless one exists.
  policy=""
  if [ ! -e /usr/sbin/policy-rc.d ]; then
    policy=/usr/sbin/policy-rc.d
    printf '#!/bin/sh\nexit 101\n' | $SUDO tee "$policy" >/dev/null
    $SUDO chmod 755 "$policy"
  fi
  rc=0
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends \
    "${missing[@]}" || rc=$?
  [ -z "$policy" ] || $SUDO rm -f "$policy"
  [ "$rc" = 0 ] || exit "$rc"
fi

if [ "$scope" = all ] && [ ! -d tests/browser/node_modules/playwright-core ]; then
  echo "install-deps: installing playwright-core for the browser tests (tests/browser/package-lock.json)"
  (cd tests/browser && npm ci --no-audit --no-fund --loglevel=error)
fi
if [ "$scope" = all ] && [ ! -d tests/interop/node_modules/node-opcua ]; then
  echo "install-deps: installing the node-opcua interop peer (pinned in tests/interop/package-lock.json)"
  (cd tests/interop && npm ci --no-audit --no-fund --loglevel=error)
fi
