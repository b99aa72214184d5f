"""The Python package: runs, results as tables, scenes changed by path.

Run with pytest after installing the wheel (see .ci/run).
"""

import math
import os

import numpy as np
import pytest

import dda

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples")
G = 9.81  # m/s², as the examples give gravity


def example(name):
    return os.path.join(EXAMPLES, name)


def column(table, name):
    """A column as a numpy array, from a DataFrame or a dict alike."""
    return np.asarray(table[name])


def rows_of_block(table, block):
    keep = column(table, "block") == block
    return {name: column(table, name)[keep] for name in table.keys()}


def slide_distance(t, incline=30.0, friction=20.0):
    """d = ½ g (sin θ − cos θ tan φ) t², m."""
    th, ph = math.radians(incline), math.radians(friction)
    return 0.5 * G * (math.sin(th) - math.cos(th) * math.tan(ph)) * t**2


def travelled(rows, axes):
    start = np.array([rows[a][0] for a in axes])
    end = np.array([rows[a][-1] for a in axes])
    return float(np.linalg.norm(end - start))


def test_sliding_block_2d_travels_as_the_closed_form_says(tmp_path):
    run = dda.run(example("sliding_block_2d.ron"), out=tmp_path / "run")
    assert run.summary["status"] == "finished"
    assert run.out == os.fspath(tmp_path / "run")
    block = rows_of_block(run.history, 1)
    assert block["time"][-1] == pytest.approx(1.0, abs=1e-12)
    d = travelled(block, ["x", "y"])
    assert d == pytest.approx(slide_distance(1.0), rel=5e-3)
    assert slide_distance(1.0) == pytest.approx(0.9064, abs=1e-4)


def test_a_3d_history_reads_back_with_3d_columns(tmp_path):
    run = dda.run(example("sliding_block_3d.ron"), out=tmp_path / "run")
    assert run.dimension == 3
    names = list(run.history.keys())
    assert names[:6] == ["step", "time", "block", "x", "y", "z"]
    assert {"rx", "ry", "rz", "wx", "wy", "wz", "szz", "syz", "szx"} <= set(names)
    assert "rotation" not in names
    block = rows_of_block(run.history, 1)
    assert travelled(block, ["x", "y", "z"]) == pytest.approx(slide_distance(1.0), rel=5e-3)
    # The dip falls 0.5 m per metre along it.
    assert block["z"][0] - block["z"][-1] == pytest.approx(0.5 * slide_distance(1.0), rel=5e-3)


def test_scene_fields_read_and_change_by_path(tmp_path):
    scene = dda.Scene.load(example("sliding_block_2d.ron"))
    assert scene.dimension == 2
    assert scene.block_count == 2
    assert scene["analysis.dt"] == pytest.approx(1e-3)
    assert scene["default_joint.friction_angle"] == 20.0
    assert scene["blocks.1.angle"] == scene["blocks[1].angle"] == 30.0
    assert scene["materials.rock.density"] == scene['materials["rock"].density'] == 2700.0
    with pytest.raises(KeyError, match="dtt"):
        scene["analysis.dtt"]

    scene["analysis.duration"] = 0.5
    assert scene["analysis.duration"] == 0.5
    assert "duration: 0.5" in scene.to_ron()
    run = scene.run(out=tmp_path / "half")
    time = column(run.history, "time")
    assert time.max() == pytest.approx(0.5, abs=1e-12)
    block = rows_of_block(run.history, 1)
    assert travelled(block, ["x", "y"]) == pytest.approx(slide_distance(0.5), rel=5e-3)
    # What ran is kept beside the results and reads back as the same scene.
    again = dda.Scene.load(tmp_path / "half" / "scene.ron")
    assert again.to_ron() == scene.to_ron()


def test_a_friction_change_changes_the_slide(tmp_path):
    scene = dda.Scene.load(example("sliding_block_2d.ron"))
    scene["default_joint"] = "Coulomb(friction_angle: 25.0)"
    assert scene["default_joint.friction_angle"] == 25.0
    scene["analysis.duration"] = 0.5
    run = scene.run(out=tmp_path / "phi25")
    block = rows_of_block(run.history, 1)
    expected = slide_distance(0.5, friction=25.0)
    assert travelled(block, ["x", "y"]) == pytest.approx(expected, rel=5e-3)


