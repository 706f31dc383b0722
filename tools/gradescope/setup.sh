#!/usr/bin/env bash
# Gradescope runs this once, as root, when it builds the autograder image (Ubuntu LTS).
# The kit is unpacked in /autograder/source (made by ./kit autograder OUT.zip).
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
cd "$(dirname "$0")"
# python3 runs the kit; bubblewrap isolates the graded code. The kit installs the rest itself
# (the same packages as for students: one list, in tools/raykit/packages.py).
apt-get update -q
apt-get install -y -q --no-install-recommends python3 bubblewrap
# Build once now, by grading the solutions: the kit's side (tools/raykit/bundle.py: the judges,
# the dispatchers, the reference, in root's ~/.cache/raykit/bundles) and the precompiled step headers
# (tools/raykit/studentpch.py), so that each submission only compiles and links its own step files.
# (The stubs would build nothing: an untouched step is scored without a build.) Each job's results then
# say "built": "student files only" (extra_data; bundle.built), or why the job built the kit's side.
RAYKIT_STUDENT_PCH=build ./kit check --steps solutions --quiet || [ $? -eq 1 ]
