#!/usr/bin/env bash
# ctest: `vigs mcap info` on an intact recording (exit 0, every channel decoded, no issues) and on
# the same recording cut in half (exit 1, a "truncated" issue with its byte offset); `vigs mcap
# oni` on the intact one (pixel-exact playback is checked in test_oni_playback).
#   vigs_mcap_info_test.sh VIGS_BINARY WRITER_BINARY WORK_DIR
set -euo pipefail
vigs="$1"
writer="$2"
work="$3"
mkdir -p "$work"
"$writer" cdr "$work/info.mcap" "$work/info.json"
out="$("$vigs" mcap info --decode "$work/info.mcap")"
grep -q '"messages": 28,' <<<"$out" || { echo "expected 28 messages: $out"; exit 1; }
grep -q '"issues": \[$' <<<"$out" && ! grep -q '"kind"' <<<"$out" || { echo "unexpected issues: $out"; exit 1; }
[ "$(grep -c '"decoded": true, "decode_errors": 0' <<<"$out")" -eq 7 ] || { echo "not all decoded: $out"; exit 1; }
size=$(stat -c %s "$work/info.mcap")
head -c $((size / 2)) "$work/info.mcap" >"$work/half.mcap"
set +e
out="$("$vigs" mcap info "$work/half.mcap")"
rc=$?
set -e
[ "$rc" -eq 1 ] || { echo "expected exit 1 on a truncated file, got $rc"; exit 1; }
grep -q '"kind": "truncated", "offset": [0-9]' <<<"$out" || { echo "no truncation reported: $out"; exit 1; }
# `vigs mcap oni`: the recording's 4 colour/depth pairs (equal stamps, 1 s apart) become a clip.
out="$("$vigs" mcap oni "$work/info.mcap" "$work/info.oni")"
grep -q '"frames": 4, "unmatched": 0, "fps": 1, "width": 7, "height": 5' <<<"$out" ||
  { echo "unexpected oni result: $out"; exit 1; }
[ -s "$work/info.oni" ] || { echo "no oni file"; exit 1; }
if "$vigs" mcap oni "$work/info.mcap" "$work/bad.oni" --rgb-topic /nope 2>/dev/null; then
  echo "expected an error without colour images"; exit 1
fi
echo "vigs mcap info / oni: ok"
