//! Broad phase: pairs of blocks whose grown bounding boxes overlap. The only
//! module that names parry (glam types stay inside it).

use nalgebra::Point3;
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::Vector;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy};

/// Pairs (i, j), i < j, of point sets whose bounding boxes grown by `range`
/// overlap, sorted.
pub fn near_pairs(blocks: &[&[Point3<f64>]], range: f64) -> Vec<(usize, usize)> {
    let boxes: Vec<Aabb> = blocks
        .iter()
        .map(|vs| {
            let (mut lo, mut hi) = (
                Vector::splat(f64::INFINITY),
                Vector::splat(f64::NEG_INFINITY),
            );
            for v in vs.iter() {
                let p = Vector::new(v.x, v.y, v.z);
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

    fn cube(x: f64, y: f64, z: f64) -> Vec<Point3<f64>> {
        let mut v = Vec::new();
        for (dx, dy, dz) in [
            (0.0, 0.0, 0.0),
            (1.0, 0.0, 0.0),
            (0.0, 1.0, 0.0),
            (0.0, 0.0, 1.0),
            (1.0, 1.0, 1.0),
        ] {
            v.push(Point3::new(x + dx, y + dy, z + dz));
        }
        v
    }

    #[test]
    fn finds_exactly_the_near_pairs() {
        // A diagonal row of cubes 1.05 apart along x and z.
        let cubes: Vec<Vec<Point3<f64>>> = (0..7)
            .map(|i| cube(1.05 * i as f64, 0.0, 1.05 * i as f64))
            .collect();
        let refs: Vec<&[Point3<f64>]> = cubes.iter().map(|c| c.as_slice()).collect();
        let near = near_pairs(&refs, 0.1);
        let expect: Vec<(usize, usize)> = (0..6).map(|i| (i, i + 1)).collect();
        assert_eq!(near, expect);
        assert!(near_pairs(&refs, 0.01).is_empty());
    }
}
