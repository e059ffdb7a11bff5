#!/usr/bin/env bash
# `skillcell demo` end to end, as the README's main command runs it but quick (high speed, no
# boot profile, one detection run per component) and with --swap: the whole cell starts as
# processes, the paper's process completes; it runs again, and once that run is under way an
# engineer swaps the Robotiq gripper in its dock for a DH AG-95, which that same run mounts and
# picks with. The evidence holds:
#   - the world model: box A and box B at the process's target poses, no tool mounted;
#   - the MES's journal: two completed runs, each of 5 steps finished at the first attempt;
#   - the AG-95's adapter was powered and detected in the second run;
#   - the detection table: a row per measured component with the paper's figure;
#   - the security the cell enforces: the operator refused an engineer's method, a client
#     without security refused, a certificate the cell CA did not issue refused by the server;
#   - the dashboard, as the observer over HTTPS: both runs, the boxes, the UR5 up;
#   - with --keep-running the cell stays up supervised as `cell up` supervises it: `cell
#     status` shows its skills, a UR5 killed with SIGKILL is restarted, `cell down` ends it.
# The demo makes its own network namespace (root). Without root the test is skipped (77),
# unless SKILLCELL_REQUIRE_NETNS=1, as in CI.
# Usage: demo_test.sh PATH/TO/skillcell
set -euo pipefail
skillcell=$1
# shellcheck source=demo_test_lib.sh
source "$(dirname "$0")/demo_test_lib.sh"
demo_require_netns
demo=
demo_on_exit='if [ -n "$demo" ]; then kill -TERM "$demo" 2>/dev/null; wait "$demo" 2>/dev/null; fi'

# With --keep-running the cell stays up after the evidence, supervised as `cell up`
# supervises it: `cell status` shows its skills, a killed UR5 comes back, `cell down` ends
# the demo (exit 0).
timeout 900 "$skillcell" demo --speed 50 --boot-profile none --runs 1 --swap --keep-running \
  --work-dir "$tmp/work" >"$tmp/out" 2>&1 &
demo=$!
for _ in $(seq 1800); do
  grep -q 'the cell keeps running' "$tmp/out" && break
  kill -0 "$demo" 2>/dev/null || break
  sleep 0.5
done
grep -q 'the cell keeps running' "$tmp/out" || { cat "$tmp/out"; fail "the demo did not finish its process"; }
# The dashboard, from inside the demo's network namespace, over HTTPS trusted by the cell CA,
# as the observer: its first event (the snapshot) holds both runs of the journal, each of 5
# finished steps, the boxes where the process put them, and the UR5 up.
page=$(grep -o 'PAGE https://[^ ]*' "$tmp/out" | head -1 | cut -d' ' -f2)
[ -n "$page" ] || fail "the demo printed no dashboard page"
openssl x509 -inform der -in "$tmp/work/ca/certs/ca.der" -out "$tmp/ca.pem"
netns=/proc/$(pgrep -f -P "$demo" "skillcell demo" | head -1)/ns/net
in_cell() { nsenter --net="$netns" curl -s --cacert "$tmp/ca.pem" "$@"; }
in_cell -c "$tmp/jar" --data-urlencode user=observer \
  --data-urlencode "password=$(cat "$tmp/work/observer.pw")" "${page}login" >/dev/null ||
  fail "the observer's login on the dashboard"
seen=
for _ in $(seq 20); do
  in_cell -b "$tmp/jar" --max-time 2 "${page}events" >"$tmp/events" || true  # a stream: cut
  if python3 - "$tmp/events" <<'PY'
