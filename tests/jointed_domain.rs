//! `JointedDomain` and `JointedDomain3D`: regions cut into blocks by joint
//! sets (Shi's DC step), the joint laws of each set, and jointed slopes.

mod common;

use dda::Scene;
use dda_2d::polygon;
use nalgebra::Point2;

fn scene(text: &str) -> Scene {
    Scene::from_str(text, "test.ron").unwrap_or_else(|e| panic!("{e}"))
}

fn area_2d(scene: &Scene) -> f64 {
    scene
        .expanded_blocks()
        .iter()
        .map(|b| {
            polygon::signed_area(
                &b.vertices
                    .iter()
                    .map(|p| Point2::new(p[0], p[1]))
                    .collect::<Vec<_>>(),
            )
        })
        .sum()
}

const GRID: &str = r#"Scene(
    analysis: (duration: 1.0),
    materials: { "rock": (density: 2600.0, young: 1e10) },
    blocks: [JointedDomain(
        region: [(0.0, 0.0), (10.0, 0.0), (10.0, 5.0), (0.0, 5.0)],
        sets: [
            (dip: 90.0, spacing: 1.0, law: Coulomb(friction_angle: 20.0)),
            (dip: 0.0, spacing: 1.0, law: Coulomb(friction_angle: 40.0)),
        ],
        min_block_area: 0.0,
    )],
)"#;

/// Two orthogonal persistent sets at 1 m cut a 10 × 5 m rectangle into 50
/// blocks (the joints through the corners lie along the boundary and cut
/// nothing), with the area kept, and each set's joints get its law.
#[test]
fn orthogonal_sets_cut_a_rectangle_into_fifty_blocks() {
    let s = scene(GRID);
    assert_eq!(s.block_count(), 50);
    let area = area_2d(&s);
    assert!((area - 50.0).abs() <= 1e-9 * 50.0, "area {area}");
    let table = s.law_table();
    let law = |phi: f64| {
        table
            .laws
            .iter()
            .position(|l| *l == dda::scene::JointLaw::Coulomb(dda::scene::Coulomb::frictional(phi)))
            .unwrap()
    };
    let count = |i: usize| table.pairs.values().filter(|&&v| v == i).count();
    // Vertical joints: 9 columns of 5; horizontal: 4 rows of 10.
    assert_eq!((count(law(20.0)), count(law(40.0))), (45, 40));
}

/// Random placement is the same for the same seed, and another seed gives
/// other blocks; either way the blocks fill the region.
#[test]
fn random_sets_are_deterministic_per_seed() {
    let text = |seed: u64| {
        format!(
            r#"Scene(
    analysis: (duration: 1.0),
    materials: {{ "rock": (density: 2600.0, young: 1e10) }},
    blocks: [JointedDomain(
        region: [(0.0, 0.0), (12.0, 0.0), (9.0, 6.0), (0.0, 6.0)],
        sets: [
            (dip: 30.0, spacing: 1.2, placement: Random(seed: {seed})),
            (dip: -70.0, spacing: 1.5, trace_length: 3.0, bridge: 1.0, placement: Random(seed: {})),
        ],
        min_block_area: 0.0,
    )],
)"#,
            seed + 1
        )
    };
    let (a, b, c) = (scene(&text(1)), scene(&text(1)), scene(&text(2)));
    assert_eq!(a.expanded_blocks(), b.expanded_blocks());
    assert_ne!(a.expanded_blocks(), c.expanded_blocks());
    for s in [&a, &c] {
        assert!(s.block_count() > 10);
        let area = area_2d(s);
        assert!((area - 63.0).abs() <= 1e-9 * 63.0, "area {area}");
    }
}

