//! Studies: the shipped studies in examples/studies/ (on reduced grids
//! where the full one is slow), their charts, bad study files, failed
//! runs, and a grid run as three shards merged back into one table.

use std::path::{Path, PathBuf};

use dda::study::{self, Options, Outcome, Report, Study, Value};
use dda_contact::LawRegistry;

mod common;

fn studies() -> PathBuf {
    common::example("studies")
}

fn options(out: &Path) -> Options {
    Options {
        out: out.to_path_buf(),
        jobs: Some(2),
        shard: None,
        progress: false,
    }
}

/// A shipped study, its sweeps cut by `reduce`, run into a fresh folder.
fn run_shipped(name: &str, reduce: impl FnOnce(&mut Study)) -> (Report, PathBuf) {
    let path = studies().join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    let mut study = Study::parse(&text, &path.display().to_string()).unwrap();
    reduce(&mut study);
    let out = common::out_dir(&format!("study-{}", name.trim_end_matches(".ron")));
    let report = study::run_study(
        &study,
        &path,
        &text,
        &options(&out),
        &LawRegistry::with_builtin(),
    )
    .unwrap_or_else(|e| panic!("{name}: {e:#}"));
    (report, out)
}

fn keep(study: &mut Study, field: &str, values: &[f64]) {
    let sweep = study.sweep.iter_mut().find(|s| s.field == field).unwrap();
    sweep.values = values.iter().map(|v| Value::Number(*v)).collect();
}

/// Every chart is an SVG and a PNG that decodes to a picture of 900 × 600.
fn assert_charts(report: &Report, at_least: usize) {
    let pngs: Vec<&PathBuf> = report
        .charts
        .iter()
        .filter(|f| f.extension().is_some_and(|e| e == "png"))
        .collect();
    assert!(pngs.len() >= at_least, "charts: {:?}", report.charts);
    for f in &report.charts {
        let bytes = std::fs::read(f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        if f.extension().is_some_and(|e| e == "svg") {
            let text = String::from_utf8(bytes).unwrap();
            assert!(
                text.starts_with("<svg") && text.trim_end().ends_with("</svg>"),
                "{}",
                f.display()
            );
            assert!(text.contains("width=\"900\"") && text.contains("height=\"600\""));
        } else {
            let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
            let mut reader = decoder
                .read_info()
                .unwrap_or_else(|e| panic!("{}: {e}", f.display()));
            let mut buf = vec![0; reader.output_buffer_size()];
            let info = reader.next_frame(&mut buf).unwrap();
            assert_eq!((info.width, info.height), (900, 600), "{}", f.display());
            // Not blank: more than a few distinct colours.
            let mut colours: Vec<&[u8]> = buf.chunks(3).collect();
            colours.sort_unstable();
            colours.dedup();
            assert!(colours.len() > 10, "{} looks blank", f.display());
        }
    }
}

#[test]
fn sliding_block_dt_sweep_follows_the_analytical_slide() {
    let (report, out) = run_shipped("sliding_block_dt.ron", |s| {
        keep(s, "analysis.dt", &[0.01, 0.005, 0.002]);
    });
    assert_eq!(report.rows.len(), 6);
    for row in &report.rows {
        assert_eq!(row.outcome, Outcome::Converged, "{row:?}");
        let e = row.relative_error.unwrap();
        // The README's verification tolerance for this scene, for both
        // integrators.
        assert!(e < 0.005, "{:?}: relative error {e}", row.values);
        assert!(out
            .join("runs")
            .join(&row.run)
            .join("history.csv")
            .is_file());
    }
    // study.csv holds what the report does.
    let (fields, rows) = study::table::read(&out.join("study.csv")).unwrap();
    assert_eq!(fields, ["analysis.integrator", "analysis.dt"]);
    assert_eq!(rows.len(), 6);
    assert_charts(&report, 2);
}

#[test]
fn a_bad_field_path_names_the_file_the_path_and_the_fields_there() {
    let dir = common::out_dir("study-bad-path");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = common::example("sliding_block_2d.ron");
    let path = dir.join("bad.ron");
    // The error of a study of the sliding block whose body, after its
    // scene, is `body`.
    let error_of = |body: &str| {
        let text = format!(
            "Study(scene: File({:?}), {body})",
            scene.display().to_string()
        );
        std::fs::write(&path, text).unwrap();
        format!(
            "{:#}",
            study::run(&path, &options(&dir.join("out"))).unwrap_err()
        )
    };
    let e = error_of("sweep: [(field: \"analysis.dtt.x\", values: [0.01])], figure: Drift");
    assert!(e.contains("bad.ron"), "{e}");
    assert!(e.contains("analysis.dtt"), "{e}");
    assert!(e.contains("duration, mode, velocity_ratio"), "{e}");

    // An unknown study field is located.
    std::fs::write(&path, "Study(\n  scene: File(\"x.ron\"),\n  sweeps: [],\n)").unwrap();
    let e = format!(
        "{:#}",
        study::run(&path, &options(&dir.join("out"))).unwrap_err()
    );
    assert!(e.contains("bad.ron:3:"), "{e}");
    assert!(e.contains("sweeps"), "{e}");

    // A place copied from a scene's error, brackets and all, is the field
    // its dots name, wherever a study names a path.
    let study = dda::study::spec::Study::parse(
        r#"Study(
            scene: File("x.ron"),
            set: {"materials[\"rock\"].density": 2600.0},
            sweep: [
                (field: "blocks[1].width", values: [1.0]),
                (field: "analysis.dt", values: [0.01]),
            ],
            figure: Drift,
            reference: Finest("blocks[1].width"),
            charts: [FigureAgainst(x: "blocks[1].width", series: "analysis.dt")],
        )"#,
        "brackets.ron",
    )
    .unwrap();
    assert_eq!(study.fields(), ["blocks.1.width", "analysis.dt"]);
    assert!(
        study.set.contains_key("materials.rock.density"),
        "{:?}",
        study.set
    );
    assert!(
        matches!(&study.reference, Some(dda::study::spec::Reference::Finest(f)) if f == "blocks.1.width")
    );
    assert!(matches!(
        &study.charts[..],
        [dda::study::spec::Chart::FigureAgainst { x, .. }] if x == "blocks.1.width"
    ));
}

