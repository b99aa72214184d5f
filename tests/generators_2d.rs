//! Arches, columns and walls: the blocks they expand into, and scenes built
//! from them.

use std::f64::consts::PI;

use dda::{Scene, SceneBlock};

/// A scene with one material and the given `blocks` entries.
fn scene(blocks: &str) -> Scene {
    let text = format!(
        r#"Scene(
    analysis: (duration: 0.01, dt: 0.001, penalty: 1e10, max_displacement_ratio: 0.002),
    materials: {{ "stone": (density: 2500.0, young: 2e10, poisson: 0.2) }},
    default_joint: Coulomb(friction_angle: 40.0),
    blocks: [
        {blocks}
    ],
)"#
    );
    Scene::from_str(&text, "generators.ron").unwrap_or_else(|e| panic!("{e}"))
}

fn blocks(entry: &str) -> Vec<SceneBlock> {
    scene(entry).expanded_blocks()
}

fn area(v: &[[f64; 2]]) -> f64 {
    let n = v.len();
    (0..n)
        .map(|i| {
            let (a, b) = (v[i], v[(i + 1) % n]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<f64>()
        / 2.0
}

/// The points two outlines share exactly.
fn shared(a: &SceneBlock, b: &SceneBlock) -> Vec<[f64; 2]> {
    a.vertices
        .iter()
        .filter(|p| b.vertices.contains(p))
        .copied()
        .collect()
}

/// Whether `p` lies on the segment a–b (within `tol`).
fn on_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2], tol: f64) -> bool {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let s = ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2;
    let (qx, qy) = (a[0] + s * dx, a[1] + s * dy);
    (-1e-12..=1.0 + 1e-12).contains(&s) && (p[0] - qx).hypot(p[1] - qy) <= tol
}

/// The edge of `outline` holding both points of `joint`.
fn edge_holding(outline: &[[f64; 2]], joint: &[[f64; 2]]) -> Option<([f64; 2], [f64; 2])> {
    let n = outline.len();
    (0..n)
        .map(|i| (outline[i], outline[(i + 1) % n]))
        .find(|&(a, b)| joint.iter().all(|&p| on_segment(p, a, b, 1e-12)))
}

const SEMICIRCLE: &str =
    r#"Arch(material: "stone", center: (2.0, 1.0), radius: 10.0, thickness: 1.128, voussoirs: 25)"#;

#[test]
fn a_semicircular_arch_has_its_voussoirs_and_abutments() {
    let (cx, cy, r, t, n) = (2.0, 1.0, 10.0, 1.128, 25);
    let (ri, re) = (r - t / 2.0, r + t / 2.0);
    let all = blocks(SEMICIRCLE);
    assert_eq!(all.len(), n + 2);
    let (voussoirs, abutments) = all.split_at(n);
    for (k, v) in voussoirs.iter().enumerate() {
        assert_eq!(v.part.as_deref(), Some(format!("voussoir {k}").as_str()));
        assert_eq!(v.entry, 0);
        assert!(!v.fixed);
        assert_eq!(v.vertices.len(), 4);
        // Two points on the intrados and two on the extrados.
        let mut radii: Vec<f64> = v
            .vertices
            .iter()
            .map(|p| (p[0] - cx).hypot(p[1] - cy))
            .collect();
        radii.sort_by(f64::total_cmp);
        for (got, want) in radii.iter().zip([ri, ri, re, re]) {
            assert!((got - want).abs() < 1e-12, "voussoir {k}: {radii:?}");
        }
    }
    assert_eq!(abutments[0].part.as_deref(), Some("left abutment"));
    assert_eq!(abutments[1].part.as_deref(), Some("right abutment"));
    assert!(abutments.iter().all(|a| a.fixed && a.velocity == [0.0; 3]));

    // Consecutive voussoirs share their joint: the same two points, exactly,
    // and numbering runs from the left springing to the right.
    for k in 0..n - 1 {
        let joint = shared(&voussoirs[k], &voussoirs[k + 1]);
        assert_eq!(joint.len(), 2, "voussoirs {k} and {}", k + 1);
        let centroid = |b: &SceneBlock| b.vertices.iter().map(|p| p[0]).sum::<f64>() / 4.0;
        assert!(centroid(&voussoirs[k]) < centroid(&voussoirs[k + 1]));
        // Radial: the joint's line passes through the centre.
        let [a, b] = [joint[0], joint[1]];
        let cross = (b[0] - a[0]) * (cy - a[1]) - (b[1] - a[1]) * (cx - a[0]);
        assert!(cross.abs() < 1e-11, "joint {} is not radial", k + 1);
    }
    for k in 0..n {
        for j in k + 2..n {
            assert!(shared(&voussoirs[k], &voussoirs[j]).is_empty());
        }
    }

    // Chord quadrilaterals, all alike: N·(r_e² − r_i²)/2·sin(π/N) in all,
    // which is sin(π/N)/(π/N) of the half annulus (0.26 % less for N = 25).
    let chord = (re * re - ri * ri) / 2.0 * (PI / n as f64).sin();
    for v in voussoirs {
        assert!(
            (area(&v.vertices) - chord).abs() < 1e-10 * chord,
            "counter-clockwise and equal"
        );
    }
    let total: f64 = voussoirs.iter().map(|v| area(&v.vertices)).sum();
    assert!((total - n as f64 * chord).abs() < 1e-10 * total);
    let annulus = PI * (re * re - ri * ri) / 2.0;
    let ratio = (PI / n as f64).sin() / (PI / n as f64);
    assert!((total / annulus - ratio).abs() < 1e-12);
    assert!((1.0 - total / annulus) < 0.003);

    // The keystone (N odd) is symmetric about x = cx.
    let key = &voussoirs[n / 2];
    for p in &key.vertices {
        let mirror = [2.0 * cx - p[0], p[1]];
        assert!(
            key.vertices
                .iter()
                .any(|q| (q[0] - mirror[0]).abs() < 1e-12 && q[1] == mirror[1]),
            "{p:?} has no mirror in the keystone {:?}",
            key.vertices
        );
    }

    // Springing joints horizontal at the level of the centre, and each
    // abutment a 2t × t rectangle whose top face holds the joint.
    let springing = |v: &SceneBlock| -> Vec<[f64; 2]> {
        v.vertices.iter().filter(|p| p[1] == cy).copied().collect()
    };
    let left = springing(&voussoirs[0]);
    let right = springing(&voussoirs[n - 1]);
    assert_eq!(left.len(), 2);
    assert_eq!(right.len(), 2);
    for (joint, abutment) in [(&left, &abutments[0]), (&right, &abutments[1])] {
        let (a, b) = edge_holding(&abutment.vertices, joint).expect("the joint lies on a face");
        assert_eq!((a[1], b[1]), (cy, cy), "the top face");
        assert!(((a[0] - b[0]).abs() - 2.0 * t).abs() < 1e-12);
        let xs: Vec<f64> = joint.iter().map(|p| p[0]).collect();
        let (lo, hi) = (xs[0].min(xs[1]), xs[0].max(xs[1]));
        assert!((lo - a[0].min(b[0]) - t / 2.0).abs() < 1e-12);
        assert!((a[0].max(b[0]) - hi - t / 2.0).abs() < 1e-12);
        let bottom = abutment
            .vertices
            .iter()
            .map(|p| p[1])
            .fold(f64::MAX, f64::min);
        assert!((bottom - (cy - t)).abs() < 1e-12);
        assert!((area(&abutment.vertices) - 2.0 * t * t).abs() < 1e-12);
    }
    // The right abutment mirrors the left.
    let mirrored: f64 = abutments[0].vertices.iter().map(|p| p[0] - cx).sum::<f64>()
        + abutments[1].vertices.iter().map(|p| p[0] - cx).sum::<f64>();
    assert!(mirrored.abs() < 1e-12);
}

#[test]
fn more_voussoirs_come_closer_to_the_annulus() {
    let (r, t) = (10.0, 1.128);
    let annulus = PI * ((r + t / 2.0_f64).powi(2) - (r - t / 2.0_f64).powi(2)) / 2.0;
    for (n, within) in [(25, 0.003), (41, 0.001), (100, 0.0002)] {
        let all = blocks(&format!(
            "Arch(center: (0.0, 0.0), radius: {r}, thickness: {t}, voussoirs: {n}, abutments: false)"
        ));
        assert_eq!(all.len(), n, "no abutments");
        let total: f64 = all.iter().map(|v| area(&v.vertices)).sum();
        assert!(
            (1.0 - total / annulus).abs() < within,
            "N = {n}: {total} vs {annulus}"
        );
    }
}

#[test]
fn an_even_arch_has_a_vertical_crown_joint() {
    let all = blocks("Arch(center: (-3.0, 0.5), radius: 4.0, thickness: 0.5, voussoirs: 8)");
    assert_eq!(all.len(), 10);
    let crown = shared(&all[3], &all[4]);
    assert_eq!(crown.len(), 2);
    assert!(crown.iter().all(|p| p[0] == -3.0), "{crown:?}");
    let mut ys: Vec<f64> = crown.iter().map(|p| p[1]).collect();
    ys.sort_by(f64::total_cmp);
    assert_eq!(ys, [0.5 + 3.75, 0.5 + 4.25]);
}

#[test]
fn a_pointed_arch_meets_at_its_apex_on_the_axis() {
    let (cx, cy, r, t, e): (f64, f64, f64, f64, f64) = (1.0, 0.0, 5.0, 0.6, 0.3);
    let (ri, re) = (r - t / 2.0, r + t / 2.0);
    let all = blocks(&format!(
        "Arch(center: ({cx}, {cy}), radius: {r}, thickness: {t}, voussoirs: 10, pointed: {e})"
    ));
    assert_eq!(all.len(), 12);
    // The crown joint: vertical on x = cx, from the intrados apex to the
    // extrados apex of the arcs about (cx ± e·r, cy).
    let crown = shared(&all[4], &all[5]);
    assert_eq!(crown.len(), 2);
    assert!(crown.iter().all(|p| p[0] == cx), "{crown:?}");
    let mut ys: Vec<f64> = crown.iter().map(|p| p[1]).collect();
    ys.sort_by(f64::total_cmp);
    let apex = |rad: f64| cy + (rad * rad - (e * r).powi(2)).sqrt();
    assert!((ys[0] - apex(ri)).abs() < 1e-12 && (ys[1] - apex(re)).abs() < 1e-12);
    // Higher than a round arch of its span (2(r_e − e·r) at the extrados),
    // and pointed: the extrados rises all the way to the crown.
    assert!(ys[1] - cy > re - e * r);
    let top = |v: &SceneBlock| v.vertices.iter().map(|p| p[1]).fold(f64::MIN, f64::max);
    assert_eq!(top(&all[4]), ys[1]);
    assert!(top(&all[3]) < ys[1] && top(&all[4]) == top(&all[5]));
    // Left voussoirs lie on the arcs about the right-hand centre.
    let centre = [cx + e * r, cy];
    for v in &all[..4] {
        let mut radii: Vec<f64> = v
            .vertices
            .iter()
            .map(|p| (p[0] - centre[0]).hypot(p[1] - centre[1]))
            .collect();
        radii.sort_by(f64::total_cmp);
        assert!((radii[0] - ri).abs() < 1e-12 && (radii[3] - re).abs() < 1e-12);
    }
    // The right half mirrors the left.
    for k in 0..5 {
        let (a, b) = (&all[k], &all[9 - k]);
        for p in &a.vertices {
            assert!(b
                .vertices
                .iter()
                .any(|q| (q[0] - (2.0 * cx - p[0])).abs() < 1e-12 && q[1] == p[1]));
        }
    }
    // Springing horizontal at the centre's level, and consecutive joints shared.
    assert_eq!(all[0].vertices.iter().filter(|p| p[1] == cy).count(), 2);
    for k in 0..9 {
        assert_eq!(shared(&all[k], &all[k + 1]).len(), 2);
    }
}

#[test]
fn a_segmental_arch_springs_at_its_angle() {
    let (cx, cy, span) = (0.0, 0.0, 120.0);
    let all = blocks(&format!(
        "Arch(center: ({cx}, {cy}), radius: 6.0, thickness: 0.5, voussoirs: 9, span_angle: {span})"
    ));
    assert_eq!(all.len(), 11);
    // The left springing joint is the voussoir 0 edge the abutment holds.
    let left = &all[9];
    let joint: Vec<[f64; 2]> = all[0]
        .vertices
        .iter()
        .filter(|p| edge_holding(&left.vertices, &[**p]).is_some())
        .copied()
        .collect();
    assert_eq!(
        joint.len(),
        2,
        "the springing joint lies on the abutment's top"
    );
    // Radial, at (180 − span)/2 = 30° above the horizontal.
    let (a, b) = (joint[0], joint[1]);
    let angle = ((b[1] - a[1]) / (b[0] - a[0])).atan().to_degrees().abs();
    assert!((angle - (180.0 - span) / 2.0).abs() < 1e-9, "{angle}");
    for p in &joint {
        let direction = (p[1] - cy).atan2(p[0] - cx).to_degrees();
        assert!((direction - (90.0 + span / 2.0)).abs() < 1e-9);
    }
    // The abutment: the joint's line, t/2 longer at each end, then t below
    // the joint's lowest point with vertical sides.
    let t = 0.5;
    let (top_a, top_b) = edge_holding(&left.vertices, &joint).unwrap();
    let top_len = (top_b[0] - top_a[0]).hypot(top_b[1] - top_a[1]);
    assert!((top_len - 2.0 * t).abs() < 1e-12);
    let low = joint.iter().map(|p| p[1]).fold(f64::MAX, f64::min);
    let bottom = left.vertices.iter().map(|p| p[1]).fold(f64::MAX, f64::min);
    assert!((bottom - (low - t)).abs() < 1e-12);
    // Segmental: the lowest voussoir point is the intrados springing point.
    let lowest = all[..9]
        .iter()
        .flat_map(|v| v.vertices.iter().map(|p| p[1]))
        .fold(f64::MAX, f64::min);
    assert!((lowest - 5.75 * 0.5).abs() < 1e-12, "{lowest}");
}

#[test]
fn a_column_stacks_its_drums() {
    let all = blocks("Column(base: (3.0, -1.0), drums: 5, drum_height: 0.8, width: 0.6)");
    assert_eq!(all.len(), 5);
    for (k, d) in all.iter().enumerate() {
        assert_eq!(d.part.as_deref(), Some(format!("drum {k}").as_str()));
        let ys: Vec<f64> = d.vertices.iter().map(|p| p[1]).collect();
        let xs: Vec<f64> = d.vertices.iter().map(|p| p[0]).collect();
        let (lo, hi) = (
            ys.iter().copied().fold(f64::MAX, f64::min),
            ys.iter().copied().fold(f64::MIN, f64::max),
        );
        assert!((lo - (-1.0 + 0.8 * k as f64)).abs() < 1e-12);
        assert!((hi - lo - 0.8).abs() < 1e-12, "drum {k} is 0.8 m high");
        assert!(xs
            .iter()
            .all(|x| (x - 2.7).abs() < 1e-12 || (x - 3.3).abs() < 1e-12));
        assert!((area(&d.vertices) - 0.48).abs() < 1e-12);
        if k > 0 {
            assert_eq!(shared(&all[k - 1], d).len(), 2, "drums {} and {k}", k - 1);
        }
    }
    let top = all[4]
        .vertices
        .iter()
        .map(|p| p[1])
        .fold(f64::MIN, f64::max);
    assert!((top - 3.0).abs() < 1e-12, "5 × 0.8 m above the base");
}

/// The bricks of each course as (left, right) x, from left to right.
fn courses(all: &[SceneBlock], count: usize) -> Vec<Vec<(f64, f64)>> {
    (0..count)
        .map(|c| {
            let prefix = format!("course {c}, brick ");
            let mut bricks: Vec<(f64, f64)> = all
                .iter()
                .filter(|b| b.part.as_deref().is_some_and(|p| p.starts_with(&prefix)))
                .map(|b| {
                    let xs = b.vertices.iter().map(|p| p[0]);
                    (
                        xs.clone().fold(f64::MAX, f64::min),
                        xs.fold(f64::MIN, f64::max),
                    )
                })
                .collect();
            bricks.sort_by(|a, b| a.0.total_cmp(&b.0));
            bricks
        })
        .collect()
}

#[test]
fn wall_courses_span_the_wall_without_gaps_or_overlaps() {
    let (x0, length, b) = (-1.0, 5.2, 0.5);
    for bond in ["Running", "Stack"] {
        let all = blocks(&format!(
            "Wall(origin: ({x0}, 2.0), length: {length}, courses: 6, brick_length: {b}, brick_height: 0.25, bond: {bond})"
        ));
        let rows = courses(&all, 6);
        assert_eq!(rows.iter().map(Vec::len).sum::<usize>(), all.len());
        for (c, row) in rows.iter().enumerate() {
            assert_eq!(row[0].0, x0, "{bond} course {c} starts at the origin");
            assert_eq!(row[row.len() - 1].1, x0 + length, "and ends at its length");
            for w in row.windows(2) {
                assert_eq!(w[0].1, w[1].0, "{bond} course {c}: no gap, no overlap");
            }
            for &(l, r) in row {
                assert!(r - l > 0.0 && r - l <= b + 1e-12);
            }
            let covered: f64 = row.iter().map(|(l, r)| r - l).sum();
            assert!((covered - length).abs() < 1e-12);
        }
        // Heights: course c from 2 + 0.25 c.
        for brick in &all {
            let c: usize = brick.part.as_ref().unwrap()["course ".len()..]
                .split(',')
                .next()
                .unwrap()
                .parse()
                .unwrap();
            let lo = brick.vertices.iter().map(|p| p[1]).fold(f64::MAX, f64::min);
            assert!((lo - (2.0 + 0.25 * c as f64)).abs() < 1e-12);
        }
        // Inner joints of each course, relative to the origin.
        let joints =
            |row: &Vec<(f64, f64)>| -> Vec<f64> { row[1..].iter().map(|(l, _)| l - x0).collect() };
        match bond {
            "Stack" => {
                // Every course alike: joints at multiples of the brick length,
                // a 0.2 m brick at the end.
                for row in &rows {
                    assert_eq!(row.len(), 11);
                    for (k, j) in joints(row).iter().enumerate() {
                        assert!((j - b * (k + 1) as f64).abs() < 1e-12);
                    }
                    assert!((row[10].1 - row[10].0 - 0.2).abs() < 1e-12);
                }
            }
            _ => {
                // Odd courses start with a half brick, so the joints
                // alternate: none of a course lines up with the next one's.
                assert_eq!(rows[1][0].1 - rows[1][0].0, b / 2.0);
                for c in 0..5 {
                    let (this, next) = (joints(&rows[c]), joints(&rows[c + 1]));
                    for j in &this {
                        let nearest = next.iter().map(|k| (k - j).abs()).fold(f64::MAX, f64::min);
                        assert!(nearest > 0.2, "course {c} joint at {j} lines up");
                    }
                    // Every other course repeats.
                    if c + 2 < 6 {
                        assert_eq!(joints(&rows[c]), joints(&rows[c + 2]));
                    }
                }
            }
        }
    }
}

#[test]
fn generated_blocks_are_numbered_in_place() {
    // A base, a 3-drum column, then a loose block: index 4 is the block.
    let text = r#"Scene(
    analysis: (duration: 0.01, dt: 0.001),
    materials: { "stone": (density: 2500.0, young: 2e10, poisson: 0.2) },
    joints: [ (blocks: [(1, 2), (2, 3)], law: Coulomb(friction_angle: 10.0)) ],
    blocks: [
        Rectangle(center: (0.0, -0.5), width: 4.0, height: 1.0, fixed: true),
        Column(base: (0.0, 0.0), drums: 3, drum_height: 0.5, width: 0.4, velocity: (0.1, 0.0, 0.0)),
        Rectangle(center: (1.5, 0.25), width: 0.5, height: 0.5),
    ],
    loads: [ PointLoad(block: 4, point: (1.5, 0.5), force: (0.0, -1.0)) ],
    fixed_points: [ (block: 3, point: (0.0, 1.5)) ],
    ground_motion: (blocks: [0], motion: Pulse(amplitude: (1.0, 0.0), period: 0.5)),
)"#;
    let scene = Scene::from_str(text, "numbered.ron").unwrap();
    assert_eq!(scene.block_count(), 5);
    let model = scene.build().unwrap();
    let system = &model.driver.system;
    assert_eq!(system.blocks.len(), 5);
    assert!((system.blocks[4].centroid().x - 1.5).abs() < 1e-12);
    assert!((system.blocks[3].centroid().y - 1.25).abs() < 1e-12);
    assert_eq!(system.loads[0].block, 4);
    assert_eq!(system.pair_laws.get(&(2, 3)), Some(&1));
    // The column's velocity on each drum, none on the others.
    let v = model.driver.velocities();
    assert!((1..4).all(|k| v[k][0] == 0.1));
    assert_eq!(v[4][0], 0.0);
    // The ground carries the base's corners only.
    for fp in &system.fixed {
        assert_eq!(fp.ground.is_some(), fp.block == 0, "{fp:?}");
    }
    assert_eq!(
        system.fixed.iter().filter(|f| f.ground.is_some()).count(),
        4
    );
}

