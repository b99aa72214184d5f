//! What a run shows its outputs: the driver hands each accepted step, each
//! output time and the end to [`Observer`]s (`history.csv`, `contacts.csv`,
//! `points.csv`, `summary.json`, the progress bar), which see the run through a
//! [`RunView`] and so never need the driver's type.

use dda_core::{ContactState, Statistics};
use serde::{Deserialize, Serialize};

/// One contact after a step, as `contacts.csv` writes it.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactLine {
    /// Like `1:v0/0:e2` (2D) or `1:v3/0:f1` (3D).
    pub label: String,
    pub blocks: [usize; 2],
    pub state: ContactState,
    pub normal_force: f64,
    pub shear_force: f64,
    /// Accumulated slip path.
    pub slip: f64,
    /// Where it acts: the entering vertex, or for crossing edges (3D) the
    /// midpoint of their nearest points; z = 0 in 2D.
    pub point: [f64; 3],
    /// Unit normal from block_b towards block_a, along which the normal
    /// force pushes block_a; zero if the contact has no entrance.
    pub normal: [f64; 3],
}

/// A measured point now, as `points.csv` writes it (z = 0 in 2D).
#[derive(Debug, Clone, PartialEq)]
pub struct PointLine {
    pub block: usize,
    /// Where it is, m.
    pub position: [f64; 3],
    /// How far it has moved since the start, m.
    pub displacement: [f64; 3],
}

/// Where an output stood at a checkpoint, so a resumed run writes on from
/// there.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Cursor {
    /// A CSV file's length in bytes.
    File { name: String, length: u64 },
    /// VTK frames: (time, frame number) of each, and the blocks' first
    /// centroids.
    Frames {
        frames: Vec<(f64, usize)>,
        start: Vec<[f64; 3]>,
    },
}

impl Cursor {
    /// The output's name: its file, or `vtk`.
    pub fn name(&self) -> &str {
        match self {
            Cursor::File { name, .. } => name,
            Cursor::Frames { .. } => "vtk",
        }
    }
}

/// A block's boundary now, as the VTK frames and pictures draw it.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockShape {
    /// Corners, z = 0 in 2D.
    pub vertices: Vec<[f64; 3]>,
    /// Faces as loops of vertex indices, outward normals by the right-hand
    /// rule; in 2D one loop, counter-clockwise.
    pub faces: Vec<Vec<usize>>,
    /// Index into the scene's materials.
    pub material: usize,
    pub rigid: bool,
}

/// A run after an accepted step, in either dimension.
pub trait RunView {
    fn time(&self) -> f64;
    /// The nominal time step.
    fn dt(&self) -> f64;
    /// The normal penalty now (after any raises).
    fn penalty(&self) -> f64;
    /// The model's automatic penalty, whatever the one in use.
    fn automatic_penalty(&self) -> f64;
    fn statistics(&self) -> &Statistics;
    /// Why automatic values were chosen.
    fn notes(&self) -> &[String];
    fn block_count(&self) -> usize;
    /// 2 or 3.
    fn dimension(&self) -> u32;
    /// Block `block`'s boundary now.
    fn block_shape(&self, block: usize) -> BlockShape;
    /// The values of a block's history row after `step,time,block`.
    fn history_values(&self, block: usize) -> Vec<f64>;
    /// Whether the block's position and velocity are finite numbers.
    fn is_finite(&self, block: usize) -> bool;
    /// The contacts the last step considered, open ones included.
    fn contact_lines(&self) -> Vec<ContactLine>;
    /// A contact's name, like `1:v0/0:e2`.
    fn contact_label(&self, key: &dda_core::ContactKey) -> String;
    /// A block's velocity (z = 0 in 2D), m/s.
    fn velocity(&self, block: usize) -> [f64; 3];
    /// The scene's measured points, in order.
    fn measured_points(&self) -> Vec<PointLine>;
}

/// Something a run tells about its progress: an output file, the progress
/// bar, later VTK frames or checkpoints.
pub trait Observer {
    /// After each accepted step.
    fn on_step(&mut self, _run: &dyn RunView) {}

    /// At time 0 and at each output time (each step without an interval).
    fn on_output(&mut self, _run: &dyn RunView) -> anyhow::Result<()> {
        Ok(())
    }

    /// Where this observer's output stands, for a checkpoint taken just
    /// after an output time.
    fn cursor(&self) -> Option<Cursor> {
        None
    }

    /// At the end; `error` says why a failed run stopped.
    fn on_finish(
        &mut self,
        _run: &dyn RunView,
        _error: Option<&anyhow::Error>,
    ) -> anyhow::Result<()> {
        Ok(())
    }
}
