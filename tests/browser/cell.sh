# shellcheck shell=bash
# A small secured cell for the dashboard's browser test and benchmark, sourced by both:
# a cell CA, the cell's users (Observer olga, Operator otto, and "cell", whom the components
# act as), the world model with a dock and a box, the dashboard, and two components with
# skills (a robot, a gripper). Run inside a
# private network namespace. Sets: tmp, pids, url (the page), spki (the pin of its key),
# gripper (the gripper server's pid). Needs: skillcell (the binary).
tmp=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
  rm -rf "$tmp"
}
trap cleanup EXIT

# The cell's CA issues every certificate; the cell's users: an Observer and an Operator for
# the browser, "cell" (Operator) whom the components act as.
export SKILLCELL_CA_DIR="$tmp/ca"
"$skillcell" pki init-ca --dir "$tmp/ca" >/dev/null
echo "olga-secret-1" | "$skillcell" user add olga --role Observer --users "$tmp/users" >/dev/null
echo "otto-secret-3" | "$skillcell" user add otto --role Operator --users "$tmp/users" >/dev/null
echo "cell-secret-2" | "$skillcell" user add cell --role Operator --users "$tmp/users" >/dev/null
echo "cell-secret-2" >"$tmp/cell.pw"
common=(--host 127.0.0.1 --port 0 --users "$tmp/users" --client-user cell
        --client-password-file "$tmp/cell.pw" --mdns-ttl 5 --mdns-query-period 1)

# Waits (bounded) for a line starting with $2 in file $1; prints its rest.
line_of() {
  for _ in $(seq 1 300); do
    if grep -q "^$2" "$1" 2>/dev/null; then
      grep -m1 "^$2" "$1" | cut -d' ' -f2-
      return 0
    fi
    sleep 0.1  # a bounded poll of a log file a child process writes
  done
  echo "no '$2' line in $1:" >&2
  cat "$1" >&2
  return 1
}

# The world model: one dock with a parallel gripper, one box (the dashboard draws them).
"$skillcell" device world "${common[@]}" --pki-dir "$tmp/pki-world" \
  --dock "dockP@0.3,-0.45,0.35" --tool "parallel:dockP@0,0,0.1" \
  --object "boxA:0.04,0.1,0.05@0.45,0.15,0.025" >"$tmp/world.out" 2>"$tmp/world.err" &
pids+=($!)
world_url=$(line_of "$tmp/world.out" "READY ")

"$skillcell" dashboard "${common[@]}" --pki-dir "$tmp/pki-dashboard" --http-port 0 \
  --world "$world_url" >"$tmp/dashboard.out" 2>"$tmp/dashboard.err" &
pids+=($!)
url=$(line_of "$tmp/dashboard.out" "DASHBOARD ")
line_of "$tmp/dashboard.out" "READY " >/dev/null

"$skillcell" server "${common[@]}" --pki-dir "$tmp/pki-robot" --application-uri urn:test:robot \
  --noop-skill CartesianLinearMoveSkillType=MoveLinear \
  --noop-skill CartesianPtpMoveSkillType=MovePtp >"$tmp/robot.out" 2>"$tmp/robot.err" &
pids+=($!)
"$skillcell" server "${common[@]}" --pki-dir "$tmp/pki-gripper" --application-uri urn:test:gripper \
  --noop-skill GraspGripperSkillType=Grasp >"$tmp/gripper.out" 2>"$tmp/gripper.err" &
gripper=$!
pids+=("$gripper")
line_of "$tmp/robot.out" "READY " >/dev/null
line_of "$tmp/gripper.out" "READY " >/dev/null

# The browser trusts the dashboard's certificate by its public key, as a cell's browsers
# would trust the cell CA.
spki=$(openssl x509 -inform der -in "$tmp/pki-dashboard/own/certs/cert.der" -pubkey -noout |
  openssl pkey -pubin -outform der | openssl dgst -sha256 -binary | base64)

