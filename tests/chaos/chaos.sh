#!/usr/bin/env bash
# The chaos suite (issue 25): while the paper's process runs in the paper's cell
# (examples/cells/paper.toml, brought up by `skillcell cell up` in a network namespace of its
# own), kill one component with SIGKILL at a random moment, and check what follows.
#
# Kinds: ur5 toolchanger pickplace world lds kb virtuoso konclude mes dashboard robotiq
# schmalz (the gripper adapters run while their tool is mounted: a trial finds the one
# running), and link: the MES runs on a host of its own (`cell up --host mes=mes-pc`, a
# network namespace linked to the cell's by v-mes-pc), and that link goes down for 1-10 s,
# then up again, as a pulled cable does.
#
# A trial runs one order of the process, or two orders of it submitted at once (the MES runs
# them as their resources allow): CHAOS_ORDERS=1 or 2; by default the long run alternates,
# odd trials one order, even trials two.
# A trial passes when all of these hold:
#  - each order completes after the component comes back (`cell up` restarts it), or stops
#    with a reason (an order with no end after 240 s is a violation: a hang);
#  - the journal shows no step of any run finished twice, and the world no box grasped twice;
#  - when it completed: both boxes at their targets, no tool mounted, each tool in its dock;
#    else each tool is in exactly one place (its dock, or mounted), none half-locked. Also
#    after a kill of the world itself: it goes on from its state file, and the devices'
#    physics waits for it meanwhile (docs/reliability.md);
#  - after `cell down`, no process of the cell is left (no orphan).
# It prints one line per trial and a table: kind x trials x completed / stopped with a reason
# / violations. Exit 0 when no trial found a violation.
#
# Usage: chaos.sh PATH/TO/skillcell SOURCE_DIR [TRIALS_PER_KIND] [KIND...]
#   SEED=N fixes the random moments (printed with each trial, to replay one).
#   CHAOS_ORDERS=1|2 runs every trial with that many orders.
#   CHAOS_CHECK_KILLED_WORLD=0 does not check the world after a kill of the world.
#   CHAOS_LOGS=DIR keeps the cell's logs and journal of each trial that did not complete, in
#   DIR/KIND-N, and the output and logs of a start that did not come up, in
#   DIR/KIND-N-startTRY.
# Needs root (network namespaces); skips (77) without, unless SKILLCELL_REQUIRE_NETNS=1.
set -euo pipefail
skillcell=$1
src=$2
trials=${3:-1}
shift $(($# >= 3 ? 3 : $#))
kinds=("$@")
[ ${#kinds[@]} -gt 0 ] || kinds=(ur5 toolchanger pickplace world lds kb virtuoso konclude mes
  dashboard robotiq schmalz link)
# shellcheck source=../support/cell_up.sh
source "$src/tests/support/cell_up.sh"
cell=$src/examples/cells/paper.toml
process=http://skillcell.dev/demo#pickAndPlaceTwoBoxes
seed=${SEED:-$RANDOM}
RANDOM=$seed
echo "chaos: seed $seed, $trials trial(s) per kind: ${kinds[*]}"

declare -A completed stopped violations
for k in "${kinds[@]}"; do completed[$k]=0; stopped[$k]=0; violations[$k]=0; done

# The pid of what kind $1 names in the running cell, or nothing.
target_pid() {
  local kind=$1
  case $kind in
    virtuoso) pgrep -f "virtuoso-t .*$work/kb/" | head -n 1 ;;
    konclude)
      local kb
      kb=$(component_pid kb)
      [ -n "$kb" ] && pgrep -P "$kb" -f Konclude | head -n 1 ;;
    # The adapter itself: its command line begins so. (Unanchored, the pattern also matched
    # the tool changer, whose arguments hold each tool's power command: a trial of a tool
    # whose adapter was not running killed the changer instead.)
    robotiq | schmalz) pgrep -f "^[^ ]*skillcell device $kind .*$work/" | head -n 1 ;;
    *) component_pid "$kind" ;;
  esac
}
component_pid() {
  "$skillcell" cell status --json --work-dir "$work" 2>/dev/null | python3 -c "import json,sys
d=json.load(sys.stdin)
print(next((str(c.get('pid','')) for c in d['components'] if c['name']=='$1' and c.get('pid')), ''))"
}
endpoint() {
  "$skillcell" cell status --json --work-dir "$work" 2>/dev/null | python3 -c "import json,sys
d=json.load(sys.stdin)
print(next((c.get('endpoint','') for c in d['components'] if c['name']=='$1'), ''))"
}
link_of() {
  "$skillcell" cell status --json --work-dir "$work" 2>/dev/null | python3 -c "import json,sys
d=json.load(sys.stdin)
print(next((c.get('link','') for c in d['components'] if c['name']=='$1'), ''))"
}
inside() { nsenter --net="/proc/$supervisor/ns/net" "$@"; }
as_operator() {
  inside "$skillcell" "$@" --pki-dir "$work/pki-operator" --user operator \
    --password-file "$work/operator.pw"
}
# The world's variables as "name = value" lines (a restarted world answers within seconds:
# bounded, 20 tries).
world() {
  local i out
  for i in $(seq 20); do
    out=$(inside "$skillcell" browse "$(endpoint world)" --start i=85 --values \
      --pki-dir "$work/pki-operator" --user observer --password-file "$work/observer.pw" \
      2>/dev/null || true)
    grep -q 'World/Robots/ur5/MountedTool' <<<"$out" && { echo "$out"; return 0; }
    sleep 0.5  # the world is restarting
  done
}

