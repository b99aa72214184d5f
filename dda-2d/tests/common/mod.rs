//! Helpers shared by the dda-2d integration tests.

use nalgebra::Point2;

/// The corners of a w × h rectangle centred on (cx, cy), counter-clockwise.
pub fn square(cx: f64, cy: f64, w: f64, h: f64) -> Vec<Point2<f64>> {
    [(-w, -h), (w, -h), (w, h), (-w, h)]
        .iter()
        .map(|&(x, y)| Point2::new(cx + x / 2.0, cy + y / 2.0))
        .collect()
}
