#!/usr/bin/env bash
# Everything the tests need on a fresh Debian machine: a Vulkan driver
# (lavapipe), Xvfb and the X11 keyboard library for the viewer's smoke test,
# and Chromium for the report's browser test. Installs only what is missing.
set -eu
cd "$(dirname "$0")"
./ensure-run-deps.sh
missing=()
command -v Xvfb >/dev/null || missing+=(xvfb)
command -v chromium >/dev/null || missing+=(chromium)
# Libraries winit opens at run time (dlopen), so no package depends on them.
have_lib() { ldconfig -p 2>/dev/null | grep -q "$1"; }
have_lib 'libxkbcommon.so.0' || missing+=(libxkbcommon0)
have_lib 'libxkbcommon-x11.so.0' || missing+=(libxkbcommon-x11-0)
have_lib 'libX11-xcb.so.1' || missing+=(libx11-xcb1)
have_lib 'libXcursor.so.1' || missing+=(libxcursor1)
have_lib 'libXi.so.6' || missing+=(libxi6)
[ ${#missing[@]} -eq 0 ] && exit 0
echo "ensure-test-deps: installing ${missing[*]}" >&2
SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
