#!/usr/bin/env bash
# `skillcell nodeset2owl` as a user runs it: usage errors exit 2 with what to give, a bad file
# exits 1 naming the file (and the line), a good run writes one Turtle file per ontology.
# Usage: nodeset2owl_cli_test.sh PATH/TO/skillcell MODELS_DIR
set -euo pipefail
skillcell=$1
models=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAILED: $*" >&2; exit 1; }

# Runs skillcell nodeset2owl ARGS, keeps stdout/stderr in $tmp/out, $tmp/err, checks the exit.
run() {
  local want=$1; shift
  local rc=0
  "$skillcell" nodeset2owl "$@" >"$tmp/out" 2>"$tmp/err" || rc=$?
  echo "--- skillcell nodeset2owl $* (exit $rc)"; head -c 600 "$tmp/err"
  [ "$rc" = "$want" ] || fail "skillcell nodeset2owl $*: exit $rc, expected $want"
}
expect_err() { grep -qF -- "$1" "$tmp/err" || fail "missing in stderr: $1"; }

# Usage errors: 2, saying what to give.
run 2
expect_err "give NodeSet2 files or --embedded"
run 2 --embedded "$models/opcfoundation/Opc.Ua.Di.NodeSet2.xml"
expect_err "give NodeSet2 files or --embedded"
run 2 --embedded
expect_err "give --output-dir"
run 2 "$tmp/no-such-file.xml"
expect_err "no-such-file.xml"

# Bad input: 1, naming the file and the line.
printf '<?xml version="1.0"?>\n<UANodeSet>\n  <UAObject NodeId="ns=1;i=1"\n' >"$tmp/broken.xml"
run 1 "$tmp/broken.xml"
expect_err "broken.xml"
# A model without the one it requires (Skills requires DI): named.
run 1 "$models/Skillcell.Skills.NodeSet2.xml"
expect_err "http://opcfoundation.org/UA/DI/"

# A good run: one file per ontology, each Turtle.
run 0 "$models/opcfoundation/Opc.Ua.Di.NodeSet2.xml" "$models/Skillcell.Skills.NodeSet2.xml" -o "$tmp/owl" --core
[ "$(grep -c '^WROTE ' "$tmp/out")" = 3 ] || fail "expected 3 WROTE lines: $(cat "$tmp/out")"
grep -q 'owl:Ontology' "$tmp/owl/opcua-core.ttl" || fail "opcua-core.ttl is not an ontology"
ls "$tmp/owl" | grep -q 'Skills' || fail "no ontology of the Skills model: $(ls "$tmp/owl")"
echo "ok"
