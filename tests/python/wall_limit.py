"""Rigid-block limit analysis of a running-bond wall under tilted gravity.

The reference for the tilted walls of `tests/settle.rs` and
`docs/limits.md`: the largest multiplier on gravity's downhill component
for which contact forces in equilibrium exist, with rigid bricks, no
tension, and Coulomb friction at each joint's two ends (forces at a flat
joint's ends stand for any compressive distribution along it). A wall
whose multiplier is below 1 cannot stand, whatever its stiffness or time
step. Above 1 it may: with friction that does not dilate, the true limit
can lie higher than this (associative) one.

The wall is the `Wall` generator's: `courses` courses of 0.25 m × 0.125 m
bricks, `length` long, every odd course starting and ending with a half
brick, on a fixed footing.

    python wall_limit.py    # the table quoted in docs/limits.md
"""

import math

import numpy as np
from scipy.optimize import linprog
from scipy.sparse import lil_matrix

BRICK = (0.25, 0.125)
DENSITY = 1800.0
G = 9.81


def bricks(length, courses):
    """The wall's bricks as (x0, x1, y0, y1), course by course."""
    width, height = BRICK
    out = []
    for k in range(courses):
        edges = [0.0] + ([width / 2] if k % 2 else [])
        while edges[-1] + width <= length + 1e-12:
            edges.append(edges[-1] + width)
        if edges[-1] < length - 1e-12:
            edges.append(length)
        out += [(a, b, k * height, (k + 1) * height) for a, b in zip(edges, edges[1:])]
    return out


def joints(blocks):
    """Each joint as (lower or left block, upper or right block, its two
    ends, its normal from the first to the second); -1 is the footing."""
    out = []
    for j, (a, b, y0, y1) in enumerate(blocks):
        if y0 == 0.0:
            out.append((-1, j, [(a, 0.0), (b, 0.0)], (0.0, 1.0)))
        for i, (c, d, z0, z1) in enumerate(blocks):
            lo, hi = max(a, c), min(b, d)
            if abs(z1 - y0) < 1e-9 and hi - lo > 1e-9:
                out.append((i, j, [(lo, y0), (hi, y0)], (0.0, 1.0)))
            if abs(z0 - y0) < 1e-9 and abs(d - a) < 1e-9:
                out.append((i, j, [(a, y0), (a, y1)], (1.0, 0.0)))
    return out


def downhill_multiplier(length, courses, fos, tilt=30.0):
    """The largest multiplier on the downhill load of a wall whose joints'
    friction is `fos` times tan(tilt)."""
    blocks = bricks(length, courses)
    ends = [(i, j, p, n) for i, j, ps, n in joints(blocks) for p in ps]
    mu = fos * math.tan(math.radians(tilt))
    # Unknowns: a normal and a shear force at each end, then the multiplier.
    unknowns = 2 * len(ends) + 1
    equilibrium = lil_matrix((3 * len(blocks), unknowns))
    loads = np.zeros(3 * len(blocks))
    for k, (i, j, p, n) in enumerate(ends):
        t = (-n[1], n[0])
        for block, sign in ((j, 1.0), (i, -1.0)):
            if block < 0:
                continue
            x0, x1, y0, y1 = blocks[block]
            rx, ry = p[0] - (x0 + x1) / 2, p[1] - (y0 + y1) / 2
            for column, d in ((2 * k, n), (2 * k + 1, t)):
                fx, fy = sign * d[0], sign * d[1]
                for row, value in enumerate((fx, fy, rx * fy - ry * fx)):
                    equilibrium[3 * block + row, column] += value
    for block, (x0, x1, y0, y1) in enumerate(blocks):
        weight = DENSITY * G * (x1 - x0) * (y1 - y0)
        equilibrium[3 * block, -1] = weight * math.sin(math.radians(tilt))
        loads[3 * block + 1] = weight * math.cos(math.radians(tilt))
    friction = lil_matrix((2 * len(ends), unknowns))
    for k in range(len(ends)):
        friction[2 * k, 2 * k], friction[2 * k, 2 * k + 1] = -mu, 1.0
        friction[2 * k + 1, 2 * k], friction[2 * k + 1, 2 * k + 1] = -mu, -1.0
    cost = np.zeros(unknowns)
    cost[-1] = -1.0
    bounds = [(0.0, None), (None, None)] * len(ends) + [(0.0, 10.0)]
    found = linprog(cost, A_ub=friction.tocsr(), b_ub=np.zeros(2 * len(ends)),
                    A_eq=equilibrium.tocsr(), b_eq=loads, bounds=bounds, method="highs")
    assert found.status == 0, found.message
    return found.x[-1]


def limit_fos(length, courses, low=0.5, high=3.0):
    """The joints' factor of safety at which the multiplier reaches 1."""
    for _ in range(24):
        middle = (low + high) / 2
        if downhill_multiplier(length, courses, middle) >= 1.0:
            high = middle
        else:
            low = middle
    return high


if __name__ == "__main__":
    for length, courses in [(2.0, 4), (2.0, 8), (4.0, 16)]:
        n = len(bricks(length, courses))
        shares = ", ".join(f"FS {f}: {downhill_multiplier(length, courses, f):.3f}"
                           for f in (0.99, 1.01, 1.16, 1.3))
        print(f"{length} m × {courses} courses ({n} bricks): {shares}; "
              f"limit at FS {limit_fos(length, courses):.4f}")
