#!/usr/bin/env bash
# Set up wgputrace on a fresh Debian/Ubuntu machine: system packages (Mesa 25 on Debian 12), then a virtual
# environment in .venv with the package and its test, bench, denoise, hdr, draco, ktx2, ray and docs extras. Safe to run again.
set -euo pipefail
cd "$(dirname "$0")/.."

as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

# mesa-vulkan-drivers gives wgpu a Vulkan adapter on any machine (lavapipe, a CPU driver) when
# there is no GPU driver; python3-venv is what Debian's python3 needs to make .venv; xvfb is the
# virtual X display the viewer's window tests (tests/app) open their windows on, and the libX*
# packages are what the glfw wheel's X11 library loads at run time.
packages=(mesa-vulkan-drivers python3-venv python3-pip xvfb libx11-6 libxrandr2 libxcursor1 libxi6 libxinerama1)
missing=()
for package in "${packages[@]}"; do
  dpkg -s "$package" >/dev/null 2>&1 || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
  as_root apt-get update -qq
  DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -qq "${missing[@]}"
fi

# Debian 12 ships Mesa 22.3; its bookworm-backports carry Mesa 25, whose lavapipe renders 1.4x to
# 1.6x as fast with the same pictures (bench/README.md's log). Debian 13 and Ubuntu use their own.
# WGPUTRACE_SYSTEM_MESA=1 keeps the system's Mesa (the renderer and its tests work on both).
. /etc/os-release
if [ "${ID:-}" = debian ] && [ "${VERSION_CODENAME:-}" = bookworm ] && [ -z "${WGPUTRACE_SYSTEM_MESA:-}" ] \
  && ! dpkg-query -W -f='${Version}' mesa-vulkan-drivers | grep -q '~bpo12'; then
  backports=/etc/apt/sources.list.d/wgputrace-bookworm-backports.sources
  if ! grep -rqs 'bookworm-backports' /etc/apt/sources.list /etc/apt/sources.list.d/; then
    printf 'Types: deb\nURIs: http://deb.debian.org/debian\nSuites: bookworm-backports\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' \
      | as_root tee "$backports" >/dev/null
  fi
  as_root apt-get update -qq
  DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -qq -t bookworm-backports mesa-vulkan-drivers
fi

python3 -m venv .venv
.venv/bin/python -m pip install -q --upgrade pip
# denoise: Intel Open Image Denoise, so that its tests (tests/denoise) run rather than skip; hdr: the
# Radiance .hdr reader, so that tests/scene/test_environment.py reads .hdr maps rather than skipping;
# draco: the Draco decoder, so that tests/loaders/test_gltf_extensions.py loads a compressed box;
# ktx2: the KTX2 transcoder, so that tests/loaders/test_gltf_ktx2.py reads the files alktx2 (test) makes;
# ray: Ray, so that tests/cluster render on a two-node cluster rather than skipping; docs: Sphinx and
# its extensions, which build the site (docs/conf.py)
.venv/bin/python -m pip install -q ".[test,bench,denoise,hdr,draco,ktx2,ray,docs]"
