//! `dda validate`: the catalogue runs, each case a row of the table and of
//! validation.csv, and a case that misses its reference fails the command.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use dda::validate::{self, Case, Options, CSV_HEADER};

mod common;

fn dda(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dda"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("dda runs")
}

/// validation.csv's header and rows, split on commas.
fn read_csv(dir: &Path) -> (String, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(dir.join("validation.csv")).expect("validation.csv");
    let mut reader = csv::Reader::from_reader(text.as_bytes());
    let header = reader
        .headers()
        .unwrap()
        .iter()
        .collect::<Vec<_>>()
        .join(",");
    let rows = reader
        .records()
        .map(|r| r.unwrap().iter().map(str::to_string).collect())
        .collect();
    (header, rows)
}

fn options(dir: &Path) -> Options {
    Options {
        out: dir.to_path_buf(),
        examples: common::example(""),
        jobs: Some(2),
    }
}

fn case(name: &str) -> Case {
    *validate::catalogue()
        .iter()
        .find(|c| c.name == name)
        .expect("a catalogue case")
}

#[test]
fn quick_catalogue_passes_with_a_row_per_case() {
    let out: PathBuf = common::out_dir("validate-quick");
    let done = dda(&["validate", "--quick", "--out", out.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&done.stdout);
    assert!(
        done.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&done.stderr)
    );
    let quick: Vec<&str> = validate::catalogue()
        .iter()
        .filter(|c| c.quick)
        .map(|c| c.name)
        .collect();
    assert!(quick.iter().any(|n| n.ends_with("_2d")) && quick.iter().any(|n| n.ends_with("_3d")));
    assert!(quick.len() < validate::catalogue().len());
    let (header, rows) = read_csv(&out);
    assert_eq!(header, CSV_HEADER);
    let column = |name: &str| CSV_HEADER.split(',').position(|c| c == name).unwrap();
    let mut names: Vec<&str> = rows.iter().map(|r| r[column("case")].as_str()).collect();
    names.sort();
    let mut expected = quick.clone();
    expected.sort();
    assert_eq!(names, expected);
    for row in &rows {
        assert_eq!(row[column("result")], "pass", "{row:?}");
        let error: f64 = row[column("error")].parse().unwrap();
        let tolerance: f64 = row[column("tolerance")].parse().unwrap();
        assert!(error <= tolerance, "{row:?}");
        // Each case's run is kept in its own folder.
        assert!(out.join(&row[column("case")]).join("history.csv").is_file());
        // And printed as a row of the table.
        assert!(
            stdout
                .lines()
                .any(|l| l.starts_with(&row[column("case")]) && l.ends_with("pass")),
            "{stdout}"
        );
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn only_runs_the_named_case() {
    let out = common::out_dir("validate-only");
    let done = dda(&[
        "validate",
        "--only",
        "free_fall_3d",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(done.status.success());
    let (_, rows) = read_csv(&out);
    assert_eq!(rows.len(), 1);
    assert_eq!(rows[0][0], "free_fall_3d");
    let bad = dda(&[
        "validate",
        "--only",
        "no_such_case",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("no case `no_such_case`"));
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn a_case_off_its_reference_fails_and_so_does_the_command() {
    let out = common::out_dir("validate-fail");
    // The same run and measure, against a reference twice the answer.
    let wrong = Case {
        name: "free_fall_2d_wrong",
        reference: |scene| Ok(2.0 * (case("free_fall_2d").reference)(scene)?),
        ..case("free_fall_2d")
    };
    // A tolerance no run can meet: the slide is never exact.
    let tight = Case {
        tolerance: 1e-12,
        ..case("sliding_block_2d")
    };
    let missing = Case {
        name: "missing_example",
        example: "no_such_scene.ron",
        ..case("free_fall_2d")
    };
    let cases = [case("free_fall_2d"), wrong, tight, missing];
    let registry = dda_contact::LawRegistry::with_builtin();
    let err = validate::command(&cases, &options(&out), &registry).unwrap_err();
    let message = format!("{err:#}");
    assert!(message.starts_with("3 of 4 cases failed"), "{message}");
    // Every case has its row, the failures included.
    let rows = validate::run_cases(&cases, &options(&out), &registry).unwrap();
    let results: Vec<(&str, bool)> = rows.iter().map(|r| (r.case.as_str(), r.passed)).collect();
    assert_eq!(
        results,
        [
            ("free_fall_2d", true),
            ("free_fall_2d_wrong", false),
            ("sliding_block_2d", false),
            ("missing_example", false)
        ]
    );
    let wrong = &rows[1];
    assert!((wrong.error.unwrap() - 0.5).abs() < 1e-6, "{wrong:?}");
    assert!(rows[3].note.contains("no_such_scene.ron"), "{:?}", rows[3]);
    let (_, written) = read_csv(&out);
    assert_eq!(written.len(), 4);
    let missing = written.iter().find(|r| r[0] == "missing_example").unwrap();
    assert_eq!(
        missing[CSV_HEADER.split(',').position(|c| c == "result").unwrap()],
        "FAIL"
    );
    let _ = std::fs::remove_dir_all(&out);
}
