#!/usr/bin/env bash
# Skill detection across three hosts, each a network namespace with its own address on one bridge
# (see lib.sh). Every host runs one component, `skillcell server --noop-skill ... --detect`:
#   h1: urn:test:robot    CartesianLinearMoveSkillType=Move, JointPtpMoveSkillType=Ptp
#   h2: urn:test:gripper  GraspGripperSkillType=Grasp, ReleaseGripperSkillType=Release
#   h3: urn:test:mes      ExecuteProcessSkillType=Execute
# and h1 also an LDS (`skillcell lds --detect`, no skills), whose detector hears every component
# twice (mDNS and its registration) and must still show each skill once.
# Each detector prints SKILL ADDED / SKILL REMOVED lines (src/apps/skill_report.hpp); folding them
# gives that detector's skill map.
# Checks: the components start in random order, all at once; every detector converges to the same
# map of all five skills (its own included) with routable 198.18.0.x endpoints; kill -9 of one
# removes its skills from the others' maps (the connection drops: well within the mDNS TTL); a
# restarted component (new StartTime) is detected again everywhere; a host that loses its link
# disappears from the others (keep-alive timeout or TTL) and reappears with the link; a SIGTERM'd
# component (mDNS goodbye and closed connections) disappears at once; everything exits 0 on
# SIGTERM without sanitizer reports.
# Usage: skill_detector_three_hosts.sh SKILLCELL_BINARY
# Needs root; otherwise exit 77 (exit 1 if SKILLCELL_REQUIRE_NETNS=1).
# NETNS_KEEP_LOGS=1 keeps the component logs. PKIs live in the run's directory, never under $HOME.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=lib.sh
. "$here/lib.sh"

BIN=${1:?usage: skill_detector_three_hosts.sh SKILLCELL_BINARY}
if ! [ -f "$BIN" ] || ! [ -x "$BIN" ]; then
  echo "FAIL: $BIN is not an executable"
  exit 1
fi
BIN=$(realpath -- "$BIN")

TTL=3   # --mdns-ttl of every component
QP=1    # --mdns-query-period
T_START=$(now_ms)
T0=$T_START
STEP="setup"

elapsed() { local t=$(($(now_ms) - T_START)); printf '%d.%03d' $((t / 1000)) $((t % 1000)); }
say() { echo "[$(elapsed)s] $*"; }
ok() { say "ok: $*"; }
since_t0() { echo "+$(($(now_ms) - T0)) ms"; }

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

# Component table (the LDS offers no skills).
COMPONENTS=(robot gripper mes lds)
declare -A HOST=([robot]=h1 [gripper]=h2 [mes]=h3 [lds]=h1)
declare -A PORT=([robot]=4840 [gripper]=4840 [mes]=4840 [lds]=4841)
declare -A URI=([robot]=urn:test:robot [gripper]=urn:test:gripper [mes]=urn:test:mes [lds]=urn:test:lds)
declare -A SKILLS=(
  [robot]="CartesianLinearMoveSkillType=Move JointPtpMoveSkillType=Ptp"
  [gripper]="GraspGripperSkillType=Grasp ReleaseGripperSkillType=Release"
  [mes]="ExecuteProcessSkillType=Execute"
  [lds]=""
)
declare -A PROC=() # component -> current process name (a restart gets a new one)
declare -A FROM=() # process name -> first line of its output that counts (per step)
addr_of() { echo "198.18.0.${HOST[$1]#h}"; }

# What every detector must show for COMPONENTS... : "<type> <uri> opc.tcp://<addr>:<port>" lines.
expected_map() {
  local c spec
  for c in "$@"; do
    for spec in ${SKILLS[$c]}; do
      echo "${spec%%=*} ${URI[$c]} opc.tcp://$(addr_of "$c"):${PORT[$c]}"
    done
  done | sort
}

# The skill map of a detector's output: its SKILL ADDED lines minus its SKILL REMOVED lines, as
# "<type> <uri> <endpoint> <nodeid>" (endpoint without a trailing '/'), sorted.
skill_map() {
  awk '
    $1 == "SKILL" && $2 == "ADDED" { sub(/\/$/, "", $5); m[$3 " " $4 " " $5 " " $6] = 1 }
    $1 == "SKILL" && $2 == "REMOVED" { sub(/\/$/, "", $5); delete m[$3 " " $4 " " $5 " " $7] }
    END { for (k in m) print k }' "$1" | sort
}

# wait_converged DEADLINE_MS OBSERVERS -- COMPONENTS: the map of every observer (a component whose
# detector is read) shows exactly the skills of COMPONENTS, and all of them show the same node ids.
wait_converged() {
  local deadline=$1 o want first map
  shift
  local observers=()
  while [ "$1" != -- ]; do observers+=("$1"); shift; done
  shift
  want=$(expected_map "$@")
  while :; do
    local good=1
    first=""
    for o in "${observers[@]}"; do
      map=$(skill_map "$NETNS_DIR/${PROC[$o]}.out")
      if [ "$(awk '{ print $1 " " $2 " " $3 }' <<<"$map" | sort)" != "$want" ]; then good=0; break; fi
      if [ -z "$first" ]; then first=$map; elif [ "$map" != "$first" ]; then good=0; break; fi
    done
    if [ $good = 1 ]; then
      for o in "${observers[@]}"; do say "   $o's detector ($(since_t0)): $(skill_map "$NETNS_DIR/${PROC[$o]}.out" | wc -l) skills"; done
      return 0
    fi
    if [ "$(now_ms)" -ge "$deadline" ]; then
      echo "----- expected on every observer:"
      echo "$want"
      for o in "${observers[@]}"; do
        echo "----- $o's detector shows:"
        skill_map "$NETNS_DIR/${PROC[$o]}.out"
      done
      fail "the detectors of [${observers[*]}] do not converge to the skills of [$*]"
    fi
    sleep 0.05
  done
}

