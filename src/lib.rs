//! DDA scenes, runs and outputs: the library behind the `dda` command.
//!
//! ```no_run
//! let scene = dda::Scene::load("examples/sliding_block_2d.ron")?;
//! let mut model = scene.build()?;
//! model.driver.advance_to(model.duration)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! 3D scenes (`dimension: 3`: polyhedra, z up) build into a [`Model3`] whose
//! driver runs `dda_3d` polyhedra; [`Scene::build_any`] takes either
//! dimension, and [`run()`] runs either, writing the outputs of its
//! dimension. [`extrude::extrude`] turns a 2D scene into its 3D prism model.
//!
//! ```no_run
//! let scene = dda::Scene::load("examples/wedge_3d.ron")?;
//! let mut model = scene.build_3d()?;
//! model.driver.advance_to(model.duration)?;
//! let wedge = &model.driver.system.blocks[1];
//! println!("the wedge is at {}", wedge.centroid());
//!
//! let flat = dda::Scene::load("examples/sliding_block_2d.ron")?;
//! let solid = dda::extrude::extrude(&flat, 1.0)?;
//! std::fs::write("sliding_block_extruded_3d.ron", solid.to_ron())?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Scenes name contact laws of other crates as `Custom(name: ..., params:
//! {...})`; build them with a registry that knows the name (see
//! `examples/custom_law.rs`):
//!
//! ```no_run
//! use dda_contact::{Coulomb, LawRegistry, Params};
//!
//! let mut registry = LawRegistry::with_builtin();
//! registry.register("sticky", |p: &mut Params| {
//!     Ok(Coulomb { cohesion: 1e5, ..Coulomb::frictional(p.take("friction_angle")?) })
//! });
//! let scene = dda::Scene::load("my_scene.ron")?;
//! let model = scene.build_with(&registry)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod bench;
pub mod checkpoint;
pub mod cli;
pub mod extrude;
pub mod features;
mod generators;
pub mod guard;
pub mod import;
pub mod observe;
pub mod output;
pub mod pictures;
pub mod progress;
pub mod run;
pub mod scene;
pub mod simulation;
pub mod step_log;
pub mod study;
pub mod summary;
pub mod validate;
pub mod values;
pub mod vtk;

pub use observe::{BlockShape, Cursor, Observer, PointLine, RunView};
pub use output::{
    read_contacts, read_history, read_history_3d, read_points, ContactRow, HistoryRow, HistoryRow3,
    PointRow,
};
pub use run::{run, run_with_registry, Summary};
pub use scene::{AnyModel, Coords, Model, Model3, Scene, SceneBlock, SceneBlock3, SceneError};
pub use simulation::Simulation;
