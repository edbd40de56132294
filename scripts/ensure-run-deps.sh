#!/usr/bin/env bash
# What building and running hroc needs on a fresh Debian machine with Rust:
# a C++ compiler (the meshopt crate builds meshoptimizer's sources), a
# Vulkan driver (lavapipe where there is none) and OpenGL through EGL
# without a display (llvmpipe). Installs only what is missing.
set -eu
cd "$(dirname "$0")"
if ! command -v c++ >/dev/null; then
  echo "ensure-run-deps: no C++ compiler found; installing g++" >&2
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends g++ >/dev/null
fi
./ensure-vulkan.sh
./ensure-gl.sh
