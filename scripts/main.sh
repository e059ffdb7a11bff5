#!/usr/bin/env bash
# The main job, until `skillcell demo` exists: installs what is missing, builds, and runs the
# paper's work cell with security on (a cell CA issues every certificate, users with roles,
# no --insecure anywhere), every component a process that finds the others by mDNS:
#   a Local Discovery Server, the knowledge base (Virtuoso + Konclude, with the demo
#   process), the world model, the UR5, the Kelvin tool changer (which powers the Robotiq
#   2F-85 and Schmalz ECBPi adapters as it attaches them), the pick-and-place composite and
#   the semantic MES. An operator hands the MES the demo process (`skillcell run`); the MES
#   reads it from the knowledge base, runs each step on the skills discovery found, and
#   journals them. Then: the world model's boxes where the process put them, the journal,
#   and an observer and an unsecured client refused.
# mDNS stays inside a private network namespace (multicast on loopback only), so nothing is
# sent to the machine's real network; that needs root.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset default >/dev/null
cmake --build --preset default -j "$(nproc)" --target skillcell

if [ "${SKILLCELL_MAIN_IN_NETNS:-0}" != 1 ]; then
  if ! unshare -n true 2>/dev/null; then
    echo "the work cell needs a private network namespace for its mDNS: run as root" >&2
    exit 1
  fi
  exec env SKILLCELL_MAIN_IN_NETNS=1 tests/netns/run_in_private_netns.sh bash "$0" "$@"
fi

skillcell=$PWD/build/src/apps/skillcell
tmp=$(mktemp -d)
pids=()
cleanup() {
  # The tool changer powers its tools off when it stops: stop it before the rest.
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

# What every component takes: loopback, quick mDNS, its PKI, the users, and whom it acts as.
component() {
  local name=$1
  echo --port 0 --host 127.0.0.1 --mdns-ttl 5 --mdns-query-period 1 --pki-dir "$tmp/pki-$name" \
    --users "$tmp/users"
}
acts_as_cell=(--client-user cell --client-password-file "$tmp/cell.pw")

# Starts a component and waits (bounded) for its READY line (interop_start); prints its URL.
# shellcheck source=SCRIPTDIR/../tests/interop/interop_lib.sh
source tests/interop/interop_lib.sh
start() {
  local name=$1 timeout=$2
  shift 2
  interop_start "$name" "$timeout" "$skillcell" "$@"
  pids+=("$last_pid")
  printf '  %-12s %s\n' "$name" "$url"
}

echo "== the cell starts (each component a process; they find each other by mDNS)"
# shellcheck disable=SC2046 # component's words are separate arguments on purpose
start lds 20 lds $(component lds)
# shellcheck disable=SC2046
start kb 180 kb --demo-process --http-port 0 --data-dir "$tmp/kb" $(component kb) "${acts_as_cell[@]}"
sparql=$(sed -n 's/^SPARQL //p' "$tmp/kb.before")
echo "               SPARQL $sparql"
# shellcheck disable=SC2046
start world 20 device world $(component world) \
  --dock 'dockP@0.3,-0.45,0.35,3.141592653589793,0,0' \
  --dock 'dockV@0.45,-0.3,0.35,3.141592653589793,0,0' \
  --tool 'parallel:dockP@0,0,0.15' --tool 'vacuum:dockV@0,0,0.12' \
  --object 'boxA:0.04,0.1,0.05@0.45,0.15,0.025' --object 'boxB:0.04,0.04,0.04@0.45,-0.05,0.02'
world=$url
tool() {  # the adapter process the changer starts when it powers a tool
  echo "$skillcell device $1 --world $world $(component "$1") --client-user cell" \
    "--client-password-file $tmp/cell.pw --speed 20 $2"
}
# shellcheck disable=SC2046
start toolchanger 20 device toolchanger $(component toolchanger) "${acts_as_cell[@]}" \
  --world "$world" --detection-timeout-ms 20000 \
  --tool parallel:1.0-1.5:urn:skillcell:device:robotiq-2f85 \
  --tool vacuum:2.0-2.5:urn:skillcell:device:schmalz-ecbpi \
  --power "parallel=$(tool robotiq '--grip-offset 0,0,0.15')" \
  --power "vacuum=$(tool schmalz '')"
# shellcheck disable=SC2046
start pickplace 20 device pickplace $(component pickplace) "${acts_as_cell[@]}" --world "$world" \
  --detection-timeout-ms 20000
# shellcheck disable=SC2046
start ur5 20 device ur5 $(component ur5) "${acts_as_cell[@]}" --world "$world" --speed 50
# shellcheck disable=SC2046
start mes 20 mes $(component mes) "${acts_as_cell[@]}" --kb "$sparql" \
  --journal "$tmp/journal.sqlite"
mes=$url

echo
echo "== the operator hands the MES the paper's process (skillcell run)"
"$skillcell" run http://skillcell.dev/demo#pickAndPlaceTwoBoxes --mes "$mes" "${operator[@]}"

echo
echo "== the world model afterwards: the boxes where the process put them, no tool mounted"
"$skillcell" browse "$world" --values "${observer[@]}" | grep -E 'World/(Objects/box[AB]/Pose|MountedTool)'
echo
echo "== the MES's journal"
sqlite3 -header -column "$tmp/journal.sqlite" \
  "SELECT idx AS step, attempt, state, substr(skill_type, instr(skill_type, 'Skills/') + 7) AS skill_type, component, ended_ms - started_ms AS ms FROM steps ORDER BY idx, attempt"

echo
echo "== security: an observer may look but not start a process; a client without security is refused"
"$skillcell" run http://skillcell.dev/demo#pickAndPlaceTwoBoxes --mes "$mes" "${observer[@]}" 2>&1 |
  grep -m1 -E 'OUTCOME|refused|Bad' || true
"$skillcell" run http://skillcell.dev/demo#pickAndPlaceTwoBoxes --mes "$mes" --insecure 2>&1 |
  grep -m1 'cannot connect' || true
