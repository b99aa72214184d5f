#!/usr/bin/env bash
# dda and MuJoCo on the same running-bond walls, one simulated second each,
# run alternately so both see the same machine: for each size, REPEATS
# rounds of (MuJoCo, then `dda bench --simulate 1`). Each run's JSON goes
# to OUT; the medians are printed at the end.
#
#   python3 -m venv target/bench-venv && target/bench-venv/bin/pip install mujoco
#   cargo build --release
#   benches/side_by_side.sh 10:3 20:1 40:1
#
# Each argument is SIZE:REPEATS. Environment: DDA (the dda binary, default
# target/release/dda), PYTHON (default target/bench-venv/bin/python), OUT
# (default target/side_by_side), MAX_WALL (dda's wall-clock cap per run in
# s, default 600: a capped run reports its rate over the time it reached).
set -euo pipefail
cd "$(dirname "$0")/.."
dda="${DDA:-target/release/dda}"
python="${PYTHON:-target/bench-venv/bin/python}"
out="${OUT:-target/side_by_side}"
cap="${MAX_WALL:-600}"
mkdir -p "$out"
for spec in "$@"; do
    n="${spec%%:*}"
    repeats="${spec#*:}"
    for r in $(seq 1 "$repeats"); do
        "$python" benches/mujoco_wall.py "$n" > "$out/mujoco_${n}_$r.json"
        echo "mujoco $n × $n, run $r: $(cat "$out/mujoco_${n}_$r.json")" >&2
        "$dda" bench --sizes "$n" --simulate 1 --max-wall "$cap" --repeats 1 \
            --json "$out/dda_${n}_$r.json" >&2
    done
done
"$python" - "$out" "$@" <<'EOF'
import json, statistics, sys
out, specs = sys.argv[1], sys.argv[2:]
print("| wall | bricks | engine | runs | dt s | wall s / simulated s (median) | simulated s reached | largest drift m |")
print("|---|---|---|---|---|---|---|---|")
for spec in specs:
    n, repeats = (int(x) for x in spec.split(":"))
    m = [json.load(open(f"{out}/mujoco_{n}_{r}.json")) for r in range(1, repeats + 1)]
    d = [json.load(open(f"{out}/dda_{n}_{r}.json"))["rows"][0] for r in range(1, repeats + 1)]
    med = lambda xs: statistics.median(xs)
    print(f"| {n} × {n} | {m[0]['bricks']} | {m[0]['engine']} | {repeats} | {m[0]['timestep']:g} | "
          f"{med([x['seconds_per_simulated_second'] for x in m]):.3g} | 1 | {med([x['drift_m'] for x in m]):.3g} |")
    print(f"| {n} × {n} | {d[0]['blocks'] - 1} | dda | {repeats} | {d[0]['dt']:.3g} | "
          f"{med([x['seconds_per_simulated_second'] for x in d]):.3g} | "
          f"{med([x['reached'] for x in d]):.3g} | {med([x['drift'] for x in d]):.3g} |")
EOF
