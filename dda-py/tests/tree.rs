//! The scene tree writes every shipped scene back as text that parses to
//! the same scene, and changes by path go through the scene's checks.

use std::path::Path;

use dda::Scene;
use dda_py::scene::EditableScene;
use dda_py::tree::{to_tree, Given, Node};

fn examples() -> Vec<std::path::PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_example_reads_back_the_same_through_the_tree() {
    let files = examples();
    assert!(files.len() > 10, "examples found: {}", files.len());
    for file in files {
        let scene = Scene::load(&file).unwrap();
        let mut tree = to_tree(&scene);
        // Ground-motion records are named relative to the file's folder.
        tree.anchor_files(file.parent().unwrap());
        let text = tree.to_ron();
        let again = Scene::from_str(&text, "tree")
            .unwrap_or_else(|e| panic!("{}: {e}\n{text}", file.display()));
        assert_eq!(to_tree(&again), tree, "{}", file.display());
    }
}

fn sliding() -> EditableScene {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/sliding_block_2d.ron");
    EditableScene::load(&file).unwrap()
}

#[test]
fn a_path_reads_fields_variants_and_list_entries() {
    let scene = sliding();
    assert_eq!(
        scene.get("analysis.dt").unwrap(),
        Node::Some(Box::new(Node::Float(0.001)))
    );
    assert_eq!(
        scene.get("default_joint.friction_angle").unwrap(),
        Node::Float(20.0)
    );
    assert_eq!(
        scene.get("blocks[1].angle").unwrap(),
        scene.get("blocks.1.angle").unwrap()
    );
    assert_eq!(
        scene.get("materials.rock.density").unwrap(),
        Node::Float(2700.0)
    );
    let error = scene.get("analysis.dtt").unwrap_err().to_string();
    assert!(
        error.contains("`analysis` has no `dtt`") && error.contains("duration"),
        "{error}"
    );
    let error = scene.get("blocks.7").unwrap_err().to_string();
    assert!(error.contains("2 entries"), "{error}");
}

#[test]
fn a_change_is_checked_and_an_integer_stays_a_float() {
    let mut scene = sliding();
    scene.set("analysis.duration", &Given::Int(2)).unwrap();
    assert_eq!(scene.scene.analysis.duration, 2.0);
    scene
        .set(
            "default_joint",
            &Given::Str("Coulomb(friction_angle: 25.0)".into()),
        )
        .unwrap();
    assert_eq!(
        scene.get("default_joint.friction_angle").unwrap(),
        Node::Float(25.0)
    );
    let before = scene.scene.clone();
    let error = format!(
        "{:#}",
        scene.set("analysis.dt", &Given::Float(-1.0)).unwrap_err()
    );
    assert!(error.contains("analysis.dt"), "{error}");
    assert!(error.contains("sliding_block_2d.ron"), "{error}");
    assert_eq!(
        scene.scene, before,
        "a refused change leaves the scene as it was"
    );
    let error = format!(
        "{:#}",
        scene.set("analysis.dtt", &Given::Float(1.0)).unwrap_err()
    );
    assert!(error.contains("dtt"), "{error}");
}

/// An optional field not written yet takes a dict as its struct:
/// `analysis.settle = {}` settles with the defaults.
#[test]
fn a_dict_sets_an_optional_struct_not_yet_written() {
    let mut scene = sliding();
    assert_eq!(scene.scene.analysis.settle, None);
    scene.set("analysis.settle", &Given::Dict(vec![])).unwrap();
    assert_eq!(
        scene.scene.analysis.settle,
        Some(dda::scene::Settle::default())
    );
    scene.set("analysis.settle.steps", &Given::Int(5)).unwrap();
    assert_eq!(scene.scene.analysis.settle.map(|s| s.steps), Some(5));
    let damping = vec![
        ("ratio".to_string(), Given::Float(0.05)),
        ("frequency".to_string(), Given::Float(2.0)),
    ];
    scene
        .set("analysis.damping", &Given::Dict(damping))
        .unwrap();
    assert_eq!(scene.scene.analysis.damping.map(|d| d.ratio), Some(0.05));
}

#[test]
fn measured_points_are_set_by_path_and_checked() {
    let mut scene = sliding();
    let points = "[(block: 1, point: (-0.5, 0.8660254037844386))]";
    scene
        .set("measured_points", &Given::Str(points.into()))
        .unwrap();
    assert_eq!(scene.scene.measured_points.len(), 1);
    assert_eq!(scene.scene.measured_points[0].block, 1);
    let error = format!(
        "{:#}",
        scene
            .set("measured_points.0.point", &Given::Str("(9.0, 9.0)".into()))
            .unwrap_err()
    );
    assert!(error.contains("measured_points[0].point"), "{error}");
}
