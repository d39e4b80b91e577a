#!/usr/bin/env bash
# ctest driver: writes a CDR and a ros1 MCAP file with the C++ writer and checks both with the
# official TypeScript reader (read_mcap.mjs); then re-writes each with the official TypeScript
# writer (write_mcap.mjs) and checks that the VIGS reader gets every message back (compare).
# Exit 77 (ctest SKIP) only when node is absent.
#   run_conformance.sh WRITER_BINARY WORK_DIR
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
writer="$1"
work="$2"
if ! command -v node >/dev/null 2>&1; then
  echo "conformance: node not found; skipping (toolchain/setup installs it)"
  exit 77
fi
if [ ! -d "$here/node_modules/@mcap/core" ]; then
  echo "conformance: $here/node_modules missing; run 'npm ci' there (toolchain/setup does)" >&2
  exit 1
fi
mkdir -p "$work"
for enc in cdr ros1; do
  "$writer" "$enc" "$work/conformance_$enc.mcap" "$work/conformance_$enc.json"
  node "$here/read_mcap.mjs" "$work/conformance_$enc.mcap" "$work/conformance_$enc.json"
  # Reverse direction: the official writer's file must read back equal through the VIGS reader.
  # @foxglove/cdr 3.x's CdrWriter sizes strings by UTF-16 length and so truncates non-ASCII
  # UTF-8 (its reader is fine, see above), so the CDR reverse check uses an ASCII-only file.
  source="$work/conformance_$enc.mcap"
  if [ "$enc" = cdr ]; then
    source="$work/ascii_$enc.mcap"
    "$writer" "$enc" "$source" "$work/ascii_$enc.json" --ascii
  fi
  node "$here/write_mcap.mjs" "$source" "$work/official_$enc.mcap"
  "$writer" compare "$source" "$work/official_$enc.mcap"
done
