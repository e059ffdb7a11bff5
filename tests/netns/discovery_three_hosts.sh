#!/usr/bin/env bash
# OPC UA multicast discovery (LDS-ME, OPC 10000-12) across three hosts, each a network namespace
# with its own address on one bridge (see lib.sh):
#   h1: LDS (port 4840)         h2: server urn:test:h2 (4841)     h3: server urn:test:h3 (4842)
#   and on every host a watcher (skillcell discover --watch).
# Checks: announcements reach every host with routable 198.18.0.x URLs; the LDS lists the servers
# (FindServersOnNetwork) and they register with it (FindServers); a SIGTERM'd server says goodbye
# and unregisters; a killed one, or one whose host loses its link, expires after its TTL (from the
# watchers, from the LDS's list and from its registrations) and comes back when the link returns;
# a one-shot 'discover' lists everyone; everything exits 0 on SIGTERM without sanitizer reports.
# Usage: discovery_three_hosts.sh SKILLCELL_BINARY
# Needs root; otherwise exit 77 (exit 1 if SKILLCELL_REQUIRE_NETNS=1).
# NETNS_KEEP_LOGS=1 keeps the component logs (path printed at the end). Each component keeps its
# PKI (application certificate) in the run's directory ($NETNS_DIR/pki-<component>; a restarted
# server reuses its own), never under $HOME.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=lib.sh
. "$here/lib.sh"

BIN=${1:?usage: discovery_three_hosts.sh SKILLCELL_BINARY}
if ! [ -f "$BIN" ] || ! [ -x "$BIN" ]; then
  echo "FAIL: $BIN is not an executable"
  exit 1
fi
BIN=$(realpath -- "$BIN")

TTL=3   # --mdns-ttl of every announcing component
QP=1    # --mdns-query-period of everyone
LDS_URL=opc.tcp://198.18.0.1:4840
T_START=$(now_ms)
T0=$T_START # start of the current step (mark_watchers)
STEP="setup"
declare -A NAME=() # component -> mDNS name, as the watchers report it
declare -A FROM=() # watcher -> first line to look at for the current step

elapsed() { local t=$(($(now_ms) - T_START)); printf '%d.%03d' $((t / 1000)) $((t % 1000)); }
say() { echo "[$(elapsed)s] $*"; }
ok() { say "ok: $*"; }

