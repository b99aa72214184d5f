//! A five-drum column under a recorded-style accelerogram
//! (examples/drum_column_2d.ron with examples/data/ground_motion_2d.csv).
//! The plinth follows the doubly integrated record, and the drums respond.

use dda_core::{GroundMotion, Quantity, Record};
use nalgebra::Vector2;

mod common;

#[test]
fn plinth_follows_the_record_and_the_column_responds() {
    let text = std::fs::read_to_string(common::example("data/ground_motion_2d.csv")).unwrap();
    let samples: Vec<(f64, Vector2<f64>)> = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("time"))
        .map(|l| {
            let f: Vec<f64> = l.split(',').map(|x| x.trim().parse().unwrap()).collect();
            (f[0], Vector2::new(f[1], f[2]) * 9.81)
        })
        .collect();
    let ground = GroundMotion::Record(Record::new(Quantity::Acceleration, &samples).unwrap());
    let rows = common::run_example("drum_column_2d.ron");
    let start = common::at(&rows, 0, 0.0);
    for t in [2.0, 5.0, 10.0] {
        let plinth = common::at(&rows, 0, t);
        let expected = ground.displacement(t);
        let moved = Vector2::new(plinth.x - start.x, plinth.y - start.y);
        // The plinth is held to the ground by stiff springs: it lags by the
        // springs' give only.
        assert!(
            (moved - expected).norm() < 1e-4 * (1.0 + expected.norm()),
            "t = {t}: {moved} vs {expected}"
        );
    }
    // The top drum moves relative to the plinth (rocking or sliding).
    let top = 5;
    let rel = |t: f64| {
        let (d, p) = (common::at(&rows, top, t), common::at(&rows, 0, t));
        (d.x - p.x, d.y - p.y)
    };
    let (a, b) = (rel(0.0), rel(5.0));
    assert!(
        ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt() > 1e-4,
        "the drums respond to the shaking"
    );
}
