//! The same scene gives byte-identical outputs, run after run and on one
//! thread or two.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs `scene` with `threads` worker threads into its own folder and
/// returns the bytes of history.csv and contacts.csv.
fn outputs(scene: &str, label: &str, threads: usize) -> (Vec<u8>, Vec<u8>) {
    let out: PathBuf = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("determinism")
        .join(format!("{label}-{threads}"));
    let _ = std::fs::remove_dir_all(&out);
    let status = Command::new(env!("CARGO_BIN_EXE_dda"))
        .args(["run", scene, "--out"])
        .arg(&out)
        .env("RAYON_NUM_THREADS", threads.to_string())
        .status()
        .unwrap();
    assert!(status.success(), "{scene} failed with {threads} threads");
    let read = |name: &str| std::fs::read(out.join(name)).unwrap_or_default();
    (read("history.csv"), read("contacts.csv"))
}

fn check(scene: &str, label: &str) {
    let one = outputs(scene, &format!("{label}-a"), 1);
    assert!(!one.0.is_empty());
    assert_eq!(
        one,
        outputs(scene, &format!("{label}-b"), 1),
        "{scene}: run to run"
    );
    assert_eq!(
        one,
        outputs(scene, label, 2),
        "{scene}: one thread against two"
    );
}

#[test]
fn a_2d_arch_collapsing_is_the_same_every_time() {
    check("examples/arch_heyman_collapse_2d.ron", "arch");
}

#[test]
fn a_3d_wedge_sliding_is_the_same_every_time() {
    check("examples/wedge_3d.ron", "wedge");
}

/// Jointed domains: the cutter's blocks and the joint set each pair of
/// blocks shares come out in one order (a pair on two joints once took
/// whichever joint a hash map gave first, and runs differed).
#[test]
fn jointed_slopes_are_the_same_every_time() {
    check("examples/jointed_slope_2d.ron", "jointed-2d");
    check("examples/jointed_slope_3d.ron", "jointed-3d");
}

/// A wall of 411 bricks: its narrow phase spreads its block pairs over the
/// threads, and the contacts come back in pair order whatever the count.
#[test]
fn a_wall_on_several_threads_is_the_same_every_time() {
    let text = r#"Scene(
    analysis: (duration: 0.02, dt: 0.001, penalty: 1e9, gravity: (0.0, -9.81)),
    materials: { "brick": (density: 1800.0, young: 5e9, poisson: 0.2) },
    default_joint: Coulomb(friction_angle: 35.0),
    blocks: [
        Rectangle(center: (5.0, -0.5), width: 12.0, height: 1.0, fixed: true),
        Wall(origin: (0.0, 0.0), length: 10.0, courses: 20, brick_length: 0.5, brick_height: 0.25, bond: Running),
    ],
)"#;
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("determinism");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("wall_20x20.ron");
    std::fs::write(&path, text).unwrap();
    check(path.to_str().unwrap(), "wall");
}

/// Within a pass the matrix and the residual are assembled block by block
/// (the matrix's off-diagonal blocks pair by pair) on every core; contact
/// by contact on one thread they come out the same to the last bit: the
/// same moves and factorisations, the same positions. A collapsing arch
/// (joints opening, closing and sliding), a settling wall of deformable
/// bricks, one whose sliding contacts' friction is coupled to their
/// normal gaps (whole-tangent moves), and a sliding 3D wedge (whose
/// friction turns with its stretch).
#[test]
fn assembly_block_by_block_is_contact_by_contact_to_the_last_bit() {
    use dda::bench::{wall, Stepping};
    use dda::scene::BlockKind;
    use dda::Scene;
    let example = |name: &str| Scene::load(Path::new("examples").join(name)).unwrap();
    let plane = |scene: &Scene, until: f64, one_thread: bool| {
        let mut model = scene.build().unwrap();
        model.driver.assemble_on_one_thread(one_thread);
        model.driver.advance_to(until).unwrap();
        let stats = model.driver.statistics();
        let at: Vec<f64> = (model.driver.system.blocks.iter())
            .flat_map(|b| b.centroid().coords.iter().copied().collect::<Vec<_>>())
            .collect();
        (
            stats.newton_iterations,
            stats.factorizations,
            at,
            stats.whole_tangent_moves,
        )
    };
    let arch = example("arch_heyman_collapse_2d.ron");
    let bricks = wall(10, 2, Stepping::Fixed, BlockKind::Deformable).unwrap();
    // At dt 1 ms and its automatic penalty the 40 × 40 deformable wall's
    // passes couple its sliding contacts' friction to their normal gaps
    // (whole-tangent moves), whose terms are gathered too.
    let coupled = wall(40, 2, Stepping::Given(1e-3), BlockKind::Deformable).unwrap();
    for (scene, until, whole) in [
        (&arch, 0.3, false),
        (&bricks, 0.02, false),
        (&coupled, 0.03, true),
    ] {
        let (moves, factorizations, at, whole_tangent) = plane(scene, until, false);
        println!("whole-tangent moves {whole_tangent}");
        assert!(moves > 0 && factorizations > 0);
        assert!(
            !whole || whole_tangent > 0,
            "{whole_tangent} whole-tangent moves"
        );
        let (one_moves, one_factorizations, one_at, one_whole) = plane(scene, until, true);
        assert_eq!(
            (moves, factorizations, whole_tangent),
            (one_moves, one_factorizations, one_whole)
        );
        assert!(at == one_at, "the blocks ended apart");
    }
    let wedge = example("wedge_3d.ron");
    let solid = |one_thread: bool| {
        let mut model = wedge.build_3d().unwrap();
        model.driver.assemble_on_one_thread(one_thread);
        model.driver.advance_to(0.1).unwrap();
        let stats = model.driver.statistics();
        let at: Vec<f64> = (model.driver.system.blocks.iter())
            .flat_map(|b| b.centroid().coords.iter().copied().collect::<Vec<_>>())
            .collect();
        (stats.newton_iterations, stats.factorizations, at)
    };
    assert_eq!(solid(false), solid(true));
}
