#!/usr/bin/env bash
# `vigs config check` end to end: the shipped robots pass; a typo in a key, an out-of-range
# value and an unknown IMU protocol each exit non-zero naming the file, line and key.
set -euo pipefail
vigs="$1"
src="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

"$vigs" config check "$src"/firmware_config/robots/*.yaml
"$vigs" config print >/dev/null

expect_failure() {  # file, expected text...
  local file="$1"
  shift
  if "$vigs" config check "$file" >"$work/out" 2>&1; then
    echo "FAIL: config check accepted $file"
    exit 1
  fi
  for text in "$@"; do
    grep -qF -- "$text" "$work/out" || {
      echo "FAIL: '$text' missing from:"
      cat "$work/out"
      exit 1
    }
  done
}

printf 'robot: r\nimu:\n  rate_hz: 200\n  gyro_nosie_density: 1.0e-4\n' >"$work/typo.yaml"
expect_failure "$work/typo.yaml" "$work/typo.yaml:4:3: key 'imu.gyro_nosie_density': unknown key" \
  "did you mean 'gyro_noise_density'"

printf 'camera:\n  rate_hz: 1000\n' >"$work/range.yaml"
expect_failure "$work/range.yaml" "$work/range.yaml:2:12: key 'camera.rate_hz'" "out of range"

printf 'imu:\n  protocol: vectornav_vn100\n' >"$work/protocol.yaml"
expect_failure "$work/protocol.yaml" "$work/protocol.yaml:2:13: key 'imu.protocol'" \
  "unknown protocol 'vectornav_vn100' (known: xsens_mt)"
# V4L2 camera: device paths under /dev/, a colour node, a known colour format, a GPIO chip name.
printf 'camera:\n  driver: v4l2\n  device: /dev/video0\n' >"$work/v4l2.yaml"
expect_failure "$work/v4l2.yaml" "key 'camera.colour_device'" "colour node's path under /dev/"
printf 'camera:\n  driver: v4l2\n  device: video0\n  colour_device: /dev/video2\n' \
  >"$work/v4l2_path.yaml"
expect_failure "$work/v4l2_path.yaml" "key 'camera.device'" "path under /dev/"
printf 'camera:\n  driver: v4l2\n  device: /dev/video0\n  colour_device: /dev/video2\n  colour_format: NV12\n' \
  >"$work/v4l2_format.yaml"
expect_failure "$work/v4l2_format.yaml" "$work/v4l2_format.yaml:5:18: key 'camera.colour_format'"
printf 'camera:\n  trigger_chip: /sys/class/gpio\n' >"$work/gpio.yaml"
expect_failure "$work/gpio.yaml" "key 'camera.trigger_chip'" "gpiochipN or /dev/gpiochipN"
echo "vigs config check: all cases passed"
