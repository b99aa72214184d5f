//! The matrix pattern changes, and the solver analyses it again, only when
//! the contact graph does (`driver/pattern.rs`): a standing wall keeps one
//! analysis for thousands of steps, and open contacts near closing enter
//! the pattern before they close.

use dda::bench::{wall, Stepping};
use dda::Scene;
use dda_core::BlockKind;

mod common;

/// The 10 × 10 rigid wall at dt 1 ms with its automatic penalty stands
/// for 2,000 steps on the one analysis of its first step.
#[test]
fn a_standing_wall_keeps_one_analysis_for_thousands_of_steps() {
    let scene = wall(10, 2, Stepping::Given(0.001), BlockKind::Rigid).unwrap();
    let mut driver = scene.build().unwrap().driver;
    driver.advance_to(2.0 - 1e-9).unwrap();
    let s = driver.statistics();
    assert_eq!(s.steps, 2000);
    assert_eq!(s.symbolic_analyses, 1, "{} analyses", s.symbolic_analyses);
}

/// `examples/jointed_slope_3d.ron` over its 0.5 s: its blocks above the
/// bedding joint slide, and the open contacts they meet lie within the
/// pattern's least reach (`PATTERN_REACH_SHARE`, a twentieth of the
/// median block), so the run keeps its first analysis. With no least
/// reach it made a second.
#[test]
fn a_sliding_slope_keeps_its_analysis() {
    let scene = Scene::load(common::example("jointed_slope_3d.ron")).unwrap();
    let end = scene.analysis.duration;
    let mut driver = scene.build_3d().unwrap().driver;
    driver.advance_to(end).unwrap();
    let s = driver.statistics();
    assert_eq!(s.steps, 500);
    assert_eq!(s.symbolic_analyses, 1, "{} analyses", s.symbolic_analyses);
}
