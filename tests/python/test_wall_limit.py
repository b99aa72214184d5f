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


def test_a_stair_wedge_tips_on_its_toe_whatever_the_friction():
    # The 68-brick wall's wedge above the crack from course 1: 16 bricks.
    wedge = wall_limit.stair_wedge(2.0, 8, 1)
    assert len(wedge) == 16
    by_moments = wall_limit.toe_multiplier(2.0, 8, 1)
    assert by_moments == pytest.approx(0.9623, abs=5e-5)
    # The analysis with the crack's ends carrying nothing but the toe's
    # finds the same, at any friction the toe does not slide at.
    for fos in (2.0, 10.0):
        alone = wall_limit.crack_opened(2.0, 8, 1)
        assert wall_limit.downhill_multiplier(2.0, 8, fos, opened=alone) == pytest.approx(
            by_moments, rel=1e-7)
    # Friction at the lowest head joint's bottom end, which slides without
    # opening as the wedge tips, holds it, given compression there.
    corner = wall_limit.crack_opened(2.0, 8, 1, keep_corner=True)
    assert wall_limit.downhill_multiplier(2.0, 8, 2.0, opened=corner) == pytest.approx(
        1.2221, abs=5e-5)
    least = wall_limit.downhill_multiplier(2.0, 8, 2.0, opened=corner,
                                           least_at=wall_limit.crack_corner(2.0, 8, 1))
    assert least == pytest.approx(568.3, abs=0.1)


def test_only_that_wedge_tips_on_its_toe_in_the_68_brick_wall():
    tips = {base: wall_limit.toe_multiplier(2.0, 8, base) for base in range(8)}
    assert [b for b, m in tips.items() if m < 1.0] == [1]
    # The 264-brick wall has six, the lowest tipping at 0.9101.
    tips = [wall_limit.toe_multiplier(4.0, 16, base) for base in range(16)]
    assert sum(m < 1.0 for m in tips) == 6
    assert min(tips) == pytest.approx(0.9101, abs=5e-5)
