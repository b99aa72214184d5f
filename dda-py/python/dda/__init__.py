"""Discontinuous Deformation Analysis from Python.

Run a scene and read its results::

    import dda
    run = dda.run("examples/sliding_block_2d.ron", out="out/sliding")
    block = run.history[run.history["block"] == 1]
    print(block["x"].iloc[-1] - block["x"].iloc[0])   # m

Change a scene field by field and run it::

    scene = dda.Scene.load("examples/sliding_block_2d.ron")
    scene["default_joint.friction_angle"] = 25.0       # degrees
    run = scene.run(out="out/sliding_25")

Units are the scene's: SI (m, s, kg, N, Pa), angles in degrees. Every
error of a scene, a run or a result file is a :class:`DdaError` whose
message names the file, the place and the fix.
"""

import json
import os

from . import _native
from ._native import DdaError

try:  # DataFrames when pandas is there, dicts of numpy arrays otherwise.
    import pandas as _pandas
except ImportError:  # pragma: no cover - depends on the environment
    _pandas = None

import numpy as _numpy

__all__ = ["DdaError", "Run", "Scene", "run", "study", "read_table"]


def read_table(path):
    """Read a results CSV (history.csv, contacts.csv, points.csv, steps.csv, study.csv) by its header.

    Returns a pandas DataFrame, or a dict of numpy arrays (column name to
    array) when pandas is not installed. Counts (step, block, block_a,
    block_b, point, and steps.csv's passes, moves, factorizations, cuts,
    unconverged, whole_tangent_moves, products) are integers, other numbers floats in the units the file
    states (m, s, rad, N, Pa), anything else text.
    """
    columns = _native.read_table(os.fspath(path))
    arrays = {name: _numpy.asarray(values) for name, values in columns.items()}
    for name, values in columns.items():
        if not values:  # an empty column has no type of its own
            arrays[name] = _numpy.asarray(values, dtype=float)
    if _pandas is not None:
        return _pandas.DataFrame(arrays)
    return arrays


class Run:
    """The results of one run, in its output folder.

    Attributes:
        out: the output folder (str).
        summary: summary.json as a dict (status, steps, time in s,
            wall_time in s, statistics, notes).
    """

    def __init__(self, out, summary=None):
        self.out = os.fspath(out)
        if summary is None:
            with open(os.path.join(self.out, "summary.json"), encoding="utf-8") as f:
                summary = json.load(f)
        self.summary = summary
        self._history = None
        self._contacts = None
        self._points = None
        self._steps = None

    @property
    def dimension(self):
        """2 or 3, as the run's scene says."""
        return self.summary.get("dimension", 2)

    @property
    def history(self):
        """history.csv: one row per block per output time.

        2D columns: step, time (s), block, x, y (m), rotation (rad), vx, vy
        (m/s), omega (rad/s), sxx, syy, sxy (Pa). 3D: step, time, block,
        x, y, z, rx, ry, rz (rotation vector, rad), vx, vy, vz, wx, wy, wz,
        sxx, syy, szz, syz, szx, sxy. Read from the file's own header.
        """
        if self._history is None:
            self._history = read_table(os.path.join(self.out, "history.csv"))
        return self._history

    @property
    def contacts(self):
        """contacts.csv: one row per contact per output time.

        Columns: step, time (s), contact (its name), block_a, block_b,
        state (open, locked, sliding), fn and fs (N per m of thickness in
        2D, N in 3D), slip (m). Only written when the scene's output asks
        for it (``output: (contacts: true)``); :class:`DdaError` otherwise.
        """
        if self._contacts is None:
            self._contacts = self._asked_for("contacts")
        return self._contacts

    @property
    def points(self):
        """points.csv: one row per measured point per output time.

        Columns: time (s), point (its index in the scene's
        ``measured_points``), block, x, y (m, where it is; x, y, z in 3D),
        dx, dy (m, how far it has moved since the start; dx, dy, dz in
        3D). None when the scene has no ``measured_points``.
        """
        if self._points is None:
            path = os.path.join(self.out, "points.csv")
            if not os.path.exists(path):
                return None
            self._points = read_table(path)
        return self._points

    @property
    def steps(self):
        """steps.csv: one row per accepted step, what it cost.

        Columns: step, time and dt (s), passes (open-close), moves
        (Newton-Raphson), factorizations, cuts (attempts cut to a third
        before it was accepted), unconverged (1 if accepted without
        open-close agreement), whole_tangent_moves, products (GMRES's),
        energy (J, J/m in 2D), wall_ms, and of that search_ms,
        assembly_ms, factorization_ms, solve_ms, open_close_ms and
        commit_ms. Only written when asked for
        (``output: (steps: true)`` or ``dda run --steps``);
        :class:`DdaError` otherwise.
        """
        if self._steps is None:
            self._steps = self._asked_for("steps")
        return self._steps

    def _asked_for(self, name):
        """NAME.csv, an output the scene's ``output.NAME`` asks for."""
        path = os.path.join(self.out, f"{name}.csv")
        if not os.path.exists(path):
            raise DdaError(
                f"{path}: no {name} were written; set `output: ({name}: true)` "
                f"in the scene (scene['output.{name}'] = True) and run it again"
            )
        return read_table(path)

    def __repr__(self):
        return (
            f"Run(out={self.out!r}, status={self.summary.get('status')!r}, "
            f"steps={self.summary.get('steps')}, time={self.summary.get('time')})"
        )


