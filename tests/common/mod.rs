//! Helpers shared by the verification tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use dda_core::assembly::CscPattern;
use dda_core::solve::{FactorUpdate, LinearSolver, SparseCholesky, UpdateTerm};
use dda_core::DdaError;

use dda::HistoryRow;

/// Path of a shipped example.
pub fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(name)
}

/// A fresh output folder for one test.
pub fn out_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dda-test-{}-{}", test, std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Runs an example the way `dda run` does and reads its history back.
pub fn run_example(name: &str) -> Vec<HistoryRow> {
    let out = out_dir(name.trim_end_matches(".ron"));
    dda::run::run(&example(name), &out).expect("the example runs");
    let rows = dda::read_history(out.join("history.csv")).expect("history.csv reads back");
    let _ = std::fs::remove_dir_all(&out);
    rows
}

/// Runs a shipped example after `edit`, as `dda run` does, into a fresh
/// folder named by `tag`; returns the summary and the folder.
pub fn run_edited(
    name: &str,
    tag: &str,
    edit: impl FnOnce(&mut dda::Scene),
) -> (dda::Summary, PathBuf) {
    let mut scene = dda::Scene::load(example(name)).unwrap();
    edit(&mut scene);
    run_scene(&scene, &format!("{tag}-{}", name.trim_end_matches(".ron")))
}

/// Runs a scene as `dda run` does into a fresh folder named by `tag`;
/// returns the summary and the folder.
pub fn run_scene(scene: &dda::Scene, tag: &str) -> (dda::Summary, PathBuf) {
    let out = out_dir(tag);
    let summary = dda::run::run_scene(
        scene,
        &out,
        Default::default(),
        &dda_contact::LawRegistry::with_builtin(),
    )
    .unwrap();
    (summary, out)
}

/// The row of `block` at the output time closest to `time`.
pub fn at(rows: &[HistoryRow], block: usize, time: f64) -> &HistoryRow {
    rows.iter()
        .filter(|r| r.block == block)
        .min_by(|a, b| (a.time - time).abs().total_cmp(&(b.time - time).abs()))
        .expect("the block has rows")
}

/// Distance between the centroids of two rows.
pub fn distance(a: &HistoryRow, b: &HistoryRow) -> f64 {
    ((a.x - b.x).powi(2) + (a.y - b.y).powi(2)).sqrt()
}

/// One row of contacts.csv.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactRow {
    pub step: usize,
    pub time: f64,
    pub label: String,
    pub blocks: (usize, usize),
    pub state: String,
    pub normal: f64,
    pub shear: f64,
    pub slip: f64,
}

/// Reads contacts.csv, checking its header.
pub fn read_contacts(path: &Path) -> Vec<ContactRow> {
    let text = std::fs::read_to_string(path).expect("contacts.csv exists");
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("step,time,contact,block_a,block_b,state,fn,fs,slip")
    );
    lines
        .map(|line| {
            let f: Vec<&str> = line.split(',').collect();
            let num = |i: usize| f[i].parse::<f64>().unwrap();
            ContactRow {
                step: f[0].parse().unwrap(),
                time: num(1),
                label: f[2].to_string(),
                blocks: (f[3].parse().unwrap(), f[4].parse().unwrap()),
                state: f[5].to_string(),
                normal: num(6),
                shear: num(7),
                slip: num(8),
            }
        })
        .collect()
}

/// Runs scene text (written to a temporary file) and returns the output
/// folder; the caller removes it.
pub fn run_text(name: &str, text: &str) -> PathBuf {
    let out = out_dir(name);
    std::fs::create_dir_all(&out).unwrap();
    let scene = out.join(format!("{name}.ron"));
    std::fs::write(&scene, text).unwrap();
    dda::run::run(&scene, &out).expect("the scene runs");
    out
}

/// An example's text with `from` replaced by `to` (which must occur).
pub fn example_with(name: &str, from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(example(name)).unwrap();
    assert!(text.contains(from), "{name} has no `{from}`");
    text.replace(from, to)
}

/// Velocity-dependent friction on a 30° incline: φ from 25° at rest to 15°
/// at speed, μ(v) = μd + (μs − μd) exp(−v/vc) with vc = 0.5 m/s.
pub const RATE_LAW: &str =
    "RateFriction(static_friction_angle: 25.0, dynamic_friction_angle: 15.0, characteristic_rate: 0.5)";