#[test]
fn a_run_that_fails_is_a_row_not_the_end_of_the_study() {
    let dir = common::out_dir("study-failed-run");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("study.ron");
    std::fs::write(
        &path,
        format!(
            "Study(scene: File({:?}), set: {{\"analysis.duration\": 0.1}}, \
             sweep: [(field: \"analysis.dt\", values: [-1.0, 0.01])], figure: Displacement(block: 1))",
            common::example("sliding_block_2d.ron").display().to_string()
        ),
    )
    .unwrap();
    let report = study::run(&path, &options(&dir.join("out"))).unwrap();
    assert_eq!(report.rows.len(), 2);
    assert_eq!(report.rows[0].outcome, Outcome::Failed);
    assert!(report.rows[0].note.contains("dt"), "{:?}", report.rows[0]);
    assert_eq!(report.rows[1].outcome, Outcome::Converged);
    assert!(report.rows[1].figure.unwrap() > 0.0);
}

/// Three shards of a grid, merged, give the rows of the whole grid run at
/// once (all but the wall time, which depends on the machine's load).
#[test]
fn three_shards_merge_into_the_rows_of_the_whole_grid() {
    let path = studies().join("spinning_rotation_update.ron");
    let base = common::out_dir("study-shards");
    let whole = study::run(&path, &options(&base.join("whole"))).unwrap();
    let mut dirs = Vec::new();
    for i in 0..3 {
        let dir = base.join(format!("shard{i}"));
        let o = Options {
            shard: Some((i, 3)),
            ..options(&dir)
        };
        let part = study::run(&path, &o).unwrap();
        assert!(part.rows.iter().all(|r| r.index % 3 == i));
        dirs.push(dir);
    }
    let merged = study::merge(&dirs, &base.join("merged")).unwrap();
    let (_, from_whole) = study::table::read(&base.join("whole").join("study.csv")).unwrap();
    let (fields, from_merge) = study::table::read(&base.join("merged").join("study.csv")).unwrap();
    assert_eq!(fields, whole.fields);
    assert_eq!(from_merge.len(), whole.rows.len());
    let same = |rows: &[study::Row]| -> Vec<study::Row> {
        rows.iter().map(study::table::deterministic).collect()
    };
    assert_eq!(same(&from_merge), same(&from_whole));
    assert_charts(&merged, 2);
    // A shard of a shard's folder twice is refused.
    let e = study::merge(&[dirs[0].clone(), dirs[0].clone()], &base.join("twice")).unwrap_err();
    assert!(format!("{e:#}").contains("more than one"), "{e:#}");
}

