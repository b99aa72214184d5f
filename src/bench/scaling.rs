//! How time per step grows with the blocks: the exponent p of
//! t ∝ N^p per series (kind and dimension), and `dda bench --chart`, a
//! log-log chart of time per step against blocks with the N^1 line.

use std::path::Path;

use serde::Serialize;

use crate::pictures::palette;
use crate::scene::BlockKind;
use crate::study::charts::{log_log, Line};

/// One measured wall: its series, blocks and milliseconds per step.
#[derive(Debug, Clone, Copy)]
pub struct Point {
    pub dimension: u32,
    pub kind: BlockKind,
    pub blocks: usize,
    pub ms_per_step: f64,
}

/// The growth of one series' time per step with its blocks.
#[derive(Debug, Clone, Serialize)]
pub struct Fit {
    pub dimension: u32,
    pub kind: BlockKind,
    /// The two largest walls' blocks, between which `exponent` is taken.
    pub from_blocks: usize,
    pub to_blocks: usize,
    /// log(t₂/t₁) / log(N₂/N₁) between the two largest walls.
    pub exponent: f64,
    /// The least-squares slope of log t against log N over all the
    /// series' walls (equal to `exponent` with two walls).
    pub least_squares: f64,
}

/// The series of `points` in first-seen order: (dimension, kind, points
/// sorted by blocks).
fn series(points: &[Point]) -> Vec<(u32, BlockKind, Vec<Point>)> {
    let mut out: Vec<(u32, BlockKind, Vec<Point>)> = Vec::new();
    for p in points
        .iter()
        .filter(|p| p.ms_per_step > 0.0 && p.blocks > 0)
    {
        match out
            .iter_mut()
            .find(|(d, k, _)| *d == p.dimension && *k == p.kind)
        {
            Some((_, _, v)) => v.push(*p),
            None => out.push((p.dimension, p.kind, vec![*p])),
        }
    }
    for (_, _, v) in &mut out {
        v.sort_by_key(|p| p.blocks);
        v.dedup_by_key(|p| p.blocks);
    }
    out
}

/// The exponent of each series of at least two distinct wall sizes.
pub fn fits(points: &[Point]) -> Vec<Fit> {
    series(points)
        .into_iter()
        .filter(|(_, _, v)| v.len() >= 2)
        .map(|(dimension, kind, v)| {
            let (a, b) = (v[v.len() - 2], v[v.len() - 1]);
            let exponent = exponent((a.blocks, a.ms_per_step), (b.blocks, b.ms_per_step));
            Fit {
                dimension,
                kind,
                from_blocks: a.blocks,
                to_blocks: b.blocks,
                exponent,
                least_squares: slope(&v),
            }
        })
        .collect()
}

/// The exponent p of t ∝ N^p between two walls' (blocks, ms a step).
pub(crate) fn exponent(a: (usize, f64), b: (usize, f64)) -> f64 {
    (b.1 / a.1).ln() / (b.0 as f64 / a.0 as f64).ln()
}

/// The least-squares slope of ln t against ln N.
fn slope(v: &[Point]) -> f64 {
    let xy: Vec<(f64, f64)> = v
        .iter()
        .map(|p| ((p.blocks as f64).ln(), p.ms_per_step.ln()))
        .collect();
    let n = xy.len() as f64;
    let (mx, my) = (
        xy.iter().map(|p| p.0).sum::<f64>() / n,
        xy.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxy: f64 = xy.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = xy.iter().map(|p| (p.0 - mx).powi(2)).sum();
    sxy / sxx
}

pub(crate) fn kind_name(kind: BlockKind) -> &'static str {
    match kind {
        BlockKind::Rigid => "rigid",
        BlockKind::Deformable => "deformable",
    }
}

/// A series' name: "deformable 2D".
pub fn series_name(dimension: u32, kind: BlockKind) -> String {
    format!("{} {dimension}D", kind_name(kind))
}

/// `dda bench --chart`: milliseconds per step against blocks, log-log, a
/// line per series with its exponent between the two largest walls in the
/// legend, and a dashed N^1 line through each series' smallest wall, into
/// `path` (`.png` or `.svg`).
pub fn chart(points: &[Point], title: &str, path: &Path) -> anyhow::Result<()> {
    let fits = fits(points);
    let mut lines = Vec::new();
    for (i, (dimension, kind, v)) in series(points).into_iter().enumerate() {
        let colour = palette(i);
        let fit = fits
            .iter()
            .find(|f| f.dimension == dimension && f.kind == kind);
        let name = match fit {
            Some(f) => format!(
                "{}: N^{:.2} from {} to {} blocks",
                series_name(dimension, kind),
                f.exponent,
                f.from_blocks,
                f.to_blocks
            ),
            None => series_name(dimension, kind),
        };
        let (first, last) = (v[0], v[v.len() - 1]);
        lines.push(Line {
            name,
            points: v.iter().map(|p| (p.blocks as f64, p.ms_per_step)).collect(),
            colour,
            dashed: false,
        });
        if v.len() >= 2 {
            let ratio = last.blocks as f64 / first.blocks as f64;
            lines.push(Line {
                name: format!(
                    "N^1 through {}'s smallest wall",
                    series_name(dimension, kind)
                ),
                points: vec![
                    (first.blocks as f64, first.ms_per_step),
                    (last.blocks as f64, first.ms_per_step * ratio),
                ],
                colour,
                dashed: true,
            });
        }
    }
    anyhow::ensure!(!lines.is_empty(), "nothing to chart: no wall was timed");
    log_log(title, "blocks", "time per step, ms", lines, path)
}
