#!/usr/bin/env bash
# Self-test of lib.sh: three hosts; unicast UDP across hosts; mDNS-group multicast from h1 reaches
# h2, h3 and h1 itself across the bridge; link_down h2 cuts h2 off and link_up brings it back;
# signals and exit status of started processes; netns_cleanup leaves nothing behind.
# Needs root and python3; otherwise exit 77 (exit 1 if SKILLCELL_REQUIRE_NETNS=1).
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=lib.sh
. "$here/lib.sh"

fail() {
  echo "FAIL: $*"
  local f
  for f in "$NETNS_DIR"/*.out "$NETNS_DIR"/*.err; do
    [ -s "$f" ] || continue
    echo "--- tail of $(basename "$f")"
    tail -n 20 "$f"
  done
  exit 1
}
ok() { echo "ok: $*"; }

if ! command -v python3 >/dev/null; then
  echo "!!! SKIPPED: python3 not found !!!" >&2
  exit 77
fi

netns_trap
netns_setup_or_skip 3
ok "3 hosts set up (namespaces ${NETNS_ID}h1..h3, bridge in ${NETNS_BR})"

# Every host has exactly lo and eth0, the right address, and no default route.
for k in 1 2 3; do
  links=$(netns_exec "h$k" ip -o link show | awk -F': ' '{print $2}' | sed 's/@.*//' | sort | tr '\n' ' ')
  [ "$links" = "eth0 lo " ] || fail "h$k has links '$links', expected 'eth0 lo '"
  netns_exec "h$k" ip -4 -o addr show dev eth0 | grep -q "inet 198.18.0.$k/24" || fail "h$k: no 198.18.0.$k/24"
  netns_exec "h$k" ip route show default | grep -q . && fail "h$k has a default route"
  [ "$(netns_exec "h$k" cat /proc/sys/kernel/hostname)" = "h$k" ] || fail "h$k: hostname is not h$k"
done
ok "hosts have only lo and eth0 with 198.18.0.K/24, no default route, hostname hK"

RECV='
import socket, struct, sys
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
s.bind(("", 5353))
s.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP,
             struct.pack("4s4s", socket.inet_aton("224.0.0.251"), socket.inet_aton("0.0.0.0")))
u = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
u.bind(("", 9999))
print("LISTENING", flush=True)
import select
while True:
    r, _, _ = select.select([s, u], [], [])
    for sock in r:
        d, a = sock.recvfrom(1500)
        print("MCAST" if sock is s else "UDP", d.decode(), a[0], flush=True)
'
SEND='
import socket, sys, time
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
s.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, 1)
for i in range(int(sys.argv[3])):
    try:
        s.sendto(sys.argv[2].encode(), (sys.argv[1], int(sys.argv[4])))
    except OSError as e:
        print("send error:", e, flush=True)
    time.sleep(0.1)
'

for k in 1 2 3; do start_in "h$k" "recv$k" python3 -c "$RECV"; done
for k in 1 2 3; do
  wait_for_line "$NETNS_DIR/recv$k.out" '^LISTENING' 10 >/dev/null || fail "receiver on h$k did not start"
done
ok "receivers listening on h1..h3"

netns_exec h3 timeout 10 python3 -c "$SEND" 198.18.0.2 unicast-3-to-2 3 9999 || fail "unicast send failed"
wait_for_line "$NETNS_DIR/recv2.out" '^UDP unicast-3-to-2 198\.18\.0\.3$' 3 >/dev/null || fail "unicast h3->h2 not received"
ok "unicast UDP h3 -> h2"

netns_exec h1 timeout 10 python3 -c "$SEND" 224.0.0.251 first 3 5353 || fail "multicast send failed"
for k in 1 2 3; do
  wait_for_line "$NETNS_DIR/recv$k.out" '^MCAST first 198\.18\.0\.1$' 3 >/dev/null || fail "multicast h1 -> h$k not received"
done
ok "multicast 224.0.0.251:5353 from h1 reaches h1, h2, h3"

