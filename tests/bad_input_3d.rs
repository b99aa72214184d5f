//! Bad 3D scenes give one clear error naming the file, the place (with its
//! line where it can be found) and the fix, and never panic.

use dda::{Scene, SceneError};

/// A valid 3D scene; each test breaks one thing in it.
const GOOD: &str = r#"// A tetrahedron resting on a fixed slab.
Scene(
    dimension: 3,
    analysis: (
        duration: 1.0,
        dt: 0.001,
        penalty: 1e9,
        gravity: (0.0, 0.0, -9.81),
    ),
    materials: {
        "rock": (density: 2700.0, young: 1e10, poisson: 0.25),
    },
    blocks: [
        Box(material: "rock", center: (0.0, 0.0, -0.5), size: (4.0, 4.0, 1.0), fixed: true),
        Polyhedron(
            vertices: [
                (0.0, 0.0, 0.0),
                (1.0, 0.0, 0.0),
                (0.0, 1.0, 0.0),
                (0.0, 0.0, 1.0),
            ],
            faces: [
                [0, 2, 1],
                [0, 1, 3],
                [0, 3, 2],
                [1, 2, 3],
            ],
        ),
        Prism(outline: [(1.5, 1.5), (1.9, 1.5), (1.9, 1.9)], z0: 0.0, z1: 0.5),
    ],
    loads: [
        PointLoad(block: 1, point: (0.2, 0.2, 0.2), force: (0.0, 0.0, -1e3)),
    ],
    fixed_points: [ (block: 0, point: (0.0, 0.0, -1.0)) ],
)
"#;

/// GOOD with `old` (which must occur once) replaced by `new`.
fn with(old: &str, new: &str) -> String {
    assert_eq!(
        GOOD.matches(old).count(),
        1,
        "{old:?} must occur once in GOOD"
    );
    GOOD.replace(old, new)
}

fn load_and_build(text: &str) -> Result<(), SceneError> {
    Scene::from_str(text, "bad.ron")?.build_3d().map(|_| ())
}

