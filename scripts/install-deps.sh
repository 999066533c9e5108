#!/usr/bin/env bash
# Installs froth's build, test and benchmark dependencies: Debian bookworm packages only.
set -euo pipefail
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO=sudo
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends \
  g++ cmake make pkg-config \
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev \
  librandom123-dev libcli11-dev libfmt-dev nlohmann-json3-dev libpugixml-dev zlib1g-dev \
  libgtest-dev libbenchmark-dev voro++-dev libopenmpi-dev openmpi-bin \
  python3 python3-dev python3-venv python3-pip python3-setuptools python3-wheel python3-numpy python3-pytest python3-scipy pybind11-dev python3-vtk9 python3-meshio python3-matplotlib python3-jsonschema xvfb xauth \
  openfoam libexodusii-dev \
  clang libclang-rt-14-dev libomp-dev
