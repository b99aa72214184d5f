//! Broad phase: pairs of blocks whose grown bounding boxes overlap. The only
//! module that names parry.

use nalgebra::Point2;
use parry2d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry2d_f64::math::Vector;
use parry2d_f64::partitioning::{Bvh, BvhBuildStrategy};

/// Pairs (i, j), i < j, of polygons whose bounding boxes grown by `range`
/// overlap, sorted.
pub fn near_pairs(polygons: &[&[Point2<f64>]], range: f64) -> Vec<(usize, usize)> {
    let boxes: Vec<Aabb> = polygons
        .iter()
        .map(|vs| {
            let (mut lo, mut hi) = (
                Vector::splat(f64::INFINITY),
                Vector::splat(f64::NEG_INFINITY),
            );
            for v in vs.iter() {
                let p = Vector::new(v.x, v.y);
                lo = lo.min(p);
                hi = hi.max(p);
            }
            let grow = Vector::splat(range / 2.0);
            Aabb::new(lo - grow, hi + grow)
        })
        .collect();
    if boxes.len() < 2 {
        return Vec::new();
    }
    let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &boxes);
    let mut pairs: Vec<(usize, usize)> = bvh
        .leaf_pairs(&bvh, |a, b| a.intersects(b))
        .map(|(i, j)| (i as usize, j as usize))
        .filter(|(i, j)| i < j && boxes[*i].intersects(&boxes[*j]))
        .collect();
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x: f64, y: f64) -> Vec<Point2<f64>> {
        vec![
            Point2::new(x, y),
            Point2::new(x + 1.0, y),
            Point2::new(x + 1.0, y + 1.0),
            Point2::new(x, y + 1.0),
        ]
    }

    #[test]
    fn finds_exactly_the_near_pairs() {
        // A row of squares 1.05 apart: neighbours are near with range 0.1, not with 0.01.
        let squares: Vec<Vec<Point2<f64>>> = (0..7).map(|i| square(1.05 * i as f64, 0.0)).collect();
        let refs: Vec<&[Point2<f64>]> = squares.iter().map(|s| s.as_slice()).collect();
        let near = near_pairs(&refs, 0.1);
        let expect: Vec<(usize, usize)> = (0..6).map(|i| (i, i + 1)).collect();
        assert_eq!(near, expect);
        assert!(near_pairs(&refs, 0.01).is_empty());
    }
}