#[test]
fn shards_come_from_the_command_line_or_slurm() {
    assert_eq!(study::shard(Some("1/3")).unwrap(), Some((1, 3)));
    assert!(study::shard(Some("3/3")).is_err());
    assert!(study::shard(Some("x")).is_err());
}

#[test]
fn resting_block_map_holds_above_the_friction_limit_and_slides_below() {
    let (report, _) = run_shipped("resting_block_friction_dt.ron", |s| {
        keep(s, "default_joint.friction_angle", &[29.0, 31.0]);
        keep(s, "analysis.dt", &[0.002, 0.001]);
    });
    assert_eq!(report.rows.len(), 4);
    for row in &report.rows {
        let phi: f64 = row.values[0].parse().unwrap();
        if phi < 30.0 {
            assert_eq!(row.outcome, Outcome::Slid, "{row:?}");
            // Coulomb's slide in the study's 1 s, within 5 %.
            let (theta, phi) = (30f64.to_radians(), phi.to_radians());
            let d = 0.5 * 9.81 * (theta.sin() - theta.cos() * phi.tan());
            let moved = row.figure.unwrap();
            assert!(
                (moved - d).abs() < 0.05 * d,
                "φ {phi}: {moved} m, Coulomb {d} m"
            );
        } else {
            assert_eq!(row.outcome, Outcome::Held, "{row:?}");
        }
    }
    assert_charts(&report, 2);
}

/// Released, the block just above its friction limit slips on its first
/// bounce; settled first, it does not move (measured 1e-13 m), at each of
/// three factors of safety.
#[test]
fn settled_blocks_hold_where_released_ones_slip() {
    let (report, out) = run_shipped("settle_near_the_limit.ron", |_| {});
    assert_eq!(report.rows.len(), 6);
    for row in &report.rows {
        let settled = row.values[1] != "None";
        let moved = row.figure.unwrap();
        if settled {
            assert!(moved < 1e-9, "{row:?}");
            assert_eq!(row.outcome, Outcome::Held, "{row:?}");
        } else {
            assert!(moved > 1e-5, "{row:?}");
        }
    }
    assert_charts(&report, 1);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn rocking_column_restitution_is_housners() {
    let (report, _) = run_shipped("rocking_restitution.ron", |s| {
        keep(s, "analysis.penalty", &[2e10]);
        keep(s, "analysis.dt", &[0.001, 0.0005]);
    });
    let housner = 1.0 - 1.5 * 0.25f64.atan().sin().powi(2);
    for row in &report.rows {
        assert!((row.reference.unwrap() - housner).abs() < 1e-12);
        // Within 1 % of the rigid block, as tests/impact_convergence_2d.rs
        // finds for the first rebound with critical contact damping.
        let e = row.relative_error.unwrap();
        assert!(
            e < 0.01,
            "dt {}: restitution {:?}, Housner {housner}",
            row.values[1],
            row.figure
        );
    }
    assert_charts(&report, 2);
}

#[test]
fn heyman_arch_least_thickness_by_bisection() {
    let (report, out) = run_shipped("arch_heyman_thickness.ron", |_| {});
    let (lo, hi) = report.bracket.unwrap();
    assert!(hi - lo <= 0.005 + 1e-12, "bracket [{lo}, {hi}]");
    // The examples stand at 1.05 × Heyman's t/R and collapse at 0.95 ×: the
    // flip lies between (R = 10 m).
    let heyman = 0.1074 * 10.0;
    assert!(
        lo >= 0.95 * heyman && hi <= 1.05 * heyman,
        "bracket [{lo}, {hi}] m, Heyman {heyman} m"
    );
    let below = report
        .rows
        .iter()
        .filter(|r| r.values[0].parse::<f64>().unwrap() <= lo);
    assert!(below.clone().all(|r| r.outcome == Outcome::Slid));
    let above = report
        .rows
        .iter()
        .filter(|r| r.values[0].parse::<f64>().unwrap() >= hi);
    assert!(above.clone().all(|r| r.outcome == Outcome::Held));
    let search: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("search.json")).unwrap()).unwrap();
    assert!(
        (search["low"].as_f64().unwrap() - lo).abs() < 1e-12,
        "{search}"
    );
    println!(
        "critical thickness in [{lo}, {hi}] m: t/R = {:.4} ± {:.4}",
        (lo + hi) / 20.0,
        (hi - lo) / 20.0
    );
    assert_charts(&report, 1);
}

