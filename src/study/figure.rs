//! The figure a study judges, read from a run's outputs (`history.csv`,
//! `contacts.csv`) and the measures taken while it ran.

use serde::{Deserialize, Serialize};

use crate::pictures::{distance, norm, RunData};

/// A quantity read from one run. Times are in s; a missing `time` is the
/// end of the run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum Figure {
    /// How far the block's centroid is from its start, m.
    Displacement {
        block: usize,
        #[serde(default)]
        time: Option<f64>,
    },
    /// The block's speed, m/s.
    Velocity {
        block: usize,
        #[serde(default)]
        time: Option<f64>,
    },
    /// The angle the block has turned, rad (2D: |θ|; 3D: |rotation vector|).
    Rotation {
        block: usize,
        #[serde(default)]
        time: Option<f64>,
    },
    /// The largest angle the block turned at any output time, rad.
    PeakTilt { block: usize },
    /// A rocking block's first impact: the time of the first peak of |ω|, s.
    FirstImpact { block: usize },
    /// A rocking block's apparent restitution: |ω| at the second impact
    /// over |ω| at the first (Housner's r for a rigid block).
    Restitution { block: usize },
    /// The largest distance any block's centroid moved from its start at
    /// any output time, m.
    Drift,
    /// The sum of the normal forces between two blocks (N/m in 2D, N in 3D);
    /// the run writes contacts.csv for it.
    ContactForce {
        blocks: (usize, usize),
        #[serde(default)]
        time: Option<f64>,
    },
    /// (E_end − E_start) / |E_start| of the total energy, where the run
    /// keeps it (nothing does work on the blocks).
    EnergyDrift,
    /// (A_end − A_start) / A_start of the block's area (volume in 3D).
    AreaDrift { block: usize },
}

/// What the run measured itself, beyond its files.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Measures {
    /// Each block's area (2D) or volume (3D) at the start and the end.
    pub size_start: Vec<f64>,
    pub size_end: Vec<f64>,
    /// Total energy at the first step it was known, and at the end, J.
    pub energy_start: Option<f64>,
    pub energy_end: Option<f64>,
}

impl Figure {
    /// Whether it needs `contacts.csv`.
    pub fn needs_contacts(&self) -> bool {
        matches!(self, Figure::ContactForce { .. })
    }

    /// Its time, for the reference's `t`.
    pub fn time(&self) -> Option<f64> {
        match self {
            Figure::Displacement { time, .. }
            | Figure::Velocity { time, .. }
            | Figure::Rotation { time, .. }
            | Figure::ContactForce { time, .. } => *time,
            _ => None,
        }
    }

    /// A short name with its unit, for chart axes.
    pub fn label(&self) -> String {
        match self {
            Figure::Displacement { block, .. } => format!("displacement of block {block} (m)"),
            Figure::Velocity { block, .. } => format!("speed of block {block} (m/s)"),
            Figure::Rotation { block, .. } => format!("rotation of block {block} (rad)"),
            Figure::PeakTilt { block } => format!("peak tilt of block {block} (rad)"),
            Figure::FirstImpact { block } => format!("first impact of block {block} (s)"),
            Figure::Restitution { block } => format!("restitution of block {block}"),
            Figure::Drift => "largest drift (m)".into(),
            Figure::ContactForce { blocks, .. } => {
                format!("normal force, blocks {} and {}", blocks.0, blocks.1)
            }
            Figure::EnergyDrift => "relative energy drift".into(),
            Figure::AreaDrift { block } => format!("relative size drift of block {block}"),
        }
    }

    /// The figure's value in a finished (or failed) run.
    pub fn read(&self, run: &RunData, m: &Measures) -> Result<f64, String> {
        let check = |b: usize| -> Result<(), String> {
            if b < run.block_count() {
                Ok(())
            } else {
                Err(format!(
                    "the figure names block {b}, but the run has {} blocks (0 to {})",
                    run.block_count(),
                    run.block_count() - 1
                ))
            }
        };
        let at = |time: Option<f64>, f: &dyn Fn(usize) -> f64| -> Result<f64, String> {
            interpolate(&run.times, time, f)
        };
        let angle = |k: usize, b: usize| {
            let r = run.blocks[k][b].rotation;
            if run.dimension == 2 {
                r[2].abs()
            } else {
                norm(r)
            }
        };
        match self {
            Figure::Displacement { block, time } => {
                check(*block)?;
                at(*time, &|k| run.displacement(k, *block))
            }
            Figure::Velocity { block, time } => {
                check(*block)?;
                at(*time, &|k| norm(run.blocks[k][*block].velocity))
            }
            Figure::Rotation { block, time } => {
                check(*block)?;
                at(*time, &|k| angle(k, *block))
            }
            Figure::PeakTilt { block } => {
                check(*block)?;
                Ok((0..run.times.len())
                    .map(|k| angle(k, *block))
                    .fold(0.0, f64::max))
            }
            Figure::FirstImpact { block } | Figure::Restitution { block } => {
                check(*block)?;
                let spin = spin_series(run, *block);
                match (impacts(&run.times, &spin).as_slice(), self) {
                    ([], _) => Err("the block never turned and slowed again (no impact)".into()),
                    ([first, ..], Figure::FirstImpact { .. }) => Ok(first.0),
                    ([first, second, ..], _) => Ok(second.1 / first.1),
                    ([first], _) => Err(format!(
                        "one impact only (at {} s): run longer for the second",
                        first.0
                    )),
                }
            }
            Figure::Drift => Ok((0..run.times.len())
                .flat_map(|k| (0..run.block_count()).map(move |b| (k, b)))
                .map(|(k, b)| distance(run.blocks[k][b].position, run.blocks[0][b].position))
                .fold(0.0, f64::max)),
            Figure::ContactForce { blocks, time } => {
                let Some(contacts) = &run.contacts else {
                    return Err("the run wrote no contacts.csv".into());
                };
                let (a, b) = *blocks;
                at(*time, &|k| {
                    contacts[k]
                        .iter()
                        .filter(|c| {
                            (c.block_a == a && c.block_b == b) || (c.block_a == b && c.block_b == a)
                        })
                        .map(|c| c.normal_force)
                        .sum()
                })
            }
            Figure::EnergyDrift => match (m.energy_start, m.energy_end) {
                (Some(a), Some(b)) if a != 0.0 => Ok((b - a) / a.abs()),
                _ => Err("the run kept no total energy (something did work on the blocks)".into()),
            },
            Figure::AreaDrift { block } => {
                check(*block)?;
                let (a, b) = (m.size_start[*block], m.size_end[*block]);
                Ok((b - a) / a)
            }
        }
    }
}