/// Distance slid from rest by `t_end` under [`RATE_LAW`]: a fine RK4
/// integration of dv/dt = g (sin θ − cos θ μ(v)).
pub fn rate_friction_slide(t_end: f64) -> f64 {
    let (theta, g, vc) = (30f64.to_radians(), 9.81, 0.5);
    let (ms, md) = (25f64.to_radians().tan(), 15f64.to_radians().tan());
    let accel = |v: f64| g * (theta.sin() - theta.cos() * (md + (ms - md) * (-v / vc).exp()));
    let n = 100_000;
    let h = t_end / n as f64;
    let (mut d, mut v) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let k1 = (v, accel(v));
        let k2 = (v + 0.5 * h * k1.1, accel(v + 0.5 * h * k1.1));
        let k3 = (v + 0.5 * h * k2.1, accel(v + 0.5 * h * k2.1));
        let k4 = (v + h * k3.1, accel(v + h * k3.1));
        d += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        v += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
    }
    d
}

/// Two-stage friction on a 30° incline (25° until 0.05 m of slip, then
/// 15°): the piecewise-parabolic distance at `t`.
pub fn two_stage_slide(t: f64) -> f64 {
    let deg = f64::to_radians;
    dda::validate::formulas::two_stage_slide(9.81, deg(30.0), deg(25.0), deg(15.0), 0.05, t)
}

/// Upward unit normal of a plane of given dip and dip direction (degrees;
/// x east, y north, z up).
pub fn plane_normal(dip: f64, direction: f64) -> nalgebra::Vector3<f64> {
    dda::validate::formulas::plane_normal(dip, direction)
}

/// The vector solution for the reference wedge on planes 50/130 and 50/230
/// (B5) with equal friction: its sliding direction ŝ, the share ŵ·ŝ of its
/// weight along ŝ and the planes' normal reactions (N1 + N2)/W, so that
/// a/g = ŵ·ŝ − (N1 + N2)/W · tan φ.
pub fn reference_wedge() -> (nalgebra::Vector3<f64>, f64, f64) {
    dda::validate::catalogue::reference_wedge()
}

/// Housner's rigid rocking block of half-width B and half-height H.
mod rocking {
    pub const B: f64 = 0.5;
    pub const H: f64 = 2.0;

    pub fn alpha() -> f64 {
        (B / H).atan()
    }

    /// Time for the rigid block to rock from θ0 at rest down to θ = 0.
    pub fn first_impact(theta0: f64) -> f64 {
        dda::validate::formulas::rocking_first_impact(B, H, 9.81, theta0)
    }

    /// Housner's amplitudes: cos(α − θ_{n+1}) = cos α + r² [cos(α − θ_n) − cos α].
    pub fn housner_amplitudes(theta0: f64, n: usize) -> Vec<f64> {
        let a = alpha();
        let r = 1.0 - 1.5 * a.sin().powi(2);
        let mut out = vec![theta0];
        for _ in 0..n {
            let last = *out.last().unwrap();
            let c = a.cos() + r * r * ((a - last).cos() - a.cos());
            out.push(a - c.acos());
        }
        out
    }
}

/// Housner's free rocking (reference B3) of examples/rocking_column_2d.ron:
/// the time to the first impact against the rigid-body answer (3 %), and
/// the first three amplitude ratios against Housner's recursion with
/// r = 1 − 1.5 sin² α (10 %). `rows` is the example's history.
pub fn assert_rocks_like_housner(rows: &[HistoryRow]) {
    let theta0 = rocking::alpha() / 2.0;
    let column: Vec<&HistoryRow> = rows.iter().filter(|r| r.block == 1).collect();
    // Tilt: released clockwise by θ0; counter-clockwise rotation rights it.
    let tilt = |r: &HistoryRow| theta0 - r.rotation;

    // The impact is where |ω| peaks: the block falls until its other corner lands.
    let first_landing = column
        .iter()
        .position(|r| tilt(r) <= 0.0)
        .expect("the block rocks back");
    let peak = column[..=first_landing + 5]
        .iter()
        .max_by(|a, b| a.omega.abs().total_cmp(&b.omega.abs()))
        .unwrap();
    let expected = rocking::first_impact(theta0);
    assert!(
        ((peak.time - expected) / expected).abs() < 0.03,
        "first impact at {:.4} s, rigid {expected:.4} s",
        peak.time
    );

    let rotations: Vec<f64> = column.iter().map(|r| r.rotation).collect();
    for (n, error) in housner_ratio_errors(&rotations).iter().enumerate() {
        assert!(
            error.abs() < 0.1,
            "ratio {}: {:+.2} % off Housner's",
            n + 1,
            100.0 * error
        );
    }
}

