//! `dda bench --study`: how well a study's runs share the cores.

use std::time::Instant;

use serde::Serialize;

/// One study timing: the runs at `jobs` at once.
#[derive(Debug, Clone, Serialize)]
pub struct StudyBenchRow {
    pub jobs: usize,
    pub runs: usize,
    /// Median wall time of the whole study, seconds.
    pub median_wall_s: f64,
    /// The sum of its runs' own wall times in that repeat, seconds.
    pub run_sum_s: f64,
    /// Wall time over the sum of run times: 1 on one core, 1/jobs at best.
    pub ratio: f64,
}

/// Times the study in `path` at each of `jobs` runs at once, `repeats`
/// times each (the median repeat is reported), its outputs in a temporary
/// folder: how well the runs share the cores.
pub fn bench_study(
    path: &std::path::Path,
    jobs: &[usize],
    repeats: usize,
) -> anyhow::Result<Vec<StudyBenchRow>> {
    let out = std::env::temp_dir().join(format!("dda-bench-study-{}", std::process::id()));
    let mut rows = Vec::new();
    for &j in jobs {
        let mut timings: Vec<(f64, f64, usize)> = (0..repeats.max(1))
            .map(|_| {
                let _ = std::fs::remove_dir_all(&out);
                let started = Instant::now();
                let report = crate::study::run(
                    path,
                    &crate::study::Options {
                        out: out.clone(),
                        jobs: Some(j),
                        shard: None,
                        progress: false,
                    },
                )?;
                let wall = started.elapsed().as_secs_f64();
                let sum = report.rows.iter().map(|r| r.wall_time).sum();
                Ok((wall, sum, report.rows.len()))
            })
            .collect::<anyhow::Result<_>>()?;
        timings.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (wall, sum, runs) = timings[timings.len() / 2];
        rows.push(StudyBenchRow {
            jobs: j,
            runs,
            median_wall_s: wall,
            run_sum_s: sum,
            ratio: wall / sum,
        });
    }
    let _ = std::fs::remove_dir_all(&out);
    Ok(rows)
}