dump_logs() {
  local f
  [ -n "$NETNS_DIR" ] && [ -d "$NETNS_DIR" ] || return 0
  for f in "$NETNS_DIR"/*.out "$NETNS_DIR"/*.err; do
    [ -s "$f" ] || continue
    echo "----- tail of $(basename "$f")"
    tail -n 25 "$f"
  done
  echo "----- end of logs"
}

fail() {
  echo "FAIL [$(elapsed)s, step: $STEP]: $*"
  dump_logs
  exit 1
}

re_escape() { printf '%s' "$1" | sed 's/[][\.*^$+?(){}|/]/\\&/g'; }

# Component table: host, port, applicationUri.
declare -A HOST=([lds]=h1 [srv2]=h2 [srv3]=h3)
declare -A PORT=([lds]=4840 [srv2]=4841 [srv3]=4842)
declare -A URI=([lds]=urn:test:lds [srv2]=urn:test:h2 [srv3]=urn:test:h3)
addr_of() { echo "198.18.0.${HOST[$1]#h}"; }
# The discovery URL of a component, as a regex: an address (never a host name), then an optional path.
url_re() { echo "opc\\.tcp://$(re_escape "$(addr_of "$1")"):${PORT[$1]}(/[^ ]*)?"; }

watcher_file() { echo "$NETNS_DIR/watch-$1.out"; }
# Starts a step: watchers are read from their next line on, latencies are counted from T0 (now).
mark_watchers() {
  local h
  for h in h1 h2 h3; do FROM[$h]=$(($(line_count "$(watcher_file "$h")") + 1)); done
  T0=$(now_ms)
}
since_t0() { echo "+$(($(now_ms) - T0)) ms"; }

# wait_announced COMPONENT DEADLINE_MS HOSTS...: every watcher on HOSTS shows ANNOUNCED for the
# component (from FROM[host] on) with its URL and applicationUri. Records the mDNS name and
# checks that every watcher reports the same one.
wait_announced() {
  local c=$1 deadline=$2 h line name re
  shift 2
  re="^ANNOUNCED (.+) $(url_re "$c") $(re_escape "${URI[$c]}") caps=([^ ]*)$"
  for h in "$@"; do
    line=$(wait_for_line_until "$(watcher_file "$h")" "$re" "$deadline" "${FROM[$h]}") ||
      fail "watcher on $h shows no 'ANNOUNCED <name> opc.tcp://$(addr_of "$c"):${PORT[$c]} ${URI[$c]} caps=...' for $c"
    [[ $line =~ $re ]] || fail "cannot parse '$line'"
    name=${BASH_REMATCH[1]}
    if [ -z "${NAME[$c]:-}" ]; then
      NAME[$c]=$name
    elif [ "${NAME[$c]}" != "$name" ]; then
      fail "watcher on $h reports $c as '$name', another watcher as '${NAME[$c]}'"
    fi
    say "   $h ($(since_t0)): $line"
  done
}

# wait_gone COMPONENT REASON DEADLINE_MS HOSTS...
wait_gone() {
  local c=$1 reason=$2 deadline=$3 h line
  shift 3
  for h in "$@"; do
    line=$(wait_for_line_until "$(watcher_file "$h")" "^GONE $(re_escape "${NAME[$c]}") " "$deadline" "${FROM[$h]}") ||
      fail "watcher on $h shows no 'GONE ${NAME[$c]} $reason' for $c in time"
    [ "$line" = "GONE ${NAME[$c]} $reason" ] || fail "watcher on $h: '$line', expected 'GONE ${NAME[$c]} $reason'"
    say "   $h ($(since_t0)): $line"
  done
}

# expect_not_gone COMPONENT HOSTS...: no GONE line for the component since FROM[host].
expect_not_gone() {
  local c=$1 h
  shift
  for h in "$@"; do
    if tail -n "+${FROM[$h]}" "$(watcher_file "$h")" | grep -E -q "^GONE $(re_escape "${NAME[$c]}") "; then
      fail "watcher on $h reports $c (${NAME[$c]}) gone, but it is still running"
    fi
  done
}

# lds_query OUTFILE [ARGS...]: one discover --lds call from h3 (bounded); stdout to OUTFILE.
lds_query() {
  local out=$1
  shift
  netns_exec h3 timeout -k 2 10 "$BIN" discover --lds "$LDS_URL" "$@" >"$out" 2>"$out.err"
}

record_re() { echo "^RECORD [0-9]+ $(re_escape "${NAME[$1]}") $(url_re "$1") caps=[^ ]*$"; }
registered_re() { echo "^REGISTERED $(re_escape "${URI[$1]}")( |$)"; }

# poll_lds KIND DEADLINE_MS PRESENT_COMPONENTS ABSENT_COMPONENTS: repeats FindServersOnNetwork
# (KIND=records) or FindServers (KIND=registered) until every PRESENT one is listed and no ABSENT
# one is (both lists space-separated, possibly empty).
poll_lds() {
  local kind=$1 deadline=$2 present=$3 absent=$4 out="$NETNS_DIR/lds-query.out" c good args=() re
  [ "$kind" = registered ] && args=(--registered)
  while :; do
    good=1
    if lds_query "$out" "${args[@]}"; then
      for c in $present; do
        if [ "$kind" = records ]; then re=$(record_re "$c"); else re=$(registered_re "$c"); fi
        grep -E -q -- "$re" "$out" || good=0
      done
      for c in $absent; do
        if [ "$kind" = records ]; then re=" $(url_re "$c") "; else re=$(registered_re "$c"); fi
        grep -E -q -- "$re" "$out" && good=0
      done
    else
      good=0
    fi
    if [ $good = 1 ]; then
      sed 's/^/   /' "$out"
      return 0
    fi
    if [ "$(now_ms)" -ge "$deadline" ]; then
      echo "----- last 'discover --lds $LDS_URL ${args[*]}' output:"
      cat "$out" "$out.err"
      fail "LDS $kind: expected [${present}] listed and [${absent}] not listed"
    fi
    sleep 0.3
  done
}

# start_component COMPONENT PROCNAME (PKI: $NETNS_DIR/pki-COMPONENT)
start_component() {
  local c=$1 p=$2 sub=server
  [ "$c" = lds ] && sub=lds
  start_in "${HOST[$c]}" "$p" "$BIN" "$sub" --port "${PORT[$c]}" --application-uri "${URI[$c]}" \
    --mdns-ttl "$TTL" --mdns-query-period "$QP" --pki-dir "$NETNS_DIR/pki-$c" --insecure
  local line
  line=$(wait_for_line "$NETNS_DIR/$p.out" '^READY ' 15) || fail "$c ($p) did not print READY"
  say "   $c on ${HOST[$c]}: $line"
}

# Every watcher's events alternate per name: no ANNOUNCED of a name already announced (a refresh
# is not an event), no GONE of a name not announced.
check_event_sequences() {
  local h errors
  for h in h1 h2 h3; do
    errors=$(awk '
      $1 == "ANNOUNCED" { if ($2 in up) print "line " NR ": ANNOUNCED " $2 " again without GONE"; up[$2] = 1 }
      $1 == "GONE" { if (!($2 in up)) print "line " NR ": GONE " $2 " that was not announced"; delete up[$2] }
    ' "$(watcher_file "$h")")
    [ -z "$errors" ] || fail "watcher on $h: inconsistent events:"$'\n'"$errors"
  done
}

all_running() {
  local p
  for p in "$@"; do proc_running "$p" || fail "$p died unexpectedly"; done
}

# ---------------------------------------------------------------------------------------------
netns_trap
netns_setup_or_skip 3
say "hosts h1 (198.18.0.1), h2 (198.18.0.2), h3 (198.18.0.3) in namespaces ${NETNS_ID}h1..h3"

STEP="a: watchers"
for h in h1 h2 h3; do
  start_in "$h" "watch-$h" "$BIN" discover --watch --duration 0 --mdns-query-period "$QP"
done
for h in h1 h2 h3; do
  wait_for_line "$(watcher_file "$h")" '^WATCHING' 10 >/dev/null || fail "watcher on $h did not print WATCHING"
done
mark_watchers
ok "watchers running on h1, h2, h3"

STEP="b: servers"
start_component srv2 server2
start_component srv3 server3

STEP="c: LDS, announcements"
start_component lds lds
d=$(($(now_ms) + 10000))
for c in srv2 srv3 lds; do wait_announced "$c" "$d" h1 h2 h3; done
if [ "${NAME[srv2]}" = "${NAME[srv3]}" ] || [ "${NAME[srv2]}" = "${NAME[lds]}" ] ||
  [ "${NAME[srv3]}" = "${NAME[lds]}" ]; then
  fail "mDNS names are not distinct: ${NAME[*]}"
fi
for h in h1 h2 h3; do
  grep -E "^ANNOUNCED $(re_escape "${NAME[lds]}") " "$(watcher_file "$h")" | head -n1 |
    grep -E -q ' caps=([^ ]*,)?LDS(,[^ ]*)?$' || fail "watcher on $h: the LDS is not announced with caps LDS"
done
ok "every watcher shows ANNOUNCED for both servers and the LDS (caps LDS), URLs on 198.18.0.x"

STEP="c2: one-shot discover"
out="$NETNS_DIR/discover-once.out"
netns_exec h2 timeout -k 2 10 "$BIN" discover --duration 3 >"$out" 2>"$out.err" ||
  fail "'discover --duration 3' on h2 failed: $(cat "$out.err")"
sed 's/^/   /' "$out"
for c in srv2 srv3 lds; do
  grep -E -q "^SERVER $(re_escape "${NAME[$c]}") $(url_re "$c") $(re_escape "${URI[$c]}") caps=[^ ]*$" "$out" ||
    fail "'discover --duration 3' on h2 does not list $c as 'SERVER ${NAME[$c]} opc.tcp://$(addr_of "$c"):${PORT[$c]} ${URI[$c]} caps=...'"
done
ok "'discover --duration 3' on h2 lists both servers and the LDS"

STEP="d: LDS lists"
poll_lds records $(($(now_ms) + 10000)) "srv2 srv3 lds" ""
ok "FindServersOnNetwork on the LDS (from h3) lists both servers and the LDS"
poll_lds registered $(($(now_ms) + 10000)) "srv2 srv3" ""
ok "FindServers on the LDS lists urn:test:h2 and urn:test:h3 (they registered)"
all_running watch-h1 watch-h2 watch-h3 server2 server3 lds

STEP="e: graceful stop of h3's server"
mark_watchers
t0=$T0
stop_gracefully server3
wait_gone srv3 goodbye $((t0 + 2000)) h1 h2 h3
ok "SIGTERM on h3's server: exit 0, every watcher shows 'GONE ${NAME[srv3]} goodbye' within 2 s"
poll_lds records $(($(now_ms) + 5000)) "srv2 lds" "srv3"
ok "the LDS no longer lists h3's server (FindServersOnNetwork)"
poll_lds registered $(($(now_ms) + 5000)) "srv2" "srv3"
ok "the LDS no longer has urn:test:h3 registered (FindServers)"
for c in srv2 lds; do expect_not_gone "$c" h1 h2 h3; done
all_running watch-h1 watch-h2 watch-h3 server2 lds

STEP="f: restart and kill -9 of h3's server"
mark_watchers
start_component srv3 server3b
wait_announced srv3 $(($(now_ms) + 10000)) h1 h2 h3
ok "h3's server announced again"
poll_lds records $(($(now_ms) + 10000)) "srv2 srv3 lds" ""
poll_lds registered $(($(now_ms) + 10000)) "srv2 srv3" ""
ok "the LDS lists and has registered h3's server again"
mark_watchers
t0=$T0
{ proc_signal server3b KILL && proc_wait_exit server3b 5; } 2>/dev/null || # (no "Killed" notice)
  fail "server3b did not die on SIGKILL"
wait_gone srv3 expired $((t0 + (TTL + 3) * 1000)) h1 h2 h3
ok "kill -9 of h3's server: every watcher shows 'GONE ${NAME[srv3]} expired' within TTL+3 s"
poll_lds records $((t0 + (TTL + 5) * 1000)) "srv2 lds" "srv3"
ok "the LDS no longer lists h3's server (FindServersOnNetwork)"
# A registration ends with the server's mDNS presence, long before --registration-timeout.
poll_lds registered $((t0 + (TTL + 5) * 1000)) "srv2" "srv3"
ok "the LDS no longer has urn:test:h3 registered (FindServers)"
for c in srv2 lds; do expect_not_gone "$c" h1 h2 h3; done
all_running watch-h1 watch-h2 watch-h3 server2 lds

STEP="g: link of h2 down and up"
mark_watchers
t0=$T0
link_down h2 || fail "link_down h2"
wait_gone srv2 expired $((t0 + (TTL + 3) * 1000)) h1 h3
ok "link of h2 down: watchers on h1 and h3 show 'GONE ${NAME[srv2]} expired' within TTL+3 s"
# And h2's own watcher has lost the LDS before the link comes back: else the link may return
# while the LDS's records are still fresh on h2, and "ANNOUNCED again" below would have
# nothing to be again (a race between the two expiries, seen in CI).
wait_gone lds expired $((t0 + (TTL + 3) * 1000)) h2
ok "link of h2 down: the watcher on h2 shows 'GONE ${NAME[lds]} expired' within TTL+3 s"
poll_lds records $((t0 + (TTL + 5) * 1000)) "lds" "srv2"
ok "the LDS no longer lists h2's server"
poll_lds registered $((t0 + (TTL + 5) * 1000)) "" "srv2"
ok "the LDS no longer has urn:test:h2 registered"
expect_not_gone lds h1 h3
all_running watch-h1 watch-h2 watch-h3 server2 lds
mark_watchers
t0=$T0
link_up h2 || fail "link_up h2"
wait_announced srv2 $((t0 + 5000)) h1 h3
ok "link of h2 up: watchers on h1 and h3 show h2's server ANNOUNCED within 5 s"
wait_announced lds $((t0 + 5000)) h2
ok "link of h2 up: the watcher on h2 shows the LDS ANNOUNCED again within 5 s"
poll_lds records $((t0 + 7000)) "srv2 lds" ""
poll_lds registered $((t0 + 7000)) "srv2" ""
ok "the LDS lists h2's server again and h2's server registered with it again"
all_running watch-h1 watch-h2 watch-h3 server2 lds

STEP="h: shutdown"
mark_watchers
t0=$T0
stop_gracefully lds
wait_gone lds goodbye $((t0 + 2000)) h1 h2 h3
ok "SIGTERM on the LDS: exit 0, every watcher shows 'GONE ${NAME[lds]} goodbye' within 2 s"
stop_gracefully server2
for h in h1 h2 h3; do stop_gracefully "watch-$h"; done
ok "h2's server and the watchers exit 0 on SIGTERM"
check_event_sequences
ok "every watcher's ANNOUNCED/GONE lines alternate per name (no duplicate events)"
check_sanitizers

say "PASS: discovery across three hosts"
exit 0
