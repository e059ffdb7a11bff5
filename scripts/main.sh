#!/usr/bin/env bash
# The main job, until the demo of a whole work cell exists: installs what is missing, builds,
# and shows Plug & Produce discovery and the OPC UA stack at work on one machine:
#   a Local Discovery Server (LDS-ME) and a demo server find each other by mDNS, the server
#   registers with the LDS, our `discover` lists both, our client browses the server,
#   node-opcua's client browses, reads, writes and calls on it, a skill of the server runs
#   (our SkillClient, then node-opcua finding it through the type hierarchy), and when the
#   server stops its goodbye removes it from the LDS.
# mDNS stays inside a private network namespace (multicast on loopback only), so nothing is
# sent to the machine's real network; that needs root. Without it, the job runs without
# discovery.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset default >/dev/null
cmake --build --preset default -j "$(nproc)" --target skillcell

if [ "${SKILLCELL_MAIN_IN_NETNS:-0}" != 1 ] && unshare -n true 2>/dev/null; then
  exec env SKILLCELL_MAIN_IN_NETNS=1 tests/netns/run_in_private_netns.sh bash "$0" "$@"
fi

skillcell=build/src/apps/skillcell
tmp=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$tmp"
}
trap cleanup EXIT

# Starts a component, waits (bounded) for its READY line; sets $url and appends its pid.
start() {
  local name=$1; shift
  mkfifo "$tmp/$name.ready"
  "$skillcell" "$@" --pki-dir "$tmp/pki-$name" --insecure >"$tmp/$name.ready" 2>"$tmp/$name.log" &
  pids+=($!)
  exec {fd}<"$tmp/$name.ready"
  local word
  if ! read -r -t 20 word url <&"$fd" || [ "$word" != READY ]; then
    echo "$name did not start:" >&2; cat "$tmp/$name.log" >&2; exit 1
  fi
}

# Skills that do nothing, successfully, for 200 ms: stand-ins until the device adapters exist.
skill_args=(--noop-skill CartesianLinearMoveSkillType=Move --noop-skill GraspGripperSkillType=Grasp
            --noop-skill-ms 200)

if [ "${SKILLCELL_MAIN_IN_NETNS:-0}" = 1 ]; then
  start lds lds --port 4840 --mdns-ttl 5 --mdns-query-period 1
  lds_url=$url
  start server server --port 4841 --mdns-ttl 5 --mdns-query-period 1 --mdns-name demo-server \
    "${skill_args[@]}"
  server_url=$url
  echo "== mDNS: the servers on the network (skillcell discover)"
  "$skillcell" discover --duration 1
  echo
  echo "== the LDS at $lds_url: FindServersOnNetwork, then the registered servers (FindServers)"
  for i in $(seq 1 50); do  # the server registers as soon as it has seen the LDS: wait for it
    "$skillcell" discover --lds "$lds_url" --registered | grep -q urn:skillcell:server && break
    sleep 0.1
  done
  "$skillcell" discover --lds "$lds_url"
  "$skillcell" discover --lds "$lds_url" --registered
else
  echo "(no network namespace: running without discovery; run as root to see it)"
  start server server --port 4841 --host 127.0.0.1 --no-discovery "${skill_args[@]}"
  server_url=$url
fi

echo
echo "== our client browses $server_url"
"$skillcell" browse "$server_url" --values --max-depth 4
echo
echo "== node-opcua's client against our server"
node tests/interop/client.js "$server_url"
echo
echo "== a skill runs: our SkillClient writes MaxVelocity, starts Move, follows its events"
"$skillcell" skill "$server_url" Move --set MaxVelocity=0.5 --timeout 10
echo
echo "== node-opcua finds the skill through the type hierarchy, runs it, reads its state"
node tests/interop/skill.js "$server_url" Move

if [ "${SKILLCELL_MAIN_IN_NETNS:-0}" = 1 ]; then
  echo
  echo "== the server stops: its goodbye and unregistration remove it from the LDS"
  kill "${pids[1]}"
  wait "${pids[1]}" 2>/dev/null || true
  "$skillcell" discover --lds "$lds_url"
  "$skillcell" discover --lds "$lds_url" --registered
fi
