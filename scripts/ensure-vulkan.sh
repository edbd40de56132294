#!/usr/bin/env bash
# Makes sure a Vulkan driver is present; on a machine without one, installs
# Mesa's CPU driver (lavapipe) from Debian's packages.
set -eu
have_icd() { compgen -G "/usr/share/vulkan/icd.d/*.json" >/dev/null || compgen -G "/etc/vulkan/icd.d/*.json" >/dev/null; }
have_loader() { ldconfig -p 2>/dev/null | grep 'libvulkan.so.1' >/dev/null; }
if have_icd && have_loader; then exit 0; fi
echo "ensure-vulkan: no Vulkan driver found; installing lavapipe (mesa-vulkan-drivers libvulkan1)" >&2
SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq mesa-vulkan-drivers libvulkan1 >/dev/null