/// The first three amplitude ratios of the rocking column, from its
/// counter-clockwise rotation at each output time (2D `rotation`; in the
/// extruded prism, whose 2D z axis is 3D −y, −`rotation[1]`), each as its
/// relative error against Housner's recursion.
pub fn housner_ratio_errors(rotations: &[f64]) -> Vec<f64> {
    let theta0 = rocking::alpha() / 2.0;
    // Tilt: released clockwise by θ0; counter-clockwise rotation rights it.
    let tilt: Vec<f64> = rotations.iter().map(|r| theta0 - r).collect();
    let first_landing = tilt
        .iter()
        .position(|&t| t <= 0.0)
        .expect("the block rocks back");
    // Amplitudes: the largest |tilt| between successive zero crossings.
    let mut amplitudes = vec![theta0];
    let mut current = 0.0f64;
    for w in tilt.windows(2).skip(first_landing) {
        let (a, b) = (w[0], w[1]);
        current = current.max(b.abs());
        if a * b < 0.0 && current > 0.0 {
            amplitudes.push(current);
            current = 0.0;
        }
    }
    let housner = rocking::housner_amplitudes(theta0, 3);
    assert!(
        amplitudes.len() >= 4,
        "three rebounds within the run: {amplitudes:?}"
    );
    (0..3)
        .map(|n| {
            let ratio = amplitudes[n + 1] / amplitudes[n];
            ratio / (housner[n + 1] / housner[n]) - 1.0
        })
        .collect()
}