fn error_of(text: &str) -> String {
    match load_and_build(text) {
        Ok(()) => panic!("the scene was accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// 1-based line of the only line containing `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    let lines: Vec<usize> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.contains(needle))
        .map(|(i, _)| i + 1)
        .collect();
    assert_eq!(lines.len(), 1, "{needle:?} must be on exactly one line");
    lines[0]
}

/// The error names the file and the line holding `line_marker`, the place,
/// and contains `phrase`.
fn assert_error(text: &str, line_marker: &str, place: &str, phrase: &str) {
    let message = error_of(text);
    let line = line_of(text, line_marker);
    assert!(
        message.starts_with(&format!("bad.ron:{line}:")),
        "expected line {line} in: {message}"
    );
    assert!(
        message.contains(&format!(": {place}: ")),
        "expected place {place} in: {message}"
    );
    assert!(
        message.contains(phrase),
        "expected {phrase:?} in: {message}"
    );
}

/// The tetrahedron's faces replaced by `faces` (written one per line).
fn with_faces(faces: &[&str]) -> String {
    let listed: String = faces
        .iter()
        .map(|f| format!("                {f},\n"))
        .collect();
    with(
        "                [0, 2, 1],\n                [0, 1, 3],\n                [0, 3, 2],\n                [1, 2, 3],\n",
        &listed,
    )
}

#[test]
fn the_good_scene_builds() {
    let scene = Scene::from_str(GOOD, "good.ron").unwrap();
    let model = scene.build_3d().unwrap();
    let system = &model.driver.system;
    assert_eq!(system.blocks.len(), 3);
    // The fixed slab holds its eight corners plus the one fixed point.
    assert_eq!(system.fixed.len(), 9);
    assert_eq!(system.loads.len(), 1);
    assert!((system.blocks[1].volume() - 1.0 / 6.0).abs() < 1e-15);
    assert!((system.blocks[2].volume() - 0.5 * 0.4 * 0.4 * 0.5).abs() < 1e-15);
    assert_eq!(system.gravity.z, -9.81);
    // The same scene, built for either dimension.
    assert_eq!(scene.build_any().unwrap().dimension(), 3);
}

/// GOOD with a cube (corners 0-3 at the bottom, 4-7 above them) inserted
/// as blocks[1], its faces written one per line.
fn with_cube(corners: &str, faces: &[&str]) -> String {
    let listed: String = faces
        .iter()
        .map(|f| format!("                {f},\n"))
        .collect();
    with(
        "        Polyhedron(",
        &format!(
            "        Polyhedron(\n            vertices: [{corners}],\n            faces: [\n{listed}            ],\n        ),\n        Polyhedron("
        ),
    )
}

const CUBE: &str = "(2.0, 2.0, 0.0), (3.0, 2.0, 0.0), (3.0, 3.0, 0.0), (2.0, 3.0, 0.0), \
                    (2.0, 2.0, 1.0), (3.0, 2.0, 1.0), (3.0, 3.0, 1.0), (2.0, 3.0, 1.0)";

#[test]
fn an_open_surface_names_the_face_and_edge() {
    // The cube without its top.
    let text = with_cube(
        CUBE,
        &[
            "[0, 3, 2, 1]",
            "[0, 1, 5, 4]",
            "[1, 2, 6, 5]",
            "[2, 3, 7, 6]",
            "[3, 0, 4, 7]",
        ],
    );
    assert_error(
        &text,
        "[0, 1, 5, 4]",
        "blocks[1]",
        "face 1: the surface is open: its edge 5-4 belongs to no other face; add the missing faces",
    );
    // Too few faces to close anything.
    let text = with_faces(&["[0, 2, 1]", "[0, 1, 3]", "[0, 3, 2]"]);
    assert_error(
        &text,
        "faces:",
        "blocks[1].faces",
        "a closed polyhedron needs at least 4 faces, this one has 3; add the missing faces",
    );
}

#[test]
fn a_face_turned_against_its_neighbours_is_named() {
    let text = with_faces(&["[0, 2, 1]", "[0, 1, 3]", "[0, 3, 2]", "[3, 2, 1]"]);
    assert_error(
        &text,
        "[3, 2, 1]",
        "blocks[1]",
        "face 3 is oriented against its neighbours: list its corners counter-clockwise seen from outside",
    );
}

#[test]
fn an_inside_out_surface_is_refused() {
    let text = with_faces(&["[0, 1, 2]", "[0, 3, 1]", "[0, 2, 3]", "[1, 3, 2]"]);
    assert_error(
        &text,
        "faces:",
        "blocks[1].faces",
        "the faces are listed clockwise seen from outside (the surface faces inward); reverse the order",
    );
}

#[test]
fn a_non_manifold_edge_is_named() {
    // Two tetrahedra sharing the edge 0-1 as one block: four faces meet there.
    let text = with(
        "                (0.0, 0.0, 1.0),\n",
        "                (0.0, 0.0, 1.0),\n                (0.5, -1.0, 0.0),\n                (0.5, -0.5, 1.0),\n",
    );
    let text = text.replace(
        "                [1, 2, 3],\n",
        "                [1, 2, 3],\n                [0, 1, 4],\n                [0, 5, 1],\n                [0, 4, 5],\n                [1, 5, 4],\n",
    );
    let message = error_of(&text);
    assert!(
        message.contains(
            ": blocks[1].faces: the surface is not manifold: edge 0-1 belongs to 4 faces, not 2"
        ),
        "{message}"
    );
}

#[test]
fn a_flat_polyhedron_has_zero_volume() {
    let text = with("(0.0, 0.0, 1.0),", "(1.0, 1.0, 0.0),");
    let message = error_of(&text);
    assert!(message.starts_with("bad.ron:"), "{message}");
    assert!(message.contains("blocks[1]"), "{message}");
    assert!(
        message.contains("zero area") || message.contains("zero volume"),
        "{message}"
    );
}

#[test]
fn a_face_off_its_plane_names_the_face_and_corner() {
    // The cube with one top corner lifted: the top face and two sides bend.
    let text = with_cube(
        &CUBE.replace("(3.0, 3.0, 1.0)", "(3.0, 3.0, 1.2)"),
        &[
            "[0, 3, 2, 1]",
            "[4, 5, 6, 7]",
            "[0, 1, 5, 4]",
            "[1, 2, 6, 5]",
            "[2, 3, 7, 6]",
            "[3, 0, 4, 7]",
        ],
    );
    assert_error(
        &text,
        "[4, 5, 6, 7]",
        "blocks[1]",
        "face 1 is not planar: vertex 5 is 4.951e-2 off its plane",
    );
    assert!(
        error_of(&text).contains("move the corner onto the plane or split the face into triangles")
    );
}

#[test]
fn bad_indices_and_repeated_corners_are_located() {
    let text = with_faces(&["[0, 2, 1]", "[0, 1, 7]", "[0, 3, 2]", "[1, 2, 3]"]);
    assert_error(
        &text,
        "[0, 1, 7]",
        "blocks[1]",
        "face 1 refers to vertex 7, but there are only 4 vertices (numbered 0 to 3)",
    );
    let text = with_faces(&["[0, 2, 1]", "[0, 1, 1, 3]", "[0, 3, 2]", "[1, 2, 3]"]);
    assert_error(
        &text,
        "[0, 1, 1, 3]",
        "blocks[1]",
        "face 1 visits vertex 1 twice",
    );
    let text = with(
        "faces: [\n                [0, 2, 1],",
        "faces: [\n                [0, 2],\n                [0, 2, 1],",
    );
    assert_error(
        &text,
        "[0, 2],",
        "blocks[1]",
        "face 0 has 2 corners; a face needs at least 3",
    );
}

#[test]
fn an_unused_corner_is_named() {
    let text = with(
        "                (0.0, 0.0, 1.0),\n",
        "                (0.0, 0.0, 1.0),\n                (0.3, 0.3, 0.3),\n",
    );
    assert_error(
        &text,
        "(0.3, 0.3, 0.3)",
        "blocks[1]",
        "vertex 4 is used by no face; remove it or add it to its faces",
    );
}

#[test]
fn nan_and_infinity_are_refused_where_written() {
    let text = with("(1.0, 0.0, 0.0),", "(1.0, NaN, 0.0),");
    assert_error(
        &text,
        "NaN",
        "blocks[1].vertices[1]",
        "vertex 1 is NaN, not a finite number",
    );
    let text = with("size: (4.0, 4.0, 1.0)", "size: (4.0, inf, 1.0)");
    assert_error(&text, "inf", "blocks[0].size", "not a finite number");
    let text = with("force: (0.0, 0.0, -1e3)", "force: (0.0, NaN, -1e3)");
    assert_error(&text, "NaN", "loads[0].force", "the force is NaN");
}

#[test]
fn boxes_and_prisms_need_sizes() {
    let text = with("size: (4.0, 4.0, 1.0)", "size: (4.0, 0.0, 1.0)");
    assert_error(
        &text,
        "size:",
        "blocks[0].size",
        "the size along its own y must be positive, got 0",
    );
    let text = with("z0: 0.0, z1: 0.5", "z0: 0.5, z1: 0.5");
    assert_error(
        &text,
        "z1:",
        "blocks[2].z1",
        "the prism's top z1 = 0.5 must lie above its bottom z0 = 0.5",
    );
    let text = with("(1.9, 1.5), (1.9, 1.9)", "(1.9, 1.5), (1.7, 1.5)");
    assert_error(&text, "outline:", "blocks[2].outline", "zero area");
}

#[test]
fn overlapping_polyhedra_name_both() {
    // The tetrahedron sinks 0.1 m into the slab.
    let text = with("(0.0, 0.0, 0.0),\n", "(0.0, 0.0, -0.1),\n");
    let message = error_of(&text);
    assert!(
        message.contains(": blocks[1]: the block overlaps blocks[0] at the start"),
        "{message}"
    );
    // A prism inside the slab.
    let text = with("z0: 0.0, z1: 0.5", "z0: -0.8, z1: -0.2");
    let message = error_of(&text);
    assert!(
        message.contains(": blocks[2]: the block overlaps blocks[0] at the start"),
        "{message}"
    );
}

#[test]
fn two_dimensional_values_in_a_three_dimensional_scene_are_named() {
    let text = with(
        "        Prism(",
        "        Rectangle(center: (5.0, 5.0), width: 1.0, height: 1.0),\n        Prism(",
    );
    assert_error(
        &text,
        "Rectangle(",
        "blocks[2]",
        "Rectangle is a 2D block, but this is a 3D scene (dimension: 3); use Polyhedron, Box or Prism",
    );
    let text = with("gravity: (0.0, 0.0, -9.81)", "gravity: (0.0, -9.81)");
    assert_error(
        &text,
        "gravity",
        "analysis.gravity",
        "gravity has 2 numbers, but this is a 3D scene: write (gx, gy, gz)",
    );
    let text = with("point: (0.2, 0.2, 0.2)", "point: (0.2, 0.2)");
    assert_error(
        &text,
        "PointLoad",
        "loads[0].point",
        "the load point has 2 numbers, but this is a 3D scene: write (x, y, z)",
    );
    let text = with(
        "(block: 0, point: (0.0, 0.0, -1.0))",
        "(block: 0, point: (0.0, 0.0, -1.0), axis: (0.0, 1.0))",
    );
    assert_error(
        &text,
        "axis",
        "fixed_points[0].axis",
        "the axis has 2 numbers, but this is a 3D scene: write (x, y, z)",
    );
    let text = with("penalty: 1e9,", "penalty: 1e9,\n        plane: Stress,");
    assert_error(
        &text,
        "plane",
        "analysis.plane",
        "plane (plane strain or plane stress) is for 2D scenes; a 3D scene has no plane: remove it",
    );
    // A 2D velocity on a 3D block is a syntax error at its place.
    let text = with(
        "z0: 0.0, z1: 0.5",
        "z0: 0.0, z1: 0.5, velocity: (1.0, 0.0, 0.0)",
    );
    let message = error_of(&text);
    assert!(
        message.starts_with(&format!("bad.ron:{}:", line_of(&text, "velocity"))),
        "{message}"
    );
    assert!(
        message.contains("length 6 but found 3 elements instead; a 3D block's velocity is (vx, vy, vz, wx, wy, wz)"),
        "{message}"
    );
}

#[test]
fn loads_fixed_points_and_histories_take_three_components() {
    let text = with(
        "force: (0.0, 0.0, -1e3)",
        "history: [(0.0, 0.0, 0.0, 0.0), (1.0, 0.0, -1e3)]",
    );
    assert_error(
        &text,
        "history",
        "loads[0].history[1]",
        "the sample has 3 numbers, but this is a 3D scene: write (t, fx, fy, fz)",
    );
    let text = with(
        "force: (0.0, 0.0, -1e3)",
        "force: (0.0, 0.0, -1e3), history: []",
    );
    assert_error(
        &text,
        "history",
        "loads[0]",
        "give either force: (fx, fy, fz) or history: [(t, fx, fy, fz), ...]",
    );
    let text = with(
        "(block: 0, point: (0.0, 0.0, -1.0))",
        "(block: 3, point: (0.0, 0.0, -1.0))",
    );
    assert_error(
        &text,
        "block: 3",
        "fixed_points[0].block",
        "there is no block 3: the scene has 3 blocks, numbered from 0 to 2",
    );
    let text = with(
        "(block: 0, point: (0.0, 0.0, -1.0))",
        "(block: 0, point: (0.0, 0.0, -1.0), axis: (0.0, 0.0, 0.0))",
    );
    assert_error(
        &text,
        "axis",
        "fixed_points[0].axis",
        "the axis (0, 0, 0) has no direction; give the direction to hold, like (0.0, 1.0, 0.0), or leave axis out to hold all three",
    );
}

fn with_ground(motion: &str) -> String {
    with(
        "    fixed_points:",
        &format!("    ground_motion: (blocks: [0], motion: {motion}),\n    fixed_points:"),
    )
}

fn record_file(name: &str, text: &str) -> std::path::PathBuf {
    let path = std::env::temp_dir().join(format!("dda-3d-{}-{name}.csv", std::process::id()));
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn ground_motions_take_three_components() {
    let ok = with_ground("Sine(amplitude: (1.0, 0.5, 0.2), frequency: 2.0, duration: 1.0)");
    load_and_build(&ok).unwrap();
    let text = with_ground("Sine(amplitude: (1.0, 0.5), frequency: 2.0, duration: 1.0)");
    assert_error(
        &text,
        "ground_motion",
        "ground_motion.motion.amplitude",
        "the amplitude has 2 numbers, but this is a 3D scene: write (ax, ay, az)",
    );
    let good = record_file(
        "good",
        "time, ax, ay, az\n0.0, 0.0, 0.0, 0.0\n0.1, 1.0, 0.0, 0.5\n",
    );
    let text = with_ground(&format!("Record(path: {:?})", good.display().to_string()));
    load_and_build(&text).unwrap();
    let short = record_file("short", "0.0, 0.0, 0.0\n0.1, 1.0, 0.0\n");
    let text = with_ground(&format!("Record(path: {:?})", short.display().to_string()));
    let message = error_of(&text);
    assert!(
        message.contains(":1: \"0.0, 0.0, 0.0\" has 3 columns; a row is `time, ax, ay, az`"),
        "{message}"
    );
    // Fewer columns when the record says which axes they are.
    let text = with_ground(&format!(
        "Record(path: {:?}, components: \"xz\")",
        short.display().to_string()
    ));
    load_and_build(&text).unwrap();
    let text = with_ground(&format!(
        "Record(path: {:?}, components: \"xw\")",
        short.display().to_string()
    ));
    assert_error(
        &text,
        "ground_motion",
        "ground_motion.motion.components",
        "components \"xw\" must name axes of this 3D scene (xyz), each once",
    );
    let text = GOOD.replace(
        "    fixed_points:",
        "    ground_motion: (blocks: [1], motion: Pulse(amplitude: (1.0, 0.0, 0.0), period: 0.5)),\n    fixed_points:",
    );
    assert_error(
        &text,
        "ground_motion",
        "ground_motion.blocks[0]",
        "block 1 is not fixed, so the ground cannot carry it",
    );
    for p in [good, short] {
        let _ = std::fs::remove_file(p);
    }
}

#[test]
fn truncated_files_never_panic() {
    let last = GOOD.rfind(')').unwrap();
    for (end, _) in GOOD[..last].char_indices() {
        let message = error_of(&GOOD[..end]);
        assert!(message.starts_with("bad.ron:"), "at {end}: {message}");
    }
}

#[test]
fn every_face_and_corner_error_is_an_error_not_a_panic() {
    // Each single-face edit of the tetrahedron either builds or gives a
    // located error.
    let faces = ["[0, 2, 1]", "[0, 1, 3]", "[0, 3, 2]", "[1, 2, 3]"];
    let edits = [
        "[]",
        "[0]",
        "[0, 1]",
        "[3, 3, 3]",
        "[0, 1, 2, 3]",
        "[9, 1, 2]",
        "[2, 1, 0]",
    ];
    for k in 0..faces.len() {
        for edit in edits {
            let mut list = faces.to_vec();
            list[k] = edit;
            match load_and_build(&with_faces(&list)) {
                Ok(()) => {}
                Err(e) => {
                    let message = e.to_string();
                    assert!(message.starts_with("bad.ron:"), "{list:?}: {message}");
                    assert!(message.contains("blocks[1]"), "{list:?}: {message}");
                }
            }
        }
    }
}

/// A ring of 100,000 staves from radius 9.5 to 10.5 m, each 0.3 mm thick
/// along the ring and 1 m tall, listed one by one: slanted slivers whose
/// boxes each meet those of thousands of others. The ring is checked (in
/// seconds, where a check of the boxes' neighbours took minutes), and a
/// stave reaching over its neighbour is found.
#[test]
fn a_hundred_thousand_slivers_are_checked() {
    let n = 100_000;
    let at = |r: f64, j: usize| {
        let a = std::f64::consts::PI * j as f64 / n as f64;
        format!("({}, {})", r * a.cos(), r * a.sin())
    };
    let ring = |wide: usize| {
        let staves: String = (0..n)
            .map(|k| {
                let reach = if k == wide { 2 } else { 1 };
                format!(
                    "        Prism(outline: [{}, {}, {}, {}], z0: 0.0, z1: 1.0),\n",
                    at(9.5, k),
                    at(10.5, k),
                    at(10.5, k + reach),
                    at(9.5, k + 1)
                )
            })
            .collect();
        format!(
            "Scene(\n    dimension: 3,\n    analysis: (duration: 0.01),\n    materials: {{\"stone\": (density: 2000.0, young: 1e9)}},\n    blocks: [\n{staves}    ],\n)"
        )
    };
    let scene = Scene::from_str(&ring(n), "ring.ron").unwrap();
    assert_eq!(scene.block_count(), n);
    let message = Scene::from_str(&ring(43_210), "ring.ron")
        .unwrap_err()
        .to_string();
    assert!(
        message.contains(": blocks[43211]: the block overlaps blocks[43210] at the start"),
        "{message}"
    );
}
