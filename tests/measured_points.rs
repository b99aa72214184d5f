//! Measured points: `measured_points` in a scene move with their blocks and
//! are written to `points.csv` at the output times of `history.csv`, in 2D
//! and 3D; a point off its block or on a missing block is a located error.

mod common;

use std::path::Path;

use dda::{read_history, read_history_3d, read_points, PointRow, Scene};
use dda_contact::LawRegistry;
use nalgebra::{Rotation2, Vector2, Vector3};

/// Runs `scene` into a fresh folder named `name`; the folder.
fn run(name: &str, scene: &Scene) -> std::path::PathBuf {
    let out = common::out_dir(name);
    dda::run::run_scene(
        scene,
        &out,
        dda::run::RunOptions::default(),
        &LawRegistry::with_builtin(),
    )
    .unwrap_or_else(|e| panic!("{e:#}"));
    out
}

/// An example with `points` as its measured points.
fn example_with_points(name: &str, points: &str) -> Scene {
    let text = common::example_with(
        name,
        "    blocks: [",
        &format!("    measured_points: [{points}],\n    blocks: ["),
    );
    Scene::from_str(&text, name).unwrap_or_else(|e| panic!("{e}"))
}

/// The rows of point `k`, in time order.
fn rows_of(rows: &[PointRow], k: usize) -> Vec<PointRow> {
    rows.iter().filter(|r| r.point == k).copied().collect()
}

