//! Large rotation: one free revolution at ω·Δt = 0.01. The exact-rotation
//! update keeps the area (reference A8/B6); Shi's linear update inflates it
//! by (1 + (ωΔt)²) per step, about 6.5 % per revolution.

use dda::scene::Scene;
use dda_2d::RotationUpdate;

mod common;

fn revolve(update: RotationUpdate) -> (f64, f64, Vec<f64>, f64) {
    let mut scene = Scene::load(common::example("spinning_block_2d.ron")).unwrap();
    scene.analysis.rotation_update = update;
    let mut model = scene.build().unwrap();
    let block = &model.driver.system.blocks[0];
    let (area, c) = (block.area(), block.centroid());
    let radii: Vec<f64> = block.vertices().iter().map(|v| (v - c).norm()).collect();
    model.driver.advance_to(model.duration).unwrap();
    let block = &model.driver.system.blocks[0];
    let c = block.centroid();
    let drift: Vec<f64> = block
        .vertices()
        .iter()
        .zip(&radii)
        .map(|(v, r)| (v - c).norm() / r - 1.0)
        .collect();
    let steps = model.driver.statistics().steps as f64;
    (block.area() / area - 1.0, block.rotation, drift, steps)
}

#[test]
fn exact_update_keeps_the_area_over_a_revolution() {
    let (area_drift, rotation, radius_drift, steps) = revolve(RotationUpdate::Exact);
    assert!(area_drift.abs() < 1e-9, "area drift {area_drift:e}");
    for d in radius_drift {
        assert!(
            d.abs() < 1e-9,
            "vertex distance to the centroid drifted by {d:e}"
        );
    }
    assert!(
        (rotation - 2.0 * std::f64::consts::PI).abs() < 1e-9,
        "swept angle {rotation}"
    );
    assert_eq!(steps, 629.0, "ω·Δt stayed 0.01: no step was cut");
}

#[test]
fn linear_update_inflates_the_area_as_predicted() {
    let (area_drift, _, _, steps) = revolve(RotationUpdate::Linear);
    // Steps of 0.01 rad do not fill the revolution: it is taken in 629
    // equal steps of 2π/629 = 0.0099893 rad.
    let h = 2.0 * std::f64::consts::PI / 629.0;
    let predicted = (1.0 + h * h).powi(629) - 1.0;
    assert_eq!(steps, 629.0);
    assert!(
        ((area_drift - predicted) / predicted).abs() < 1e-6,
        "drift {area_drift} vs {predicted}"
    );
    assert!(
        area_drift > 0.064,
        "the linear update must visibly inflate the block"
    );
}
