#!/usr/bin/env python3
"""The wall `dda bench` runs, in MuJoCo at its default options, for comparison.

A running-bond wall of N courses of N bricks (0.5 m x 0.25 m, density
1800 kg/m^3, friction coefficient tan 35 deg) stands on a fixed base under
gravity -9.81 m/s^2, as `dda bench` builds it: odd courses start and end
with a half brick. The 2D wall becomes boxes 0.25 m deep (along y, z up),
each a free body: nothing holds them to the plane. Everything else is
MuJoCo's default (`<option>` left out: timestep 2 ms, Euler, pyramidal
cones, Newton solver, soft contacts); only the arena is sized so no contact
is dropped.

Runs the wall for SECONDS of simulated time (default 1) and prints JSON:
wall-clock seconds per simulated second (mj_step alone, the model built
beforehand), steps, the largest brick drift (centroid displacement from
where it was built, the largest over every step), and MuJoCo's warnings.

    python3 -m venv target/bench-venv
    target/bench-venv/bin/pip install mujoco
    target/bench-venv/bin/python benches/mujoco_wall.py 40 [--seconds 1]
"""

import argparse
import json
import math
import platform
import time

import mujoco
import numpy as np

BRICK = (0.5, 0.25)  # length along x, height along z, m
DEPTH = 0.25  # along y, m
DENSITY = 1800.0
FRICTION = math.tan(math.radians(35.0))


def bricks(n):
    """(x0, x1, z0, z1) of each brick, courses from the bottom up."""
    length, (bl, bh) = n * BRICK[0], BRICK
    out = []
    for c in range(n):
        offset = bl / 2.0 if c % 2 == 1 else 0.0
        cuts = [0.0] + ([offset] if offset > 0 else [])
        x = offset + bl
        while x < length - 1e-9:
            cuts.append(x)
            x += bl
        cuts.append(length)
        for a, b in zip(cuts, cuts[1:]):
            out.append((a, b, c * bh, (c + 1) * bh))
    return out


def model_xml(n):
    length = n * BRICK[0]
    parts = [
        '<mujoco model="wall">',
        # Room for every contact of a standing wall (MuJoCo's default arena
        # overflows past a few hundred boxes); no physics option is set.
        '<size memory="%dM"/>' % max(64, n * n // 2),
        f'<default><geom friction="{FRICTION:.6f} 0.005 0.0001" density="{DENSITY}"/></default>',
        "<worldbody>",
        # The fixed base: 1 m high, a metre wider than the wall each side.
        f'<geom name="base" type="box" pos="{length / 2} 0 -0.5" size="{length / 2 + 1} {DEPTH / 2 + 0.5} 0.5"/>',
    ]
    for i, (x0, x1, z0, z1) in enumerate(bricks(n)):
        parts.append(
            f'<body name="b{i}" pos="{(x0 + x1) / 2} 0 {(z0 + z1) / 2}"><freejoint/>'
            f'<geom type="box" size="{(x1 - x0) / 2} {DEPTH / 2} {(z1 - z0) / 2}"/></body>'
        )
    parts += ["</worldbody>", "</mujoco>"]
    return "\n".join(parts)


def run(n, seconds):
    model = mujoco.MjModel.from_xml_string(model_xml(n))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    start = data.xpos[1:].copy()
    steps = int(round(seconds / model.opt.timestep))
    drift = 0.0
    stepping = 0.0
    for _ in range(steps):
        t = time.perf_counter()
        mujoco.mj_step(model, data)
        stepping += time.perf_counter() - t
        d = np.sqrt(((data.xpos[1:] - start) ** 2).sum(axis=1)).max()
        drift = max(drift, float(d))
    warnings = {
        mujoco.mjtWarning(i).name: int(w.number)
        for i, w in enumerate(data.warning)
        if w.number > 0
    }
    return {
        "engine": "mujoco " + mujoco.__version__,
        "python": platform.python_version(),
        "courses": n,
        "bricks": model.nbody - 1,
        "timestep": model.opt.timestep,
        "simulated_s": data.time,
        "steps": steps,
        "wall_s": stepping,
        "seconds_per_simulated_second": stepping / data.time,
        "ms_per_step": stepping * 1e3 / steps,
        "drift_m": drift,
        "contacts_at_end": int(data.ncon),
        "warnings": warnings,
    }


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("courses", type=int, help="N: N courses of N bricks")
    p.add_argument("--seconds", type=float, default=1.0, help="simulated time, s")
    a = p.parse_args()
    if a.courses < 1 or not (a.seconds > 0):
        p.error("courses must be 1 or more and seconds more than 0")
    print(json.dumps(run(a.courses, a.seconds)))


if __name__ == "__main__":
    main()
