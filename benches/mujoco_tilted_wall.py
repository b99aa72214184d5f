#!/usr/bin/env python3
"""The tilted walls of docs/limits.md in MuJoCo, for comparison.

The running-bond walls of `tests/python/wall_limit.py` (0.25 m x 0.125 m
bricks, density 1800 kg/m^3, odd courses ending in half bricks) become
boxes 0.25 m deep on a fixed footing, each a free body. Gravity is tilted
by 30 degrees toward +x and the friction coefficient is FS times tan 30
degrees, as in `tests/settle.rs`. MuJoCo's options are set for holding
contacts (elliptic cones, impratio 100, 20 no-slip iterations, 1 ms
steps) unless `--defaults` is given.

Prints, every tenth of the run, the farthest any brick has moved from
where it was built (m).

    target/bench-venv/bin/python benches/mujoco_tilted_wall.py 2.0 8 2.0 [--seconds 1]
"""

import argparse
import math
import os
import sys

import mujoco
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests", "python"))
from wall_limit import DENSITY, bricks  # noqa: E402

DEPTH = 0.25
HOLDING = 'cone="elliptic" impratio="100" noslip_iterations="20" timestep="0.001"'


def model_xml(length, courses, fos, options):
    mu = fos * math.tan(math.radians(30.0))
    sin, cos = math.sin(math.radians(30.0)), math.cos(math.radians(30.0))
    parts = [
        '<mujoco model="tilted wall">',
        f'<option gravity="{9.81 * sin} 0 {-9.81 * cos}" {options}/>',
        '<size memory="256M"/>',
        f'<default><geom friction="{mu:.6f} 0.005 0.0001" density="{DENSITY}"/></default>',
        "<worldbody>",
        f'<geom name="footing" type="box" pos="{length / 2} 0 -0.25" '
        f'size="{length / 2 + 0.5} {DEPTH / 2 + 0.5} 0.25"/>',
    ]
    for x0, x1, z0, z1 in bricks(length, courses):
        parts.append(
            f'<body pos="{(x0 + x1) / 2} 0 {(z0 + z1) / 2}"><freejoint/>'
            f'<geom type="box" size="{(x1 - x0) / 2} {DEPTH / 2} {(z1 - z0) / 2}"/></body>'
        )
    parts += ["</worldbody>", "</mujoco>"]
    return "\n".join(parts)


def farthest_by_time(length, courses, fos, seconds, options):
    model = mujoco.MjModel.from_xml_string(model_xml(length, courses, fos, options))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    start = data.xpos[1:].copy()
    steps = int(round(seconds / model.opt.timestep))
    every = max(1, steps // 10)
    out = []
    for k in range(steps):
        mujoco.mj_step(model, data)
        if (k + 1) % every == 0:
            far = np.sqrt(((data.xpos[1:] - start) ** 2).sum(axis=1)).max()
            out.append((data.time, float(far)))
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("length", type=float, help="the wall's length, m")
    p.add_argument("courses", type=int, help="its courses")
    p.add_argument("fos", type=float, help="the bed joints' factor of safety")
    p.add_argument("--seconds", type=float, default=1.0, help="simulated time, s")
    p.add_argument("--defaults", action="store_true", help="MuJoCo's default options")
    a = p.parse_args()
    if a.length <= 0 or a.courses < 1 or a.fos <= 0 or not (a.seconds > 0):
        p.error("length, courses, fos and seconds must be positive")
    options = "" if a.defaults else HOLDING
    for t, far in farthest_by_time(a.length, a.courses, a.fos, a.seconds, options):
        print(f"t = {t:.3f} s: farthest {far:.3e} m")


if __name__ == "__main__":
    main()
