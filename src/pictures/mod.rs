//! Pictures of a run without ParaView: `dda plot` (time-series charts,
//! [`plot`]) and `dda render` (an animation and a still, [`render`]), both
//! from the files a run wrote. This module reads those files into
//! [`RunData`] and holds the font and colours the two share.

pub mod plot;
pub mod render;

use std::path::{Path, PathBuf};
use std::sync::Once;

use anyhow::{bail, Context};

use crate::output::{read_contacts, read_history, read_history_3d, ContactRow};
use crate::output::{HISTORY_HEADER, HISTORY_HEADER_3D};
use crate::summary::Summary;

/// DejaVu Sans cut to Latin-1, Greek and a few signs (see
/// `assets/fonts/LICENSE.txt`): text without system fonts.
static FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans-subset.ttf");

/// The font family the pictures name.
pub const FAMILY: &str = "sans-serif";

/// Makes [`FAMILY`] the embedded font (once).
pub fn register_font() {
    static DONE: Once = Once::new();
    DONE.call_once(|| {
        // The font is shipped and parses; a failure would leave text blank.
        let _ = plotters::style::register_font(FAMILY, plotters::style::FontStyle::Normal, FONT);
    });
}

/// A block at an output time, in 3D terms (z = 0 and rotation about z in 2D).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlockState {
    /// Centroid, m.
    pub position: [f64; 3],
    /// Accumulated rotation vector, rad (2D: (0, 0, θ)).
    pub rotation: [f64; 3],
    /// Velocity of the centroid, m/s.
    pub velocity: [f64; 3],
    /// Von Mises equivalent stress, Pa (2D: of the plane components).
    pub stress: f64,
}

/// What a run wrote: `history.csv` by output time, `contacts.csv` if it
/// exists, `summary.json` if it exists.
pub struct RunData {
    pub dir: PathBuf,
    pub dimension: u32,
    /// Output times, s.
    pub times: Vec<f64>,
    /// `blocks[k][i]`: block i at output time k.
    pub blocks: Vec<Vec<BlockState>>,
    /// Contacts at each output time (empty without `contacts.csv`).
    pub contacts: Option<Vec<Vec<ContactRow>>>,
    pub summary: Option<Summary>,
}

impl RunData {
    /// Reads the run in `dir`, with errors that name the missing file and
    /// what makes it.
    pub fn load(dir: &Path) -> anyhow::Result<Self> {
        if !dir.is_dir() {
            bail!(
                "{} is not a folder: give the folder a run wrote (`dda run SCENE --out {}`)",
                dir.display(),
                dir.display()
            );
        }
        let history = dir.join("history.csv");
        if !history.is_file() {
            bail!(
                "{} not found: {} is not the folder of a run (`dda run SCENE --out {}` writes it)",
                history.display(),
                dir.display(),
                dir.display()
            );
        }
        let first = std::fs::read_to_string(&history)
            .with_context(|| format!("cannot read {}", history.display()))?;
        let header = first.lines().next().unwrap_or("").trim().to_string();
        let mut rows: Vec<(f64, usize, BlockState)> = Vec::new();
        let dimension = if header == HISTORY_HEADER {
            for r in read_history(&history)? {
                let stress = (r.sxx * r.sxx - r.sxx * r.syy + r.syy * r.syy + 3.0 * r.sxy * r.sxy)
                    .max(0.0)
                    .sqrt();
                let state = BlockState {
                    position: [r.x, r.y, 0.0],
                    rotation: [0.0, 0.0, r.rotation],
                    velocity: [r.vx, r.vy, 0.0],
                    stress,
                };
                rows.push((r.time, r.block, state));
            }
            2
        } else if header == HISTORY_HEADER_3D {
            for r in read_history_3d(&history)? {
                let [sx, sy, sz, syz, szx, sxy] = r.stress;
                let stress = (0.5 * ((sx - sy).powi(2) + (sy - sz).powi(2) + (sz - sx).powi(2))
                    + 3.0 * (syz * syz + szx * szx + sxy * sxy))
                    .max(0.0)
                    .sqrt();
                let state = BlockState {
                    position: r.position,
                    rotation: r.rotation,
                    velocity: r.velocity,
                    stress,
                };
                rows.push((r.time, r.block, state));
            }
            3
        } else {
            bail!(
                "{}: the first line is not a history header (2D: {HISTORY_HEADER:?}, 3D: {HISTORY_HEADER_3D:?})",
                history.display()
            );
        };
        let (times, blocks) = by_time(rows);
        if times.is_empty() {
            bail!(
                "{} has no rows: the run wrote nothing to draw",
                history.display()
            );
        }
        let contacts_path = dir.join("contacts.csv");
        let contacts = if contacts_path.is_file() {
            let mut at: Vec<Vec<ContactRow>> = vec![Vec::new(); times.len()];
            for c in read_contacts(&contacts_path)? {
                // Contact rows carry the same times as the history's.
                if let Some(k) = times.iter().position(|&t| t == c.time) {
                    at[k].push(c);
                }
            }
            Some(at)
        } else {
            None
        };
        let summary_path = dir.join("summary.json");
        let summary = match std::fs::read_to_string(&summary_path) {
            Ok(text) => Some(
                serde_json::from_str(&text)
                    .with_context(|| format!("{} is not a run summary", summary_path.display()))?,
            ),
            Err(_) => None,
        };
        Ok(Self {
            dir: dir.to_path_buf(),
            dimension,
            times,
            blocks,
            contacts,
            summary,
        })
    }