# removal_reasons OBSERVER COMPONENT: the reasons of the SKILL REMOVED lines for COMPONENT since
# the step began (FROM), space-separated.
removal_reasons() {
  local p=${PROC[$1]}
  tail -n "+${FROM[$p]:-1}" "$NETNS_DIR/$p.out" |
    awk -v uri="${URI[$2]}" '$1 == "SKILL" && $2 == "REMOVED" && $4 == uri { print $6 }' | sort -u | xargs
}

mark() {
  local c
  for c in "${COMPONENTS[@]}"; do
    [ -n "${PROC[$c]:-}" ] && FROM[${PROC[$c]}]=$(($(line_count "$NETNS_DIR/${PROC[$c]}.out") + 1))
  done
  T0=$(now_ms)
}

start_component() {
  local c=$1 p=$2 spec sub=server args=()
  [ "$c" = lds ] && sub=lds
  for spec in ${SKILLS[$c]}; do args+=(--noop-skill "$spec"); done
  start_in "${HOST[$c]}" "$p" "$BIN" "$sub" --port "${PORT[$c]}" --application-uri "${URI[$c]}" \
    --mdns-ttl "$TTL" --mdns-query-period "$QP" --pki-dir "$NETNS_DIR/pki-$c" --insecure --detect "${args[@]}"
  PROC[$c]=$p
}

wait_ready() {
  local c=$1 line
  line=$(wait_for_line "$NETNS_DIR/${PROC[$c]}.out" '^READY ' 15) || fail "$c (${PROC[$c]}) did not print READY"
  say "   $c on ${HOST[$c]}: $line"
}

all_running() {
  local c
  for c in "$@"; do proc_running "${PROC[$c]}" || fail "$c (${PROC[$c]}) died unexpectedly"; done
}

# ---------------------------------------------------------------------------------------------
netns_trap
netns_setup_or_skip 3
say "hosts h1 (198.18.0.1), h2 (198.18.0.2), h3 (198.18.0.3) in namespaces ${NETNS_ID}h1..h3"

STEP="a: start in random order"
mapfile -t order < <(printf '%s\n' "${COMPONENTS[@]}" | shuf)
say "start order: ${order[*]}"
T0=$(now_ms)
for c in "${order[@]}"; do start_component "$c" "$c"; done
for c in "${order[@]}"; do wait_ready "$c"; done
wait_converged $((T0 + 15000)) robot gripper mes lds -- robot gripper mes
ok "every detector (the LDS's too) shows the same five skills (its own included), endpoints on 198.18.0.x"

STEP="b: kill -9 of h3's component"
mark
t0=$T0
{ proc_signal mes KILL && proc_wait_exit mes 5; } 2>/dev/null || fail "mes did not die on SIGKILL"
wait_converged $((t0 + (TTL + 3) * 1000)) robot gripper lds -- robot gripper
for o in robot gripper lds; do say "   $o: mes's skills removed ($(removal_reasons "$o" mes))"; done
ok "kill -9 of the MES component: its skill is gone from the other detectors within TTL+3 s"
all_running robot gripper lds

STEP="c: restart of h3's component"
mark
start_component mes mes2
wait_ready mes
wait_converged $((T0 + 10000)) robot gripper mes lds -- robot gripper mes
ok "the restarted MES component is detected again everywhere, and detects everyone"

STEP="d: link of h2 down and up"
mark
t0=$T0
link_down h2 || fail "link_down h2"
wait_converged $((t0 + (TTL + 3) * 1000)) robot mes lds -- robot mes
for o in robot mes lds; do say "   $o: gripper's skills removed ($(removal_reasons "$o" gripper))"; done
ok "link of h2 down: the gripper's skills are gone from h1 and h3 (keep-alive timeout or TTL)"
mark
link_up h2 || fail "link_up h2"
wait_converged $((T0 + 10000)) robot gripper mes lds -- robot gripper mes
ok "link of h2 up: every detector shows the five skills again"
all_running robot gripper mes lds

STEP="e: SIGTERM of h1's component"
mark
t0=$T0
stop_gracefully robot
wait_converged $((t0 + 4000)) gripper mes lds -- gripper mes
for o in gripper mes lds; do
  reasons=$(removal_reasons "$o" robot)
  say "   $o: robot's skills removed ($reasons)"
  # Its goodbye, its unregistration or its closed connection: at once, not at its TTL.
  [[ $reasons =~ ^(goodbye|disconnected|unregistered)( (goodbye|disconnected|unregistered))*$ ]] ||
    fail "$o removed the robot's skills for '$reasons', expected goodbye, unregistered or disconnected"
done
grep -q '^SNAPSHOT ' "$NETNS_DIR/robot.out" || fail "the robot component printed no SNAPSHOT on exit"
ok "SIGTERM of the robot component: exit 0, its skills gone everywhere by goodbye (not expiry)"

STEP="f: shutdown"
stop_gracefully gripper
stop_gracefully mes2
stop_gracefully lds
ok "the other components and the LDS exit 0 on SIGTERM"
check_sanitizers

say "PASS: skill detection across three hosts"
exit 0
