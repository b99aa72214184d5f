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
    assert_eq!(report.rows.len(), 3);
    for row in &report.rows {
        assert_eq!(row.outcome, Outcome::Converged, "{row:?}");
        let e = row.relative_error.unwrap();
        // The README's verification tolerance for this scene.
        assert!(e < 0.01, "dt {}: relative error {e}", row.values[0]);
        assert!(out
            .join("runs")
            .join(&row.run)
            .join("history.csv")
            .is_file());
    }
    // study.csv holds what the report does.
    let (fields, rows) = study::table::read(&out.join("study.csv")).unwrap();
    assert_eq!(fields, ["analysis.dt"]);
    assert_eq!(rows.len(), 3);
    assert_charts(&report, 2);
}

#[test]
fn a_bad_field_path_names_the_file_the_path_and_the_fields_there() {
    let dir = common::out_dir("study-bad-path");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = common::example("sliding_block_2d.ron");
    let path = dir.join("bad.ron");
    std::fs::write(
        &path,
        format!(
            "Study(scene: File({:?}), sweep: [(field: \"analysis.dtt.x\", values: [0.01])], figure: Drift)",
            scene.display().to_string()
        ),
    )
    .unwrap();
    let e = format!(
        "{:#}",
        study::run(&path, &options(&dir.join("out"))).unwrap_err()
    );
    assert!(e.contains("bad.ron"), "{e}");
    assert!(e.contains("analysis.dtt"), "{e}");
    assert!(e.contains("duration, dt, mode"), "{e}");

    // An unknown study field is located.
    std::fs::write(&path, "Study(\n  scene: File(\"x.ron\"),\n  sweeps: [],\n)").unwrap();
    let e = format!(
        "{:#}",
        study::run(&path, &options(&dir.join("out"))).unwrap_err()
    );
    assert!(e.contains("bad.ron:3:"), "{e}");
    assert!(e.contains("sweeps"), "{e}");
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