#[test]
fn spinning_block_keeps_its_area_only_with_the_exact_update() {
    let (report, _) = run_shipped("spinning_rotation_update.ron", |_| {});
    for row in &report.rows {
        let drift = row.figure.unwrap();
        let dt: f64 = row.values[1].parse().unwrap();
        if row.values[0] == "Exact" {
            assert!(drift.abs() < 1e-9, "exact update, dt {dt}: drift {drift}");
        } else if dt <= 0.01 {
            // (1 + (ω·Δt)²) per step over one revolution (ω = 1 rad/s), within 2 %.
            let expected = (1.0 + dt * dt).powf(std::f64::consts::TAU / dt) - 1.0;
            assert!(
                (drift - expected).abs() < 0.02 * expected,
                "linear, dt {dt}: {drift}, expected {expected}"
            );
        } else {
            assert!(drift > 0.1, "linear, dt {dt}: {drift}");
        }
    }
    assert_charts(&report, 2);
}

/// The same figure in 2D and for the extruded prisms.
fn two_and_three(name: &str) -> (study::Row, study::Row) {
    let (report, _) = run_shipped(name, |_| {});
    assert_eq!(report.rows.len(), 2);
    assert_charts(&report, 1);
    assert!(report.rows[1].run.contains("dimension=3"));
    (report.rows[0].clone(), report.rows[1].clone())
}

#[test]
fn two_d_against_three_d_sliding_and_resting_blocks() {
    let (flat, solid) = two_and_three("sliding_block_2d_3d.ron");
    for r in [&flat, &solid] {
        assert!(r.relative_error.unwrap() < 0.01, "{r:?}");
    }
    let (a, b) = (flat.figure.unwrap(), solid.figure.unwrap());
    assert!((a - b).abs() < 0.01 * a, "2D {a} m, 3D {b} m");
    let (flat, solid) = two_and_three("resting_block_2d_3d.ron");
    assert_eq!(
        (flat.outcome, solid.outcome),
        (Outcome::Held, Outcome::Held)
    );
}

#[test]
fn two_d_against_three_d_column_and_arch() {
    let (flat, solid) = two_and_three("rocking_column_2d_3d.ron");
    for r in [&flat, &solid] {
        // The rigid block's first impact within 3 % (tests/housner_rocking_2d.rs).
        assert!(r.relative_error.unwrap() < 0.03, "{r:?}");
    }
    let (flat, solid) = two_and_three("arch_2d_3d.ron");
    assert_eq!(
        (flat.outcome, solid.outcome),
        (Outcome::Held, Outcome::Held)
    );
}

