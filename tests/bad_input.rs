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
fn three_dimensional_scenes_are_not_supported_yet() {
    let text = with("Scene(", "Scene(\n    dimension: 3,");
    assert_error(
        &text,
        "dimension",
        "dimension",
        "3D scenes are not supported yet",
    );
    // Even with 3D-only fields the dimension is what gets reported.
    let text = with("Scene(", "Scene(\n    dimension: 3,\n    polyhedra: [],");
    assert_error(
        &text,
        "dimension",
        "dimension",
        "3D scenes are not supported yet",
    );
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
