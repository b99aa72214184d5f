//! Every example in docs/scenes.md parses and validates with the scene
//! reader: the `ron` blocks as they are, the last column of each table in
//! the place its first word says (a block, a joint law, a ground motion, a
//! load, or top-level fields of a small scene).

use dda::Scene;

const BLOCKS_2D: &[&str] = &["Polygon", "Rectangle", "Arch", "Column", "Wall"];
const BLOCKS_3D: &[&str] = &["Polyhedron", "Box", "Prism"];
const LAWS: &[&str] = &[
    "Coulomb",
    "ThresholdBond",
    "DisplacementStrength",
    "SlipFriction",
    "RateFriction",
    "Custom",
];
const MOTIONS: &[&str] = &["Sine", "Pulse", "Record"];

fn doc() -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/scenes.md");
    std::fs::read_to_string(path).expect("docs/scenes.md exists")
}

/// The top-level fields of a small scene of each dimension.
fn base(dimension: u32) -> Vec<(&'static str, String)> {
    let blocks = if dimension == 3 {
        "[Box(center: (0.0, 0.0, -0.5), size: (4.0, 4.0, 1.0), fixed: true), \
         Box(center: (0.0, 0.0, 0.5), size: (1.0, 1.0, 1.0))]"
    } else {
        "[Rectangle(center: (0.0, -0.5), width: 4.0, height: 1.0, fixed: true), \
         Rectangle(center: (0.0, 0.5), width: 1.0, height: 1.0)]"
    };
    vec![
        ("dimension", dimension.to_string()),
        ("analysis", "(duration: 1.0)".into()),
        (
            "materials",
            r#"{ "rock": (density: 2700.0, young: 1e10) }"#.into(),
        ),
        ("blocks", blocks.into()),
    ]
}

/// The names of the fields a fragment like `a: (..), b: [..]` sets.
fn top_level_fields(fragment: &str) -> Vec<String> {
    let mut depth = 0;
    let mut fields = Vec::new();
    let mut word = String::new();
    let mut in_string = false;
    for c in fragment.chars() {
        match c {
            '"' => in_string = !in_string,
            _ if in_string => {}
            '(' | '[' | '{' => depth += 1,
            ')' | ']' | '}' => depth -= 1,
            ':' if depth == 0 && !word.is_empty() => fields.push(std::mem::take(&mut word)),
            c if depth == 0 && (c.is_alphanumeric() || c == '_') => word.push(c),
            _ if depth == 0 => word.clear(),
            _ => {}
        }
    }
    fields
}

/// A scene of `dimension` with `fragment`'s fields, the base's others.
fn scene_with(fragment: &str, dimension: u32) -> String {
    let set = top_level_fields(fragment);
    let mut text = String::from("Scene(\n");
    for (name, value) in base(dimension) {
        if !set.iter().any(|f| f == name) {
            text += &format!("    {name}: {value},\n");
        }
    }
    text + "    " + fragment + ",\n)"
}

/// The scenes an example could stand in (it passes if one of them parses).
fn candidates(example: &str) -> Vec<String> {
    let head: String = example
        .chars()
        .take_while(|c| c.is_alphanumeric())
        .collect();
    let both = |fragment: String| vec![scene_with(&fragment, 2), scene_with(&fragment, 3)];
    if BLOCKS_2D.contains(&head.as_str()) {
        vec![scene_with(&format!("blocks: [{example}]"), 2)]
    } else if BLOCKS_3D.contains(&head.as_str()) {
        vec![scene_with(&format!("blocks: [{example}]"), 3)]
    } else if LAWS.contains(&head.as_str()) {
        both(format!("default_joint: {example}"))
    } else if MOTIONS.contains(&head.as_str()) {
        both(format!("ground_motion: (blocks: [0], motion: {example})"))
    } else if head == "PointLoad" {
        both(format!("loads: [{example}]"))
    } else {
        both(example.to_string())
    }
}

/// Record files are named relative to examples/, where such scenes live.
fn parse(text: &str) -> Result<Scene, String> {
    let text = text.replace("path: \"data/", "path: \"examples/data/");
    Scene::from_str(&text, "docs/scenes.md").map_err(|e| e.to_string())
}

