//! `dda plot` and `dda render`: the charts, the animation and the still
//! exist and are images of the size asked for; the animation has a frame
//! per output time (or as many as asked); bad input is a clear error.

use std::path::{Path, PathBuf};
use std::process::Command;

use dda::pictures::plot::{plot, PlotOptions};
use dda::pictures::render::{render, ColorField, RenderOptions};
use dda::run::{run_scene, RunOptions};
use dda::Scene;
use dda_contact::LawRegistry;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dda-pictures-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Runs a shipped example cut to `duration` s, with contacts.csv; returns
/// the run's folder and its number of output times.
fn run(name: &str, duration: f64, dir: &Path) -> usize {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(name);
    let mut scene = Scene::load(&path).unwrap();
    scene.analysis.duration = duration;
    scene.output.contacts = true;
    let registry = LawRegistry::with_builtin();
    run_scene(&scene, dir, RunOptions::default(), &registry).unwrap();
    let history = std::fs::read_to_string(dir.join("history.csv")).unwrap();
    let mut times: Vec<&str> = history
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap())
        .collect();
    times.dedup();
    times.len()
}

/// Width and height from a PNG's header.
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(
        &bytes[..8],
        b"\x89PNG\r\n\x1a\n",
        "{} is not a PNG",
        path.display()
    );
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |b: &[u8]| u32::from_be_bytes([b[0], b[1], b[2], b[3]]);
    (be(&bytes[16..20]), be(&bytes[20..24]))
}

/// Width, height and frame count of a GIF, decoding every frame.
fn gif_frames(path: &Path) -> (u16, u16, usize) {
    let file = std::fs::File::open(path).unwrap();
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::Indexed);
    let mut decoder = options.read_info(file).unwrap();
    let (w, h) = (decoder.width(), decoder.height());
    let mut frames = 0;
    while let Some(frame) = decoder.read_next_frame().unwrap() {
        assert_eq!((frame.width, frame.height), (w, h));
        frames += 1;
    }
    (w, h, frames)
}

fn is_svg(path: &Path) -> bool {
    let text = std::fs::read_to_string(path).unwrap();
    text.contains("<svg") && text.trim_end().ends_with("</svg>")
}

#[test]
fn a_2d_run_gives_charts_an_animation_and_a_still() {
    let dir = scratch("arch");
    let times = run("arch_heyman_collapse_2d.ron", 0.5, &dir);
    assert_eq!(times, 11);

    let files = plot(&dir, &PlotOptions::default()).unwrap();
    for name in ["displacement", "velocity", "rotation", "contact_forces"] {
        let png = dir.join("plots").join(format!("{name}.png"));
        assert!(files.contains(&png));
        assert_eq!(png_size(&png), (900, 540));
        assert!(is_svg(&dir.join("plots").join(format!("{name}.svg"))));
    }
    // No steps.csv, no charts of the steps.
    assert_eq!(files.len(), 8, "{files:?}");

    let options = RenderOptions {
        color: ColorField::Stress,
        ..RenderOptions::default()
    };
    let rendered = render(&dir, &options, &LawRegistry::with_builtin()).unwrap();
    assert_eq!(rendered.frames, times);
    let out = dir.join("render");
    assert_eq!(gif_frames(&out.join("animation.gif")), (800, 600, times));
    assert_eq!(png_size(&out.join("still.png")), (800, 600));
    assert!(is_svg(&out.join("still.svg")));

    // Fewer frames when asked, at another size.
    let options = RenderOptions {
        frames: Some(4),
        size: (320, 240),
        out: Some(dir.join("small")),
        ..RenderOptions::default()
    };
    render(&dir, &options, &LawRegistry::with_builtin()).unwrap();
    assert_eq!(gif_frames(&dir.join("small/animation.gif")), (320, 240, 4));

    // Up to 0.2 s: the output times 0, 0.05, ..., 0.2.
    let options = RenderOptions {
        until: Some(0.2),
        out: Some(dir.join("early")),
        ..RenderOptions::default()
    };
    let rendered = render(&dir, &options, &LawRegistry::with_builtin()).unwrap();
    assert_eq!(rendered.frames, 5);
    assert_eq!(gif_frames(&dir.join("early/animation.gif")).2, 5);
}

#[test]
fn a_3d_run_is_drawn_in_an_oblique_view() {
    let dir = scratch("wedge");
    let times = run("wedge_3d.ron", 0.05, &dir);
    plot(
        &dir,
        &PlotOptions {
            blocks: vec![1],
            out: None,
        },
    )
    .unwrap();
    assert_eq!(png_size(&dir.join("plots/rotation.png")), (900, 540));
    let rendered = render(
        &dir,
        &RenderOptions::default(),
        &LawRegistry::with_builtin(),
    )
    .unwrap();
    assert_eq!(
        gif_frames(&dir.join("render/animation.gif")),
        (800, 600, times)
    );
    assert_eq!(rendered.frames, times);
}

