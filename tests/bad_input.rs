//! Bad scenes give one clear error naming the file, the place (with its line
//! where it can be found) and the fix, and never panic.

use dda::{Scene, SceneError};

/// A valid scene; each test breaks one thing in it.
const GOOD: &str = r#"// A block resting on a fixed base.
Scene(
    analysis: (
        duration: 1.0,
        dt: 0.001,
        penalty: 1e9,
        gravity: (0.0, -9.81),
    ),
    output: (interval: 0.01),
    materials: {
        "rock": (density: 2700.0, young: 1e10, poisson: 0.25),
    },
    joints: [
        (between: ("rock", "rock"), law: Coulomb(friction_angle: 30.0, cohesion: 0.0)),
    ],
    blocks: [
        Rectangle(material: "rock", center: (0.0, -0.5), width: 4.0, height: 1.0, fixed: true),
        Polygon(vertices: [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]),
    ],
    loads: [
        PointLoad(block: 1, point: (0.5, 1.0), force: (0.0, -1e4)),
    ],
    fixed_points: [ (block: 0, point: (0.0, -1.0)) ],
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
    Scene::from_str(text, "bad.ron")?.build().map(|_| ())
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

#[test]
fn the_good_scene_builds_and_touching_blocks_are_fine() {
    let scene = Scene::from_str(GOOD, "good.ron").unwrap();
    let model = scene.build().unwrap();
    assert_eq!(model.driver.system.blocks.len(), 2);
    assert_eq!(model.duration, 1.0);
    assert_eq!(model.output_interval, Some(0.01));
    assert_eq!(model.driver.dt(), 0.001);
    // The fixed base holds its four corners plus the one fixed point.
    assert_eq!(model.driver.system.fixed.len(), 5);
    assert_eq!(model.driver.system.loads.len(), 1);
}

#[test]
fn malformed_syntax_gives_file_line_and_column() {
    // A missing comma between two fields.
    let text = with("duration: 1.0,", "duration: 1.0");
    let message = error_of(&text);
    let line = line_of(&text, "dt: 0.001");
    assert!(
        message.starts_with(&format!("bad.ron:{line}:9: ")),
        "{message}"
    );
    assert!(message.contains("Expected comma"), "{message}");
    assert!(message.contains("fix the syntax"), "{message}");
}

#[test]
fn an_unclosed_list_is_a_syntax_error() {
    let message = error_of(&with(
        "fixed_points: [ (block: 0, point: (0.0, -1.0)) ],",
        "fixed_points: [ (block: 0,",
    ));
    assert!(message.starts_with("bad.ron:"), "{message}");
    let position: Vec<&str> = message.splitn(4, ':').collect();
    assert!(
        position[1].parse::<usize>().is_ok() && position[2].parse::<usize>().is_ok(),
        "{message}"
    );
}

#[test]
fn unknown_fields_are_rejected_with_their_position() {
    let text = with("dt: 0.001,", "dtt: 0.001,");
    let message = error_of(&text);
    let line = line_of(&text, "dtt");
    assert!(
        message.starts_with(&format!("bad.ron:{line}:")),
        "{message}"
    );
    assert!(
        message.contains("Unexpected field named `dtt`"),
        "{message}"
    );
    assert!(
        message.contains("remove the field or correct its spelling"),
        "{message}"
    );

    // Inside a block variant and a law, too.
    let text = with("fixed: true)", "fixed: true, colour: 3)");
    let message = error_of(&text);
    assert!(
        message.starts_with(&format!("bad.ron:{}:", line_of(&text, "colour"))),
        "{message}"
    );
    assert!(message.contains("`colour`"), "{message}");
    let message = error_of(&with("cohesion: 0.0", "cohesion: 0.0, dilation: 5.0"));
    assert!(message.contains("`dilation`"), "{message}");
    let message = error_of(&with("Scene(", "Scene(\n    colour: 3,"));
    assert!(message.starts_with("bad.ron:3:"), "{message}");
}

#[test]
fn self_intersecting_polygon() {
    let text = with("(1.0, 1.0), (0.0, 1.0)]", "(0.0, 1.0), (1.0, 1.0)]");
    assert_error(
        &text,
        "Polygon(",
        "blocks[1]",
        "the polygon is self-intersecting (edges 1 and 3 cross each other); reorder its vertices",
    );
}

#[test]
fn zero_area_polygon() {
    let text = with("(1.0, 1.0), (0.0, 1.0)]", "(2.0, 0.0), (3.0, 0.0)]");
    assert_error(&text, "Polygon(", "blocks[1]", "zero area");
}

#[test]
fn too_few_vertices() {
    let text = with("(1.0, 1.0), (0.0, 1.0)]", "]");
    assert_error(
        &text,
        "Polygon(",
        "blocks[1]",
        "at least 3 vertices, this one has 2",
    );
}

#[test]
fn a_rigid_block_with_an_initial_stress() {
    let text = with(
        "Polygon(vertices: [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)])",
        "Polygon(kind: Rigid, vertices: [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)],\n            stress: (-1e5, 0.0, 0.0))",
    );
    assert_error(
        &text,
        "stress:",
        "blocks[1].stress",
        "a rigid block carries no stress",
    );
    // The material's kind applies to blocks that do not give their own.
    let text = with("poisson: 0.25)", "poisson: 0.25, kind: Rigid)").replace(
        "(0.0, 1.0)])",
        "(0.0, 1.0)],\n            stress: (-1e5, 0.0, 0.0))",
    );
    assert_error(&text, "stress:", "blocks[1].stress", "carries no stress");
    let text = text.replace("Polygon(", "Polygon(kind: Deformable, ");
    assert!(load_and_build(&text).is_ok());
}

#[test]
fn nan_and_infinity_are_rejected() {
    let text = with("(1.0, 1.0), (0.0, 1.0)]", "(1.0, NaN), (0.0, 1.0)]");
    assert_error(
        &text,
        "NaN",
        "blocks[1].vertices[2]",
        "is NaN, not a finite number",
    );
    let text = with("gravity: (0.0, -9.81)", "gravity: (0.0, -inf)");
    assert_error(
        &text,
        "gravity",
        "analysis.gravity",
        "is -inf, not a finite number",
    );
    // Finite, but beyond any gravity a model spins at: a run once
    // overflowed on it and asked for a smaller step.
    let text = with("gravity: (0.0, -9.81)", "gravity: (1e300, -9.81)");
    assert_error(
        &text,
        "gravity",
        "analysis.gravity",
        "gravity's magnitude 1e300 m/s² is above 1e5",
    );
    let text = with("force: (0.0, -1e4)", "force: (inf, -1e4)");
    assert_error(&text, "PointLoad", "loads[0].force", "not a finite number");
}

#[test]
fn nan_anywhere_is_an_error() {
    // Every float literal of the good scene, in turn.
    let mut replaced = 0;
    for (start, token) in
        GOOD.match_indices(|c: char| c.is_ascii_digit() || c == '.' || c == '-' || c == 'e')
    {
        let _ = token;
        let before = GOOD[..start].chars().last().unwrap_or(' ');
        if !matches!(before, ' ' | '(') {
            continue;
        }
        let end = start
            + GOOD[start..]
                .find(|c: char| !(c.is_ascii_digit() || matches!(c, '.' | '-' | 'e')))
                .unwrap();
        let literal = &GOOD[start..end];
        if !literal.contains('.') && !literal.contains('e') {
            continue;
        }
        let text = format!("{}NaN{}", &GOOD[..start], &GOOD[end..]);
        let message = error_of(&text);
        assert!(
            message.contains("NaN, not a finite number"),
            "{literal} at {start}: {message}"
        );
        assert!(message.starts_with("bad.ron:"), "{message}");
        replaced += 1;
    }
    assert!(replaced >= 20, "only {replaced} literals tried");
}

#[test]
fn material_values() {
    let rock = r#""rock": (density"#;
    let text = with("density: 2700.0", "density: -2700.0");
    assert_error(
        &text,
        rock,
        r#"materials["rock"].density"#,
        "the density must be positive, got -2700",
    );
    let text = with("density: 2700.0", "density: 0.0");
    assert_error(
        &text,
        rock,
        r#"materials["rock"].density"#,
        "must be positive, got 0",
    );
    let text = with("young: 1e10", "young: 0");
    assert_error(
        &text,
        rock,
        r#"materials["rock"].young"#,
        "Young's modulus must be positive",
    );
    let text = with("poisson: 0.25", "poisson: 0.5");
    assert_error(
        &text,
        rock,
        r#"materials["rock"].poisson"#,
        "Poisson's ratio must lie in [0, 0.5), got 0.5",
    );
    let text = with("poisson: 0.25", "poisson: -0.1");
    assert_error(&text, rock, r#"materials["rock"].poisson"#, "[0, 0.5)");
    // Densities no material has: a run once failed on them with advice
    // meant for real blocks.
    let text = with("density: 2700.0", "density: 1e-300");
    assert_error(
        &text,
        rock,
        r#"materials["rock"].density"#,
        "the density 1e-300 kg/m³ is below 0.01 kg/m³, lighter than any solid",
    );
    let text = with("density: 2700.0", "density: 1e300");
    assert_error(
        &text,
        rock,
        r#"materials["rock"].density"#,
        "the density 1e300 kg/m³ is above 1e6 kg/m³, denser than any material",
    );
}

#[test]
fn analysis_values() {
    let text = with("dt: 0.001", "dt: 0.0");
    assert_error(
        &text,
        "dt: 0.0",
        "analysis.dt",
        "the time step dt must be positive, got 0",
    );
    let text = with("duration: 1.0", "duration: -1.0");
    assert_error(
        &text,
        "duration",
        "analysis.duration",
        "the duration must be positive, got -1",
    );
    let text = with("penalty: 1e9", "penalty: -1e9");
    assert_error(
        &text,
        "penalty",
        "analysis.penalty",
        "the penalty must be positive",
    );
    let text = with("penalty: 1e9,", "penalty: 1e9, fixed_penalty: 0.0,");
    assert_error(
        &text,
        "fixed_penalty",
        "analysis.fixed_penalty",
        "must be positive",
    );
    let text = with("penalty: 1e9,", "penalty: 1e9, velocity_ratio: 1.5,");
    assert_error(&text, "velocity_ratio", "analysis.velocity_ratio", "[0, 1]");
    let text = with("penalty: 1e9,", "penalty: 1e9, restitution: 1.2,");
    assert_error(&text, "restitution", "analysis.restitution", "[0, 1]");
    let text = with(
        "penalty: 1e9,",
        "penalty: 1e9, restitution: 0.0, integrator: Explicit,",
    );
    assert_error(
        &text,
        "restitution",
        "analysis.restitution",
        "implicit integrator",
    );
    let text = with("interval: 0.01", "interval: -0.01");
    assert_error(&text, "interval", "output.interval", "must not be negative");
}

#[test]
fn a_missing_duration_is_named() {
    let message = error_of(&with("duration: 1.0,", ""));
    assert!(message.contains("analysis.duration: "), "{message}");
    assert!(message.contains("it is required"), "{message}");
}

#[test]
fn joint_law_values() {
    let law = "law: Coulomb";
    let text = with("friction_angle: 30.0", "friction_angle: 90.0");
    assert_error(
        &text,
        law,
        "joints[0].law.friction_angle",
        "[0, 90) degrees, got 90",
    );
    let text = with("friction_angle: 30.0", "friction_angle: -5.0");
    assert_error(&text, law, "joints[0].law.friction_angle", "[0, 90)");
    let text = with("cohesion: 0.0", "cohesion: -1.0");
    assert_error(
        &text,
        law,
        "joints[0].law.cohesion",
        "the cohesion must not be negative",
    );
    let text = with("cohesion: 0.0", "cohesion: 0.0, tensile_strength: -1.0");
    assert_error(
        &text,
        law,
        "joints[0].law.tensile_strength",
        "must not be negative",
    );
    let text = with("cohesion: 0.0", "cohesion: 0.0, normal_stiffness: -1e9");
    assert_error(
        &text,
        law,
        "joints[0].law.normal_stiffness",
        "must be positive",
    );
    let text = with("cohesion: 0.0", "cohesion: 0.0, shear_stiffness: 0.0");
    assert_error(
        &text,
        law,
        "joints[0].law.shear_stiffness",
        "must be positive",
    );
    let text = with(
        "output:",
        "default_joint: Coulomb(friction_angle: 95.0),\n    output:",
    );
    assert_error(
        &text,
        "default_joint",
        "default_joint.friction_angle",
        "[0, 90)",
    );
}

#[test]
fn unknown_material_names() {
    let text = with(
        "Polygon(vertices",
        r#"Polygon(material: "granite", vertices"#,
    );
    assert_error(
        &text,
        "granite",
        "blocks[1].material",
        r#"unknown material "granite"; the materials are "rock""#,
    );
    let text = with(r#"("rock", "rock")"#, r#"("rock", "clay")"#);
    assert_error(
        &text,
        "clay",
        "joints[0].between[1]",
        r#"unknown material "clay""#,
    );
    // With two materials a block must say which.
    let text = with(
        "    },\n    joints",
        "        \"clay\": (density: 1800.0, young: 1e8),\n    },\n    joints",
    );
    assert_error(&text, "Polygon(", "blocks[1]", "names no material");
}

#[test]
fn loads_and_fixed_points_need_existing_blocks() {
    let text = with("PointLoad(block: 1", "PointLoad(block: 5");
    assert_error(
        &text,
        "PointLoad",
        "loads[0].block",
        "there is no block 5: the scene has 2 blocks",
    );
    let text = with(
        "(block: 0, point: (0.0, -1.0))",
        "(block: 2, point: (0.0, -1.0))",
    );
    assert_error(
        &text,
        "fixed_points",
        "fixed_points[0].block",
        "there is no block 2",
    );
    let text = with(
        "force: (0.0, -1e4)",
        "force: (0.0, -1e4), history: [(0.0, 0.0, 0.0)]",
    );
    assert_error(&text, "PointLoad", "loads[0]", "either force");
    let text = with(
        "force: (0.0, -1e4)",
        "history: [(1.0, 0.0, 0.0), (0.5, 0.0, 1.0)]",
    );
    assert_error(&text, "PointLoad", "loads[0].history[1]", "time order");
}

#[test]
fn overlapping_blocks_name_both() {
    let text = with(
        "    ],\n    loads",
        "        Rectangle(center: (1.4, 0.5), width: 1.0, height: 1.0),\n    ],\n    loads",
    );
    assert_error(
        &text,
        "center: (1.4",
        "blocks[2]",
        "overlaps blocks[1] at the start",
    );
    // Touching along an edge is fine.
    let text = with(
        "    ],\n    loads",
        "        Rectangle(center: (1.5, 0.5), width: 1.0, height: 1.0),\n    ],\n    loads",
    );
    load_and_build(&text).unwrap();
}

#[test]
fn dimensions_other_than_two_and_three_are_refused() {
    let text = with("Scene(", "Scene(\n    dimension: 4,");
    assert_error(&text, "dimension", "dimension", "dimension must be 2 (");
    // Even with unknown fields the dimension is what gets reported.
    let text = with("Scene(", "Scene(\n    dimension: 1,\n    polyhedra: [],");
    assert_error(
        &text,
        "dimension",
        "dimension",
        "or 3 (polyhedra, z up), got 1",
    );
}

#[test]
fn three_dimensional_values_in_a_two_dimensional_scene_are_named() {
    let text = with(
        "        Polygon(vertices",
        "        Box(center: (5.0, 0.0, 0.5), size: (1.0, 1.0, 1.0)),\n        Polygon(vertices",
    );
    assert_error(
        &text,
        "Box(",
        "blocks[1]",
        "Box is a 3D block, but this is a 2D scene (dimension: 2, the default); add dimension: 3",
    );
    let text = with("gravity: (0.0, -9.81)", "gravity: (0.0, 0.0, -9.81)");
    assert_error(
        &text,
        "gravity",
        "analysis.gravity",
        "gravity has 3 numbers, but this is a 2D scene: write (gx, gy) (or add dimension: 3",
    );
    let text = with("force: (0.0, -1e4)", "force: (0.0, 0.0, -1e4)");
    assert_error(
        &text,
        "force:",
        "loads[0].force",
        "the force has 3 numbers, but this is a 2D scene: write (fx, fy)",
    );
    let text = with("point: (0.0, -1.0)", "point: (0.0, -1.0, 2.0)");
    assert_error(
        &text,
        "fixed_points",
        "fixed_points[0].point",
        "the fixed point has 3 numbers, but this is a 2D scene: write (x, y)",
    );
    // A 3D scene built as 2D says which builder to use.
    let scene = Scene::from_str(
        "Scene(dimension: 3, analysis: (duration: 1.0), materials: {\"rock\": (density: 1.0, young: 1.0)}, blocks: [Box(center: (0.0, 0.0, 0.0), size: (1.0, 1.0, 1.0))])",
        "cube.ron",
    )
    .unwrap();
    let message = scene.build().err().unwrap().to_string();
    assert!(
        message
            .contains("this is a 3D scene, and Scene::build builds 2D ones; use Scene::build_3d"),
        "{message}"
    );
    assert!(scene.build_any().is_ok());
}

#[test]
fn duplicate_material_names() {
    let text = with(
        "    },\n    joints",
        "        \"rock\": (density: 1.0, young: 1.0),\n    },\n    joints",
    );
    let message = error_of(&text);
    assert!(message.starts_with("bad.ron:"), "{message}");
    assert!(message.contains("\"rock\" is defined twice"), "{message}");
}

#[test]
fn files_are_named_in_errors() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/overlapping.ron");
    let message = Scene::load(path).unwrap_err().to_string();
    assert!(
        message.starts_with(&format!("{path}:9:9: blocks[1]: ")),
        "{message}"
    );
    assert!(message.contains("overlaps blocks[0]"), "{message}");

    let missing = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/no_such_scene.ron");
    let message = Scene::load(missing).unwrap_err().to_string();
    assert!(message.starts_with(missing), "{message}");
    assert!(message.contains("cannot read the scene file"), "{message}");
}

#[test]
fn truncated_files_never_panic() {
    // Every prefix of a good scene is an error with a position, not a panic.
    let last = GOOD.rfind(')').unwrap();
    for (end, _) in GOOD[..last].char_indices() {
        let message = error_of(&GOOD[..end]);
        assert!(message.starts_with("bad.ron:"), "at {end}: {message}");
    }
}

/// GOOD with a second joint entry, a joint set over block pairs.
fn with_joint_set(entry: &str) -> String {
    with(
        "    ],\n    blocks",
        &format!("        {entry},\n    ],\n    blocks"),
    )
}

/// GOOD with `law` as the default joint law.
fn with_default_joint(law: &str) -> String {
    with(
        "    output:",
        &format!("    default_joint: {law},\n    output:"),
    )
}

#[test]
fn new_law_variants_joint_sets_and_driven_points_build() {
    let laws = [
        "ThresholdBond(friction_angle: 30.0, max_opening: 1e-4, max_shear: 1e-4, normal_stiffness: 1e10, shear_stiffness: 4e9)",
        "DisplacementStrength(friction_angle: 20.0, cohesion: 5556.0, weakening: Step(at: 0.001))",
        "DisplacementStrength(friction_angle: 25.0, residual_friction_angle: 20.0, cohesion: 1e4, residual_cohesion: 0.0, tensile_strength: 1e3, weakening: Exponential(length: 0.01))",
        "SlipFriction(peak_friction_angle: 25.0, residual_friction_angle: 15.0, weakening: Linear(start: 0.0, end: 0.05))",
        "RateFriction(static_friction_angle: 28.0, dynamic_friction_angle: 15.0, characteristic_rate: 0.1)",
        r#"Custom(name: "coulomb", params: {"friction_angle": 30.0, "cohesion": 1e4})"#,
        r#"Custom(name: "slip_friction", params: {"peak_friction_angle": 25.0, "residual_friction_angle": 15.0, "weakening_step": 0.05})"#,
    ];
    for law in laws {
        load_and_build(&with_default_joint(law)).unwrap_or_else(|e| panic!("{law}: {e}"));
    }

    let text = with_joint_set("(blocks: [(1, 0)], law: SlipFriction(peak_friction_angle: 25.0, residual_friction_angle: 15.0, weakening: Step(at: 0.05)))");
    let text = text.replace(
        "(block: 0, point: (0.0, -1.0))",
        "(block: 1, point: (0.5, 1.0), velocity: (0.1, 0.0), axis: (3.0, 4.0))",
    );
    let scene = Scene::from_str(&text, "good.ron").unwrap();
    let table = scene.law_table();
    // The rock-rock law is the default one, so it is not repeated.
    assert_eq!(table.laws.len(), 2, "the default and the joint set's");
    assert_eq!(table.materials, vec![vec![0]]);
    assert_eq!(table.pairs.get(&(0, 1)), Some(&1));
    let model = scene.build().unwrap();
    let system = &model.driver.system;
    assert_eq!(system.pair_laws.get(&(0, 1)), Some(&1));
    let driven = system.fixed.iter().find(|f| f.block == 1).unwrap();
    assert_eq!(driven.velocity, nalgebra::Vector2::new(0.1, 0.0));
    let axis = driven.axis.expect("an axis");
    assert!((axis - nalgebra::Vector2::new(0.6, 0.8)).norm() < 1e-15);
    assert!(!model.write_contacts);
    // Leaving velocity and axis out holds the point in place, both ways.
    let model = Scene::from_str(GOOD, "good.ron").unwrap().build().unwrap();
    // The scene's point comes before the fixed base's corners.
    let held = &model.driver.system.fixed[0];
    assert_eq!(held.point, nalgebra::Point2::new(0.0, -1.0));
    assert_eq!(held.velocity, nalgebra::Vector2::zeros());
    assert_eq!(held.axis, None);
}

#[test]
fn new_law_values_are_located() {
    let text = with_default_joint(
        "SlipFriction(peak_friction_angle: 95.0, residual_friction_angle: 15.0, weakening: Step(at: 0.05))",
    );
    assert_error(
        &text,
        "default_joint",
        "default_joint.peak_friction_angle",
        "the peak friction angle must lie in [0, 90) degrees, got 95",
    );
    let text = with(
        "Coulomb(friction_angle: 30.0, cohesion: 0.0)",
        "RateFriction(static_friction_angle: 28.0, dynamic_friction_angle: -1.0, characteristic_rate: 0.1)",
    );
    assert_error(
        &text,
        "RateFriction",
        "joints[0].law.dynamic_friction_angle",
        "[0, 90) degrees, got -1",
    );
    let text = with(
        "Coulomb(friction_angle: 30.0, cohesion: 0.0)",
        "RateFriction(static_friction_angle: 28.0, dynamic_friction_angle: 15.0, characteristic_rate: 0.0)",
    );
    assert_error(
        &text,
        "RateFriction",
        "joints[0].law.characteristic_rate",
        "the characteristic rate must be positive, got 0",
    );
    let text = with(
        "Coulomb(friction_angle: 30.0, cohesion: 0.0)",
        "ThresholdBond(friction_angle: 30.0, max_opening: -1e-4, max_shear: 1e-4)",
    );
    assert_error(
        &text,
        "ThresholdBond",
        "joints[0].law.max_opening",
        "max_opening must be positive, got -0.0001",
    );
    let text = with(
        "Coulomb(friction_angle: 30.0, cohesion: 0.0)",
        "DisplacementStrength(friction_angle: 20.0, cohesion: 5556.0, residual_cohesion: -1.0, weakening: Step(at: 0.001))",
    );
    assert_error(
        &text,
        "DisplacementStrength",
        "joints[0].law.residual_cohesion",
        "the residual cohesion must not be negative",
    );
    let text = with(
        "Coulomb(friction_angle: 30.0, cohesion: 0.0)",
        "DisplacementStrength(friction_angle: 20.0, residual_friction_angle: NaN, weakening: Step(at: 0.001))",
    );
    assert_error(
        &text,
        "DisplacementStrength",
        "joints[0].law.residual_friction_angle",
        "is NaN, not a finite number",
    );
    let text = with(
        "Coulomb(friction_angle: 30.0, cohesion: 0.0)",
        "SlipFriction(peak_friction_angle: 25.0, residual_friction_angle: 15.0, weakening: Step(at: 0.05), shear_stiffness: 0.0)",
    );
    assert_error(
        &text,
        "SlipFriction",
        "joints[0].law.shear_stiffness",
        "the shear stiffness must be positive",
    );
}

#[test]
fn bad_weakening_is_located() {
    let law = |w: &str| {
        with(
            "Coulomb(friction_angle: 30.0, cohesion: 0.0)",
            &format!("SlipFriction(peak_friction_angle: 25.0, residual_friction_angle: 15.0,\n            weakening: {w})"),
        )
    };
    assert_error(
        &law("Linear(start: 0.02, end: 0.01)"),
        "weakening:",
        "joints[0].law.weakening",
        "a linear weakening needs 0 <= start < end, got start 0.02 and end 0.01",
    );
    assert_error(
        &law("Linear(start: 0.01, end: 0.01)"),
        "weakening:",
        "joints[0].law.weakening",
        "0 <= start < end",
    );
    assert_error(
        &law("Exponential(length: 0.0)"),
        "weakening:",
        "joints[0].law.weakening",
        "the exponential weakening length must be positive, got 0",
    );
    assert_error(
        &law("Step(at: -1.0)"),
        "weakening:",
        "joints[0].law.weakening",
        "must be zero or positive, got -1",
    );
    assert_error(
        &law("Step(at: inf)"),
        "weakening:",
        "joints[0].law.weakening",
        "is inf, not a finite number",
    );
    // Unknown forms and fields are syntax errors at their position.
    let text = law("Cubic(at: 1.0)");
    let message = error_of(&text);
    assert!(
        message.starts_with(&format!("bad.ron:{}:", line_of(&text, "Cubic"))),
        "{message}"
    );
    assert!(message.contains("Cubic"), "{message}");
    let message = error_of(&law("Step(at: 1.0, end: 2.0)"));
    assert!(message.contains("`end`"), "{message}");
}

#[test]
fn custom_laws_are_checked_by_the_registry_at_their_place() {
    let custom = |law: &str| with("Coulomb(friction_angle: 30.0, cohesion: 0.0)", law);
    // An unknown name lists the known ones.
    let text = custom(r#"Custom(name: "barton_bandis", params: {"jrc": 10.0, "jcs": 1e8})"#);
    assert_error(
        &text,
        "Custom(",
        "joints[0].law",
        "no contact law is registered as `barton_bandis`; known laws: coulomb, displacement_strength, rate_friction, slip_friction, threshold_bond",
    );
    assert!(error_of(&text).contains("LawRegistry::register"));
    // `dda check`'s scene is the same: built with the built-in registry.
    let message = error_of(&with_default_joint(r#"Custom(name: "nope")"#));
    assert!(
        message.contains(": default_joint: no contact law is registered as `nope`"),
        "{message}"
    );

    // An unknown parameter.
    let text =
        custom(r#"Custom(name: "coulomb", params: {"friction_angle": 30.0, "dilation": 5.0})"#);
    assert_error(
        &text,
        "Custom(",
        "joints[0].law",
        "the law `coulomb` has no parameter dilation; remove it from params or correct its spelling",
    );
    // A missing required parameter.
    let text = custom(
        r#"Custom(name: "threshold_bond", params: {"friction_angle": 30.0, "max_opening": 1e-4})"#,
    );
    assert_error(
        &text,
        "Custom(",
        "joints[0].law",
        "the law `threshold_bond`: the parameter `max_shear` is required; add it to params",
    );
    // The registry's own checks (a weakening that makes no sense).
    let text = custom(
        r#"Custom(name: "slip_friction", params: {"peak_friction_angle": 25.0, "residual_friction_angle": 15.0, "weakening_start": 0.1, "weakening_end": 0.0})"#,
    );
    assert_error(&text, "Custom(", "joints[0].law", "0 <= start < end");
    // A law built by name checks its values as the typed law does.
    let text = custom(r#"Custom(name: "coulomb", params: {"friction_angle": 95.0})"#);
    assert_error(
        &text,
        "Custom(",
        "joints[0].law",
        "friction_angle: the friction angle must lie in [0, 90) degrees, got 95",
    );
    // Values are checked before any builder sees them.
    let text = custom(r#"Custom(name: "coulomb", params: {"friction_angle": NaN})"#);
    assert_error(
        &text,
        "Custom(",
        r#"joints[0].law.params["friction_angle"]"#,
        r#"the parameter "friction_angle" is NaN"#,
    );
    let message = error_of(&custom(
        r#"Custom(name: "coulomb", params: {"friction_angle": 30.0, "friction_angle": 20.0})"#,
    ));
    assert!(
        message.contains("\"friction_angle\" is defined twice"),
        "{message}"
    );
    let text = custom(r#"Custom(name: "")"#);
    assert_error(
        &text,
        "Custom(",
        "joints[0].law.name",
        "the law's name is empty",
    );
}

#[test]
fn a_registry_can_add_laws() {
    let text = with(
        "Coulomb(friction_angle: 30.0, cohesion: 0.0)",
        r#"Custom(name: "sticky", params: {"friction_angle": 40.0})"#,
    );
    let scene = Scene::from_str(&text, "good.ron").unwrap();
    // Loading knows nothing of registries; building does.
    let message = scene
        .build()
        .err()
        .expect("unknown to the built-in registry")
        .to_string();
    assert!(message.contains("`sticky`"), "{message}");
    let mut registry = dda_contact::LawRegistry::with_builtin();
    registry.register("sticky", |p: &mut dda_contact::Params| {
        Ok(dda_contact::Coulomb {
            cohesion: 1e5,
            ..dda_contact::Coulomb::frictional(p.take("friction_angle")?)
        })
    });
    let model = scene.build_with(&registry).unwrap();
    assert_eq!(model.driver.system.blocks.len(), 2);
}

#[test]
fn joint_sets_name_existing_blocks_once() {
    let law = "law: Coulomb(friction_angle: 10.0)";
    // A block that does not exist.
    let text = with_joint_set(&format!("(blocks: [(0, 1), (1, 5)], {law})"));
    assert_error(
        &text,
        "(blocks:",
        "joints[1].blocks[1]",
        "there is no block 5: the scene has 2 blocks",
    );
    // A block with itself.
    let text = with_joint_set(&format!("(blocks: [(1, 1)], {law})"));
    assert_error(
        &text,
        "(blocks:",
        "joints[1].blocks[0]",
        "pairs block 1 with itself",
    );
    // A pair in two sets, in either order.
    let text = with(
        "    ],\n    blocks",
        &format!(
            "        (blocks: [(0, 1)], {law}),\n        (blocks: [(1, 0)], law: Coulomb(friction_angle: 20.0)),\n    ],\n    blocks"
        ),
    );
    assert_error(
        &text,
        "(blocks: [(1, 0)]",
        "joints[2].blocks[0]",
        "the block pair (1, 0) is already listed in joints[1]; a pair belongs to one joint set only",
    );
    let text = with_joint_set(&format!("(blocks: [(0, 1), (1, 0)], {law})"));
    assert_error(
        &text,
        "(blocks:",
        "joints[1].blocks[1]",
        "already listed earlier in this set",
    );
    // Exactly one of between and blocks.
    let text = with_joint_set(&format!(
        r#"(between: ("rock", "rock"), blocks: [(0, 1)], {law})"#
    ));
    assert_error(
        &text,
        "(between: (\"rock\", \"rock\"), blocks",
        "joints[1]",
        "not both",
    );
    let text = with_joint_set(&format!("({law})"));
    assert_error(
        &text,
        "(law:",
        "joints[1]",
        "neither which materials nor which blocks",
    );
    let text = with_joint_set(&format!("(blocks: [], {law})"));
    assert_error(
        &text,
        "(blocks: []",
        "joints[1].blocks",
        "lists no block pairs",
    );
    // And the law of a joint set is checked at its place.
    let text = with_joint_set("(blocks: [(0, 1)], law: Coulomb(friction_angle: 91.0))");
    assert_error(&text, "(blocks:", "joints[1].law.friction_angle", "[0, 90)");
}

#[test]
fn driven_points_need_a_direction_and_finite_values() {
    let point = "(block: 0, point: (0.0, -1.0))";
    let text = with(point, "(block: 0, point: (0.0, -1.0), axis: (0.0, 0.0))");
    assert_error(
        &text,
        "fixed_points",
        "fixed_points[0].axis",
        "the axis (0, 0) has no direction",
    );
    let text = with(point, "(block: 0, point: (0.0, -1.0), axis: (NaN, 1.0))");
    assert_error(
        &text,
        "fixed_points",
        "fixed_points[0].axis",
        "is NaN, not a finite number",
    );
    let text = with(
        point,
        "(block: 0, point: (0.0, -1.0), velocity: (inf, 0.0))",
    );
    assert_error(
        &text,
        "fixed_points",
        "fixed_points[0].velocity",
        "is inf, not a finite number",
    );
    // A tiny axis is still a direction.
    let text = with(
        point,
        "(block: 0, point: (0.0, -1.0), axis: (1e-300, 1e-300))",
    );
    let model = Scene::from_str(&text, "good.ron").unwrap().build().unwrap();
    let fixed = &model.driver.system.fixed;
    let axis = fixed.iter().find_map(|f| f.axis).expect("the point's axis");
    assert!((axis.norm() - 1.0).abs() < 1e-15 && axis.x > 0.0);
}

/// GOOD with `entry` added to the blocks (as blocks[2]).
fn with_block(entry: &str) -> String {
    with(
        "    ],\n    loads",
        &format!("        {entry},\n    ],\n    loads"),
    )
}

/// An arch clear of GOOD's blocks, with `extra` parameters.
fn arch(extra: &str) -> String {
    with_block(&format!(
        "Arch(center: (10.0, 0.0), radius: 2.0, thickness: 0.4, voussoirs: 6{extra})"
    ))
}

#[test]
fn generators_build_and_are_counted() {
    let text = arch(", span_angle: 150.0");
    let scene = Scene::from_str(&text, "good.ron").unwrap();
    assert_eq!(scene.blocks.len(), 3);
    assert_eq!(
        scene.block_count(),
        10,
        "2 blocks, 6 voussoirs, 2 abutments"
    );
    let model = scene.build().unwrap();
    assert_eq!(model.driver.system.blocks.len(), 10);
    // The abutments are fixed: four corners each, besides the base's.
    let held = |b: usize| {
        model
            .driver
            .system
            .fixed
            .iter()
            .filter(|f| f.block == b)
            .count()
    };
    assert_eq!((held(8), held(9), held(7)), (4, 4, 0));
    // Indices past the first two now exist.
    let text = text.replace("PointLoad(block: 1", "PointLoad(block: 9");
    load_and_build(&text).unwrap();
}

#[test]
fn bad_arch_parameters_are_located() {
    let line = "Arch(";
    assert_error(
        &arch(", pointed: 0.2").replace("voussoirs: 6", "voussoirs: 1"),
        line,
        "blocks[2].voussoirs",
        "voussoirs must be at least 2, got 1",
    );
    assert_error(
        &arch("").replace("radius: 2.0", "radius: 0.2"),
        line,
        "blocks[2].radius",
        "the radius (0.2) must exceed half the thickness (0.4)",
    );
    assert_error(
        &arch("").replace("thickness: 0.4", "thickness: -0.4"),
        line,
        "blocks[2].thickness",
        "the thickness must be positive, got -0.4",
    );
    assert_error(
        &arch(", span_angle: 200.0"),
        line,
        "blocks[2].span_angle",
        "the span angle must lie in (0, 180] degrees, got 200",
    );
    assert_error(
        &arch(", span_angle: 0.0"),
        line,
        "blocks[2].span_angle",
        "(0, 180]",
    );
    assert_error(
        &arch(", pointed: 1.0"),
        line,
        "blocks[2].pointed",
        "pointed must lie in [0, 1), got 1",
    );
    assert_error(
        &arch(", pointed: 0.2").replace("voussoirs: 6", "voussoirs: 7"),
        line,
        "blocks[2].voussoirs",
        "a pointed arch needs an even number of voussoirs",
    );
    assert_error(
        &arch(", pointed: 0.95"),
        line,
        "blocks[2].pointed",
        "the intrados (radius 1.8) does not reach the crown",
    );
    assert_error(
        &arch(", pointed: 0.5, span_angle: 40.0"),
        line,
        "blocks[2].span_angle",
        "ends above the crown of this pointed arch",
    );
    assert_error(
        &arch("").replace("center: (10.0, 0.0)", "center: (10.0, NaN)"),
        line,
        "blocks[2].center",
        "is NaN, not a finite number",
    );
    // Unknown fields and missing ones are syntax errors at their place.
    let text = arch(", keystone: true");
    let message = error_of(&text);
    assert!(
        message.starts_with(&format!("bad.ron:{}:", line_of(&text, line))),
        "{message}"
    );
    assert!(message.contains("`keystone`"), "{message}");
    let message = error_of(&arch("").replace("voussoirs: 6", "voussoirs: -6"));
    assert!(message.starts_with("bad.ron:"), "{message}");
}

#[test]
fn bad_column_and_wall_parameters_are_located() {
    let column = |c: &str| with_block(&format!("Column(base: (10.0, 0.0), {c})"));
    assert_error(
        &column("drums: 0, drum_height: 0.5, width: 0.3"),
        "Column(",
        "blocks[2].drums",
        "drums must be at least 1, got 0",
    );
    assert_error(
        &column("drums: 2, drum_height: 0.0, width: 0.3"),
        "Column(",
        "blocks[2].drum_height",
        "the drum height must be positive, got 0",
    );
    assert_error(
        &column("drums: 2, drum_height: 0.5, width: inf"),
        "Column(",
        "blocks[2].width",
        "is inf, not a finite number",
    );
    assert_error(
        &column("drums: 2000000, drum_height: 0.5, width: 0.3"),
        "Column(",
        "blocks[2].drums",
        "more than the 100000 a generator makes",
    );
    let wall = |w: &str| with_block(&format!("Wall(origin: (10.0, 0.0), {w})"));
    assert_error(
        &wall("length: 2.0, courses: 0, brick_length: 0.5, brick_height: 0.2"),
        "Wall(",
        "blocks[2].courses",
        "courses must be at least 1, got 0",
    );
    assert_error(
        &wall("length: 2.0, courses: 3, brick_length: -0.5, brick_height: 0.2"),
        "Wall(",
        "blocks[2].brick_length",
        "the brick length must be positive, got -0.5",
    );
    assert_error(
        &wall("length: 0.0, courses: 3, brick_length: 0.5, brick_height: 0.2"),
        "Wall(",
        "blocks[2].length",
        "the length must be positive, got 0",
    );
    assert_error(
        &wall("length: 1e6, courses: 100, brick_length: 0.5, brick_height: 0.2"),
        "Wall(",
        "blocks[2]",
        "more than 100000",
    );
    let text = wall("length: 2.0, courses: 3, brick_length: 0.5, brick_height: 0.2, bond: Flemish");
    let message = error_of(&text);
    assert!(
        message.starts_with(&format!("bad.ron:{}:", line_of(&text, "Flemish"))),
        "{message}"
    );
    assert!(
        message.contains("Flemish") && message.contains("use one of the listed names"),
        "{message}"
    );
}

#[test]
fn generated_blocks_are_named_by_their_part() {
    // A column standing in the loose block: its first drum overlaps it.
    let text = with_block("Column(base: (0.5, 0.0), drums: 2, drum_height: 0.5, width: 0.4)");
    assert_error(
        &text,
        "Column(",
        "blocks[2] (drum 0)",
        "the block overlaps blocks[1] at the start",
    );
    // Two generators: the second arch's left abutment overlaps the first's right one.
    let text = with_block(
        "Arch(center: (10.0, 0.0), radius: 2.0, thickness: 0.4, voussoirs: 6),\n        Arch(center: (14.6, 0.0), radius: 2.0, thickness: 0.4, voussoirs: 6)",
    );
    assert_error(
        &text,
        "center: (14.6",
        "blocks[3] (left abutment)",
        "the block overlaps blocks[2] (right abutment) at the start",
    );
    // A wall whose courses are too thin for their bricks.
    let text = with_block(
        "Wall(origin: (10.0, 0.0), length: 1.0, courses: 2, brick_length: 0.5, brick_height: 1e-14)",
    );
    assert_error(
        &text,
        "Wall(",
        "blocks[2] (course 0, brick 0)",
        "the generated block is degenerate: vertices 0 and 3 coincide; change the generator's sizes",
    );
    // Indices count generated blocks.
    let text = with_block("Column(base: (10.0, 0.0), drums: 3, drum_height: 0.5, width: 0.4)")
        .replace("PointLoad(block: 1", "PointLoad(block: 5");
    assert_error(
        &text,
        "PointLoad",
        "loads[0].block",
        "there is no block 5: the scene has 5 blocks (generators counted block by block), numbered from 0 to 4",
    );
}

/// GOOD with a ground motion.
fn with_ground(spec: &str) -> String {
    with(
        "    fixed_points:",
        &format!("    ground_motion: {spec},\n    fixed_points:"),
    )
}

/// A record file with `text` in the temporary folder, and its path.
fn record_file(name: &str, text: &str) -> std::path::PathBuf {
    let path = std::env::temp_dir().join(format!("dda-bad-{}-{name}.csv", std::process::id()));
    std::fs::write(&path, text).unwrap();
    path
}

fn record_motion(path: &std::path::Path) -> String {
    format!(
        "(blocks: [0], motion: Record(path: {:?}, scale: 9.81))",
        path.display().to_string()
    )
}

#[test]
fn ground_motions_build_on_fixed_base_blocks() {
    let text = with_ground(
        "(blocks: [0], motion: Sine(amplitude: (2.0, 0.0), frequency: 2.0, duration: 1.0))",
    );
    let model = Scene::from_str(&text, "good.ron").unwrap().build().unwrap();
    let fixed = &model.driver.system.fixed;
    // All five points of the base (its corners and the scene's point) move
    // with one shared motion.
    assert!(fixed.iter().all(|f| f.block == 0 && f.ground.is_some()));
    let first = fixed[0].ground.as_ref().unwrap();
    assert!(fixed
        .iter()
        .all(|f| std::sync::Arc::ptr_eq(f.ground.as_ref().unwrap(), first)));
    let a = first.acceleration(0.125);
    assert!((a.x - 2.0).abs() < 1e-12 && a.y == 0.0, "{a}");
    // A point held at t follows the ground's displacement.
    let u = first.displacement(0.3);
    assert_eq!(fixed[0].target_at(0.3), fixed[0].target + u);

    let path = record_file("good", "t, ax, ay\n0.0, 0.1, 0.0\n1.0, 0.1, 0.0\n");
    let text = with_ground(&record_motion(&path));
    let model = Scene::from_str(&text, "good.ron").unwrap().build().unwrap();
    let ground = model.driver.system.fixed[0].ground.as_ref().unwrap();
    // Scaled by 9.81, integrated twice.
    assert!((ground.displacement(1.0).x - 0.981 / 2.0).abs() < 1e-12);
    let _ = std::fs::remove_file(&path);
}

#[test]
fn ground_motion_errors_are_located() {
    let motion = "motion: Pulse(amplitude: (3.0, 0.0), period: 0.5)";
    assert_error(
        &with_ground(&format!("(blocks: [1], {motion})")),
        "ground_motion",
        "ground_motion.blocks[0]",
        "block 1 is not fixed, so the ground cannot carry it; add fixed: true to blocks[1]",
    );
    assert_error(
        &with_ground(&format!("(blocks: [0, 7], {motion})")),
        "ground_motion",
        "ground_motion.blocks[1]",
        "there is no block 7: the scene has 2 blocks",
    );
    assert_error(
        &with_ground(&format!("(blocks: [], {motion})")),
        "ground_motion",
        "ground_motion.blocks",
        "drives no blocks",
    );
    assert_error(
        &with_ground(&format!("(blocks: [0, 0], {motion})")),
        "ground_motion",
        "ground_motion.blocks[1]",
        "listed twice",
    );
    assert_error(
        &with_ground("(blocks: [0], motion: Pulse(amplitude: (3.0, 0.0), period: -0.5))"),
        "ground_motion",
        "ground_motion.motion.period",
        "the period must be positive, got -0.5",
    );
    assert_error(
        &with_ground(
            "(blocks: [0], motion: Sine(amplitude: (2.0, 0.0), frequency: 0.0, duration: 1.0))",
        ),
        "ground_motion",
        "ground_motion.motion.frequency",
        "the frequency must be positive, got 0",
    );
    assert_error(
        &with_ground(
            "(blocks: [0], motion: Sine(amplitude: (2.0, 0.0), frequency: 2.0, duration: 0.0))",
        ),
        "ground_motion",
        "ground_motion.motion.duration",
        "the duration must be positive",
    );
    assert_error(
        &with_ground(
            "(blocks: [0], motion: Sine(amplitude: (NaN, 0.0), frequency: 2.0, duration: 1.0))",
        ),
        "ground_motion",
        "ground_motion.motion.amplitude",
        "is NaN, not a finite number",
    );
    // A generated base: an arch's abutment can be driven, a voussoir cannot.
    let text = with_block("Arch(center: (10.0, 0.0), radius: 2.0, thickness: 0.4, voussoirs: 6)");
    load_and_build(&with_ground_on(&text, "[0, 8, 9]")).unwrap();
    assert_error(
        &with_ground_on(&text, "[0, 4]"),
        "ground_motion",
        "ground_motion.blocks[1]",
        "block 4 (blocks[2], voussoir 2) is not fixed, so the ground cannot carry it; list fixed base blocks instead",
    );
}

fn with_ground_on(text: &str, blocks: &str) -> String {
    text.replace(
        "    fixed_points:",
        &format!(
            "    ground_motion: (blocks: {blocks}, motion: Pulse(amplitude: (3.0, 0.0), period: 0.5)),\n    fixed_points:"
        ),
    )
}

#[test]
fn bad_record_files_are_named_with_their_line() {
    // A missing file: the resolved path, at the record's path.
    let missing = std::env::temp_dir().join("dda-no-such-record.csv");
    let text = with_ground(&record_motion(&missing));
    let message = error_of(&text);
    assert_error(
        &text,
        "ground_motion",
        "ground_motion.motion.path",
        &format!("cannot read the record file {}", missing.display()),
    );
    assert!(
        message.contains("relative to the scene file's folder"),
        "{message}"
    );

    // A relative path from a string scene is taken from the current folder.
    let text = with_ground(
        r#"(blocks: [0], motion: Record(path: "tests/data/constant_acceleration.csv"))"#,
    );
    load_and_build(&text).unwrap();
    let text = with_ground(r#"(blocks: [0], motion: Record(path: "data/none.csv"))"#);
    assert_error(
        &text,
        "ground_motion",
        "ground_motion.motion.path",
        "cannot read the record file data/none.csv",
    );

    let cases = [
        ("word", "time, ax, ay\n0.0, 0.1, 0.0\n0.5, 0.1x, 0.0\n", ":3: \"0.5, 0.1x, 0.0\" is not a row of numbers `time, ax, ay`"),
        ("columns", "0.0, 0.1\n", ":1: \"0.0, 0.1\" has 2 columns"),
        ("order", "# t, ax, ay\n0.0, 0.1, 0.0\n1.0, 0.1, 0.0\n1.0, 0.2, 0.0\n", ":4: the time 1 does not come after the previous sample's (1, line 3); times must increase"),
        ("nan", "0.0, 0.1, 0.0\n0.1, NaN, 0.0\n", ":2: NaN is not a finite number"),
        ("three_d", "0.0, 0.1, 0.0, 0.0\n0.1, 0.1, 0.0, 0.2\n", ":2: the third component is 0.2: a 3D record in a 2D scene"),
        ("empty", "time, ax, ay\n# nothing yet\n", "has no samples"),
    ];
    for (name, csv, phrase) in cases {
        let path = record_file(name, csv);
        let text = with_ground(&record_motion(&path));
        assert_error(
            &text,
            "ground_motion",
            "ground_motion.motion",
            &format!(
                "{}{phrase}",
                if phrase.starts_with(':') {
                    path.display().to_string()
                } else {
                    String::new()
                }
            ),
        );
        let _ = std::fs::remove_file(&path);
    }

    // A third column of zeros is fine.
    let path = record_file("zeros", "0.0, 0.1, 0.0, 0.0\n1.0, 0.1, 0.0, 0.0\n");
    load_and_build(&with_ground(&record_motion(&path))).unwrap();
    let _ = std::fs::remove_file(&path);
    // A scale that is not a number.
    let path = record_file("scale", "0.0, 0.1, 0.0\n");
    let text = with_ground(&record_motion(&path).replace("scale: 9.81", "scale: inf"));
    assert_error(
        &text,
        "ground_motion",
        "ground_motion.motion.scale",
        "is inf",
    );
    let _ = std::fs::remove_file(&path);
}

#[test]
fn damping_is_checked_and_set() {
    let damped = |d: &str| with("penalty: 1e9,", &format!("penalty: 1e9, damping: {d},"));
    let model = Scene::from_str(&damped("(ratio: 0.05, frequency: 2.0)"), "good.ron")
        .unwrap()
        .build()
        .unwrap();
    let alpha = 2.0 * 0.05 * 2.0 * std::f64::consts::PI * 2.0;
    assert!((model.settings.mass_damping - alpha).abs() < 1e-15);
    let model = Scene::from_str(GOOD, "good.ron").unwrap().build().unwrap();
    assert_eq!(model.settings.mass_damping, 0.0, "off by default");
    assert_error(
        &damped("(ratio: -0.05, frequency: 2.0)"),
        "damping",
        "analysis.damping.ratio",
        "the damping ratio must not be negative, got -0.05",
    );
    assert_error(
        &damped("(ratio: 0.05, frequency: 0.0)"),
        "damping",
        "analysis.damping.frequency",
        "the damping frequency must be positive, got 0",
    );
    assert_error(
        &damped("(ratio: NaN, frequency: 2.0)"),
        "damping",
        "analysis.damping.ratio",
        "is NaN, not a finite number",
    );
    let message = error_of(&damped("(ratio: 0.05)"));
    assert!(message.contains("frequency"), "{message}");
}

#[test]
fn acceleration_records_are_baseline_corrected_unless_told_not_to() {
    // A constant 0.1 g over ten samples: all of it is the drift a
    // baseline correction takes out.
    let rows: String = (0..=10)
        .map(|k| format!("{}, 0.1, 0.0\n", k as f64 * 0.1))
        .collect();
    let path = record_file("offset", &rows);
    let spec = |extra: &str| {
        format!(
            "(blocks: [0], motion: Record(path: {:?}, scale: 9.81{extra}))",
            path.display().to_string()
        )
    };
    let model = Scene::from_str(&with_ground(&spec("")), "good.ron")
        .unwrap()
        .build()
        .unwrap();
    let ground = model.driver.system.fixed[0].ground.as_ref().unwrap();
    assert!(ground.displacement(1.0).norm() < 1e-9);
    let note = model
        .notes
        .iter()
        .find(|n| n.contains("baseline corrected"));
    assert!(
        note.is_some_and(|n| n.contains("ends 0.49")),
        "{:?}",
        model.notes
    );

    let model = Scene::from_str(
        &with_ground(&spec(", baseline_correction: false")),
        "good.ron",
    )
    .unwrap()
    .build()
    .unwrap();
    let ground = model.driver.system.fixed[0].ground.as_ref().unwrap();
    assert!((ground.displacement(1.0).x - 0.981 / 2.0).abs() < 1e-12);
    assert!(
        model
            .notes
            .iter()
            .any(|n| n.contains("no baseline correction")),
        "{:?}",
        model.notes
    );

    // Only acceleration records have a baseline to correct.
    assert_error(
        &with_ground(&spec(", quantity: Velocity, baseline_correction: true")),
        "ground_motion",
        "ground_motion.motion.baseline_correction",
        "baseline correction applies to acceleration records only",
    );
    let _ = std::fs::remove_file(&path);
}

#[test]
fn an_automatic_output_interval_is_noted() {
    // Left out: the duration / 200, so 201 output times.
    let text = with("    output: (interval: 0.01),\n", "");
    let model = Scene::from_str(&text, "good.ron").unwrap().build().unwrap();
    assert_eq!(model.output_interval, Some(0.005));
    assert!(
        model
            .notes
            .iter()
            .any(|n| n.starts_with("output interval 5.0000e-3 s")
                && n.contains("201 rows per block")),
        "{:?}",
        model.notes
    );
    // Never shorter than the time step.
    let text = text.replace("dt: 0.001", "dt: 0.02");
    let model = Scene::from_str(&text, "good.ron").unwrap().build().unwrap();
    assert_eq!(model.output_interval, Some(0.02));
    // 0 writes every step, and is no automatic choice.
    let text = with("interval: 0.01", "interval: 0.0");
    let model = Scene::from_str(&text, "good.ron").unwrap().build().unwrap();
    assert_eq!(model.output_interval, None);
    assert!(model.notes.iter().all(|n| !n.contains("output interval")));
}

/// Validation is near linear in the number of blocks: a column of 100,000
/// drums (every drum in the same x range, the worst case of a sweep along
/// x) and an arch of 100,000 voussoirs are checked, overlaps included, in
/// seconds; a pairwise check would take hours.
#[test]
fn a_hundred_thousand_generated_blocks_are_checked() {
    let column = r#"Scene(
    analysis: (duration: 0.01),
    materials: {"stone": (density: 2000.0, young: 1e9)},
    blocks: [
        Rectangle(center: (0.0, -0.5), width: 4.0, height: 1.0, fixed: true),
        Column(base: (0.0, 0.0), drums: 100000, drum_height: 0.5, width: 1.0),
    ],
)"#;
    let scene = Scene::from_str(column, "column.ron").unwrap();
    assert_eq!(scene.block_count(), 100_001);
    let arch = column.replace(
        "Column(base: (0.0, 0.0), drums: 100000, drum_height: 0.5, width: 1.0)",
        "Arch(center: (0.0, 10.0), radius: 1000.0, thickness: 1.0, voussoirs: 100000)",
    );
    let scene = Scene::from_str(&arch, "arch.ron").unwrap();
    assert_eq!(scene.block_count(), 100_003);
    // An overlap among them is still found.
    let overlapping = column.replace("width: 4.0, height: 1.0", "width: 4.0, height: 1.5");
    let message = Scene::from_str(&overlapping, "column.ron")
        .unwrap_err()
        .to_string();
    assert!(message.contains("overlaps blocks[0]"), "{message}");
}

/// A modulus of 1e-300 Pa once ran without a word.
#[test]
fn a_meaningless_modulus_is_an_error() {
    let text = with("young: 1e10", "young: 1e-300");
    let message = error_of(&text);
    assert!(message.contains(".young: "), "{message}");
    assert!(
        message.contains("Young's modulus 1e-300 Pa is below 1 Pa"),
        "{message}"
    );
}

/// The corners of voussoir k of n in a half ring about the origin, from
/// radius 9.5 to 10.5 m; `reach` voussoirs wide at the outside.
fn voussoir(k: usize, n: usize, reach: usize) -> String {
    let at = |r: f64, j: usize| {
        let a = std::f64::consts::PI * j as f64 / n as f64;
        format!("({}, {})", r * a.cos(), r * a.sin())
    };
    format!(
        "        Polygon(vertices: [{}, {}, {}, {}]),\n",
        at(9.5, k),
        at(10.5, k),
        at(10.5, k + reach),
        at(9.5, k + 1)
    )
}

/// Slanted slivers, whose boxes each meet those of thousands of
/// neighbours: an arch of radius 10 m in 100,000 voussoirs 0.3 mm thick
/// along the arc, generated or listed one by one, is checked (in about a
/// second, where a check of the boxes' neighbours took minutes), and an
/// overlap among the slivers is still found.
#[test]
fn a_hundred_thousand_slivers_are_checked() {
    let head = r#"Scene(
    analysis: (duration: 0.01),
    materials: {"stone": (density: 2000.0, young: 1e9)},
    blocks: [
"#;
    let generated =
        "        Arch(center: (0.0, 0.0), radius: 10.0, thickness: 1.1277, voussoirs: 100000),\n";
    let text = format!("{head}{generated}    ],\n)");
    let scene = Scene::from_str(&text, "arch.ron").unwrap();
    assert_eq!(scene.block_count(), 100_002);
    // A sliver across the ring at 45 degrees, 0.1 mm thick.
    let (c, s) = (
        std::f64::consts::FRAC_1_SQRT_2,
        std::f64::consts::FRAC_1_SQRT_2,
    );
    let w = 5e-5;
    let sliver = format!(
        "        Polygon(vertices: [({}, {}), ({}, {}), ({}, {}), ({}, {})]),\n",
        9.8 * c + w * s,
        9.8 * s - w * c,
        10.2 * c + w * s,
        10.2 * s - w * c,
        10.2 * c - w * s,
        10.2 * s + w * c,
        9.8 * c - w * s,
        9.8 * s + w * c,
    );
    let text = format!("{head}{generated}{sliver}    ],\n)");
    let message = Scene::from_str(&text, "arch.ron").unwrap_err().to_string();
    assert!(
        message.contains(": blocks[1]: the block overlaps blocks[0] (voussoir "),
        "{message}"
    );

    let n = 100_000;
    let listed = |wide: usize| {
        let blocks: String = (0..n)
            .map(|k| voussoir(k, n, if k == wide { 2 } else { 1 }))
            .collect();
        format!("{head}{blocks}    ],\n)")
    };
    let scene = Scene::from_str(&listed(n), "arch.ron").unwrap();
    assert_eq!(scene.block_count(), n);
    // Voussoir 61,234 reaches over its neighbour at the outside.
    let message = Scene::from_str(&listed(61_234), "arch.ron")
        .unwrap_err()
        .to_string();
    assert!(
        message.contains(": blocks[61235]: the block overlaps blocks[61234] at the start"),
        "{message}"
    );
}
