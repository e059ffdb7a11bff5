#!/usr/bin/env bash
# The cell with two robots (examples/cells/two-robots.toml) runs its process of two branches
# (examples/processes/two-robots.ttl), brought up by `cell up` in a network namespace of its own:
#  - the order completes;
#  - the journal shows the branches at the same time: each branch's tool change overlaps the
#    other's, and the two picks overlap or the later one waited only for its own branch (its
#    tool change, then its gripper's detection, which the journal's note of the step gives);
#  - each step ran on the robot that reaches its dock or box: the left tool changer and the
#    left UR5 for boxL, the right ones for boxR (from the choice the journal keeps);
#  - the world has each box where the process puts it, each gripper back in its dock and no
#    tool on either flange.
# Needs root (network namespaces); skips (77) without, unless SKILLCELL_REQUIRE_NETNS=1.
# Usage: two_robots_cell.sh PATH/TO/skillcell SOURCE_DIR
set -euo pipefail
skillcell=$1
src=$2
# shellcheck source=../../support/cell_up.sh
source "$src/tests/support/cell_up.sh"
command -v sqlite3 >/dev/null || fail "sqlite3 is needed to read the journal"

"$skillcell" cell up "$src/examples/cells/two-robots.toml" --work-dir "$work" >"$tmp/up.out" \
  2>"$tmp/up.err" &
supervisor=$!
for _ in $(seq 480); do  # bounded: 4 minutes
  grep -q 'is up' "$tmp/up.out" && break
  kill -0 "$supervisor" 2>/dev/null || break
  sleep 0.5  # a bounded poll of the output a child process writes
done
grep -q 'is up' "$tmp/up.out" || fail "the cell did not come up"
netns=$(grep -o '/proc/[0-9]*/ns/net' "$tmp/up.out" | head -1)
# The devices run from skillcell-component, the program beside skillcell that links only what
# components need; the knowledge base and the MES from skillcell.
children=$(ps --ppid "$supervisor" -o args=)
grep -q '/skillcell-component device ur5 ' <<<"$children" ||
  fail "the UR5s do not run from skillcell-component: $children"
grep -q '/skillcell mes ' <<<"$children" || fail "the MES does not run from skillcell: $children"
endpoint() { grep -E "^  $1 " "$tmp/up.out" | awk '{print $2}'; }
as() {  # as USER: a command inside the cell's network, with that user's credentials
  local user=$1
  shift
  nsenter --net="$netns" "$skillcell" "$@" --pki-dir "$work/pki-operator" --user "$user" \
    --password-file "$work/$user.pw"
}

# The MES chooses each branch's tool changer and robot by what the knowledge base knows of
# them (which dock each reaches). The order goes in once the KB has recorded them all: what
# the journal checks below is the MES running the branches at once, not how soon after the
# cell's start the KB knew its components (CI run 97: under the sanitizers the KB recorded
# the right tool changer 2 s after the order came, and step 2 could only start then).
for uri in kelvin-toolchanger:changer-left kelvin-toolchanger:changer-right ur5:left ur5:right \
  pick-and-place:pickplace-1 pick-and-place:pickplace-2; do
  for _ in $(seq 240); do  # bounded: 2 minutes
    grep -q "kb: recorded urn:skillcell:device:$uri " "$work/logs/kb.log" 2>/dev/null && break
    sleep 0.5  # a bounded poll of the log a child process writes
  done
  grep -q "kb: recorded urn:skillcell:device:$uri " "$work/logs/kb.log" ||
    fail "the knowledge base did not record urn:skillcell:device:$uri"
done

as operator run http://skillcell.dev/demo/two-robots#twoBoxesWithTwoRobots --mes "$(endpoint mes)" \
  >"$tmp/run.out" 2>"$tmp/run.err" || true
grep -q '^OUTCOME Finished' "$tmp/run.out" || {
  cat "$tmp/run.out" >&2
  fail "the order did not complete"
}

