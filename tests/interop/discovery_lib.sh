# shellcheck shell=bash disable=SC2016,SC2034
# (SC2016: sed/awk programs are single-quoted on purpose; SC2034: DL_* variables are for the caller)
# Helpers for the discovery interop drivers (node_lds_sees_skillcell_server.sh,
# skillcell_lds_accepts_node_server.sh). Source it from a bash script running under set -euo pipefail.
#
#   dl_init SCRIPT ARGS...     skips (exit 77) without node/node-opcua (unless
#                              SKILLCELL_REQUIRE_NODE=1), then re-executes SCRIPT inside a private
#                              network namespace (tests/netns/run_in_private_netns.sh: loopback
#                              only, multicast on) unless already there; checks that no interface
#                              but lo exists; creates $DL_TMP and installs the cleanup trap.
#   dl_init_skillcell SCRIPT ARGS...  dl_init, then the one argument the drivers take: the
#                              skillcell binary, into $skillcell (usage error: exit 2).
#   dl_start NAME CMD...       starts CMD in the background; stdout -> $DL_TMP/NAME.out,
#                              stderr -> $DL_TMP/NAME.err.
#   dl_wait_ready NAME TIMEOUT_S   waits (bounded) for a "READY <url>" stdout line of NAME and
#                              sets DL_URL to <url> and DL_PORT to its port; fails (dl_fail) on a
#                              "FAILED" line, when NAME exits, or at the deadline.
#   dl_stop NAME TIMEOUT_S     SIGTERM, waits (bounded) for the exit, SIGKILL at the deadline;
#                              sets DL_RC to its exit status (or "killed"). Returns 1 if killed.
#   dl_node SCRIPT ARGS...     runs a node script of this folder (bounded by `timeout`), its stderr
#                              to $DL_TMP/node-scripts.err; prints its stdout; returns its status.
#   dl_poll TIMEOUT_S PRESENT|ABSENT REGEX CMD...
#                              runs CMD (each run bounded to 15 s) every 0.5 s until its stdout has
#                              (PRESENT) or has no (ABSENT) line matching the extended REGEX; prints
#                              the matching line (PRESENT); at the deadline prints the last output
#                              to stderr and returns 1.
#   dl_fail MSG                prints MSG and the logs of every process, exits 1.
#   dl_step MSG                progress line on stderr.
#   dl_re STRING               STRING with the extended-regex metacharacters escaped.

DL_HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source=SCRIPTDIR/interop_lib.sh
source "$DL_HERE/interop_lib.sh"
DL_NETNS_WRAPPER="$DL_HERE/../netns/run_in_private_netns.sh"
DL_TMP=""
DL_NAMES=()
declare -A DL_PIDS=()
DL_RC=""
DL_URL=""
DL_PORT=""
DL_DUMPED=0

dl_step() { echo "[$(date +%T.%3N)] $*" >&2; }

dl_re() { printf '%s' "$1" | sed -e 's/[][\.*^$(){}?+|/\\]/\\&/g'; }

dl_init() {
  local script=$1
  shift
  # DL_NEEDS_NODE=0: a driver of skillcell processes only (tests/netns/secure_cell.sh)
  if [ "${DL_NEEDS_NODE:-1}" = 1 ]; then interop_require_node; fi
  if [ "${SKILLCELL_INTEROP_IN_NETNS:-0}" != 1 ]; then
    export SKILLCELL_INTEROP_IN_NETNS=1
    exec "$DL_NETNS_WRAPPER" bash "$script" "$@" # exits 77 when no namespace can be made
  fi
  # mDNS must never reach a real network: only lo may exist here
  local others
  others=$(ip -o link show | awk -F': ' '$2 != "lo" {print $2}')
  if [ -n "$others" ]; then
    echo "refusing to run: interfaces other than lo present: $others" >&2
    exit 1
  fi
  DL_TMP=$(mktemp -d "${TMPDIR:-/tmp}/skillcell-discovery-interop.XXXXXX")
  trap dl_cleanup EXIT
  trap 'exit 143' TERM
  trap 'exit 130' INT
}

dl_init_skillcell() {
  local script=$1
  dl_init "$@"
  shift
  [ $# -eq 1 ] || { echo "usage: $script PATH/TO/skillcell" >&2; exit 2; }
  skillcell=$1
}

dl_start() {
  local name=$1
  shift
  "$@" >"$DL_TMP/$name.out" 2>"$DL_TMP/$name.err" &
  DL_PIDS[$name]=$!
  DL_NAMES+=("$name")
  dl_step "started $name (pid ${DL_PIDS[$name]}): $*"
}

dl_running() {
  local pid=${DL_PIDS[$1]:-}
  [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null
}

dl_wait_ready() {
  local name=$1 timeout_s=$2 deadline line
  deadline=$((SECONDS + timeout_s))
  while :; do
    line=$(grep -m1 -E '^(READY|FAILED)( |$)' "$DL_TMP/$name.out" || true)
    case "$line" in
      READY\ *)
        dl_step "$name: $line"
        DL_URL=$(echo "${line#READY }" | awk '{print $1}')
        DL_PORT=$(echo "$DL_URL" | sed -E 's|^opc\.tcp://[^/]*:([0-9]+).*$|\1|')
        return 0
        ;;
      FAILED*) dl_fail "$name did not become ready: $line" ;;
    esac
    dl_running "$name" || dl_fail "$name exited before printing READY"
    [ $SECONDS -lt $deadline ] || dl_fail "$name printed no READY line within $timeout_s s"
    sleep 0.2
  done
}