/// The code span of each table row's last cell, with its line number.
fn table_examples(doc: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (n, line) in doc.lines().enumerate() {
        let line = line.trim();
        if !line.starts_with('|') || line.starts_with("|---") {
            continue;
        }
        let cells: Vec<&str> = line.trim_matches('|').split(" | ").collect();
        let last = cells.last().unwrap().trim();
        if last == "example" {
            continue;
        }
        if let Some(code) = last.strip_prefix('`').and_then(|c| c.strip_suffix('`')) {
            out.push((n + 1, code.to_string()));
        }
    }
    out
}

fn ron_blocks(doc: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut current: Option<(usize, String)> = None;
    for (n, line) in doc.lines().enumerate() {
        match &mut current {
            None if line.trim() == "```ron" => current = Some((n + 2, String::new())),
            Some(_) if line.trim() == "```" => out.extend(current.take()),
            Some((_, text)) => {
                text.push_str(line);
                text.push('\n');
            }
            None => {}
        }
    }
    out
}

#[test]
fn every_table_example_parses() {
    let doc = doc();
    let examples = table_examples(&doc);
    assert!(
        examples.len() >= 55,
        "found only {} examples",
        examples.len()
    );
    let mut failures = Vec::new();
    for (line, example) in &examples {
        let errors: Vec<String> = candidates(example)
            .iter()
            .filter_map(|text| parse(text).err())
            .collect();
        if errors.len() == candidates(example).len() {
            failures.push(format!(
                "docs/scenes.md:{line}: {example}\n  {}",
                errors.join("\n  ")
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn every_ron_block_parses_and_builds() {
    let doc = doc();
    let blocks = ron_blocks(&doc);
    assert!(!blocks.is_empty());
    for (line, text) in blocks {
        let scene = parse(&text).unwrap_or_else(|e| panic!("docs/scenes.md:{line}: {e}"));
        scene
            .build_any()
            .unwrap_or_else(|e| panic!("docs/scenes.md:{line}: {e}"));
    }
}

#[test]
fn every_field_of_the_format_is_documented() {
    // The defaults written out name every field the scene types have.
    let doc = doc();
    let fields = [
        "dimension",
        "analysis",
        "output",
        "materials",
        "joints",
        "default_joint",
        "blocks",
        "loads",
        "fixed_points",
        "measured_points",
        "ground_motion",
        "duration",
        "dt",
        "mode",
        "velocity_ratio",
        "penalty",
        "fixed_penalty",
        "raise_penalty",
        "open_close_limit",
        "max_displacement_ratio",
        "max_penetration_ratio",
        "min_dt_ratio",
        "length_scale",
        "gravity",
        "plane",
        "rotation_update",
        "damping",
        "interval",
        "contacts",
        "density",
        "young",
        "poisson",
        "baseline_correction",
        "components",
        "quantity",
        "scale",
    ];
    for field in fields {
        assert!(
            doc.contains(&format!("| `{field}` |")),
            "{field} has no row"
        );
    }
    for kind in BLOCKS_2D.iter().chain(BLOCKS_3D).chain(LAWS).chain(MOTIONS) {
        assert!(doc.contains(&format!("| `{kind}` |")), "{kind} has no row");
    }
    // Every analysis setting a scene accepts has a row: a scene naming a
    // setting the table lacks would not be caught above, so compare with
    // the serialised defaults.
    let defaults = parse(&scene_with("analysis: (duration: 1.0)", 2))
        .unwrap()
        .to_ron();
    let after = defaults.split_once("analysis:").unwrap().1;
    let open = after.find('(').unwrap();
    let mut depth = 0;
    let close = after[open..]
        .char_indices()
        .find_map(|(i, c)| {
            depth += match c {
                '(' | '[' | '{' => 1,
                ')' | ']' | '}' => -1,
                _ => 0,
            };
            (depth == 0).then_some(open + i)
        })
        .unwrap();
    let settings = top_level_fields(&after[open + 1..close]);
    assert!(settings.len() >= 13, "{settings:?}");
    for name in settings {
        assert!(
            doc.contains(&format!("| `{name}` |")),
            "analysis.{name} has no row"
        );
    }
}
