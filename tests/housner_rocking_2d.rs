//! Housner's free rocking (reference B3): a 1 m × 4 m block released at
//! half its slenderness angle on a rigid base with high friction. The time
//! to the first impact against the rigid-body answer (3 %), and the first
//! three amplitude ratios against Housner's recursion with
//! r = 1 − 1.5 sin² α (10 %), at the penalty (1e10 N/m) and time step
//! (0.5 ms) of examples/rocking_column_2d.ron.

mod common;

#[test]
fn rocking_block_impacts_on_time_and_loses_housners_share_each_impact() {
    common::assert_rocks_like_housner(&common::run_example("rocking_column_2d.ron"));
}