/// A 4 × 2 m region, vertical joints at x = 1, 2, 3 and one horizontal
/// joint at y = 1 in 1.5 m traces with 0.5 m bridges from x = 0: traces
/// [0, 1.5] and [2, 3.5]. The first and third columns are cut across; in
/// the second and fourth the trace ends inside, so they stay whole: 6 blocks.
#[test]
fn traces_with_bridges_cut_only_where_they_cross() {
    let s = scene(
        r#"Scene(
    analysis: (duration: 1.0),
    materials: { "rock": (density: 2600.0, young: 1e10) },
    blocks: [JointedDomain(
        region: [(0.0, 0.0), (4.0, 0.0), (4.0, 2.0), (0.0, 2.0)],
        sets: [
            (dip: 90.0, spacing: 1.0),
            (dip: 0.0, spacing: 2.0, origin: (0.0, 1.0), trace_length: 1.5, bridge: 0.5),
        ],
        min_block_area: 0.0,
    )],
)"#,
    );
    let blocks = s.expanded_blocks();
    assert_eq!(blocks.len(), 6);
    let mut areas: Vec<f64> = blocks
        .iter()
        .map(|b| {
            polygon::signed_area(
                &b.vertices
                    .iter()
                    .map(|p| Point2::new(p[0], p[1]))
                    .collect::<Vec<_>>(),
            )
        })
        .collect();
    areas.sort_by(f64::total_cmp);
    let expected = [1.0, 1.0, 1.0, 1.0, 2.0, 2.0];
    for (a, e) in areas.iter().zip(expected) {
        assert!((a - e).abs() < 1e-12, "areas {areas:?}");
    }
}

/// `fixed_below` fixes the blocks under a level: a 4 × 3 m region from
/// y = −1 with horizontal joints at y = 0 and 1 and vertical ones at
/// x = 2 has two blocks below y = 0, and only those are fixed.
#[test]
fn blocks_below_a_level_are_fixed() {
    let s = scene(
        r#"Scene(
    analysis: (duration: 1.0),
    materials: { "rock": (density: 2600.0, young: 1e10) },
    blocks: [JointedDomain(
        region: [(0.0, -1.0), (4.0, -1.0), (4.0, 2.0), (0.0, 2.0)],
        sets: [(dip: 0.0, spacing: 1.0), (dip: 90.0, spacing: 2.0)],
        fixed_below: 0.0,
    )],
)"#,
    );
    let blocks = s.expanded_blocks();
    assert_eq!(blocks.len(), 6);
    for b in &blocks {
        let top = b.vertices.iter().map(|p| p[1]).fold(f64::MIN, f64::max);
        assert_eq!(b.fixed, top <= 0.0, "{b:?}");
    }
    assert_eq!(blocks.iter().filter(|b| b.fixed).count(), 2);
}

/// Random 3D sets are the same for the same seed and fill the box.
#[test]
fn random_planes_are_deterministic_per_seed() {
    let text = |seed: u64| {
        format!(
            r#"Scene(
    dimension: 3,
    analysis: (duration: 1.0),
    materials: {{ "rock": (density: 2600.0, young: 1e10) }},
    blocks: [JointedDomain3D(
        region: Box(min: (0.0, 0.0, 0.0), max: (5.0, 4.0, 3.0)),
        sets: [
            (dip: 60.0, dip_direction: 30.0, spacing: 1.0, placement: Random(seed: {seed})),
            (dip: 20.0, dip_direction: 200.0, spacing: 1.0, placement: Random(seed: {seed})),
        ],
        min_block_volume: 0.0,
    )],
)"#
        )
    };
    let (a, b, c) = (scene(&text(3)), scene(&text(3)), scene(&text(4)));
    assert_eq!(a.expanded_blocks_3d(), b.expanded_blocks_3d());
    assert_ne!(a.expanded_blocks_3d(), c.expanded_blocks_3d());
    for s in [a, c] {
        let model = s.build_3d().unwrap();
        let volume: f64 = model.driver.system.blocks.iter().map(|b| b.volume()).sum();
        assert!((volume - 60.0).abs() <= 1e-9 * 60.0, "volume {volume}");
    }
}