    pub fn block_count(&self) -> usize {
        self.blocks[0].len()
    }

    /// How far block i's centroid is from where it started, m.
    pub fn displacement(&self, k: usize, i: usize) -> f64 {
        distance(self.blocks[k][i].position, self.blocks[0][i].position)
    }
}

/// Rows grouped by time, blocks in order; a time with fewer blocks than the
/// first (a run cut mid-write) is left out.
fn by_time(rows: Vec<(f64, usize, BlockState)>) -> (Vec<f64>, Vec<Vec<BlockState>>) {
    let mut times: Vec<f64> = Vec::new();
    let mut blocks: Vec<Vec<BlockState>> = Vec::new();
    for (t, i, state) in rows {
        if times.last() != Some(&t) {
            times.push(t);
            blocks.push(Vec::new());
        }
        let at = blocks.last_mut().expect("pushed above");
        if at.len() == i {
            at.push(state);
        }
    }
    let n = blocks.first().map_or(0, Vec::len);
    while blocks.last().is_some_and(|b| b.len() < n) {
        blocks.pop();
        times.pop();
    }
    (times, blocks)
}

pub fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

pub fn norm(a: [f64; 3]) -> f64 {
    distance(a, [0.0; 3])
}

/// Viridis at `t` in [0, 1] (dark blue, green, yellow), by five stops.
pub fn viridis(t: f64) -> (u8, u8, u8) {
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * 4.0;
    let k = (x.floor() as usize).min(3);
    let f = x - k as f64;
    let (a, b) = (STOPS[k], STOPS[k + 1]);
    let mix = |p: f64, q: f64| (p + (q - p) * f).round() as u8;
    (mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Distinct colours for lines and blocks by index.
pub fn palette(i: usize) -> (u8, u8, u8) {
    const COLOURS: [(u8, u8, u8); 10] = [
        (31, 119, 180),
        (255, 127, 14),
        (44, 160, 44),
        (214, 39, 40),
        (148, 103, 189),
        (140, 86, 75),
        (227, 119, 194),
        (127, 127, 127),
        (188, 189, 34),
        (23, 190, 207),
    ];
    COLOURS[i % COLOURS.len()]
}

/// Creates `dir` (and its parents) with an error naming it.
pub fn create_dir(dir: &Path) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))
}
