"""The limit analysis behind the tilted walls of tests/settle.rs: checked
on a case with a closed form, then the numbers the Rust tests and
docs/limits.md quote."""

import math

import pytest

import wall_limit


def test_a_slender_column_topples_at_its_width_over_its_height(monkeypatch):
    # Eight bricks 0.125 m square stacked, friction ample: the column
    # tips when the downhill load reaches width/height of the weight.
    column = [(0.0, 0.125, k * 0.125, (k + 1) * 0.125) for k in range(8)]
    monkeypatch.setattr(wall_limit, "bricks", lambda length, courses: column)
    expected = (0.125 / 1.0) / math.tan(math.radians(30))
    assert wall_limit.downhill_multiplier(0.0, 0, 10.0) == pytest.approx(expected, rel=1e-9)
    # With little friction it slides first, at its factor of safety.
    assert wall_limit.downhill_multiplier(0.0, 0, 0.2) == pytest.approx(0.2, rel=1e-9)


def test_the_low_wall_is_held_by_its_bed_joints_friction():
    for fos in (0.99, 1.01):
        assert wall_limit.downhill_multiplier(2.0, 4, fos) == pytest.approx(fos, rel=1e-9)


def test_the_taller_walls_topple_at_their_downhill_end_first():
    assert wall_limit.downhill_multiplier(2.0, 8, 1.01) == pytest.approx(0.946, abs=5e-4)
    assert wall_limit.downhill_multiplier(2.0, 8, 1.16) == pytest.approx(0.994, abs=5e-4)
    assert wall_limit.limit_fos(2.0, 8) == pytest.approx(1.1746, abs=1e-4)
    assert wall_limit.downhill_multiplier(4.0, 16, 1.01) == pytest.approx(0.806, abs=5e-4)