import json, sys
first = next(l for l in open(sys.argv[1]) if l.startswith("data: "))
s = json.loads(first[6:])
runs = s.get("runs", [])
assert [r["state"] for r in runs] == ["completed", "completed"], runs
assert all(len(r["steps"]) == 5 and all(t["state"] == "finished" for t in r["steps"]) for r in runs)
boxes = {o["id"]: o["position"] for o in s["scene"]["objects"]}
assert abs(boxes["boxA"][0] - 0.25) < 1e-3 and abs(boxes["boxA"][1] - 0.35) < 1e-3, boxes
assert any(c["uri"].endswith(":ur5") and c["up"] for c in s["components"]), s["components"]
PY
  then
    seen=1
    break
  fi
  sleep 0.5  # the dashboard reads the journal twice a second: a bounded wait for it
done
[ -n "$seen" ] || fail "the dashboard's snapshot lacks the runs, the scene or the UR5: $(head -c 2000 "$tmp/events")"

status() { "$skillcell" cell status --json --work-dir "$tmp/work"; }
ur5() { status | python3 -c "import json,sys
print(next(str(c['$1']) for c in json.load(sys.stdin)['components'] if c['name']=='ur5'))"; }
status | grep -q CartesianLinearMoveSkillType || fail "cell status shows no UR5 skills: $(status)"
kill -KILL "$(ur5 pid)"
for _ in $(seq 120); do [ "$(ur5 restarts)" = 1 ] && [ "$(ur5 state)" = up ] && break; sleep 0.5; done
[ "$(ur5 restarts)" = 1 ] || fail "the killed UR5 was not restarted: $(status)"
"$skillcell" cell down --work-dir "$tmp/work" >/dev/null || fail "cell down of the demo"
rc=0
wait "$demo" || rc=$?
demo=
cat "$tmp/out"
[ "$rc" = 0 ] || fail "skillcell demo exited $rc"

expect() { grep -qE -- "$1" "$tmp/out" || fail "missing in the demo's output: $1"; }
[ "$(grep -c 'outcome: Finished' "$tmp/out")" = 2 ] || fail "not two runs that finished"
expect 'the parallel gripper of this run: the DH AG-95'
# The swap came during the second run, before its step 1 (the tool change) finished.
awk '/the swap, the run under way/ {swap=NR}
     /step 1\/5 ChangeToolSkillType finished/ {if (swap) after=1}
     END {exit !(swap && after)}' "$tmp/out" || fail "the swap did not come during the second run"
# The world model's poses: x y z (m) and angles; the targets of models/owl/demo-process.ttl.
expect 'World/Objects/boxA/Pose.*0\.25(0*)?[ ,;].*0\.35(0*)?[ ,;].*0\.025'
expect 'World/Objects/boxB/Pose.*0\.25(0*)?[ ,;].*-0\.2(0*)?[ ,;].*0\.02'
grep -E 'World/Robots/[^/]+/MountedTool' "$tmp/out" | grep -qvE 'parallel|vacuum|ag95' || fail "a tool is still mounted"
for row in 'UR5 .* 313$' 'pick-and-place .* 211$' 'tool changer .* 253$' \
  'Robotiq adapter .* 8422$' 'Schmalz adapter .* 9635$'; do
  expect "$row"
done
expect 'the operator moving a tool .* BadUserAccessDenied$'
expect 'a client without security .* BadSecurityPolicyRejected$'
expect "certificate the cell's CA did not issue .* BadCertificateUntrusted \\(kept in the world model's rejected/\\)$"

# The journal, read by SQLite itself: two completed runs, each of steps 1..5, one attempt
# each, all finished.
journal=$tmp/work/journal.sqlite
runs=$(sqlite3 "$journal" "SELECT group_concat(state, ' ') FROM (SELECT state FROM runs ORDER BY id)")
[ "$runs" = "completed completed" ] || fail "journal runs: $runs"
for run in 1 2; do
  steps=$(sqlite3 "$journal" "SELECT group_concat(idx || ':' || attempt || ':' || state, ' ') \
    FROM (SELECT * FROM steps WHERE run = $run ORDER BY idx, attempt)")
  [ "$steps" = "1:1:finished 2:1:finished 3:1:finished 4:1:finished 5:1:finished" ] ||
    fail "journal steps of run $run: $steps"
done
echo "ok"