def _default_out(scene_path):
    stem = os.path.splitext(os.path.basename(os.fspath(scene_path)))[0] or "scene"
    return os.path.join("out", stem)


def run(scene, out=None):
    """Run a scene file (RON) to its end and return its :class:`Run`.

    Args:
        scene: path of the scene file.
        out: output folder (created if missing); default out/<scene name>
            under the current folder, as ``dda run``.

    The run is quiet (no progress bar) and releases the GIL while it runs.
    Raises :class:`DdaError` naming the file and the place when the scene
    is wrong or the run fails (a failed run still leaves summary.json and
    the rows it wrote in ``out``).
    """
    out = os.fspath(out) if out is not None else _default_out(scene)
    summary = _native.run_file(os.fspath(scene), out)
    return Run(out, json.loads(summary))


def study(study_file, out, jobs=None):
    """Run a parameter study (``dda study STUDY --out OUT --jobs N``).

    Args:
        study_file: path of the study file (RON).
        out: output folder; each case runs into a folder of its own there.
        jobs: how many cases run at once (default: the command's choice).

    Returns ``OUT/study.csv`` (one row per case: its parameters and
    results) as a DataFrame, or a dict of numpy arrays without pandas.
    Raises :class:`DdaError` with the message when the study cannot run;
    a case that fails is a row with its outcome.
    """
    out = os.fspath(out)
    _native.run_study(os.fspath(study_file), out, jobs)
    return read_table(os.path.join(out, "study.csv"))


class Scene:
    """A scene, read from a file or text, changed field by field and run.

    Fields are named by dotted paths in the words of the scene file:
    ``scene["analysis.dt"]`` (s), ``scene["blocks.1.angle"]`` (degrees),
    ``scene["materials.rock.density"]`` (kg/m³),
    ``scene["default_joint.friction_angle"]`` (degrees). Each change is
    checked as a file with that value would be: a bad value raises
    :class:`DdaError` naming the field, and the scene is left as it was.
    Compound values read back as dicts and lists; one may be replaced by a
    dict, a list, or its RON text (``scene["default_joint"] =
    "Coulomb(friction_angle: 25.0)"``).
    """

    def __init__(self, native):
        self._native = native

    @classmethod
    def load(cls, path):
        """Read and check a scene file (RON); :class:`DdaError` if it is wrong."""
        return cls(_native.NativeScene.load(os.fspath(path)))

    @classmethod
    def from_ron(cls, text, origin="<text>"):
        """Parse and check scene text; ``origin`` names it in error messages.

        Files the scene names (ground-motion records) are relative to the
        current folder.
        """
        return cls(_native.NativeScene.from_ron(text, origin))

    def __getitem__(self, path):
        """The value at a dotted path (KeyError naming what is there if none)."""
        return self._native.get(path)

    def __setitem__(self, path, value):
        """Set the value at a dotted path and check the whole scene again."""
        self._native.set(path, value)

    def get(self, path, default=None):
        """The value at a dotted path, or ``default`` if there is none."""
        try:
            return self._native.get(path)
        except KeyError:
            return default

    def to_ron(self):
        """The scene as RON text that :meth:`from_ron` reads back."""
        return self._native.to_ron()

    @property
    def origin(self):
        """The file (or text) the scene came from, and what was changed."""
        return self._native.origin()

    @property
    def dimension(self):
        """2 or 3."""
        return self._native.dimension()

    @property
    def block_count(self):
        """How many blocks the scene has, generators expanded."""
        return self._native.block_count()

    def run(self, out):
        """Run the scene into the folder ``out`` and return its :class:`Run`.

        A changed scene is first written to ``out/scene.ron``, which the
        run's summary names. Releases the GIL while it runs; raises
        :class:`DdaError` if the run fails.
        """
        out = os.fspath(out)
        summary = self._native.run(out)
        return Run(out, json.loads(summary))

    def __repr__(self):
        return f"Scene({self.origin!r}, dimension={self.dimension}, blocks={self.block_count})"