/// The sbatch example of docs/studies.md: array tasks take their shard from
/// SLURM's variables, and `--merge` gathers them.
#[test]
fn slurm_array_tasks_and_merge_through_the_command() {
    let study = studies().join("spinning_rotation_update.ron");
    let base = common::out_dir("study-slurm");
    let dda = env!("CARGO_BIN_EXE_dda");
    let mut shards = Vec::new();
    for id in 1..=2 {
        let dir = base.join(format!("shard-{id}"));
        let status = std::process::Command::new(dda)
            .args([
                "study",
                study.to_str().unwrap(),
                "--jobs",
                "1",
                "--out",
                dir.to_str().unwrap(),
            ])
            .env("SLURM_ARRAY_TASK_ID", id.to_string())
            .env("SLURM_ARRAY_TASK_COUNT", "2")
            .env("SLURM_ARRAY_TASK_MIN", "1")
            .output()
            .unwrap();
        assert!(
            status.status.success(),
            "{}",
            String::from_utf8_lossy(&status.stderr)
        );
        let (_, rows) = study::table::read(&dir.join("study.csv")).unwrap();
        assert_eq!(rows.len(), 4);
        assert!(rows.iter().all(|r| r.index % 2 == id - 1));
        shards.push(dir);
    }
    let merged = base.join("all");
    let out = std::process::Command::new(dda)
        .args(["study", "--merge"])
        .args(&shards)
        .args(["--out", merged.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (_, rows) = study::table::read(&merged.join("study.csv")).unwrap();
    assert_eq!(
        rows.iter().map(|r| r.index).collect::<Vec<_>>(),
        (0..8).collect::<Vec<_>>()
    );
    assert!(merged.join("charts").join("0_figure.png").is_file());
}

/// The block kind swept by path (a field the scene does not write), with
/// the contact force as the figure: the resting block's weight component
/// normal to the 30° incline, ρ g a² cos 30°, whatever the kind.
#[test]
fn block_kind_sweep_and_contact_force() {
    let dir = common::out_dir("study-kind");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("kind.ron");
    std::fs::write(
        &path,
        format!(
            "Study(scene: File({:?}), set: {{\"analysis.duration\": 0.5, \"analysis.contact_damping\": 1.0}}, \
             sweep: [(field: \"materials.rock.kind\", values: [\"Rigid\", \"Deformable\"])], \
             figure: ContactForce(blocks: (0, 1)), reference: Expression(\"2700 * 9.81 * cos(rad(30))\"), \
             held: (block: 1, tolerance: 1e-4))",
            common::example("resting_block_2d.ron").display().to_string()
        ),
    )
    .unwrap();
    let report = study::run(&path, &options(&dir.join("out"))).unwrap();
    for row in &report.rows {
        assert_eq!(row.outcome, Outcome::Held, "{row:?}");
        // With critical contact damping the springs have settled by 0.5 s.
        assert!(row.relative_error.unwrap() < 1e-6, "{row:?}");
        let scene =
            std::fs::read_to_string(dir.join("out/runs").join(&row.run).join("scene.ron")).unwrap();
        assert!(
            scene.contains(&format!("kind: {}", row.values[0])),
            "{scene}"
        );
    }
}

#[test]
fn an_inline_scene_and_a_search_that_does_not_flip() {
    let dir = common::out_dir("study-inline");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = std::fs::read_to_string(common::example("free_fall_2d.ron")).unwrap();
    let path = dir.join("inline.ron");
    std::fs::write(
        &path,
        format!(
            "Study(scene: Inline({scene:?}), search: Bisect(field: \"analysis.dt\", low: 0.001, high: 0.01, tolerance: 0.001), \
             figure: Drift, held: (block: 0, tolerance: 1e-3))"
        ),
    )
    .unwrap();
    let e = format!(
        "{:#}",
        study::run(&path, &options(&dir.join("out"))).unwrap_err()
    );
    assert!(e.contains("both ends") && e.contains("slid"), "{e}");
    // The two runs are in the table all the same.
    let (_, rows) = study::table::read(&dir.join("out/study.csv")).unwrap();
    assert_eq!(rows.len(), 2);
}

/// A study file of a few lines next to the output, on a shipped scene.
fn small_study(name: &str, body: &str) -> (Report, PathBuf) {
    let dir = common::out_dir(&format!("study-{name}"));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.ron"));
    std::fs::write(&path, format!("Study({body})")).unwrap();
    let out = dir.join("out");
    let report = study::run(&path, &options(&out)).unwrap_or_else(|e| panic!("{e:#}"));
    (report, out)
}

#[test]
fn finest_run_reference_and_energy_drift() {
    let scene = common::example("sliding_block_2d.ron")
        .display()
        .to_string();
    let (report, _) = small_study(
        "finest",
        &format!(
            "scene: File({scene:?}), sweep: [(field: \"analysis.dt\", values: [0.004, 0.002, 0.001])], \
             figure: Velocity(block: 1, time: 1.0), reference: Finest(\"analysis.dt\")"
        ),
    );
    let finest = report.rows[2].figure.unwrap();
    // v(1 s) = g (sin 30° − cos 30° tan 20°), within 0.1 %.
    let a = 9.81 * (0.5 - 30f64.to_radians().cos() * 20f64.to_radians().tan());
    assert!((finest - a).abs() < 1e-3 * a, "{finest} m/s against {a}");
    assert_eq!(report.rows[2].error, Some(0.0));
    for row in &report.rows {
        assert_eq!(row.reference, Some(finest));
    }

    let scene = common::example("spinning_block_2d.ron")
        .display()
        .to_string();
    let (report, _) = small_study(
        "energy",
        &format!(
            "scene: File({scene:?}), sweep: [(field: \"analysis.rotation_update\", values: [\"Exact\", \"Linear\"])], \
             figure: EnergyDrift"
        ),
    );
    // A free spinning block keeps its kinetic energy with the exact
    // update; the linear one inflates the block (6.5 % in area), and the
    // energy with it.
    assert!(
        report.rows[0].figure.unwrap().abs() < 1e-9,
        "{:?}",
        report.rows[0]
    );
    assert!(
        report.rows[1].figure.unwrap() > 0.05,
        "{:?}",
        report.rows[1]
    );
}
