#!/usr/bin/env bash
# Installs every Debian 12 package pelt needs to build, test, benchmark and plot.
# Run as root on a fresh machine; safe to run again.
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
apt-get update
apt-get install -y --no-install-recommends \
  build-essential cmake ninja-build pkg-config git \
  libglm-dev libtinygltf-dev libstb-dev nlohmann-json3-dev \
  libopenimageio-dev openimageio-tools libpng-dev libjpeg62-turbo-dev libopenexr-dev \
  libbenchmark-dev libgtest-dev libgmock-dev \
  libhwy-dev libtbb-dev libcli11-dev libtinyobjloader-dev libmeshoptimizer-dev \
  python3 python3-matplotlib \
  clang libfuzzer-14-dev
