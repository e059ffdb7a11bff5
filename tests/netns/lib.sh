# shellcheck shell=bash disable=SC2016,SC2034
# (SC2016: the sh -c scripts are single-quoted on purpose; SC2034: variables for the caller)
# Small library for multi-host tests in network namespaces. Source it from a bash script.
#
#   netns_setup N              hosts h1..hN: one namespace each with lo and eth0 (198.18.0.K/24,
#                              multicast on, route 224.0.0.0/4 dev eth0, no default route), every
#                              eth0 a veth whose peer is a port of bridge br0 in a namespace of its
#                              own. Nothing is created in, or routed to, the caller's namespace.
#                              Returns 77 if no namespace can be created (not root?), 1 on other
#                              errors. netns_setup_or_skip N turns 77 into the usual SKIPPED exit.
#   netns_exec HOST CMD...     runs CMD in HOST's namespace, with a UTS namespace of its own whose
#                              hostname is HOST (the hosts would otherwise share one hostname).
#   start_in HOST NAME CMD...  starts CMD in the background there; stdout/stderr go to
#                              $NETNS_DIR/NAME.out and NAME.err; the pid is remembered under NAME.
#   proc_pid NAME, proc_signal NAME SIG, proc_running NAME,
#   proc_wait_exit NAME TIMEOUT_S   waits (bounded) for NAME to exit; sets PROC_RC to its status;
#                              returns 1 if it is still running at the deadline.
#   wait_for_line FILE REGEX TIMEOUT_S [FROM_LINE]   polls FILE (from line FROM_LINE on, 1-based)
#                              for a line matching the extended REGEX; prints the first match and
#                              returns 0, or returns 1 at the deadline.
#   wait_for_line_until FILE REGEX DEADLINE_MS [FROM_LINE]   same with an absolute deadline (now_ms).
#   line_count FILE            number of lines in FILE so far (to wait for lines after it).
#   sanitizer_report NAME      prints the head of the sanitizer report in NAME.err, if any (for
#                              a failure message: a CI log keeps its beginning, not every tail).
#   stop_gracefully NAME       SIGTERM; NAME must exit within 5 s, with status 0.
#   check_sanitizers           no process's stderr holds a sanitizer report.
#                              Both fail through the caller's `fail` if it has one, else
#                              netns_fail.
#   now_ms                     milliseconds since the epoch.
#   netns_fail MESSAGE         prints FAIL: MESSAGE and the last lines of every process's output
#                              in $NETNS_DIR, then exits 1 (the trap cleans up).
#   link_down HOST, link_up HOST   take HOST's side of its veth down or up (link_up restores the
#                              multicast route that going down removed).
#   netns_cleanup              kills every process started here and every process still inside
#                              the namespaces, deletes the veths, the bridge and the namespaces.
#                              Idempotent; netns_trap installs it on EXIT, INT and TERM.
#   For when no trap can run (SIGKILL, e.g. a ctest timeout): netns_setup starts a watchdog (in
#   a session of its own) that does the same once this shell is gone, and first removes what
#   earlier killed runs left behind (netns_reap_stale: sc<pid>... namespaces whose pid is gone).
#
# Names carry the caller's pid ($$), so that concurrent runs (ctest -j) do not collide. Addresses
# come only from 198.18.0.0/15 (RFC 2544 benchmarking range).

NETNS_ID="sc$$"
NETNS_BR="${NETNS_ID}br"
NETNS_DIR=""
NETNS_HOSTS=()
NETNS_CREATED=()
declare -A NETNS_PIDS=()
NETNS_CLEANED=0
PROC_RC=""