#[test]
fn bad_sets_are_located_errors() {
    let bad = |from: &str, to: &str| {
        let text = GRID.replace(from, to);
        assert_ne!(text, GRID);
        Scene::from_str(&text, "test.ron").unwrap_err().to_string()
    };
    let e = bad("(dip: 90.0, spacing: 1.0", "(dip: 90.0, spacing: 0.0");
    assert!(
        e.contains("blocks[0].sets[0].spacing") && e.contains("positive"),
        "{e}"
    );
    let e = bad(
        "(dip: 0.0, spacing: 1.0",
        "(dip: 0.0, spacing: 1.0, bridge: 0.5",
    );
    assert!(
        e.contains("blocks[0].sets[1].bridge") && e.contains("trace_length"),
        "{e}"
    );
    let e = bad("(dip: 0.0, spacing: 1.0", "(dip: 0.0, spacing: 1e-6");
    assert!(
        e.contains("blocks[0].sets[1]") && e.contains("larger spacing"),
        "{e}"
    );
    let e = bad("(dip: 0.0,", "(dip: -90.0,");
    assert!(e.contains("blocks[0].sets[1].dip"), "{e}");
    let e = bad("(10.0, 5.0), (0.0, 5.0)]", "(10.0, 5.0), (10.0, 5.0)]");
    assert!(e.contains("blocks[0].region"), "{e}");
    let e = bad(
        "(dip: 0.0, spacing: 1.0",
        "(dip: 0.0, spacing: 1.0, dip_direction: 90.0",
    );
    assert!(e.contains("blocks[0].sets[1].dip_direction"), "{e}");
}

#[test]
fn orthogonal_planes_cut_a_box_into_blocks() {
    let s = scene(
        r#"Scene(
    dimension: 3,
    analysis: (duration: 1.0),
    materials: { "rock": (density: 2600.0, young: 1e10) },
    blocks: [JointedDomain3D(
        region: Box(min: (0.0, 0.0, 0.0), max: (4.0, 3.0, 2.0)),
        sets: [
            (dip: 90.0, dip_direction: 90.0, spacing: 1.0),
            (dip: 90.0, spacing: 1.0),
            (dip: 0.0, spacing: 1.0, law: Coulomb(friction_angle: 40.0)),
        ],
        min_block_volume: 0.0,
    )],
)"#,
    );
    let blocks = s.expanded_blocks_3d();
    assert_eq!(blocks.len(), 24);
    let model = s.build_3d().unwrap();
    let volume: f64 = model.driver.system.blocks.iter().map(|b| b.volume()).sum();
    assert!((volume - 24.0).abs() <= 1e-9 * 24.0, "volume {volume}");
    // Horizontal joints (set 2): one level of 4 × 3 pairs.
    let table = s.law_table();
    assert_eq!(table.pairs.len(), 12);
    let jointed_3d = s.to_ron();
    assert!(jointed_3d.contains("JointedDomain3D"));
}

/// The crest wedge of `examples/jointed_slope_2d.ron` lies above a bedding
/// joint dipping 35° that daylights in the face; at φ = 15° it slides
/// d = ½ g (sin 35° − cos 35° tan 15°) t², at φ = 45° it holds.
#[test]
fn jointed_slope_2d_slides_on_weak_bedding_and_holds_on_strong() {
    // A point of the crest wedge (above the bedding joint through
    // n·x = 6.09 m, n = (sin 35°, cos 35°)) and one of the slab below it.
    let (wedge, slab) = (Point2::new(4.0, 5.5), Point2::new(4.0, 3.0));
    let run = |text: String| {
        let s = scene(&text);
        let find = |p: &Point2<f64>| {
            s.expanded_blocks()
                .iter()
                .position(|b| {
                    let v: Vec<Point2<f64>> =
                        b.vertices.iter().map(|q| Point2::new(q[0], q[1])).collect();
                    polygon::contains(&v, p)
                })
                .expect("a block holds the point")
        };
        let (w, b) = (find(&wedge), find(&slab));
        let mut model = s.build().unwrap();
        let start = [w, b].map(|k| model.driver.system.blocks[k].centroid());
        model.driver.advance_to(0.5).unwrap();
        let end = [w, b].map(|k| model.driver.system.blocks[k].centroid());
        [0, 1].map(|i| end[i] - start[i])
    };
    let text = std::fs::read_to_string(common::example("jointed_slope_2d.ron")).unwrap();
    let [w, b] = run(text.clone());
    let (dip, phi, g) = (35f64.to_radians(), 15f64.to_radians(), 9.81);
    let exact = 0.5 * g * (dip.sin() - dip.cos() * phi.tan()) * 0.25;
    // Down the dip is (cos 35°, −sin 35°).
    let along = w.x * dip.cos() - w.y * dip.sin();
    println!(
        "2D wedge slid {along:.5} m, exact {exact:.5} m; slab moved {:.2e} m",
        b.norm()
    );
    assert!(
        ((along - exact) / exact).abs() < 0.02,
        "slid {along} m, exact {exact} m"
    );
    assert!(b.norm() < 1e-3, "the slab moved {} m", b.norm());
    let strong = text.replace(
        "law: Coulomb(friction_angle: 15.0)",
        "law: Coulomb(friction_angle: 45.0)",
    );
    assert_ne!(strong, text);
    let [w, _] = run(strong);
    println!("2D wedge on strong bedding moved {:.2e} m", w.norm());
    assert!(w.norm() < 1e-3, "the wedge moved {} m", w.norm());
}

