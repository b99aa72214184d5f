//! Checkpoints: `dda run --checkpoint-every T` saves the whole run (the
//! driver's state, where each output file stands, the next output time) to
//! `DIR/checkpoint.bin` at the first output time after every T simulated
//! seconds; `dda run --resume DIR` goes on from there, and writes on the
//! outputs byte for byte as an uninterrupted run would.
//!
//! The file is written beside and renamed over the last one, so a run
//! killed while writing it resumes from the one before. It names the crate
//! version and a digest of the scene; another version's checkpoint, or one
//! of a scene changed since, is refused. It ends with a digest of itself,
//! so a byte changed on disk is refused rather than resumed from.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
use serde::{Deserialize, Serialize};

use crate::observe::Cursor;
use crate::output::write_atomically;
use crate::summary::SettleReport;
use crate::Scene;

/// The checkpoint's file name in the run's folder.
pub const FILE: &str = "checkpoint.bin";

/// What a checkpoint file starts with.
const MAGIC: &[u8] = b"dda checkpoint\n";

/// A saved run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Checkpoint {
    /// The version of dda that wrote it.
    pub version: String,
    /// The scene file, as an absolute path where it is a file.
    pub scene: String,
    /// FNV-1a digest of the scene as parsed ([`Scene::to_ron`]), so an edit
    /// of its comments does not matter and one of its values does.
    pub digest: u64,
    /// The driver's state ([`dda_core::Driver::save`]).
    pub driver: Vec<u8>,
    /// Index of the next output time (k of k · interval).
    pub next_output: u64,
    /// Where each output stands.
    pub cursors: Vec<Cursor>,
    /// Simulated seconds between checkpoints, and the next checkpoint time.
    pub every: f64,
    pub next_checkpoint: f64,
    /// Wall-clock seconds the run took before this checkpoint.
    pub wall_time: f64,
    /// What the settling before the run did (`analysis.settle`), for the
    /// resumed run's summary: a resumed run does not settle again.
    pub settling: Option<SettleReport>,
}

/// FNV-1a, 64 bits: stable across builds and platforms, unlike std's hasher.
pub fn digest(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The digest a scene's checkpoints carry.
pub fn scene_digest(scene: &Scene) -> u64 {
    digest(scene.to_ron().as_bytes())
}

/// The scene's file as a checkpoint names it: absolute when it exists.
pub fn scene_path(scene: &Scene) -> String {
    std::fs::canonicalize(scene.origin())
        .map(|p| p.display().to_string())
        .unwrap_or_else(|_| scene.origin().to_string())
}

impl Checkpoint {
    /// Writes `dir/checkpoint.bin` whole or not at all: the magic line,
    /// the encoded checkpoint, then the encoding's digest (8 bytes, little
    /// endian).
    pub fn write(&self, dir: &Path) -> anyhow::Result<()> {
        let body = postcard::to_stdvec(self).context("cannot encode the checkpoint")?;
        let mut bytes = MAGIC.to_vec();
        bytes.extend(&body);
        bytes.extend(digest(&body).to_le_bytes());
        write_atomically(&dir.join(FILE), &bytes)
    }

    /// Reads `dir/checkpoint.bin`, refusing one of another version.
    pub fn read(dir: &Path) -> anyhow::Result<Self> {
        let path = dir.join(FILE);
        let bytes = std::fs::read(&path).with_context(|| {
            format!(
                "cannot read {}: a run writes it only with --checkpoint-every SECONDS",
                path.display()
            )
        })?;
        let Some(body) = bytes.strip_prefix(MAGIC) else {
            bail!("{} is not a dda checkpoint", path.display());
        };
        // The version comes first, so it reads even when the rest changed shape.
        let (version, _) = postcard::take_from_bytes::<String>(body)
            .map_err(|e| anyhow::anyhow!("{} is damaged ({e})", path.display()))?;
        let ours = env!("CARGO_PKG_VERSION");
        if version != ours {
            bail!(
                "{} was written by dda {version}, and this is dda {ours}: resume it with dda {version}, or run the scene again from the start",
                path.display()
            );
        }
        // A byte changed since it was written (the version, read above,
        // still names the release to resume with).
        let sum = body.len().checked_sub(8).map(|at| body.split_at(at));
        let Some((body, _)) = sum.filter(|(b, s)| digest(b).to_le_bytes() == **s) else {
            bail!(
                "{} is damaged or was written by another build of dda {ours} (its digest does not match its contents); run the scene again",
                path.display()
            );
        };
        // A build of the same version whose saved state changed shape
        // reads it no better than a damaged file.
        postcard::from_bytes(body).map_err(|e| {
            anyhow::anyhow!(
                "{} is damaged or was written by another build of dda {ours} ({e}); run the scene again",
                path.display()
            )
        })
    }

    /// The scene to resume: `scene` if given, else the one the checkpoint
    /// names; refused if it is not the scene the checkpoint was taken of.
    pub fn scene(&self, dir: &Path, scene: Option<&Path>) -> anyhow::Result<Scene> {
        let path = scene
            .map(Path::to_path_buf)
            .unwrap_or_else(|| PathBuf::from(&self.scene));
        let loaded = Scene::load(&path)?;
        if scene_digest(&loaded) != self.digest {
            bail!(
                "{} was taken of another scene than {} (or of this one before it changed): run the scene again from the start, into another folder",
                dir.join(FILE).display(),
                path.display()
            );
        }
        Ok(loaded)
    }

    /// Where the output named `name` stood.
    pub fn cursor(&self, name: &str) -> Option<&Cursor> {
        self.cursors.iter().find(|c| c.name() == name)
    }
}

/// When checkpoints are due.
#[derive(Debug, Clone, Copy)]
pub struct Schedule {
    /// Simulated seconds between checkpoints.
    pub every: f64,
    /// The next checkpoint time.
    pub next: f64,
}

impl Schedule {
    /// Whether a checkpoint is due at `time`, and if so the schedule moves
    /// on past it.
    pub fn due(&mut self, time: f64) -> bool {
        if time < self.next * (1.0 - 1e-12) {
            return false;
        }
        while self.next <= time * (1.0 + 1e-12) {
            self.next += self.every;
        }
        true
    }
}
