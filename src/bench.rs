//! `dda bench`: step time of running-bond walls of growing size.
//!
//! The machines are shared and noisy, so each size is run several times and
//! reported by its median, and as a ratio to the smallest wall measured in
//! the same run (the baseline).

use std::time::Instant;

use serde::Serialize;

use crate::scene::{BlockKind, Scene};

/// What to measure.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    /// Wall sizes: `n` courses of `n` bricks.
    pub sizes: Vec<usize>,
    /// Steps timed per run (after one untimed step).
    pub steps: usize,
    /// Runs per size; the median is reported.
    pub repeats: usize,
    /// The bricks' kind: rigid bricks solve for half the unknowns.
    pub kind: BlockKind,
}

/// One size's result.
#[derive(Debug, Clone, Serialize)]
pub struct BenchRow {
    pub courses: usize,
    pub kind: BlockKind,
    pub blocks: usize,
    pub contacts: usize,
    /// Unknowns of the step's system.
    pub unknowns: usize,
    /// Median wall time per step, milliseconds.
    pub median_ms_per_step: f64,
    /// The same relative to the smallest wall's.
    pub ratio_to_baseline: f64,
    /// Open-close passes and factorizations per step (from the last run).
    pub passes_per_step: f64,
    pub factorizations_per_step: f64,
}

/// A running-bond wall of `n` courses of `n` bricks (0.5 m × 0.25 m) on a
/// fixed base, at rest under gravity.
pub fn wall_scene(n: usize) -> Scene {
    let length = 0.5 * n as f64;
    let text = format!(
        r#"Scene(
    analysis: (duration: 1.0, dt: 0.001, penalty: 1e9, gravity: (0.0, -9.81)),
    materials: {{ "brick": (density: 1800.0, young: 5e9, poisson: 0.2) }},
    default_joint: Coulomb(friction_angle: 35.0),
    blocks: [
        Rectangle(center: ({c:?}, -0.5), width: {w:?}, height: 1.0, fixed: true),
        Wall(origin: (0.0, 0.0), length: {length:?}, courses: {n}, brick_length: 0.5, brick_height: 0.25, bond: Running),
    ],
)"#,
        c = length / 2.0,
        w = length + 2.0,
    );
    Scene::from_str(&text, &format!("wall_{n}x{n}.ron"))
        .expect("the benchmark wall is a valid scene")
}

/// Runs the benchmark.
pub fn bench(options: &BenchOptions) -> anyhow::Result<Vec<BenchRow>> {
    let mut rows: Vec<BenchRow> = Vec::new();
    for &n in &options.sizes {
        let mut times = Vec::with_capacity(options.repeats);
        let mut last = None;
        for _ in 0..options.repeats.max(1) {
            let mut scene = wall_scene(n);
            scene.materials[0].1.kind = options.kind;
            let mut model = scene.build()?;
            let dt = model.driver.dt();
            model.driver.step(dt)?;
            let before = model.driver.statistics().clone();
            let started = Instant::now();
            for _ in 0..options.steps {
                model.driver.step(dt)?;
            }
            times.push(started.elapsed().as_secs_f64() * 1e3 / options.steps as f64);
            let after = model.driver.statistics().clone();
            last = Some((model, before, after));
        }
        times.sort_by(f64::total_cmp);
        let median = times[times.len() / 2];
        let (model, before, after) = last.expect("at least one run");
        let steps = (after.steps - before.steps) as f64;
        rows.push(BenchRow {
            courses: n,
            kind: options.kind,
            unknowns: model.driver.unknowns(),
            blocks: model.driver.system.blocks.len(),
            contacts: model.driver.contacts().len(),
            median_ms_per_step: median,
            ratio_to_baseline: 1.0,
            passes_per_step: (after.open_close_iterations - before.open_close_iterations) as f64
                / steps,
            factorizations_per_step: (after.factorizations - before.factorizations) as f64 / steps,
        });
    }
    let baseline = rows.first().map(|r| r.median_ms_per_step).unwrap_or(1.0);
    for r in &mut rows {
        r.ratio_to_baseline = r.median_ms_per_step / baseline;
    }
    Ok(rows)
}