/// f at `time` (linear between output times); the last time when `None`.
fn interpolate(times: &[f64], time: Option<f64>, f: &dyn Fn(usize) -> f64) -> Result<f64, String> {
    let last = times.len() - 1;
    let Some(t) = time else {
        return Ok(f(last));
    };
    let tol = 1e-9 * t.abs().max(1e-9);
    if t > times[last] + tol {
        return Err(format!("the run ended at {} s, before {t} s", times[last]));
    }
    let k = times.partition_point(|&s| s < t - tol);
    if k == 0 || (times[k] - t).abs() <= tol {
        return Ok(f(k.min(last)));
    }
    let (t0, t1) = (times[k - 1], times[k]);
    let w = (t - t0) / (t1 - t0);
    Ok(f(k - 1) * (1.0 - w) + f(k) * w)
}

/// The block's spin along its main axis (ω in 2D, signed).
fn spin_series(run: &RunData, block: usize) -> Vec<f64> {
    // Spin is not in RunData's block state; differentiate the rotation.
    let rot: Vec<[f64; 3]> = (0..run.times.len())
        .map(|k| run.blocks[k][block].rotation)
        .collect();
    let axis = rot
        .iter()
        .copied()
        .max_by(|a, b| norm(*a).total_cmp(&norm(*b)))
        .filter(|a| norm(*a) > 0.0)
        .map(|a| {
            let n = norm(a);
            [a[0] / n, a[1] / n, a[2] / n]
        })
        .unwrap_or([0.0, 0.0, 1.0]);
    let angle: Vec<f64> = rot
        .iter()
        .map(|r| r[0] * axis[0] + r[1] * axis[1] + r[2] * axis[2])
        .collect();
    let t = &run.times;
    (0..t.len())
        .map(|k| {
            if k == 0 {
                0.0
            } else {
                (angle[k] - angle[k - 1]) / (t[k] - t[k - 1])
            }
        })
        .collect()
}

/// The impacts of a rocking block: the peaks of |ω| (it speeds up until a
/// corner lands, then slows as it climbs), each confirmed once |ω| has
/// fallen below half of it, the next sought once it has nearly stopped
/// and speeds up again. The
/// first two, as (time, |ω|); with energy kept between impacts, the second impact
/// carries exactly the speed the first left, so the ratio is the
/// restitution (Housner's r = 1 − 1.5 sin² α for a rigid block).
fn impacts(times: &[f64], spin: &[f64]) -> Vec<(f64, f64)> {
    let mut peaks: Vec<(f64, f64)> = Vec::new();
    let mut best = (0.0f64, 0.0f64);
    // After a peak, |ω| must nearly vanish (the top of the climb) and
    // grow again before the next peak is sought.
    let mut climbing = false;
    let mut low = f64::INFINITY;
    for (k, w) in spin.iter().enumerate() {
        let w = w.abs();
        if climbing {
            let p = peaks.last().map_or(0.0, |p| p.1);
            low = low.min(w);
            climbing = !(low < 0.1 * p && w > low + 0.05 * p);
            continue;
        }
        if w > best.1 {
            best = (times[k], w);
        } else if best.1 > 0.0 && w < 0.5 * best.1 {
            peaks.push(best);
            best = (0.0, 0.0);
            climbing = true;
            low = f64::INFINITY;
            if peaks.len() == 2 {
                break;
            }
        }
    }
    peaks
}

/// The area of a 2D block's outline or the volume of a 3D block.
pub fn size(shape: &crate::observe::BlockShape, dimension: u32) -> f64 {
    let v = &shape.vertices;
    if dimension == 2 {
        let n = v.len();
        0.5 * (0..n)
            .map(|i| {
                let (a, b) = (v[i], v[(i + 1) % n]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum::<f64>()
            .abs()
    } else {
        // Divergence theorem over fan triangles of each face.
        let mut vol = 0.0;
        for face in &shape.faces {
            let p0 = v[face[0]];
            for w in face[1..].windows(2) {
                let (p1, p2) = (v[w[0]], v[w[1]]);
                vol += p0[0] * (p1[1] * p2[2] - p1[2] * p2[1])
                    - p0[1] * (p1[0] * p2[2] - p1[2] * p2[0])
                    + p0[2] * (p1[0] * p2[1] - p1[1] * p2[0]);
            }
        }
        (vol / 6.0).abs()
    }
}
