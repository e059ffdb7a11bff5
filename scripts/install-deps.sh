#!/usr/bin/env bash
# Installs what building and testing skillcell needs on a fresh Debian 12 machine:
# the Debian packages, and the pinned node-opcua interop peer (tests/interop/package.json).
# Safe to run again: it installs only what is missing.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake ninja-build ccache clang clang-format clang-tidy libclang-rt-14-dev
  libasio-dev libspdlog-dev libfmt-dev libcli11-dev libpugixml-dev libmdnsd-dev libssl-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  liborocos-kdl-dev libeigen3-dev libmodbus-dev pkg-config
  iproute2 util-linux procps
  # the knowledge base: Turtle (libserd), the triple store (Virtuoso), the reasoner (Konclude);
  # the MES's journal (SQLite; the sqlite3 shell to look into it)
  libserd-dev virtuoso-opensource konclude libsqlite3-dev sqlite3
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Node.js may come from Debian or elsewhere (NodeSource ships npm inside nodejs): check the
# commands, not the package names.
command -v node >/dev/null || missing+=(nodejs)
command -v npm >/dev/null || missing+=(npm)
command -v python3 >/dev/null || missing+=(python3)  # the netns test harness and fuzz seeds
if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get update -q
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

if [ ! -d tests/interop/node_modules/node-opcua ]; then
  echo "install-deps: installing the node-opcua interop peer (pinned in tests/interop/package-lock.json)"
  (cd tests/interop && npm ci --no-audit --no-fund --loglevel=error)
fi
