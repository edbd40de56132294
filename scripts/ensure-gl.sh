#!/usr/bin/env bash
# Makes sure OpenGL runs without a display (wgpu's GL backend through EGL);
# on a machine without it, installs Mesa's EGL and GL drivers (llvmpipe)
# from Debian's packages.
set -eu
have() { ldconfig -p 2>/dev/null | grep "$1" >/dev/null; }
if have 'libEGL.so.1' && have 'libEGL_mesa.so.0' && have 'libGLESv2.so.2' && compgen -G "/usr/lib/*/dri/swrast_dri.so" >/dev/null; then exit 0; fi
echo "ensure-gl: no EGL/GL driver found; installing llvmpipe (libegl1 libegl-mesa0 libgles2 libgl1-mesa-dri)" >&2
SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends libegl1 libegl-mesa0 libgles2 libgl1-mesa-dri >/dev/null