#[test]
fn the_generator_scene_checks_and_runs() {
    let result = std::process::Command::new(env!("CARGO_BIN_EXE_dda"))
        .args(["check", "tests/data/arch.ron"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let stdout = String::from_utf8(result.stdout).unwrap();
    assert!(result.status.success(), "{stdout}");
    assert!(
        stdout.starts_with("tests/data/arch.ron: ok (78 blocks, 1 material"),
        "{stdout}"
    );

    // It starts without overlaps (validation) and runs its few steps quietly.
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/arch.ron");
    let mut model = Scene::load(path).unwrap().build().unwrap();
    let before: Vec<_> = model
        .driver
        .system
        .blocks
        .iter()
        .map(|b| b.centroid())
        .collect();
    model.driver.advance_to(model.duration).unwrap();
    let stats = model.driver.statistics();
    assert_eq!((stats.penalty_raises, stats.unconverged_steps), (0, 0));
    for (b, c0) in model.driver.system.blocks.iter().zip(&before) {
        assert!((b.centroid() - c0).norm() < 5e-3);
    }
}

/// The drop of the keystone of a semicircular arch of 25 voussoirs (radius
/// 10 m) standing on its abutments for 1 s.
fn keystone_drop(thickness: f64) -> f64 {
    let mut model = scene(&format!(
        "Arch(center: (0.0, 0.0), radius: 10.0, thickness: {thickness}, voussoirs: 25)"
    ))
    .build()
    .unwrap();
    let y0 = model.driver.system.blocks[12].centroid().y;
    model.driver.advance_to(1.0).unwrap();
    y0 - model.driver.system.blocks[12].centroid().y
}

#[test]
fn an_arch_thicker_than_heymans_minimum_stands_and_a_thinner_one_falls() {
    // Heyman's least thickness of a semicircular arch is t/R = 0.1075 (with
    // friction enough to stop sliding): the arch at 0.1128 stands, settling
    // by its joints' compression, and one at 0.10 collapses.
    let standing = keystone_drop(1.128);
    assert!(standing > 0.0 && standing < 0.005, "{standing}");
    let falling = keystone_drop(1.0);
    assert!(falling > 0.1, "{falling}");
}