journal=$work/journal.sqlite
# "START END" of the finished step IDX of the run.
span() {
  sqlite3 "$journal" "SELECT started_ms || ' ' || ended_ms FROM steps WHERE run = 1 AND \
    idx = $1 AND state = 'finished'"
}
# What the MES noted of the finished step IDX's waits (its journal note): for a suitable skill
# of its own (a pick waits for the gripper that its branch's tool change powered to be
# detected), or for components other steps held.
note() {
  sqlite3 "$journal" "SELECT note FROM steps WHERE run = 1 AND idx = $1 AND state = 'finished'"
}
# at_once A B [PA PB]: the finished steps A and B, of the two branches, did not wait for each
# other. They overlapped; or, when they did not, the one that started later could not have
# started sooner for its own branch's reasons (one branch running slower than the other, as
# under the sanitizers on two busy cores): its predecessor (PA for A, PB for B) ended only
# after the other step had ended, or it waited for a skill of its own to appear. A step that
# waited for components other steps held fails the check either way. Without predecessors
# both could start at once: they must overlap.
at_once() {
  local a b pa pb
  read -r -a a <<<"$(span "$1")"
  read -r -a b <<<"$(span "$2")"
  [ "${#a[@]}" = 2 ] && [ "${#b[@]}" = 2 ] || fail "steps $1 and $2 are not both finished"
  [ "${a[0]}" -lt "${b[1]}" ] && [ "${b[0]}" -lt "${a[1]}" ] && return 0
  if [ $# = 4 ]; then
    read -r -a pa <<<"$(span "$3")"
    read -r -a pb <<<"$(span "$4")"
    local later=$2 pl=${pb[1]} other=${a[1]}
    if [ "${a[0]}" -ge "${b[1]}" ]; then later=$1 pl=${pa[1]} other=${b[1]}; fi
    local n
    n=$(note "$later")
    if [[ $n != *"for components others held"* ]]; then
      [ "$pl" -ge "$other" ] && return 0
      [[ $n =~ waited\ [0-9]+\ ms\ for\ a\ suitable ]] && return 0
    fi
  fi
  local before=""
  [ $# = 4 ] && before="; before them, step $3 ${pa[*]} and step $4 ${pb[*]}; \
their notes: '$(note "$1")', '$(note "$2")'"
  fail "steps $1 (${a[*]}) and $2 (${b[*]}) ran one after the other$before"
}
at_once 1 2      # the two tool changes
at_once 3 4 1 2  # the two picks, each after its branch's tool change
component() { sqlite3 "$journal" "SELECT component FROM steps WHERE run = 1 AND idx = $1 AND \
  state = 'finished'"; }
[[ $(component 1) == *changer-left ]] || fail "step 1 (dockL) ran on $(component 1)"
[[ $(component 2) == *changer-right ]] || fail "step 2 (dockR) ran on $(component 2)"
[[ $(component 5) == *changer-left ]] || fail "step 5 (dockL) ran on $(component 5)"
choice() { sqlite3 "$journal" "SELECT choice FROM steps WHERE run = 1 AND idx = $1 AND \
  state = 'finished'"; }
grep -q 'CartesianLinearMoveSkillType: Skills/CartesianLinearMove of urn:skillcell:device:ur5:left' \
  <<<"$(choice 3)" || fail "boxL was not moved by the left UR5: $(choice 3)"
grep -q 'CartesianLinearMoveSkillType: Skills/CartesianLinearMove of urn:skillcell:device:ur5:right' \
  <<<"$(choice 4)" || fail "boxR was not moved by the right UR5: $(choice 4)"
grep -q 'gripType "vacuum": Skills/Grasp of urn:skillcell:device:schmalz-ecbpi:changer-right' \
  <<<"$(choice 4)" || fail "boxR was not gripped by the right robot's vacuum gripper: $(choice 4)"

world=$(as observer browse "$(endpoint world)" --start i=85 --values 2>/dev/null)
value() { grep -F "[Variable ns=2;s=World/$1]" <<<"$world" | sed 's/.*\] = //'; }
[[ $(value Objects/boxL/Pose) == "3DFrame(0.250, 0.900, 0.025"* ]] ||
  fail "boxL is at $(value Objects/boxL/Pose)"
[[ $(value Objects/boxR/Pose) == "3DFrame(0.250, -0.800, 0.020"* ]] ||
  fail "boxR is at $(value Objects/boxR/Pose)"
[ "$(value Docks/dockL/Tool)" = '"parallel"' ] && [ "$(value Docks/dockR/Tool)" = '"vacuum"' ] ||
  fail "the docks hold $(value Docks/dockL/Tool) and $(value Docks/dockR/Tool)"
[ "$(value Robots/left/MountedTool)" = '""' ] && [ "$(value Robots/right/MountedTool)" = '""' ] ||
  fail "a tool is still mounted: $(value Robots/left/MountedTool) $(value Robots/right/MountedTool)"

"$skillcell" cell down --work-dir "$work" >/dev/null || fail "cell down"
wait "$supervisor" || fail "cell up did not end with 0"
supervisor=
echo "two robots: both branches at once, each on its own robot; the world agrees"
