#!/usr/bin/env bash
# The main job, until the demo of a whole work cell exists: installs what is missing, builds,
# and shows Plug & Produce discovery and the OPC UA stack at work on one machine, with
# security on as in a real cell (a cell CA, users with roles, no --insecure anywhere):
#   a Local Discovery Server (LDS-ME) and a demo server find each other by mDNS, the server
#   registers with the LDS over a secured channel, our `discover` lists both, our client
#   browses the server, node-opcua's client browses, reads, writes and calls on it over
#   Aes256_Sha256_RsaPss/SignAndEncrypt as an operator, a skill of the server runs (our
#   SkillClient, then node-opcua finding it through the type hierarchy), an observer and an
#   unsecured client are refused, and when the server stops its goodbye removes it from the
#   LDS.
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

# The cell's security: a CA that issues every component's certificate (so they trust each
# other), and one user database: an operator, an observer, and "cell", the user the
# components act as when they connect to each other.
export SKILLCELL_CA_DIR=$tmp/ca
"$skillcell" pki init-ca --dir "$SKILLCELL_CA_DIR" >/dev/null
printf 'operator-pw\n' >"$tmp/operator.pw"
printf 'observer-pw\n' >"$tmp/observer.pw"
printf 'cell-pw\n' >"$tmp/cell.pw"
"$skillcell" user add operator --role Operator --users "$tmp/users" <"$tmp/operator.pw" >/dev/null
"$skillcell" user add observer --role Observer --users "$tmp/users" <"$tmp/observer.pw" >/dev/null
"$skillcell" user add cell --role Operator --users "$tmp/users" <"$tmp/cell.pw" >/dev/null
operator=(--pki-dir "$tmp/pki-cli" --user operator --password-file "$tmp/operator.pw")
observer=(--pki-dir "$tmp/pki-cli" --user observer --password-file "$tmp/observer.pw")
# node-opcua's client gets its certificate from the cell CA too.
"$skillcell" pki issue --ca "$SKILLCELL_CA_DIR" --uri urn:skillcell:interop:node-opcua-client \
  --pki-dir "$tmp/pki-node" >/dev/null
export SKILLCELL_NODE_SECURITY=SignAndEncrypt SKILLCELL_NODE_USER=operator:operator-pw
export SKILLCELL_NODE_CERTIFICATE=$tmp/pki-node/own/certs/cert.der
export SKILLCELL_NODE_PRIVATE_KEY=$tmp/pki-node/own/private/key.pem
export SKILLCELL_NODE_PKI=$tmp/pki-node  # it trusts the cell CA

# Starts a component, waits (bounded) for its READY line; sets $url and appends its pid.
start() {
  local name=$1; shift
  mkfifo "$tmp/$name.ready"
  "$skillcell" "$@" --pki-dir "$tmp/pki-$name" --users "$tmp/users" --client-user cell \
    --client-password-file "$tmp/cell.pw" >"$tmp/$name.ready" 2>"$tmp/$name.log" &
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
"$skillcell" browse "$server_url" --values --max-depth 4 "${observer[@]}"
echo
echo "== node-opcua's client against our server (Aes256_Sha256_RsaPss, SignAndEncrypt, operator)"
node tests/interop/client.js "$server_url"
echo
echo "== a skill runs: our SkillClient writes MaxVelocity, starts Move, follows its events"
"$skillcell" skill "$server_url" Move --set MaxVelocity=0.5 --timeout 10 "${operator[@]}"
echo
echo "== node-opcua finds the skill through the type hierarchy, runs it, reads its state"
node tests/interop/skill.js "$server_url" Move
echo
echo "== security: an observer may look but not start a skill; a client without security is refused"
"$skillcell" skill "$server_url" Move --timeout 10 "${observer[@]}" 2>&1 | grep -m1 -E 'OUTCOME|refused|Bad' || true
"$skillcell" skill "$server_url" Move --timeout 10 --insecure 2>&1 | grep -m1 'cannot connect' || true

if [ "${SKILLCELL_MAIN_IN_NETNS:-0}" = 1 ]; then
  echo
  echo "== the server stops: its goodbye and unregistration remove it from the LDS"
  kill "${pids[1]}"
  wait "${pids[1]}" 2>/dev/null || true
  "$skillcell" discover --lds "$lds_url"
  "$skillcell" discover --lds "$lds_url" --registered
fi
