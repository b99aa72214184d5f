//! Past one machine: a slice of the grid per shard (`--shard I/N`, or
//! SLURM's array variables), and `--merge` gathering the slices.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context};

use super::grid::fill_references;
use super::spec::Study;
use super::table::{self, Row};
use super::{draw_charts, Report};

/// Gathers the study.csv of shard folders (each with its study.ron) into
/// `out`: one table in index order, references filled, the charts drawn.
pub fn merge(dirs: &[PathBuf], out: &Path) -> anyhow::Result<Report> {
    let Some(first) = dirs.first() else {
        bail!("--merge needs the folders of the shards to gather");
    };
    let spec_path = first.join("study.ron");
    let text = std::fs::read_to_string(&spec_path).with_context(|| {
        format!(
            "{}: not a study folder (no study.ron): give folders `dda study --shard` wrote",
            first.display()
        )
    })?;
    let study = Study::parse(&text, &spec_path.display().to_string())?;
    let mut fields: Option<Vec<String>> = None;
    let mut rows: Vec<Row> = Vec::new();
    for dir in dirs {
        let other = std::fs::read_to_string(dir.join("study.ron")).unwrap_or_default();
        if other != text {
            bail!(
                "{}: its study.ron differs from {}'s: merge only shards of one study",
                dir.display(),
                first.display()
            );
        }
        let (f, r) = table::read(&dir.join("study.csv"))?;
        if fields.as_ref().is_some_and(|g| *g != f) {
            bail!(
                "{}: its study.csv has other columns than the first",
                dir.display()
            );
        }
        fields = Some(f);
        for row in r {
            if rows.iter().any(|q| q.index == row.index) {
                bail!(
                    "run {} is in more than one of the folders: merge each shard once",
                    row.index
                );
            }
            rows.push(row);
        }
    }
    let fields = fields.unwrap_or_default();
    rows.sort_by_key(|r| r.index);
    fill_references(&study, &fields, &mut rows)?;
    crate::pictures::create_dir(out)?;
    std::fs::write(out.join("study.ron"), &text)?;
    let names: Vec<&str> = fields.iter().map(String::as_str).collect();
    table::write_all(&out.join("study.csv"), &names, &rows)?;
    let title = study.title_or(&spec_path);
    let charts = draw_charts(&study, &title, &fields, &rows, out)?;
    Ok(Report {
        fields,
        rows,
        charts,
        bracket: None,
    })
}

/// `I/N` (0 ≤ I < N), or SLURM's array task id and count when not given.
pub fn shard(text: Option<&str>) -> anyhow::Result<Option<(usize, usize)>> {
    let env = |k: &str| std::env::var(k).ok();
    let (i, n, from) = match text {
        Some(t) => {
            let bad = || anyhow::anyhow!("--shard {t}: give I/N with 0 ≤ I < N, like 0/3");
            let (i, n) = t.split_once('/').ok_or_else(bad)?;
            let i: usize = i.trim().parse().map_err(|_| bad())?;
            let n: usize = n.trim().parse().map_err(|_| bad())?;
            (i, n, "--shard")
        }
        None => match (env("SLURM_ARRAY_TASK_ID"), env("SLURM_ARRAY_TASK_COUNT")) {
            (Some(id), Some(count)) => {
                let num = |s: &str, what: &str| -> anyhow::Result<usize> {
                    s.trim()
                        .parse()
                        .with_context(|| format!("{what}={s} is not a whole number"))
                };
                let min = env("SLURM_ARRAY_TASK_MIN")
                    .map(|m| num(&m, "SLURM_ARRAY_TASK_MIN"))
                    .transpose()?
                    .unwrap_or(0);
                let id = num(&id, "SLURM_ARRAY_TASK_ID")?;
                (
                    id.saturating_sub(min),
                    num(&count, "SLURM_ARRAY_TASK_COUNT")?,
                    "SLURM_ARRAY_TASK_ID/COUNT",
                )
            }
            _ => return Ok(None),
        },
    };
    if n == 0 || i >= n {
        bail!("{from}: shard {i} of {n}: give 0 ≤ I < N");
    }
    Ok(Some((i, n)))
}
