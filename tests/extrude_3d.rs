//! 2D versus 3D: a 2D scene and its extruded prism model (`dda extrude`)
//! give the same answers. 2D (x, y) is 3D (x, 0, y), so the 2D y
//! displacement is the 3D z one, and the 2D stress (σx, σy, τxy) is the 3D
//! (σx, σz, τzx).

use std::path::Path;

use dda::extrude::{extrude, extrude_with, Extrusion};
use dda::run::{run_scene, RunOptions};
use dda::{read_history, read_history_3d, HistoryRow, HistoryRow3, Scene};
use dda_contact::LawRegistry;

mod common;

fn load(name: &str) -> Scene {
    Scene::load(common::example(name)).unwrap()
}

fn run_2d(scene: &Scene, name: &str) -> Vec<HistoryRow> {
    let out = common::out_dir(name);
    run_scene(
        scene,
        &out,
        RunOptions::default(),
        &LawRegistry::with_builtin(),
    )
    .unwrap();
    let rows = read_history(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    rows
}

fn run_3d(scene: &Scene, name: &str) -> Vec<HistoryRow3> {
    let out = common::out_dir(name);
    let summary = run_scene(
        scene,
        &out,
        RunOptions::default(),
        &LawRegistry::with_builtin(),
    )
    .unwrap();
    assert_eq!(summary.dimension, 3);
    let rows = read_history_3d(out.join("history.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    rows
}

/// A block's 2D displacement from t = 0 to `t`.
fn moved_2d(rows: &[HistoryRow], block: usize, t: f64) -> [f64; 2] {
    let (a, b) = (common::at(rows, block, 0.0), common::at(rows, block, t));
    assert!((b.time - t).abs() < 1e-12);
    [b.x - a.x, b.y - a.y]
}

/// A block's 3D displacement from t = 0 to `t`.
fn moved_3d(rows: &[HistoryRow3], block: usize, t: f64) -> [f64; 3] {
    let at = |time: f64| {
        rows.iter()
            .filter(|r| r.block == block)
            .min_by(|a, b| (a.time - time).abs().total_cmp(&(b.time - time).abs()))
            .unwrap()
    };
    let (a, b) = (at(0.0), at(t));
    assert!((b.time - t).abs() < 1e-12);
    [0, 1, 2].map(|k| b.position[k] - a.position[k])
}

#[test]
fn the_mapping_keeps_blocks_loads_and_gravity() {
    let flat = load("uniaxial_compression_2d.ron");
    let solid = extrude(&flat, 0.5).unwrap();
    assert_eq!(solid.dimension, 3);
    assert_eq!(solid.gravity(), [0.0, 0.0, 0.0]);
    assert_eq!(
        extrude(&load("sliding_block_2d.ron"), 1.0)
            .unwrap()
            .gravity(),
        [0.0, 0.0, -9.81]
    );
    let blocks = solid.expanded_blocks_3d();
    assert_eq!(blocks.len(), 1);
    let ys: Vec<f64> = blocks[0].vertices.iter().map(|v| v[1]).collect();
    assert_eq!(ys.iter().cloned().fold(f64::MIN, f64::max), 0.25);
    assert_eq!(ys.iter().cloned().fold(f64::MAX, f64::min), -0.25);
    // The 1 m × 2 m rectangle standing on y = 0 becomes a box standing on z = 0.
    let zs: Vec<f64> = blocks[0].vertices.iter().map(|v| v[2]).collect();
    assert_eq!(zs.iter().cloned().fold(f64::MAX, f64::min), 0.0);
    assert_eq!(zs.iter().cloned().fold(f64::MIN, f64::max), 2.0);
    // Loads are per unit thickness in 2D: times the depth, on the mid-plane.
    match &solid.loads[0] {
        dda::scene::Load::PointLoad { point, force, .. } => {
            assert_eq!(point.as_slice(), [-0.5, 0.0, 2.0]);
            assert_eq!(force.as_ref().unwrap().as_slice(), [0.0, 0.0, -250.0]);
        }
    }
    assert_eq!(solid.fixed_points[0].point.as_slice(), [0.0, 0.0, 0.0]);
    // The written file reads back as the same scene.
    let again = Scene::from_str(&solid.to_ron(), "again.ron").unwrap();
    assert_eq!(again.expanded_blocks_3d(), blocks);
    assert_eq!(again.loads, solid.loads);
    assert_eq!(again.analysis, solid.analysis);
    // 3D scenes and bad depths are refused.
    assert!(extrude(&solid, 1.0)
        .unwrap_err()
        .to_string()
        .contains("already a 3D scene"));
    assert!(extrude(&flat, 0.0)
        .unwrap_err()
        .to_string()
        .contains("the depth must be a positive length"));
}

#[test]
fn initial_velocity_and_stress_follow_the_axes() {
    let text = r#"Scene(
        analysis: (duration: 0.01, dt: 0.001, gravity: (0.0, 0.0)),
        materials: { "rock": (density: 2000.0, young: 1e9) },
        blocks: [
            Rectangle(center: (0.0, 0.0), width: 1.0, height: 1.0,
                      velocity: (1.0, 2.0, 3.0), stress: (-4.0, -5.0, 6.0)),
        ],
    )"#;
    let solid = extrude(&Scene::from_str(text, "v.ron").unwrap(), 2.0).unwrap();
    let block = &solid.expanded_blocks_3d()[0];
    // A counter-clockwise 2D turn (about +z) is a turn about −y in 3D.
    assert_eq!(block.velocity, [1.0, 0.0, 2.0, 0.0, -3.0, 0.0]);
    assert_eq!(block.stress, [-4.0, 0.0, -5.0, 0.0, 6.0, 0.0]);
    let mut model = solid.build_3d().unwrap();
    model.driver.advance_to(0.01).unwrap();
    let b = &model.driver.system.blocks[0];
    // Spinning at 3 rad/s counter-clockwise in the xz plane seen from −y.
    assert!((b.rotation.y + 0.03).abs() < 1e-9, "{}", b.rotation);
}

#[test]
fn the_sliding_block_slides_as_far_in_3d() {
    let flat = load("sliding_block_2d.ron");
    let rows2 = run_2d(&flat, "extrude-slide-2d");
    for depth in [1.0, 2.5] {
        let rows3 = run_3d(&extrude(&flat, depth).unwrap(), "extrude-slide-3d");
        for t in [0.5, 1.0] {
            let [dx, dy] = moved_2d(&rows2, 1, t);
            let [x, y, z] = moved_3d(&rows3, 1, t);
            let (d2, d3) = (dx.hypot(dy), x.hypot(z));
            assert!(
                ((d3 - d2) / d2).abs() < 0.01,
                "depth {depth}, t = {t}: 3D slid {d3:.6} m, 2D {d2:.6} m"
            );
            assert!(y.abs() < 1e-6 * d2, "moved {y:e} m out of the plane");
        }
    }
}

#[test]
fn the_resting_block_rests_in_both() {
    let flat = load("resting_block_2d.ron");
    let rows2 = run_2d(&flat, "extrude-rest-2d");
    let rows3 = run_3d(&extrude(&flat, 1.0).unwrap(), "extrude-rest-3d");
    let [dx, dy] = moved_2d(&rows2, 1, 2.0);
    let d3 = moved_3d(&rows3, 1, 2.0);
    let (d2, d3) = (dx.hypot(dy), d3.iter().map(|v| v * v).sum::<f64>().sqrt());
    assert!(d2 < 1e-4, "2D moved {d2:e} m");
    assert!(d3 < 1e-4, "3D moved {d3:e} m");
}

/// With its corners held against motion along y (`--plane-strain`), the
/// prism is in plane strain and matches the 2D plane-strain block: σz = −q,
/// σx = 0, the lateral strain εx = ν(1 + ν)q/E and the out-of-plane stress
/// σy = −νq.
#[test]
fn the_compressed_prism_with_held_ends_is_in_plane_strain() {
    let (q, e, nu) = (1e3, 1e10, 0.25);
    let flat = load("uniaxial_compression_2d.ron");
    let mut model2 = flat.build().unwrap();
    model2.driver.advance_to(model2.duration).unwrap();
    let b2 = &model2.driver.system.blocks[0];
    let mut solid = extrude_with(
        &flat,
        &Extrusion {
            depth: 1.0,
            plane_strain: true,
        },
    )
    .unwrap();
    // 1 point at the base plus a roller at each of the 8 corners.
    assert_eq!(solid.fixed_points.len(), 9);
    // The rollers are penalty springs: they hold εy to (block stiffness) /
    // (spring stiffness), so they must be far stiffer than the block.
    solid.analysis.fixed_penalty = Some(1e18);
    let mut model3 = solid.build_3d().unwrap();
    model3.driver.advance_to(model3.duration).unwrap();
    let b3 = &model3.driver.system.blocks[0];
    let close = |value: f64, expected: f64, what: &str| {
        assert!(
            ((value - expected) / expected).abs() < 1e-6,
            "{what}: {value:e}, expected {expected:e}"
        );
    };
    close(b3.stress[2], -q, "σz");
    close(b3.stress[1], -nu * q, "σy (out of plane)");
    assert!(b3.stress[0].abs() < 1e-6 * q, "σx = {}", b3.stress[0]);
    for k in 3..6 {
        assert!(b3.stress[k].abs() < 1e-6 * q, "shear {k}: {}", b3.stress[k]);
    }
    close(b3.strain[0], nu * (1.0 + nu) * q / e, "εx (in plane)");
    close(b3.strain[2], -(1.0 - nu * nu) * q / e, "εz");
    assert!(b3.strain[1].abs() < 1e-6 * q / e, "εy = {}", b3.strain[1]);
    // The 2D answers, component by component.
    close(b3.stress[2], b2.stress.y, "σz against the 2D σy");
    close(b3.strain[0], b2.strain.x, "εx against 2D");
    close(b3.strain[2], b2.strain.y, "εz against the 2D εy");
}

#[test]
fn the_command_writes_a_scene_that_runs() {
    let dir = common::out_dir("extrude-cli");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("slide_3d.ron");
    let result = std::process::Command::new(env!("CARGO_BIN_EXE_dda"))
        .args([
            "extrude",
            "examples/sliding_block_2d.ron",
            "--depth",
            "1.5",
            "-o",
        ])
        .arg(&out)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.starts_with("// The 3D prism model of examples/sliding_block_2d.ron"));
    let scene = Scene::load(&out).unwrap();
    assert_eq!(scene.dimension, 3);
    assert_eq!(scene.expanded_blocks_3d().len(), 2);
    scene.build_3d().unwrap();
    let bad = std::process::Command::new(env!("CARGO_BIN_EXE_dda"))
        .args([
            "extrude",
            "examples/sliding_block_2d.ron",
            "--depth=-1",
            "-o",
        ])
        .arg(dir.join("bad.ron"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("the depth must be a positive length"));
    assert!(!Path::new(&dir.join("bad.ron")).exists());
    let _ = std::fs::remove_dir_all(&dir);
}