dl_stop() {
  local name=$1 timeout_s=$2 pid deadline
  pid=${DL_PIDS[$name]:-}
  DL_RC=""
  [ -n "$pid" ] || return 0
  unset "DL_PIDS[$name]"
  if kill -0 "$pid" 2>/dev/null; then
    kill -TERM "$pid" 2>/dev/null || true
    deadline=$((SECONDS + timeout_s))
    while kill -0 "$pid" 2>/dev/null && [ $SECONDS -lt $deadline ]; do sleep 0.1; done
    if kill -0 "$pid" 2>/dev/null; then
      kill -KILL "$pid" 2>/dev/null || true
      wait "$pid" 2>/dev/null || true
      DL_RC=killed
      dl_step "$name did not exit within $timeout_s s after SIGTERM: killed"
      return 1
    fi
  fi
  DL_RC=0
  wait "$pid" 2>/dev/null || DL_RC=$?
  dl_step "$name exited with status $DL_RC"
  return 0
}

dl_node() {
  local script=$1
  shift
  echo "--- node $script $*" >>"$DL_TMP/node-scripts.err"
  timeout 120 node "$DL_HERE/$script" "$@" 2>>"$DL_TMP/node-scripts.err"
}

dl_poll() {
  local timeout_s=$1 mode=$2 regex=$3 deadline out match
  shift 3
  deadline=$((SECONDS + timeout_s))
  while :; do
    out=$(timeout 15 "$@" 2>>"$DL_TMP/poll.err" || true)
    match=$(printf '%s\n' "$out" | grep -m1 -E -- "$regex" || true)
    if [ "$mode" = PRESENT ] && [ -n "$match" ]; then
      printf '%s\n' "$match"
      return 0
    fi
    if [ "$mode" = ABSENT ] && [ -z "$match" ]; then return 0; fi
    if [ $SECONDS -ge $deadline ]; then
      {
        echo "dl_poll: after $timeout_s s, $* still has $([ "$mode" = PRESENT ] && echo no)" \
          "line matching '$regex'; last output:"
        printf '%s\n' "$out"
        echo "(stderr of the last runs:)"
        tail -n 20 "$DL_TMP/poll.err"
      } >&2
      return 1
    fi
    sleep 0.5
  done
}

dl_dump_logs() {
  local name f
  for name in "${DL_NAMES[@]}"; do
    for f in "$DL_TMP/$name.out" "$DL_TMP/$name.err"; do
      [ -s "$f" ] || continue
      echo "----- $(basename "$f") (last 60 lines; node-opcua's timestamped traces left out) -----"
      grep -v -E '^[0-9]{2}:[0-9]{2}:[0-9]{2}\.[0-9]{3}Z :' "$f" | tail -n 60 || true
    done
  done
  f="$DL_TMP/node-scripts.err"
  if [ -s "$f" ]; then
    echo "----- $(basename "$f") (last 80 lines) -----"
    grep -v -E '^[0-9]{2}:[0-9]{2}:[0-9]{2}\.[0-9]{3}Z :' "$f" | tail -n 80 || true
  fi
}

dl_fail() {
  echo "FAILED: $*" >&2
  DL_DUMPED=1
  dl_dump_logs >&2 || true
  exit 1
}

dl_cleanup() {
  local status=$? name
  trap - EXIT
  # stop the processes still running, newest first
  local i
  for ((i = ${#DL_NAMES[@]} - 1; i >= 0; i--)); do
    name=${DL_NAMES[$i]}
    if [ -n "${DL_PIDS[$name]:-}" ]; then dl_stop "$name" 10 >/dev/null 2>&1 || true; fi
  done
  if [ $status -ne 0 ] && [ "${DL_DUMPED:-0}" != 1 ] && [ -n "$DL_TMP" ]; then
    echo "exit status $status; logs:" >&2
    dl_dump_logs >&2 || true
  fi
  if [ -n "$DL_TMP" ]; then
    if [ "${SKILLCELL_INTEROP_KEEP_LOGS:-0}" = 1 ]; then
      echo "logs kept in $DL_TMP" >&2
    else
      rm -rf "$DL_TMP"
    fi
  fi
  exit $status
}
