#!/usr/bin/env bash
# Every speed target of the walls measured in one run, on one machine:
# MuJoCo on the 40 × 40 wall (one simulated second at its defaults), then
# `dda bench --targets` with that run, which prints the Markdown table of
# targets, readings and verdicts under the machine and the date.
#
#   python3 -m venv target/bench-venv && target/bench-venv/bin/pip install mujoco
#   cargo build --release
#   benches/targets.sh
#
# Environment: DDA (the dda binary, default target/release/dda), PYTHON
# (default target/bench-venv/bin/python), OUT (default target/targets:
# mujoco_40.json and targets.json go there).
set -euo pipefail
cd "$(dirname "$0")/.."
dda="${DDA:-target/release/dda}"
python="${PYTHON:-target/bench-venv/bin/python}"
out="${OUT:-target/targets}"
mkdir -p "$out"
"$python" benches/mujoco_wall.py 40 > "$out/mujoco_40.json"
echo "mujoco 40 × 40: $(cat "$out/mujoco_40.json")" >&2
"$dda" bench --targets --mujoco "$out/mujoco_40.json" --json "$out/targets.json"