link_down h2 || fail "link_down h2"
from2=$(($(line_count "$NETNS_DIR/recv2.out") + 1))
netns_exec h1 timeout 10 python3 -c "$SEND" 224.0.0.251 while-down 3 5353 || fail "multicast send failed"
wait_for_line "$NETNS_DIR/recv3.out" '^MCAST while-down ' 3 >/dev/null || fail "h3 missed multicast while h2 is down"
netns_exec h2 timeout 10 python3 -c "$SEND" 224.0.0.251 from-down-h2 2 5353 >"$NETNS_DIR/send-down.out" 2>&1
wait_for_line "$NETNS_DIR/recv1.out" '^MCAST from-down-h2 ' 1 >/dev/null && fail "h1 received multicast from h2 whose link is down"
tail -n "+$from2" "$NETNS_DIR/recv2.out" | grep -q 'while-down' && fail "h2 received multicast while its link is down"
ok "link_down h2: h2 neither receives nor sends, h3 still receives"

link_up h2 || fail "link_up h2"
netns_exec h2 ip route show 224.0.0.0/4 | grep -q 'dev eth0' || fail "link_up did not restore the multicast route"
netns_exec h1 timeout 10 python3 -c "$SEND" 224.0.0.251 after-up 3 5353 || fail "multicast send failed"
wait_for_line "$NETNS_DIR/recv2.out" '^MCAST after-up 198\.18\.0\.1$' 3 >/dev/null || fail "h2 missed multicast after link_up"
netns_exec h2 timeout 10 python3 -c "$SEND" 224.0.0.251 from-h2 3 5353 || fail "multicast send failed"
wait_for_line "$NETNS_DIR/recv1.out" '^MCAST from-h2 198\.18\.0\.2$' 3 >/dev/null || fail "h1 missed multicast from h2 after link_up"
ok "link_up h2: h2 receives and sends again"

# Signals and exit status.
start_in h1 sleeper sh -c 'trap "exit 7" TERM; while :; do sleep 0.1; done'
proc_running sleeper || fail "sleeper not running"
proc_wait_exit sleeper 0.3 && fail "proc_wait_exit returned although sleeper runs"
proc_signal sleeper TERM
proc_wait_exit sleeper 3 || fail "sleeper did not exit on SIGTERM"
[ "$PROC_RC" = 7 ] || fail "sleeper exit status $PROC_RC, expected 7"
ok "proc_signal / proc_wait_exit / PROC_RC"

# A process not started by start_in, left inside a namespace, must be killed by netns_cleanup.
stray=$(netns_exec h3 sh -c 'sleep 300 </dev/null >/dev/null 2>&1 & echo $!')
ip netns pids "${NETNS_ID}h3" | grep -qx "$stray" || fail "stray process $stray not found in h3"

ns_list="${NETNS_CREATED[*]}"
netns_cleanup
for ns in $ns_list; do
  ip netns list | grep -qw "$ns" && fail "namespace $ns still exists after cleanup"
done
_pid_running "$stray" && fail "stray process $stray survived cleanup" # (a zombie is fine)
[ -d "$NETNS_DIR" ] && [ "${NETNS_KEEP_LOGS:-0}" != 1 ] && fail "temp dir $NETNS_DIR still exists"
ok "netns_cleanup removed namespaces, processes and logs"

# A run killed by SIGKILL (no trap runs): its watchdog removes its namespaces and processes.
nested_out=$(mktemp)
bash -c '. "$1"; netns_setup 1 || exit 1; start_in h1 sleeper sleep 300
  echo "READY $NETNS_ID $(proc_pid sleeper)"; exec sleep 300' nested "$here/lib.sh" >"$nested_out" 2>&1 &
nested=$!
line=$(wait_for_line "$nested_out" '^READY ' 10) || { cat "$nested_out"; rm -f "$nested_out"; fail "nested run did not start"; }
rm -f "$nested_out"
read -r _ nested_id nested_sleeper <<<"$line"
ip netns list | grep -qw "${nested_id}h1" || fail "nested run has no namespace ${nested_id}h1"
{ kill -9 "$nested" && wait "$nested"; } 2>/dev/null
deadline=$(($(now_ms) + 10000))
while ip netns list | grep -Eq "^${nested_id}(br|h1)( |$)"; do
  [ "$(now_ms)" -ge "$deadline" ] && fail "the watchdog did not remove ${nested_id}br/h1 within 10 s"
  sleep 0.1
done
_pid_running "$nested_sleeper" && fail "process $nested_sleeper of the killed run survived"
ok "after SIGKILL of a run, its watchdog removed its namespaces and processes"
echo "PASS: netns lib self-test"