fn listed(out: &Path) -> Vec<String> {
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    summary["outputs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .collect()
}

/// The block on a 30° incline (reference B1): a point at its centroid moves
/// as the centroid does in history.csv, to round-off, and slides
/// ½ g (sin θ − cos θ tan φ) t² down the dip; a point off the centroid
/// follows the centroid and the block's small rotation.
#[test]
fn points_on_a_sliding_block_follow_its_centroid() {
    let centroid = [-0.5, 0.8660254037844386];
    let off = [-0.3, 0.95];
    let scene = example_with_points(
        "sliding_block_2d.ron",
        &format!(
            "(block: 1, point: ({:?}, {:?})), (block: 1, point: ({:?}, {:?}))",
            centroid[0], centroid[1], off[0], off[1]
        ),
    );
    let out = run("points-sliding", &scene);
    let history: Vec<_> = read_history(out.join("history.csv"))
        .unwrap()
        .into_iter()
        .filter(|r| r.block == 1)
        .collect();
    let points = read_points(out.join("points.csv")).unwrap();
    assert!(listed(&out).contains(&"points.csv".to_string()));
    let (at_centroid, at_off) = (rows_of(&points, 0), rows_of(&points, 1));
    assert_eq!(at_centroid.len(), history.len(), "one row per output time");
    let (theta, phi, g) = (30f64.to_radians(), 20f64.to_radians(), 9.81);
    let a = g * (theta.sin() - theta.cos() * phi.tan());
    let (c0, p0) = (Vector2::new(history[0].x, history[0].y), Vector2::from(off));
    for ((h, p), q) in history.iter().zip(&at_centroid).zip(&at_off) {
        assert_eq!((p.time, q.time), (h.time, h.time), "the same output times");
        assert_eq!((p.block, q.block), (1, 1));
        let c = Vector2::new(h.x, h.y);
        let moved = Vector2::new(p.displacement[0], p.displacement[1]);
        assert!(
            (moved - (c - c0)).norm() < 1e-10,
            "t = {}: the point moved {moved:?}, the centroid {:?}",
            h.time,
            c - c0
        );
        let here = Vector2::new(p.position[0], p.position[1]);
        assert!((here - c).norm() < 1e-10, "t = {}", h.time);
        // Off the centroid: the rigid motion, give or take the strain.
        let expected = c + Rotation2::new(h.rotation) * (p0 - c0);
        let there = Vector2::new(q.position[0], q.position[1]);
        assert!(
            (there - expected).norm() < 1e-6,
            "t = {}: at {there:?}, rigid motion {expected:?}",
            h.time
        );
        let shift = Vector2::new(q.displacement[0], q.displacement[1]);
        assert!((shift - (there - p0)).norm() < 1e-12);
    }
    let last = at_centroid.last().unwrap();
    assert_eq!(last.time, 1.0);
    let along = -(last.displacement[0] * theta.cos() + last.displacement[1] * theta.sin());
    let exact = 0.5 * a;
    assert!(
        ((along - exact) / exact).abs() < 0.01,
        "slid {along:.6} m, exact {exact:.6} m"
    );
    let _ = std::fs::remove_dir_all(out);
}

/// A free square spinning at 1 rad/s for a revolution: a corner and a point
/// inside keep their distances from the centroid, and their angles about it
/// turn by the block's rotation in history.csv. A scene without measured
/// points writes no points.csv.
#[test]
fn points_on_a_spinning_block_turn_with_it() {
    let scene = example_with_points(
        "spinning_block_2d.ron",
        "(block: 0, point: (3.5, 4.5)), (block: 0, point: (3.2, 3.9))",
    );
    let out = run("points-spinning", &scene);
    let history = read_history(out.join("history.csv")).unwrap();
    let points = read_points(out.join("points.csv")).unwrap();
    let c0 = Vector2::new(3.0, 4.0);
    for (k, start) in [[3.5, 4.5], [3.2, 3.9]].into_iter().enumerate() {
        let r0: Vector2<f64> = Vector2::from(start) - c0;
        let rows = rows_of(&points, k);
        assert_eq!(rows.len(), history.len());
        for (h, p) in history.iter().zip(&rows) {
            assert_eq!(p.time, h.time);
            let r = Vector2::new(p.position[0] - h.x, p.position[1] - h.y);
            assert!(
                (r.norm() / r0.norm() - 1.0).abs() < 1e-9,
                "t = {}: {} m from the centroid, {} at the start",
                h.time,
                r.norm(),
                r0.norm()
            );
            let turned = Rotation2::rotation_between(&r0, &r).angle();
            let expected = Rotation2::new(h.rotation).angle();
            assert!(
                Rotation2::new(turned - expected).angle().abs() < 1e-9,
                "t = {}: turned {turned}, the block {}",
                h.time,
                h.rotation
            );
        }
        // A whole revolution brings it back.
        let last = rows.last().unwrap();
        assert!(last.displacement[0].hypot(last.displacement[1]) < 1e-8);
    }
    assert!((history.last().unwrap().rotation - std::f64::consts::TAU).abs() < 1e-9);
    let _ = std::fs::remove_dir_all(out);

    let mut plain = Scene::load(common::example("spinning_block_2d.ron")).unwrap();
    plain.analysis.duration = 0.1;
    let out = run("points-none", &plain);
    assert!(out.join("history.csv").exists());
    assert!(!out.join("points.csv").exists());
    assert!(!listed(&out).contains(&"points.csv".to_string()));
    let _ = std::fs::remove_dir_all(out);
}

/// 3D: the sliding block extruded 1 m deep, its measured point carried to
/// the mid-plane: the point at the prism's centroid moves as the centroid
/// in history.csv and slides the analytical distance down the dip.
#[test]
fn a_point_on_an_extruded_sliding_block() {
    let flat = example_with_points(
        "sliding_block_2d.ron",
        "(block: 1, point: (-0.5, 0.8660254037844386))",
    );
    let scene = dda::extrude::extrude(&flat, 1.0).unwrap();
    assert_eq!(
        scene.measured_points[0].point.as_slice(),
        [-0.5, 0.0, 0.8660254037844386]
    );
    let out = run("points-3d", &scene);
    let history: Vec<_> = read_history_3d(out.join("history.csv"))
        .unwrap()
        .into_iter()
        .filter(|r| r.block == 1)
        .collect();
    let points = read_points(out.join("points.csv")).unwrap();
    let header = std::fs::read_to_string(out.join("points.csv")).unwrap();
    assert!(header.starts_with("time,point,block,x,y,z,dx,dy,dz\n"));
    assert_eq!(points.len(), history.len());
    let c0 = Vector3::from(history[0].position);
    for (h, p) in history.iter().zip(&points) {
        assert_eq!(p.time, h.time);
        let moved = Vector3::from(p.displacement);
        let centroid = Vector3::from(h.position) - c0;
        assert!(
            (moved - centroid).norm() < 1e-10,
            "t = {}: the point moved {moved:?}, the centroid {centroid:?}",
            h.time
        );
    }
    let (theta, phi, g) = (30f64.to_radians(), 20f64.to_radians(), 9.81);
    let exact = 0.5 * g * (theta.sin() - theta.cos() * phi.tan());
    let dip = Vector3::new(-theta.cos(), 0.0, -theta.sin());
    let last = points.last().unwrap();
    assert_eq!(last.time, 1.0);
    let along = Vector3::from(last.displacement).dot(&dip);
    assert!(
        ((along - exact) / exact).abs() < 0.01,
        "slid {along:.6} m, exact {exact:.6} m"
    );
    let _ = std::fs::remove_dir_all(out);
}

/// The error of a scene that must not load.
fn refused(text: &str) -> String {
    match Scene::from_str(text, "bad.ron") {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn a_point_off_its_block_or_on_a_missing_block_is_refused() {
    let scene = |points: &str| {
        common::example_with(
            "sliding_block_2d.ron",
            "    blocks: [",
            &format!("    measured_points: [{points}],\n    blocks: ["),
        )
    };
    let e = refused(&scene("(block: 2, point: (-0.5, 0.9))"));
    assert!(e.contains("measured_points[0].block"), "{e}");
    assert!(e.contains("there is no block 2"), "{e}");
    // Inside the incline, named as block 1's.
    let e = refused(&scene("(block: 1, point: (0.0, 0.0))"));
    assert!(e.contains("measured_points[0].point"), "{e}");
    assert!(e.contains("outside block 1"), "{e}");
    assert!(e.contains("it lies in block 0: give block: 0"), "{e}");
    // In no block at all.
    let e = refused(&scene("(block: 1, point: (30.0, 30.0))"));
    assert!(e.contains("measured_points[0].point"), "{e}");
    assert!(e.contains("it lies in no block"), "{e}");
    let e = refused(&scene("(block: 1, point: (-0.5, 0.9, 0.0))"));
    assert!(e.contains("measured_points[0].point"), "{e}");
    assert!(e.contains("write (x, y)"), "{e}");
    // On an edge or a corner is on the block.
    let on = "(block: 0, point: (0.0, 0.0)), (block: 1, point: (-0.25, 0.4330127018922193)), \
              (block: 1, point: (-0.6830127018922193, 0.1830127018922193))";
    if let Err(e) = Scene::from_str(&scene(on), "ok.ron") {
        panic!("{e}");
    }

    // 3D: outside the cube.
    let cube = common::example_with(
        "sliding_block_3d.ron",
        "    blocks: [",
        "    measured_points: [(block: 1, point: (5.0, 5.0, 5.0))],\n    blocks: [",
    );
    let e = refused(&cube);
    assert!(e.contains("measured_points[0].point"), "{e}");
    assert!(e.contains("outside block 1"), "{e}");
}