# One trial of kind $1 (number $2): prints "kind n: outcome (details)"; sets $outcome to
# completed, stopped or violation.
trial() {
  local kind=$1 n=$2 why="" link_fault="" hung=""
  outcome=violation
  # Up (a second try when the first does not come up: the trial is about what follows).
  local i attempt placement=()
  [ "$kind" != link ] || placement=(--host mes=mes-pc)
  for attempt in 1 2; do
    rm -rf "$work"
    "$skillcell" cell up "$cell" --work-dir "$work" "${placement[@]}" >"$tmp/up.out" \
      2>"$tmp/up.err" &
    supervisor=$!
    for i in $(seq 480); do  # bounded: 2 minutes
      grep -q 'is up' "$tmp/up.out" && break
      kill -0 "$supervisor" 2>/dev/null || break
      sleep 0.25  # a bounded poll of cell up's output
    done
    grep -q 'is up' "$tmp/up.out" && break
    local rc=0
    kill -0 "$supervisor" 2>/dev/null && kill -TERM "$supervisor"
    wait "$supervisor" || rc=$?
    echo "trial $kind $n: the cell did not come up (try $attempt; cell up exit $rc):" >&2
    tail -n 20 "$tmp/up.out" "$tmp/up.err" >&2 || true
    if [ -n "${CHAOS_LOGS:-}" ]; then  # the failed start's output and logs, for a post-mortem
      local kept=$CHAOS_LOGS/$kind-$n-start$attempt
      mkdir -p "$kept"
      cp "$tmp/up.out" "$tmp/up.err" "$kept/" 2>/dev/null || true
      find "$work" -maxdepth 2 -name '*.log' -exec cp {} "$kept/" \; 2>/dev/null || true
    fi
    supervisor=
  done
  [ -n "$supervisor" ] || fail "trial $kind $n: the cell did not come up, twice"
  local mes orders=${CHAOS_ORDERS:-$((2 - n % 2))} o
  mes=$(endpoint mes)
  for o in $(seq "$orders"); do
    as_operator run "$process" --no-wait --mes "$mes" >"$tmp/run.out" 2>"$tmp/run.err" ||
      fail "trial $kind $n: order $o was not accepted: $(cat "$tmp/run.out" "$tmp/run.err")"
  done
  # The random moment: 0.2 to 4 s after the orders, while the process runs (about 4 s here
  # per order), or to 8 s for two.
  local delay_ms=$((200 + RANDOM % (3800 + (orders - 1) * 4000)))
  sleep "$(printf '%d.%03d' $((delay_ms / 1000)) $((delay_ms % 1000)))"
  local pid killed
  if [ "$kind" = link ]; then
    # The fault lasts as long as the cable is out: 1 to 10 s.
    local down_ms=$((1000 + RANDOM % 9001)) address link
    address=${mes#opc.tcp://}
    address=${address%%/*}
    link=$(link_of mes)
    [ -n "$link" ] || fail "trial $kind $n: cell status shows no host link for the MES"
    local downAt=${EPOCHREALTIME/./}
    inside ip link set "$link" down
    # The fault is real only if the MES's host is cut off: its endpoint, reached from the
    # cell's namespace, must not answer (the connect is bounded by timeout).
    if inside timeout 1 bash -c "exec 3<>/dev/tcp/${address%:*}/${address##*:}" 2>/dev/null; then
      link_fault="the MES's endpoint $address still answered with its host's link down"
    fi
    local left_ms=$((down_ms - (${EPOCHREALTIME/./} - downAt) / 1000))
    [ "$left_ms" -le 0 ] || sleep "$(printf '%d.%03d' $((left_ms / 1000)) $((left_ms % 1000)))"
    inside ip link set "$link" up
    killed="the MES's host link ($link) down at +${delay_ms} ms for ${down_ms} ms"
  else
    pid=$(target_pid "$kind" || true)
    killed="no $kind running at +${delay_ms} ms"
    if [ -n "$pid" ]; then
      kill -KILL "$pid" 2>/dev/null && killed="killed $kind (pid $pid) at +${delay_ms} ms"
    fi
  fi
  # Follow each order to its end; a killed MES ends the following: follow it again once the
  # supervisor has restarted it (bounded: 12 tries, 4 minutes in all, per order). The trial's
  # result is the first order's that did not finish, else Finished.
  local result="" each
  for o in $(seq "$orders"); do
    each=""
    for i in $(seq 12); do
      local followed
      followed=$(as_operator orders wait "$o" --timeout 240 --mes "$(endpoint mes)" 2>/dev/null ||
        true)
      each=$(grep '^OUTCOME' <<<"$followed" || true)
      # `orders wait` cancels an order with no end after its timeout: a hang, not a stop.
      if grep -q '^PROGRESS no end after' <<<"$followed"; then
        hung="order $o had no end after 240 s (${each#OUTCOME })"
      fi
      case $each in "OUTCOME Finished"* | "OUTCOME Failed"* | "OUTCOME Cancelled"*) break ;; esac
      sleep 1  # the MES is restarting: its supervisor reports it up again within seconds
    done
    [ -n "$result" ] && [[ $result != "OUTCOME Finished"* ]] || result=$each
  done
  local journal=$work/journal.sqlite
  local twice
  twice=$(sqlite3 "$journal" "SELECT group_concat(run || '.' || idx) FROM (SELECT run, idx \
    FROM steps WHERE state = 'finished' GROUP BY run, idx HAVING COUNT(*) > 1)" 2>&1 || true)
  local snapshot
  snapshot=$(world)
  value() { grep -F "[Variable ns=2;s=World/$1]" <<<"$snapshot" | sed 's/.*\] = //' || true; }
  local mounted dockP dockV
  mounted=$(value Robots/ur5/MountedTool)
  dockP=$(value Docks/dockP/Tool)
  dockV=$(value Docks/dockV/Tool)
  # Each box is taken hold of once, however many orders move it and whatever was killed: a
  # run cut short is carried on, a box at its place is left there.
  local grasps="" box g
  local checked=1
  [ "$kind" = world ] && [ "${CHAOS_CHECK_KILLED_WORLD:-1}" = 0 ] && checked=0
  for box in boxA boxB; do
    [ $checked = 1 ] || break
    g=$(value "Objects/$box/Grasps")
    [[ $g =~ ^[0-9]+$ ]] && [ "$g" -le 1 ] || grasps="$grasps $box grasped ${g:-?} times;"
  done
  if [ -n "$link_fault" ]; then
    why=$link_fault
  elif [ -n "$hung" ]; then
    why=$hung
  elif [ -n "$twice" ]; then
    why="step(s) $twice (run.step) finished twice"
  elif [ -n "$grasps" ]; then
    why="a box moved twice:$grasps"
  elif [[ $result == "OUTCOME Finished"* ]]; then
    if [ $checked = 1 ] && {
      [[ $(value Objects/boxA/Pose) != "3DFrame(0.250, 0.350, 0.025"* ]] ||
        [[ $(value Objects/boxB/Pose) != "3DFrame(0.250, -0.200, 0.020"* ]] ||
        [ "$mounted" != '""' ] || [ "$dockP" != '"parallel"' ] || [ "$dockV" != '"vacuum"' ]
    }; then
      why="completed, but the world disagrees: boxA $(value Objects/boxA/Pose), boxB \
$(value Objects/boxB/Pose), mounted $mounted, docks $dockP $dockV"
    else
      outcome=completed
    fi
  elif [[ $result == "OUTCOME Failed ("* ]]; then
    local placed=0 tool
    for tool in parallel vacuum; do
      local places=0
      [ "$mounted" = "\"$tool\"" ] && places=$((places + 1))
      [ "$dockP" = "\"$tool\"" ] && places=$((places + 1))
      [ "$dockV" = "\"$tool\"" ] && places=$((places + 1))
      [ $places = 1 ] && placed=$((placed + 1))
    done
    if [ $checked = 1 ] && [ $placed != 2 ]; then
      why="stopped, and a tool is not in exactly one place: mounted $mounted, docks $dockP $dockV"
    else
      outcome=stopped
      why=${result#OUTCOME Failed }
    fi
  else
    why="no end of the order: '${result:-nothing}'"
  fi
  # Down, and nothing of the cell left behind.
  "$skillcell" cell down --work-dir "$work" >/dev/null 2>&1 || true
  timeout 60 tail --pid="$supervisor" -f /dev/null || true
  supervisor=
  local left
  left=$(pgrep -af -- "$work/" || true)
  if [ -n "$left" ]; then
    outcome=violation
    why="orphans after cell down: $(tr '\n' ';' <<<"$left")"
    pkill -KILL -f -- "$work/" || true
  fi
  # The cell's logs of a trial that did not complete, kept for a post-mortem.
  if [ -n "${CHAOS_LOGS:-}" ] && [ "$outcome" != completed ]; then
    local kept=$CHAOS_LOGS/$kind-$n
    mkdir -p "$kept"
    find "$work" -maxdepth 2 -name '*.log' -exec cp {} "$kept/" \; 2>/dev/null || true
    cp "$work/journal.sqlite" "$kept/" 2>/dev/null || true
  fi
  echo "trial $kind $n (seed $seed, $orders order(s)): $killed; $outcome${why:+ - $why}"
}

for kind in "${kinds[@]}"; do
  for n in $(seq "$trials"); do
    trial "$kind" "$n"
    case $outcome in
      completed) completed[$kind]=$((completed[$kind] + 1)) ;;
      stopped) stopped[$kind]=$((stopped[$kind] + 1)) ;;
      *) violations[$kind]=$((violations[$kind] + 1)) ;;
    esac
  done
done

printf '\n%-12s %7s %10s %9s %11s\n' kind trials completed stopped violations
bad=0
for kind in "${kinds[@]}"; do
  printf '%-12s %7d %10d %9d %11d\n' "$kind" "$trials" "${completed[$kind]}" \
    "${stopped[$kind]}" "${violations[$kind]}"
  bad=$((bad + violations[$kind]))
done
[ $bad = 0 ] || { echo "chaos: $bad violation(s)"; exit 1; }
echo "chaos: no violation"