def test_a_bad_value_is_refused_with_the_field_named():
    scene = dda.Scene.load(example("sliding_block_2d.ron"))
    before = scene.to_ron()
    with pytest.raises(dda.DdaError) as error:
        scene["analysis.dt"] = -1.0
    message = str(error.value)
    assert "analysis.dt" in message
    assert "sliding_block_2d.ron" in message
    assert "positive" in message
    assert scene.to_ron() == before
    with pytest.raises(dda.DdaError, match="dtt"):
        scene["analysis.dtt"] = 1.0


def test_a_scene_from_text(tmp_path):
    text = dda.Scene.load(example("free_fall_2d.ron")).to_ron()
    scene = dda.Scene.from_ron(text, origin="falling")
    assert scene.origin == "falling"
    scene["analysis.duration"] = 0.2
    run = scene.run(out=tmp_path / "fall")
    block = rows_of_block(run.history, 0)
    t = block["time"][-1]
    assert t == pytest.approx(0.2, abs=1e-12)
    # y = y0 − g t²/2
    assert block["y"][0] - block["y"][-1] == pytest.approx(0.5 * G * t**2, rel=1e-6)
    with pytest.raises(dda.DdaError, match="falling"):
        dda.Scene.from_ron("Scene(analysis: (duration: -1.0))", origin="falling")


def test_contacts_carry_the_weight_and_slide_at_the_friction_angle(tmp_path):
    scene = dda.Scene.load(example("sliding_block_2d.ron"))
    scene["output.contacts"] = True
    run = scene.run(out=tmp_path / "contacts")
    contacts = run.contacts
    assert list(contacts.keys()) == [
        "step", "time", "contact", "block_a", "block_b", "state", "fn", "fs", "slip",
    ]
    time = column(contacts, "time")
    last = time == time.max()
    states = set(column(contacts, "state")[last])
    assert states == {"sliding"}
    fn = column(contacts, "fn")[last]
    fs = column(contacts, "fs")[last]
    # The block's weight normal to the incline, per metre of thickness:
    # ρ g cos 30° over a 1 m square.
    weight = 2700.0 * G * math.cos(math.radians(30.0))
    assert fn.sum() == pytest.approx(weight, rel=1e-3)
    assert fs / fn == pytest.approx(np.full(len(fn), math.tan(math.radians(20.0))), rel=1e-6)
    slip = column(contacts, "slip")[last]
    assert slip.max() == pytest.approx(slide_distance(1.0), rel=5e-3)


def test_steps_add_up_to_the_run(tmp_path):
    scene = dda.Scene.load(example("sliding_block_2d.ron"))
    scene["analysis.duration"] = 0.2
    scene["output.steps"] = True
    run = scene.run(out=tmp_path / "steps")
    steps = run.steps
    assert list(steps.keys()) == [
        "step", "time", "dt", "passes", "moves", "factorizations", "cuts",
        "unconverged", "whole_tangent_moves", "products", "energy", "wall_ms",
        "search_ms", "assembly_ms", "factorization_ms", "solve_ms",
        "open_close_ms", "commit_ms",
    ]
    assert column(steps, "moves").dtype.kind == "i"
    assert len(column(steps, "step")) == run.summary["steps"]
    assert column(steps, "moves").sum() == run.summary["newton_iterations"]
    assert column(steps, "passes").sum() == run.summary["open_close_iterations"]
    assert column(steps, "dt").sum() == pytest.approx(0.2, abs=1e-12)
    assembly = run.summary["phases"]["assembly"]
    assert column(steps, "assembly_ms").sum() == pytest.approx(1e3 * assembly, abs=1e-3 * len(column(steps, "step")))
    with pytest.raises(dda.DdaError, match="steps: true"):
        dda.run(example("free_fall_2d.ron"), out=tmp_path / "none").steps


