"""Rigid-block limit analysis of a running-bond wall under tilted gravity.

The reference for the tilted walls of `tests/settle.rs` and
`docs/limits.md`: the largest multiplier on gravity's downhill component
for which contact forces in equilibrium exist, with rigid bricks, no
tension, and Coulomb friction at each joint's two ends (forces at a flat
joint's ends stand for any compressive distribution along it). A wall
whose multiplier is below 1 cannot stand, whatever its stiffness or time
step. Above 1 it may: with friction that does not dilate, the factor of
safety a wall needs can lie higher than this (associative) analysis says.

Joints that slide without dilating can also topple a wall this analysis
holds up: `stair_wedge` finds the wedge that breaks off at the downhill
end along a stair-stepped crack. Rotating about its toe, every joint of
its crack opens but the lowest head joint's bottom end, which slides
with no opening, so with no friction there it stands only where its
weight's moment about the toe outweighs the downhill load's
(`toe_multiplier`). The associative analysis holds it by friction across
the crack, where a crack that opens as it slides pays dilatancy against
the load; a joint that does not dilate carries no friction once open.

The wall is the `Wall` generator's: `courses` courses of 0.25 m × 0.125 m
bricks, `length` long, every odd course starting and ending with a half
brick, on a fixed footing.

    python wall_limit.py    # the table quoted in docs/limits.md
"""

import math

import numpy as np

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


def downhill_multiplier(length, courses, fos, tilt=30.0, opened=None, least_at=None):
    """The largest multiplier on the downhill load of a wall whose joints'
    friction is `fos` times tan(tilt). `opened(i, j, point, normal)` says
    which joint ends carry nothing (default: none). With `least_at`, a
    joint end as (i, j, point, normal), the least compression (N/m) that
    end needs to carry the whole load instead."""
    # Imported here so the wall's geometry needs numpy alone
    # (benches/mujoco_tilted_wall.py builds the same wall).
    from scipy.optimize import linprog
    from scipy.sparse import lil_matrix

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
    for k, end in enumerate(ends):
        if opened is not None and opened(*end):
            bounds[2 * k] = bounds[2 * k + 1] = (0.0, 0.0)
    if least_at is not None:
        k = ends.index(least_at)
        cost[-1], cost[2 * k] = 0.0, 1.0
        bounds[-1] = (1.0, 1.0)
    found = linprog(cost, A_ub=friction.tocsr(), b_ub=np.zeros(2 * len(ends)),
                    A_eq=equilibrium.tocsr(), b_eq=loads, bounds=bounds, method="highs")
    assert found.status == 0, found.message
    return found.x[2 * k] if least_at is not None else found.x[-1]


def limit_fos(length, courses, low=0.5, high=3.0):
    """The joints' factor of safety at which the multiplier reaches 1."""
    for _ in range(24):
        middle = (low + high) / 2
        if downhill_multiplier(length, courses, middle) >= 1.0:
            high = middle
        else:
            low = middle
    return high


def stair_wedge(length, courses, base):
    """The bricks above a stair-stepped crack from the wall's downhill end
    at course `base`: the end brick of that course, and each course above
    it half a brick wider, so the crack climbs at the bond's 45 degrees."""
    width, height = BRICK
    blocks = bricks(length, courses)
    first = [b for b in blocks if abs(b[2] - base * height) < 1e-9]
    reach = first[-1][1] - first[-1][0]
    return [i for i, (x0, x1, y0, y1) in enumerate(blocks)
            if y0 > base * height - 1e-9
            and x0 >= length - reach - width / 2 * round((y0 - base * height) / height) - 1e-9]


def toe_multiplier(length, courses, base, tilt=30.0):
    """The downhill load's multiplier at which a stair wedge (`stair_wedge`)
    standing on its toe alone tips: its weight's moment about the toe over
    the downhill load's."""
    blocks = bricks(length, courses)
    toe = (length, base * BRICK[1])
    # Each brick's weight is its area times one density, which cancels.
    area = lambda b: (b[1] - b[0]) * (b[3] - b[2])
    wedge = [blocks[i] for i in stair_wedge(length, courses, base)]
    down = sum(area(b) * ((b[2] + b[3]) / 2 - toe[1]) for b in wedge)
    into = sum(area(b) * (toe[0] - (b[0] + b[1]) / 2) for b in wedge)
    return into * math.cos(math.radians(tilt)) / (down * math.sin(math.radians(tilt)))


def crack_opened(length, courses, base, keep_corner=False):
    """`opened` for `downhill_multiplier`: every end of the stair wedge's
    crack but its toe (and, with `keep_corner`, its lowest head joint's
    bottom end, which slides as the wedge tips and does not open)."""
    wedge = set(stair_wedge(length, courses, base))
    toe = (length, base * BRICK[1])
    corner = crack_corner(length, courses, base)

    def opened(i, j, point, normal):
        if (i in wedge) == (j in wedge):
            return False
        if normal == (0.0, 1.0) and math.dist(point, toe) < 1e-9:
            return False
        return not (keep_corner and (i, j, point, normal) == corner)
    return opened


def crack_corner(length, courses, base):
    """The stair wedge's lowest head joint's bottom end, as a joint end."""
    blocks = bricks(length, courses)
    wedge = set(stair_wedge(length, courses, base))
    lowest = min(wedge, key=lambda i: (blocks[i][2], blocks[i][0]))
    x0, _, y0, _ = blocks[lowest]
    left = next(i for i, b in enumerate(blocks) if abs(b[1] - x0) < 1e-9 and abs(b[2] - y0) < 1e-9)
    return (left, lowest, (x0, y0), (1.0, 0.0))


if __name__ == "__main__":
    for length, courses in [(2.0, 4), (2.0, 8), (4.0, 16)]:
        n = len(bricks(length, courses))
        shares = ", ".join(f"FS {f}: {downhill_multiplier(length, courses, f):.3f}"
                           for f in (0.99, 1.01, 1.16, 1.3))
        print(f"{length} m × {courses} courses ({n} bricks): {shares}; "
              f"limit at FS {limit_fos(length, courses):.4f}")
    wedge = stair_wedge(2.0, 8, 1)
    print(f"2.0 m × 8 courses: the {len(wedge)}-brick stair wedge from course 1 tips on its "
          f"toe alone at {toe_multiplier(2.0, 8, 1):.4f}")
    for fos in (1.5, 2.0, 2.5, 3.0, 10.0):
        alone = downhill_multiplier(2.0, 8, fos, opened=crack_opened(2.0, 8, 1))
        corner = downhill_multiplier(2.0, 8, fos, opened=crack_opened(2.0, 8, 1, True))
        least = downhill_multiplier(2.0, 8, fos, opened=crack_opened(2.0, 8, 1, True),
                                    least_at=crack_corner(2.0, 8, 1))
        print(f"  FS {fos}: crack open but the toe {alone:.4f}; and its corner {corner:.4f}, "
              f"which needs {least:.0f} N/m of compression to carry the load")