now_ms() {
  local t=${EPOCHREALTIME//[.,]/}
  echo $((t / 1000))
}

# seconds (possibly fractional, e.g. 2.5) -> milliseconds
_netns_ms() {
  local s=$1 int frac
  int=${s%%.*}
  if [[ $s == *.* ]]; then frac=${s#*.}000; frac=${frac:0:3}; else frac=000; fi
  echo $((10#${int:-0} * 1000 + 10#$frac))
}

_netns_ns() { echo "${NETNS_ID}$1"; }

netns_log() { echo "[netns $(date +%T.%3N)] $*" >&2; }

netns_fail() {
  echo "FAIL: $*"
  local f
  for f in "$NETNS_DIR"/*.out "$NETNS_DIR"/*.err; do
    [ -s "$f" ] && { echo "----- $(basename "$f")"; tail -n 20 "$f"; }
  done
  exit 1
}

# Namespaces of earlier runs that were killed so that neither their trap nor their watchdog could
# clean up: names of this scheme (sc<pid>br, sc<pid>h<k>) whose pid is gone. Kills what still
# runs inside and deletes them; also their log directories, unless kept (NETNS_KEEP_LOGS=1).
netns_reap_stale() {
  local ns pid
  for ns in $(ip netns list 2>/dev/null | awk '{print $1}'); do
    [[ $ns =~ ^sc([0-9]+)(br|h[0-9]+)$ ]] || continue
    pid=${BASH_REMATCH[1]}
    [ "$pid" = $$ ] && continue
    kill -0 "$pid" 2>/dev/null && continue
    netns_log "removing stale namespace $ns (its run, pid $pid, is gone)"
    ip netns pids "$ns" 2>/dev/null | xargs -r kill -9 2>/dev/null
    ip netns del "$ns" 2>/dev/null
  done
  local dir
  for dir in "${TMPDIR:-/tmp}"/skillcell-netns.sc*; do
    if ! [[ $dir =~ /skillcell-netns\.sc([0-9]+)\.[^/]*$ ]] || [ -e "$dir/.kept" ]; then continue; fi
    pid=${BASH_REMATCH[1]}
    [ "$pid" = $$ ] && continue
    kill -0 "$pid" 2>/dev/null || rm -rf "$dir"
  done
}

# A watchdog, orphaned (so that a kill of our process tree, as ctest does on a timeout, does not
# reach it) and in a session of its own: once this shell is gone without having cleaned up, it
# kills what still runs in our namespaces and deletes them. netns_cleanup stops it. Bounded: it
# gives up after 2 h. Silent, and holds none of our output pipes (ctest waits for them to close).
NETNS_WATCHDOG_PID=""
_netns_start_watchdog() {
  local n=$1 k names=("$NETNS_BR")
  for ((k = 1; k <= n; k++)); do names+=("$(_netns_ns "h$k")"); done
  # $( ... & ) returns once the watchdog has printed its pid and closed stdout; the subshell that
  # started it exits at once, so the watchdog is reparented away from us.
  NETNS_WATCHDOG_PID=$(
    setsid bash -c '
      echo $$
      exec >/dev/null 2>&1
      parent=$1 dir=$2 keep=$3
      shift 3
      end=$((SECONDS + 7200))
      while kill -0 "$parent" && [ "$SECONDS" -lt "$end" ]; do sleep 0.5; done
      for ns in "$@"; do ip netns pids "$ns" | xargs -r kill -9; done
      for ns in "$@"; do [ -e "/run/netns/$ns" ] && ip netns del "$ns"; done
      if [ "$keep" = 1 ]; then touch "$dir/.kept"; else rm -rf "$dir"; fi
    ' netns-watchdog "$$" "$NETNS_DIR" "${NETNS_KEEP_LOGS:-0}" "${names[@]}" </dev/null 2>/dev/null &
  )
}

netns_setup() {
  local n=$1 k ns
  netns_reap_stale
  if [ -e "/run/netns/$NETNS_BR" ] || [ -e "/var/run/netns/$NETNS_BR" ]; then
    netns_log "namespace $NETNS_BR exists already (left over from a killed run?)"
    return 1
  fi
  if ! ip netns add "$NETNS_BR" 2>/dev/null; then
    return 77
  fi
  NETNS_CREATED+=("$NETNS_BR")
  NETNS_DIR=$(mktemp -d "${TMPDIR:-/tmp}/skillcell-netns.${NETNS_ID}.XXXXXX") || return 1
  _netns_start_watchdog "$n"
  ip -n "$NETNS_BR" link add br0 type bridge stp_state 0 mcast_snooping 0 || return 1
  ip -n "$NETNS_BR" link set br0 up || return 1
  for ((k = 1; k <= n; k++)); do
    ns=$(_netns_ns "h$k")
    ip netns add "$ns" || return 1
    NETNS_CREATED+=("$ns")
    NETNS_HOSTS+=("h$k")
    ip -n "$NETNS_BR" link add "v$k" type veth peer name eth0 netns "$ns" || return 1
    ip -n "$NETNS_BR" link set "v$k" master br0 || return 1
    ip -n "$NETNS_BR" link set "v$k" up || return 1
    ip -n "$ns" link set lo up || return 1
    ip -n "$ns" addr add "198.18.0.$k/24" dev eth0 || return 1
    ip -n "$ns" link set eth0 multicast on up || return 1
    ip -n "$ns" route add 224.0.0.0/4 dev eth0 || return 1
  done
  return 0
}

netns_setup_or_skip() {
  local rc=0
  netns_setup "$1" || rc=$?
  if [ "$rc" = 77 ]; then
    echo "!!! SKIPPED: cannot create a network namespace (not root?) !!!" >&2
    [ "${SKILLCELL_REQUIRE_NETNS:-0}" = 1 ] && exit 1
    exit 77
  elif [ "$rc" != 0 ]; then
    echo "FAIL: could not set up the network namespaces" >&2
    exit 1
  fi
}

netns_exec() {
  local host=$1
  shift
  ip netns exec "$(_netns_ns "$host")" unshare --uts -- \
    sh -c 'echo "$0" > /proc/sys/kernel/hostname && exec "$@"' "$host" "$@"
}

start_in() {
  local host=$1 name=$2
  shift 2
  # A simple command (not the netns_exec function) so that bash forks and execs it directly and
  # ip, unshare and sh each exec the next: $! is then the pid of CMD itself, and signals reach it.
  ip netns exec "$(_netns_ns "$host")" unshare --uts -- \
    sh -c 'echo "$0" > /proc/sys/kernel/hostname && exec "$@"' "$host" "$@" \
    >"$NETNS_DIR/$name.out" 2>"$NETNS_DIR/$name.err" </dev/null &
  NETNS_PIDS[$name]=$!
}

proc_pid() { echo "${NETNS_PIDS[$1]:-}"; }

proc_signal() {
  local pid=${NETNS_PIDS[$1]:-}
  [ -n "$pid" ] && kill "-$2" "$pid" 2>/dev/null
}

# running = exists and is not a zombie (an exited child stays a zombie until waited for)
_pid_running() {
  local pid=$1 stat
  stat=$(cat "/proc/$pid/stat" 2>/dev/null) || return 1
  stat=${stat##*) }
  [ "${stat%% *}" != Z ]
}

proc_running() {
  local pid=${NETNS_PIDS[$1]:-}
  [ -n "$pid" ] && _pid_running "$pid"
}

proc_wait_exit() {
  local name=$1 deadline pid=${NETNS_PIDS[$1]:-}
  deadline=$(($(now_ms) + $(_netns_ms "$2")))
  PROC_RC=""
  [ -n "$pid" ] || return 1
  {
    while _pid_running "$pid"; do
      [ "$(now_ms)" -ge "$deadline" ] && return 1
      sleep 0.05
    done
    wait "$pid"
    PROC_RC=$?
  } 2>/dev/null # also silences bash's "Killed" job notice
  unset "NETNS_PIDS[$name]"
  return 0
}

sanitizer_report() {
  local f="$NETNS_DIR/$1.err"
  [ -f "$f" ] || return 0
  # The report's headlines and the frames in our code: the asio frames between them say little.
  grep -E 'Sanitizer|runtime error|leak of|in skillcell::' "$f" | sed 's/^ *//' | cut -c1-240 | head -n 40
}

# The caller's own failure (with its step and logs), or the library's.
netns_fail_as_caller() {
  if declare -F fail >/dev/null; then fail "$@"; else netns_fail "$@"; fi
}

stop_gracefully() {
  local p=$1
  proc_signal "$p" TERM || netns_fail_as_caller "$p is not running (it should be)"
  proc_wait_exit "$p" 5 || netns_fail_as_caller "$p did not exit within 5 s of SIGTERM"
  [ "$PROC_RC" = 0 ] || {
    sanitizer_report "$p"
    netns_fail_as_caller "$p exited with status $PROC_RC after SIGTERM (expected 0)"
  }
}

check_sanitizers() {
  local f
  for f in "$NETNS_DIR"/*.err; do
    if grep -E -q 'ERROR: (Address|Leak|Thread|UndefinedBehavior)Sanitizer|runtime error:' "$f"; then
      netns_fail_as_caller "sanitizer report in $(basename "$f")"
    fi
  done
}

line_count() {
  local n
  n=$(wc -l <"$1" 2>/dev/null) || n=0
  echo "$n"
}

wait_for_line_until() {
  local file=$1 regex=$2 deadline=$3 from=${4:-1} line
  while :; do
    if [ -f "$file" ]; then
      line=$(tail -n "+$from" "$file" | grep -E -m1 -- "$regex") && {
        echo "$line"
        return 0
      }
    fi
    [ "$(now_ms)" -ge "$deadline" ] && return 1
    sleep 0.05
  done
}

wait_for_line() {
  wait_for_line_until "$1" "$2" $(($(now_ms) + $(_netns_ms "$3"))) "${4:-1}"
}

link_down() { ip -n "$(_netns_ns "$1")" link set eth0 down; }

link_up() {
  local ns
  ns=$(_netns_ns "$1")
  ip -n "$ns" link set eth0 up && ip -n "$ns" route replace 224.0.0.0/4 dev eth0
}

netns_cleanup() {
  local name pid ns k deadline
  [ "$NETNS_CLEANED" = 1 ] && return 0
  NETNS_CLEANED=1
  {
    for name in "${!NETNS_PIDS[@]}"; do
      pid=${NETNS_PIDS[$name]}
      kill -9 "$pid"
    done
    for ns in "${NETNS_CREATED[@]}"; do
      ip netns pids "$ns" | xargs -r kill -9
    done
    for name in "${!NETNS_PIDS[@]}"; do
      wait "${NETNS_PIDS[$name]}"
    done
  } 2>/dev/null # also silences bash's "Killed" job notices
  NETNS_PIDS=()
  # processes inside the namespaces that were not our children: wait (bounded) until they are gone
  deadline=$(($(now_ms) + 5000))
  for ns in "${NETNS_CREATED[@]}"; do
    while [ -n "$(ip netns pids "$ns" 2>/dev/null)" ] && [ "$(now_ms)" -lt "$deadline" ]; do
      sleep 0.05
    done
  done
  for ((k = 1; k <= ${#NETNS_HOSTS[@]}; k++)); do
    ip -n "$NETNS_BR" link del "v$k" 2>/dev/null
  done
  for ns in "${NETNS_CREATED[@]}"; do
    ip netns del "$ns" 2>/dev/null || netns_log "warning: could not delete namespace $ns"
  done
  NETNS_CREATED=()
  if [ -n "$NETNS_WATCHDOG_PID" ]; then
    kill "$NETNS_WATCHDOG_PID" 2>/dev/null # not our child (orphaned on purpose): nothing to wait for
    NETNS_WATCHDOG_PID=""
  fi
  if [ -n "$NETNS_DIR" ] && [ -d "$NETNS_DIR" ]; then
    if [ "${NETNS_KEEP_LOGS:-0}" = 1 ]; then
      touch "$NETNS_DIR/.kept"
      netns_log "logs kept in $NETNS_DIR"
    else
      rm -rf "$NETNS_DIR"
    fi
  fi
  return 0
}

netns_trap() {
  trap 'netns_cleanup' EXIT
  trap 'netns_cleanup; trap - EXIT; exit 130' INT
  trap 'netns_cleanup; trap - EXIT; exit 143' TERM
}
