//! DDA scenes, runs and outputs: the library behind the `dda` command.
//!
//! ```no_run
//! let scene = dda::Scene::load("examples/sliding_block_2d.ron")?;
//! let mut model = scene.build()?;
//! model.driver.advance_to(model.duration)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod output;
pub mod run;
pub mod scene;

pub use output::{read_history, HistoryRow};
pub use run::{run, Summary};
pub use scene::{Model, Scene, SceneError};
