//! Scenes from other DDA codes' input files: Doolin's DDAML (`.geo` and
//! `.ana`, XML), read with roxmltree, whose nodes carry their position in
//! the text, so every error names its line.

mod ddaml;

pub use ddaml::{import_ddaml, ImportError, Imported};
