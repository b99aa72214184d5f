"""A block on a 30° incline for several joint friction angles.

Runs examples/sliding_block_2d.ron, changes the friction angle of its
joint, and compares how far the block slides in 1 s with the closed form
d = ½ g (sin 30° − cos 30° tan φ) t² (zero once φ ≥ 30°: the block holds).

    python examples/python/sliding_block.py [OUT_FOLDER]

Needs the dda package (see README, "Look at the results"); draws
sliding_block.png with matplotlib when it is installed.
"""

import math
import os
import sys

import numpy as np

import dda

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.normpath(os.path.join(HERE, "..", "sliding_block_2d.ron"))
OUT = sys.argv[1] if len(sys.argv) > 1 else os.path.join("out", "python_sliding_block")
G = 9.81  # m/s²


def closed_form(friction, t=1.0, incline=30.0):
    """Distance slid in t seconds, m (0 when friction holds the block)."""
    th, ph = math.radians(incline), math.radians(friction)
    a = G * (math.sin(th) - math.cos(th) * math.tan(ph))
    return max(a, 0.0) * t**2 / 2


def slid(run, block=1):
    """Time (s) and distance of the block's centroid from its start (m)."""
    history = run.history
    keep = np.asarray(history["block"]) == block
    t = np.asarray(history["time"])[keep]
    x = np.asarray(history["x"])[keep]
    y = np.asarray(history["y"])[keep]
    return t, np.hypot(x - x[0], y - y[0])


scene = dda.Scene.load(SCENE)
print(f"{scene}: friction angle {scene['default_joint.friction_angle']}°")

curves = {}
print(" φ (°)   d(1 s) DDA (m)   closed form (m)")
for friction in [10.0, 15.0, 20.0, 25.0, 35.0]:
    scene["default_joint.friction_angle"] = friction
    run = scene.run(out=os.path.join(OUT, f"phi_{friction:g}"))
    t, d = slid(run)
    curves[friction] = (t, d)
    print(f"{friction:5.1f}   {d[-1]:14.4f}   {closed_form(friction):15.4f}")

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print("matplotlib is not installed: no plot")
else:
    fig, ax = plt.subplots(figsize=(6, 4))
    for friction, (t, d) in curves.items():
        ax.plot(t, d, label=f"φ = {friction:g}°")
        ax.plot(t, [closed_form(friction, s) for s in t], "k:", linewidth=0.8)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("distance slid (m)")
    ax.set_title("Block on a 30° incline (dotted: closed form)")
    ax.legend()
    path = os.path.join(OUT, "sliding_block.png")
    fig.savefig(path, dpi=120, bbox_inches="tight")
    print(f"plot: {path}")
