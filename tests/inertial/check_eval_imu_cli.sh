#!/usr/bin/env bash
# ctest: `vigs eval imu` end to end. On the real EuRoC V1_02 files it prints JSON with the
# window count and the three error blocks; on a malformed CSV it fails with an error naming
# the file, the line and the field.
#   check_eval_imu_cli.sh VIGS_BINARY SHARED_DATA_DIR
set -u
vigs="$1"
data="$2/euroc_v102"
fail() { echo "FAIL: $*" >&2; exit 1; }

out="$("$vigs" eval imu --imu "$data/imu0.csv" --gt "$data/groundtruth.csv" --window 1.0)" ||
  fail "eval imu on EuRoC V1_02 exited non-zero"
for key in '"windows": 38' '"rotation_deg": {"rms": ' '"velocity_mps": {"rms": ' \
  '"position_m": {"rms": ' '"bias": "gt"' '"predicted_sigma"'; do
  grep -qF "$key" <<<"$out" || fail "missing $key in: $out"
done

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
printf '#t,wx,wy,wz,ax,ay,az\n1000,0,0,0,0,0,9.8\n2000,0,0,0.1,0,oops,9.8\n' >"$tmp/imu.csv"
if err="$("$vigs" eval imu --imu "$tmp/imu.csv" --gt "$data/groundtruth.csv" 2>&1)"; then
  fail "malformed CSV accepted"
fi
grep -qF "$tmp/imu.csv:3: field 'a_y': 'oops' is not a finite number" <<<"$err" ||
  fail "unexpected error text: $err"

if err="$("$vigs" eval imu --imu "$data/imu0.csv" --gt "$data/imu0.csv" 2>&1)"; then
  fail "IMU file accepted as ground truth"
fi
grep -qF "groundtruth" <<<"$err" && fail "wrong file named: $err"
grep -qF "imu0.csv:2: field 'q_z': missing (line has 7 fields, expected 17)" <<<"$err" ||
  fail "unexpected error text: $err"
echo "ok"
