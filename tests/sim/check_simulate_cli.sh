#!/usr/bin/env bash
# `vigs simulate` end to end: two runs with the same options give byte-identical files, a
# different seed gives a different file, and (when tests/conformance/node_modules exists) the
# official TypeScript MCAP reader reads every message back with CRCs checked.
#   check_simulate_cli.sh VIGS_BINARY WORK_DIR NODE_MODULES_DIR
set -euo pipefail
vigs="$1"
work="$2"
node_modules="$3"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
mkdir -p "$work"
args=(simulate --preset apartment --humans 12 --seconds 0.5 --quiet)
"$vigs" "${args[@]}" --seed 4 --out "$work/a.mcap" >/dev/null
"$vigs" "${args[@]}" --seed 4 --out "$work/b.mcap" >/dev/null
"$vigs" "${args[@]}" --seed 5 --out "$work/c.mcap" >/dev/null
cmp "$work/a.mcap" "$work/b.mcap"
if cmp -s "$work/a.mcap" "$work/c.mcap"; then
  echo "check_simulate_cli: seeds 4 and 5 gave the same file" >&2
  exit 1
fi
if [ -d "$node_modules/@mcap/core" ] && command -v node >/dev/null 2>&1; then
  node "$here/read_sim_mcap.cjs" "$node_modules" "$work/a.mcap" 0.5
else
  echo "check_simulate_cli: no node or $node_modules; official-reader part not run"
fi
rm -f "$work"/a.mcap "$work"/b.mcap "$work"/c.mcap