def test_a_measured_point_slides_with_its_block(tmp_path):
    scene = dda.Scene.load(example("sliding_block_2d.ron"))
    scene["measured_points"] = "[(block: 1, point: (-0.5, 0.8660254037844386))]"
    run = scene.run(out=tmp_path / "points")
    points = run.points
    assert list(points.keys()) == ["time", "point", "block", "x", "y", "dx", "dy"]
    assert set(column(points, "block")) == {1}
    block = rows_of_block(run.history, 1)
    # The point is the block's centroid: it moves as history.csv says.
    assert np.allclose(column(points, "x"), block["x"], rtol=0, atol=1e-9)
    assert np.allclose(column(points, "dy"), block["y"] - block["y"][0], rtol=0, atol=1e-9)
    th = math.radians(30.0)
    dx, dy = column(points, "dx")[-1], column(points, "dy")[-1]
    along = -(dx * math.cos(th) + dy * math.sin(th))
    assert along == pytest.approx(slide_distance(1.0), rel=0.01)
    assert dda.run(example("free_fall_2d.ron"), out=tmp_path / "none").points is None


def test_a_settled_stack_starts_at_rest(tmp_path):
    """analysis.settle set from Python as a dict: the ten-block stack
    starts at its static settlement and stays there (tests/settle.rs)."""
    scene = dda.Scene.load(example("stacked_blocks_2d.ron"))
    scene["analysis.settle"] = {}
    scene["analysis.duration"] = 0.2
    run = scene.run(out=tmp_path / "settled")
    settling = run.summary["settling"]
    assert settling["settled"] and settling["steps"] <= 3
    top = rows_of_block(run.history, 10)
    assert 4.75 - top["y"][0] > 3e-4
    assert np.ptp(top["y"]) < 1e-9


def test_contacts_not_asked_for_say_how_to_get_them(tmp_path):
    run = dda.run(example("free_fall_2d.ron"), out=tmp_path / "fall")
    with pytest.raises(dda.DdaError, match="contacts: true"):
        run.contacts


def test_a_missing_file_is_a_dda_error(tmp_path):
    missing = tmp_path / "no_such_scene.ron"
    with pytest.raises(dda.DdaError, match="no_such_scene.ron") as error:
        dda.run(missing, out=tmp_path / "out")
    assert "cannot read" in str(error.value)
    with pytest.raises(dda.DdaError, match="no_such_scene.ron"):
        dda.Scene.load(missing)
    with pytest.raises(dda.DdaError, match="missing.csv"):
        dda.read_table(tmp_path / "missing.csv")


def test_tables_without_pandas_are_dicts_of_numpy_arrays(tmp_path, monkeypatch):
    run = dda.run(example("free_fall_2d.ron"), out=tmp_path / "fall")
    monkeypatch.setattr(dda, "_pandas", None)
    table = dda.read_table(os.path.join(run.out, "history.csv"))
    assert isinstance(table, dict)
    assert table["step"].dtype.kind == "i"
    assert table["time"].dtype.kind == "f"
    assert len(table["time"]) == len(table["block"])


def test_a_study_sweeps_dt_and_returns_its_rows(tmp_path):
    study = tmp_path / "dt.ron"
    scene = os.path.abspath(example("sliding_block_2d.ron"))
    study.write_text(
        "Study(\n"
        f"    scene: File({scene!r}),\n".replace("'", '"')
        + "    sweep: [(field: \"analysis.dt\", values: [0.002, 0.001])],\n"
        "    figure: Displacement(block: 1, time: 1.0),\n"
        "    reference: Number(%r),\n"
        ")\n" % slide_distance(1.0)
    )
    rows = dda.study(study, tmp_path / "out", jobs=1)
    dts = sorted(column(rows, "analysis.dt").tolist())
    assert dts == [0.001, 0.002]
    # Each run slides as the closed form says, within 0.1 %.
    for figure in column(rows, "figure"):
        assert abs(figure - slide_distance(1.0)) <= 1e-3 * slide_distance(1.0)


def test_a_bad_study_is_a_dda_error(tmp_path):
    study = tmp_path / "bad.ron"
    study.write_text("Study(scene: File(\"nowhere.ron\"))")
    with pytest.raises(dda.DdaError):
        dda.study(study, tmp_path / "out")