/// The same in 3D, `examples/jointed_slope_3d.ron`, for 0.2 s. The blocks
/// above the daylighting bedding joint (n·x > 6.09 m, n = (sin 35°, 0,
/// cos 35°)) slide down the dip, but not all at the free-sliding rate: the
/// crest block carries part of a wedge at the free back face that slides
/// west on a cross joint (φ = 30° < 55°), and was measured at 90 % of it,
/// the face block at 99.8 %. Friction can only slow a block, so the slide
/// lies between half the free slide and the free slide; blocks below the
/// joint and away from the back face stay, and at φ = 45° nothing above
/// the joint moves.
#[test]
fn jointed_slope_3d_slides_on_weak_bedding_and_holds_on_strong() {
    let (dip, g, t) = (35f64.to_radians(), 9.81, 0.2);
    let n = nalgebra::Vector3::new(dip.sin(), 0.0, dip.cos());
    let down = nalgebra::Vector3::new(dip.cos(), 0.0, -dip.sin());
    let above = |c: &nalgebra::Point3<f64>| n.dot(&c.coords) > 6.09;
    // (above the joint, away from the back face, moved along the dip, moved)
    let run = |text: String| {
        let s = scene(&text);
        let mut model = s.build_3d().unwrap();
        let start: Vec<_> = model
            .driver
            .system
            .blocks
            .iter()
            .map(|b| b.centroid())
            .collect();
        model.driver.advance_to(t).unwrap();
        model
            .driver
            .system
            .blocks
            .iter()
            .zip(&start)
            .map(|(b, c)| {
                let d = b.centroid() - c;
                (above(c), c.x > 2.0, d.dot(&down), d.norm())
            })
            .collect::<Vec<_>>()
    };
    let text = std::fs::read_to_string(common::example("jointed_slope_3d.ron")).unwrap();
    let free = 0.5 * g * (dip.sin() - dip.cos() * 15f64.to_radians().tan()) * t * t;
    let weak = run(text.clone());
    assert!(weak.iter().filter(|b| b.0).count() >= 2);
    for &(up, front, along, moved) in &weak {
        if up {
            println!("3D block above the joint slid {along:.5} m, free slide {free:.5} m");
            assert!(
                along > 0.5 * free && along < 1.01 * free,
                "slid {along} m, free {free} m"
            );
        } else if front {
            assert!(moved < 1e-3, "a block below the joint moved {moved} m");
        }
    }
    let strong = text.replace(
        "law: Coulomb(friction_angle: 15.0)",
        "law: Coulomb(friction_angle: 45.0)",
    );
    assert_ne!(strong, text);
    for (up, _, _, moved) in run(strong) {
        if up {
            println!("3D block above the joint on strong bedding moved {moved:.2e} m");
            assert!(moved < 1e-3, "moved {moved} m");
        }
    }
}

/// `dda extrude` writes a jointed domain block by block, and keeps the
/// laws its sets gave the block pairs.
#[test]
fn extruding_a_jointed_domain_keeps_the_sets_laws() {
    let flat = Scene::load(common::example("jointed_slope_2d.ron")).unwrap();
    let solid = dda::extrude::extrude(&flat, 1.0).unwrap();
    let solid = Scene::from_str(&solid.to_ron(), "extruded.ron").unwrap();
    let (a, b) = (flat.law_table(), solid.law_table());
    assert_eq!(a.laws.len(), b.laws.len());
    assert_eq!(a.pairs.len(), b.pairs.len());
    for (pair, law) in &a.pairs {
        assert_eq!(a.laws[*law], b.laws[b.pairs[pair]]);
    }
}
