//! A scene changed field by field: every change goes through the scene's
//! own parser and checks, so a bad value gets the error a file with that
//! value would get.

use std::path::{Path, PathBuf};

use anyhow::Context;
use dda::run::{run_scene, RunOptions};
use dda::{Scene, Summary};
use dda_contact::LawRegistry;

use crate::tree::{to_tree, Given, Node, PathError};

/// A loaded scene and the folder its files are relative to.
#[derive(Debug, Clone)]
pub struct EditableScene {
    pub scene: Scene,
    /// The scene file's folder, for ground-motion records named relative
    /// to it; `None` for a scene made from text.
    dir: Option<PathBuf>,
    /// The file the scene is, while it has not been changed.
    file: Option<PathBuf>,
}

impl EditableScene {
    /// Reads and checks a scene file.
    pub fn load(path: &Path) -> anyhow::Result<Self> {
        let scene = Scene::load(path)?;
        let dir = path.parent().map(|d| {
            if d.as_os_str().is_empty() {
                PathBuf::from(".")
            } else {
                d.to_path_buf()
            }
        });
        Ok(EditableScene {
            scene,
            dir,
            file: Some(path.to_path_buf()),
        })
    }

    /// Parses and checks scene text; `origin` names it in errors.
    pub fn from_ron(text: &str, origin: &str) -> anyhow::Result<Self> {
        let scene = Scene::from_str(text, origin)?;
        Ok(EditableScene {
            scene,
            dir: None,
            file: None,
        })
    }

    /// The scene as a tree of RON values.
    pub fn tree(&self) -> Node {
        to_tree(&self.scene)
    }

    /// The value at a dotted path (`analysis.dt`, `blocks.1.angle`,
    /// `materials.rock.density`).
    pub fn get(&self, path: &str) -> Result<Node, PathError> {
        self.tree().get(path).cloned()
    }

    /// Sets the value at `path` and checks the whole scene again; on an
    /// error the scene is left as it was.
    pub fn set(&mut self, path: &str, value: &Given) -> anyhow::Result<()> {
        let mut tree = self.tree();
        tree.set(path, value)
            .with_context(|| format!("{}: cannot set `{path}`", self.scene.origin()))?;
        if let Some(dir) = &self.dir {
            tree.anchor_files(dir);
        }
        let text = tree.to_ron();
        // The lines of a located error are those of `to_ron()`; the origin
        // says which change it was.
        let origin = format!("{} (with {path} changed)", base_origin(self.scene.origin()));
        self.scene = Scene::from_str(&text, &origin)?;
        self.file = None;
        Ok(())
    }

    /// Runs the scene into `out` (quietly: no progress, no notes). A scene
    /// changed since it was read is first written to `out/scene.ron`, so
    /// the run's summary names a file that holds what ran.
    pub fn run(&self, out: &Path, registry: &LawRegistry) -> anyhow::Result<Summary> {
        let options = RunOptions::default();
        if let Some(file) = &self.file {
            return run_scene(&self.scene, out, options, registry)
                .with_context(|| format!("{}: the run failed", file.display()));
        }
        let mut tree = self.tree();
        let here = std::env::current_dir().unwrap_or_else(|_| PathBuf::from("."));
        tree.anchor_files(self.dir.as_deref().unwrap_or(&here));
        std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
        let file = out.join("scene.ron");
        std::fs::write(&file, tree.to_ron())
            .with_context(|| format!("cannot write {}", file.display()))?;
        let scene = Scene::load(&file)?;
        run_scene(&scene, out, options, registry)
            .with_context(|| format!("{}: the run failed", file.display()))
    }
}

/// The scene's first origin, without the notes of earlier changes.
fn base_origin(origin: &str) -> &str {
    origin.split(" (with ").next().unwrap_or(origin)
}