fn error_of(result: anyhow::Result<impl std::fmt::Debug>) -> String {
    format!("{:#}", result.unwrap_err())
}

#[test]
fn bad_input_names_the_file_and_the_fix() {
    let missing = scratch("missing");
    let e = error_of(plot(&missing, &PlotOptions::default()));
    assert!(
        e.contains("is not a folder") && e.contains("dda run"),
        "{e}"
    );

    let empty = scratch("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let e = error_of(render(
        &empty,
        &RenderOptions::default(),
        &LawRegistry::with_builtin(),
    ));
    assert!(e.contains("history.csv not found"), "{e}");

    let dir = scratch("bad");
    run("sliding_block_2d.ron", 0.02, &dir);
    let e = error_of(plot(
        &dir,
        &PlotOptions {
            blocks: vec![0, 7],
            out: None,
        },
    ));
    assert!(e.contains("block 7") && e.contains("2 blocks"), "{e}");
    let options = RenderOptions {
        frames: Some(1000),
        ..RenderOptions::default()
    };
    let e = error_of(render(&dir, &options, &LawRegistry::with_builtin()));
    assert!(e.contains("--frames 1000"), "{e}");
    let options = RenderOptions {
        scene: Some(dir.join("nowhere.ron")),
        ..RenderOptions::default()
    };
    let e = error_of(render(&dir, &options, &LawRegistry::with_builtin()));
    assert!(e.contains("nowhere.ron") && e.contains("--scene"), "{e}");

    // An unknown field is refused by the command with the ones it knows.
    let out = Command::new(env!("CARGO_BIN_EXE_dda"))
        .args(["render", dir.to_str().unwrap(), "--color", "temperature"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("displacement") && stderr.contains("stress"),
        "{stderr}"
    );
}

/// With `steps.csv` (`output.steps`) the charts also show each step's wall
/// time, work and length.
#[test]
fn a_run_with_its_steps_charts_them() {
    let dir = scratch("steps");
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/arch_heyman_collapse_2d.ron");
    let mut scene = Scene::load(&path).unwrap();
    scene.analysis.duration = 0.2;
    scene.output.steps = true;
    run_scene(
        &scene,
        &dir,
        RunOptions::default(),
        &LawRegistry::with_builtin(),
    )
    .unwrap();
    let files = plot(&dir, &PlotOptions::default()).unwrap();
    let names = ["step_time", "step_phases", "step_work", "step_length"];
    for name in names {
        let png = dir.join("plots").join(format!("{name}.png"));
        assert!(files.contains(&png), "{files:?}");
        assert_eq!(png_size(&png), (900, 540));
        assert!(is_svg(&dir.join("plots").join(format!("{name}.svg"))));
    }
    // The phases' bands are named in the legend.
    let svg = std::fs::read_to_string(dir.join("plots/step_phases.svg")).unwrap();
    for band in [
        "contact search",
        "assembly",
        "factorisation",
        "substitutions",
        "other",
    ] {
        assert!(svg.contains(band), "{band}");
    }

    // A steps file alone (as `dda bench --step-log` writes one per wall)
    // is charted beside it, its charts named after it.
    let alone = scratch("steps_alone");
    std::fs::create_dir_all(&alone).unwrap();
    let file = alone.join("10x10_rigid_2d.csv");
    std::fs::copy(dir.join("steps.csv"), &file).unwrap();
    let files = plot(&file, &PlotOptions::default()).unwrap();
    assert_eq!(files.len(), 2 * names.len());
    for name in names {
        let png = alone
            .join("plots")
            .join(format!("10x10_rigid_2d_{name}.png"));
        assert!(files.contains(&png), "{files:?}");
        assert_eq!(png_size(&png), (900, 540));
    }
    let chosen = PlotOptions {
        blocks: vec![0],
        ..PlotOptions::default()
    };
    let error = plot(&file, &chosen).unwrap_err().to_string();
    assert!(error.contains("a steps file, which has none"), "{error}");

    // A steps file of its header alone (a run stopped before its first
    // step): the run's other charts without the step ones, and the file
    // alone refused; neither hangs on an empty range.
    let text = std::fs::read_to_string(dir.join("steps.csv")).unwrap();
    let header = text.lines().next().unwrap().to_string() + "\n";
    std::fs::write(dir.join("steps.csv"), &header).unwrap();
    let files = plot(&dir, &PlotOptions::default()).unwrap();
    assert!(files.iter().any(|f| f.ends_with("displacement.png")));
    assert!(!files.iter().any(|f| f.to_string_lossy().contains("step_")));
    std::fs::write(&file, &header).unwrap();
    let error = plot(&file, &PlotOptions::default())
        .unwrap_err()
        .to_string();
    assert!(error.contains("no step yet"), "{error}");
    let missing = alone.join("missing.csv");
    let error = plot(&missing, &PlotOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("not found") && error.contains("a steps file"),
        "{error}"
    );
}
