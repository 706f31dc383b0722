#!/usr/bin/env bash
# Gradescope runs this once, as root, when it builds the autograder image.
# The kit itself is unpacked in /autograder/source (zip the kit, without build/).
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
apt-get update -q
apt-get install -y -q --no-install-recommends python3 cmake ninja-build g++ pkg-config \
  libglm-dev doctest-dev libstb-dev
# Build once now, so each submission only compiles its own step files.
cd /autograder/source && ./kit check --quiet || true