/// The thrown box of `free_fall_3d.ron` follows x0 + v0 t + g t²/2 and
/// v0 + g t to 1e-9 at every output time, to its end at 1 s.
pub fn assert_thrown_box_follows_the_parabola(rows: &[dda::HistoryRow3]) {
    let (x0, v0, g) = ([3.0, -2.0, 10.0], [1.0, 2.0, 3.0], [0.0, 0.0, -9.81]);
    let norm = |v: [f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    for row in rows {
        let t = row.time;
        let x: [f64; 3] = [0, 1, 2].map(|k| x0[k] + v0[k] * t + g[k] * t * t / 2.0);
        let v: [f64; 3] = [0, 1, 2].map(|k| v0[k] + g[k] * t);
        let dx = norm([0, 1, 2].map(|k| row.position[k] - x[k]));
        let dv = norm([0, 1, 2].map(|k| row.velocity[k] - v[k]));
        assert!(dx < 1e-9 * norm(x), "t = {t}: {:?} vs {x:?}", row.position);
        assert!(dv < 1e-9 * norm(v), "t = {t}: {:?} vs {v:?}", row.velocity);
    }
    assert_eq!(rows.last().expect("rows").time, 1.0);
}

/// Sparse Cholesky posing as a large factor, writing down what it is
/// asked: `F` a factorisation, `S` an exact solve, `C` a correction (on
/// the single-precision copy where the solver keeps one), `U` an update
/// of the factor by rank-one terms, `|` a new step.
pub struct LargeLogged {
    pub solver: SparseCholesky,
    pub log: Arc<Mutex<String>>,
}

impl LinearSolver for LargeLogged {
    fn analyse(&mut self, pattern: &CscPattern) -> Result<(), DdaError> {
        self.solver.analyse(pattern)
    }
    fn factorize(&mut self, values: &[f64]) -> Result<(), DdaError> {
        self.log.lock().unwrap().push('F');
        self.solver.factorize(values)
    }
    fn solve(&self, rhs: &mut [f64]) {
        self.log.lock().unwrap().push('S');
        self.solver.solve(rhs);
    }
    fn solve_correction(&self, rhs: &mut [f64]) {
        self.log.lock().unwrap().push('C');
        self.solver.solve_correction(rhs);
    }
    fn update(&self, terms: &[UpdateTerm]) -> Option<FactorUpdate> {
        self.log.lock().unwrap().push('U');
        self.solver.update(terms)
    }
    fn solve_updated(&self, update: &FactorUpdate, rhs: &mut [f64], exact: bool) {
        self.log.lock().unwrap().push(if exact { 'S' } else { 'C' });
        self.solver.solve_updated(update, rhs, exact);
    }
    fn corrections_inexact(&self) -> bool {
        self.solver.corrections_inexact()
    }
    fn start_step(&mut self) {
        self.log.lock().unwrap().push('|');
    }
    fn factor_entries(&self) -> usize {
        usize::MAX
    }
}

/// A solver posing as a factor of `entries` entries (which decides the
/// driver's large-factor rules), otherwise `solver` itself.
pub struct Posing<S> {
    pub solver: S,
    pub entries: usize,
}

impl<S: LinearSolver> LinearSolver for Posing<S> {
    fn analyse(&mut self, pattern: &CscPattern) -> Result<(), DdaError> {
        self.solver.analyse(pattern)
    }
    fn factorize(&mut self, values: &[f64]) -> Result<(), DdaError> {
        self.solver.factorize(values)
    }
    fn solve(&self, rhs: &mut [f64]) {
        self.solver.solve(rhs);
    }
    fn solve_correction(&self, rhs: &mut [f64]) {
        self.solver.solve_correction(rhs);
    }
    fn update(&self, terms: &[UpdateTerm]) -> Option<FactorUpdate> {
        self.solver.update(terms)
    }
    fn solve_updated(&self, update: &FactorUpdate, rhs: &mut [f64], exact: bool) {
        self.solver.solve_updated(update, rhs, exact);
    }
    fn corrections_inexact(&self) -> bool {
        self.solver.corrections_inexact()
    }
    fn start_step(&mut self) {
        self.solver.start_step();
    }
    fn factor_entries(&self) -> usize {
        self.entries
    }
}

/// A run took its `steps` steps, none cut, none accepted unconverged, no
/// Newton-Raphson iteration left at its best iterate.
pub fn ran_clean(s: &dda_core::Statistics, steps: usize) {
    assert_eq!(s.steps, steps);
    assert_eq!(s.open_close_cuts, 0);
    assert_eq!(s.unconverged_steps, 0);
    assert_eq!(s.newton_failures, 0);
}

/// The largest distance between two runs' centroids (x, y, z), m.
pub fn apart(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    (a.iter().zip(b))
        .map(|(a, b)| (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt())
        .fold(0.0, f64::max)
}

/// A 2D run's moves, factorisations, one more count of its statistics,
/// and every block's centroid (x, y).
pub type Progress = (usize, usize, usize, Vec<[f64; 2]>);

/// Steps `driver` `n` times; its progress, with `count` read off its
/// statistics.
pub fn steps(
    driver: &mut dda_2d::Driver2d,
    n: usize,
    count: fn(&dda_core::Statistics) -> usize,
) -> Progress {
    for _ in 0..n {
        driver.step(1.0).unwrap();
    }
    let s = driver.statistics();
    let centroids = (driver.system.blocks.iter()).map(|b| [b.centroid().x, b.centroid().y]);
    (
        s.newton_iterations,
        s.factorizations,
        count(s),
        centroids.collect(),
    )
}

/// A driver made by `fresh`, run `before` steps, saved and run `after`
/// more; and one made afresh, restored from the save and run `after`:
/// the progress at the save, after it, and resumed.
pub fn save_and_resume(
    fresh: impl Fn() -> dda_2d::Driver2d,
    before: usize,
    after: usize,
    count: fn(&dda_core::Statistics) -> usize,
) -> [Progress; 3] {
    let mut going = fresh();
    let saved_at = steps(&mut going, before, count);
    let saved = going.save().unwrap();
    let went = steps(&mut going, after, count);
    let mut resumed = fresh();
    resumed.restore(&saved).unwrap();
    let came = steps(&mut resumed, after, count);
    [saved_at, went, came]
}
