//! The VTK frames of a run: one per output time, tied by whole `.pvd`
//! collections, with a cell per block (its corners, its faces in 3D) and a
//! point per contact. `tests/python/check_vtk.py` reads the same files with
//! VTK's own reader.

use std::path::{Path, PathBuf};

use dda::run::{run_scene, RunOptions};
use dda::{read_contacts, read_history, read_history_3d, Scene};
use dda_contact::LawRegistry;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dda-vtk-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// A shipped example cut to `duration` seconds, writing contacts too.
fn example(name: &str, duration: f64, vtk_in_scene: bool) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(name);
    let mut scene = Scene::load(&path).unwrap();
    scene.analysis.duration = duration;
    scene.output.contacts = true;
    scene.output.vtk = vtk_in_scene;
    scene
}

fn run(scene: &Scene, dir: &Path, vtk_flag: bool) {
    let options = RunOptions {
        vtk: vtk_flag,
        ..RunOptions::default()
    };
    run_scene(scene, dir, options, &LawRegistry::with_builtin()).unwrap();
}

/// The `file` attributes of a `.pvd`, checking it is a whole collection.
fn collection(path: &Path) -> Vec<(f64, String)> {
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.starts_with("<?xml"), "{}", path.display());
    assert!(text.contains("<VTKFile type=\"Collection\""));
    assert!(text.trim_end().ends_with("</Collection>\n</VTKFile>"));
    text.lines()
        .filter(|l| l.starts_with("<DataSet"))
        .map(|l| {
            (
                attribute(l, "timestep").parse().unwrap(),
                attribute(l, "file"),
            )
        })
        .collect()
}

fn attribute(line: &str, name: &str) -> String {
    let start = line.find(&format!("{name}=\"")).unwrap() + name.len() + 2;
    let end = start + line[start..].find('"').unwrap();
    line[start..end].to_string()
}

/// The numbers of a named DataArray.
fn array(text: &str, name: &str) -> Vec<f64> {
    let start = text.find(&format!("Name=\"{name}\"")).unwrap();
    let body = &text[start..];
    let body = &body[body.find('>').unwrap() + 1..body.find("</DataArray>").unwrap()];
    body.split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect()
}

fn piece(text: &str) -> (usize, usize) {
    let line = text.lines().find(|l| l.starts_with("<Piece")).unwrap();
    (
        attribute(line, "NumberOfPoints").parse().unwrap(),
        attribute(line, "NumberOfCells").parse().unwrap(),
    )
}

#[test]
fn a_2d_run_has_a_polygon_per_block_at_each_output_time() {
    let dir = scratch("2d");
    run(
        &example("arch_heyman_collapse_2d.ron", 0.1, false),
        &dir,
        true,
    );
    let history = read_history(dir.join("history.csv")).unwrap();
    let contacts = read_contacts(dir.join("contacts.csv")).unwrap();
    let frames = collection(&dir.join("blocks.pvd"));
    let times: Vec<f64> = history
        .iter()
        .filter(|r| r.block == 0)
        .map(|r| r.time)
        .collect();
    assert_eq!(frames.iter().map(|f| f.0).collect::<Vec<_>>(), times);
    assert_eq!(collection(&dir.join("contacts.pvd")).len(), times.len());
    assert!(!dir.join("blocks.pvd.partial").exists());

    let blocks = history.iter().filter(|r| r.time == 0.0).count();
    for (k, (time, file)) in frames.iter().enumerate() {
        let text = std::fs::read_to_string(dir.join(file)).unwrap();
        let (points, cells) = piece(&text);
        assert_eq!(cells, blocks);
        assert_eq!(array(&text, "types"), vec![7.0; blocks]);
        let corners = array(&text, "Points");
        assert_eq!(corners.len(), 3 * points);
        assert!(corners.chunks(3).all(|p| p[2] == 0.0));
        // The velocity array is the history's, number for number.
        let rows: Vec<_> = history.iter().filter(|r| r.time == *time).collect();
        let velocity = array(&text, "velocity");
        for (r, v) in rows.iter().zip(velocity.chunks(3)) {
            assert_eq!([r.vx, r.vy, 0.0], [v[0], v[1], v[2]], "frame {k}");
        }
        let text = std::fs::read_to_string(dir.join(file.replace("blocks", "contacts"))).unwrap();
        let here: Vec<_> = contacts.iter().filter(|c| c.time == *time).collect();
        assert_eq!(piece(&text), (here.len(), here.len()));
        if !here.is_empty() {
            let fn_ = array(&text, "normal_force");
            assert_eq!(fn_, here.iter().map(|c| c.normal_force).collect::<Vec<_>>());
        }
    }
}

#[test]
fn a_3d_run_has_polyhedra_with_their_faces() {
    let dir = scratch("3d");
    // Asked for by the scene, not the flag.
    run(&example("wedge_3d.ron", 0.05, true), &dir, false);
    let history = read_history_3d(dir.join("history.csv")).unwrap();
    let frames = collection(&dir.join("blocks.pvd"));
    assert_eq!(frames.len(), history.len() / 2);
    let text = std::fs::read_to_string(dir.join(&frames.last().unwrap().1)).unwrap();
    assert_eq!(piece(&text), (14, 2));
    assert_eq!(array(&text, "types"), vec![42.0, 42.0]);
    // The trough's 7 faces (5 + 5 + 4 × 5 ids) and the wedge's 4 triangles.
    let faces = array(&text, "faces");
    assert_eq!(array(&text, "faceoffsets"), vec![38.0, 38.0 + 17.0]);
    assert_eq!((faces[0], faces[38]), (7.0, 4.0));
    // The wedge's displacement is its centroid's move.
    let first = &history[1];
    let last = history.last().unwrap();
    let d = array(&text, "displacement");
    for k in 0..3 {
        assert_eq!(d[3 + k], last.position[k] - first.position[k]);
    }
    let summary = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    assert!(summary.contains("blocks.pvd") && summary.contains("contacts.pvd"));
}

#[test]
fn without_vtk_no_frames_are_written() {
    let dir = scratch("none");
    run(&example("sliding_block_2d.ron", 0.02, false), &dir, false);
    assert!(!dir.join("blocks.pvd").exists());
    assert!(!dir.join("vtk").exists());
}
