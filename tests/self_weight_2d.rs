//! A block under its own weight on a fixed base (reference B7.2): the
//! uniform-strain block carries the volume-average stress σy = −ρ g h / 2.

mod common;

#[test]
fn standing_block_carries_half_its_weight_per_area() {
    let rows = common::run_example("self_weight_2d.ron");
    let (rho, g, h) = (2700.0, 9.81, 2.0);
    let expected = -rho * g * h / 2.0;
    let last = common::at(&rows, 1, 1.0);
    assert!(
        ((last.syy - expected) / expected).abs() < 1e-4,
        "σy = {}, expected {expected}",
        last.syy
    );
}
