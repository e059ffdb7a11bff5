#!/usr/bin/env bash
# `skillcell device world` on a bad scene: a fuse slot's hidden misalignment that is not three
# numbers, or names no --fuse-slot, and a fuse slot without a pose, are each refused at start
# with a message naming the option and what was expected, and exit 1, before the server
# listens.
# Usage: device_world_scene_cli.sh PATH/TO/skillcell
set -euo pipefail
skillcell=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
refused() {
  local expected=$1
  shift
  local rc=0
  timeout 20 "$skillcell" device world --port 0 --host 127.0.0.1 --no-discovery --insecure \
    --pki-dir "$tmp/pki" "$@" >"$tmp/out" 2>&1 || rc=$?
  if [ "$rc" != 1 ] || ! grep -qF -- "$expected" "$tmp/out" || grep -q '^READY' "$tmp/out"; then
    echo "FAILED: $* exited $rc; expected exit 1 and: $expected" >&2
    cat "$tmp/out" >&2
    exit 1
  fi
  echo "ok  $*: $expected"
}
slot=(--fuse-slot 'F1@0.45,0.25,0.06')
refused '--misaligned-slot F9: no --fuse-slot F9' "${slot[@]}" --misaligned-slot 'F9:0.001,0,0'
refused '--misaligned-slot F1:0.001,0: expected ID:DX,DY,DZ' "${slot[@]}" \
  --misaligned-slot 'F1:0.001,0'
refused '--misaligned-slot F1: expected ID:DX,DY,DZ' "${slot[@]}" --misaligned-slot 'F1'
refused '--fuse-slot F2: expected ID@X,Y,Z[,A,B,C]' --fuse-slot 'F2'
