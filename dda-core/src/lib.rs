//! Dimension-agnostic core of Discontinuous Deformation Analysis (DDA).
//!
//! The dimension crates implement [`Element`] (a block's geometry,
//! T-matrix, integrals, narrow phase and motion), and the shared
//! [`BlockSet`] over it is the [`BlockSystem`] (blocks with `N` DOF each,
//! contacts with `T` tangential directions); the [`Driver`] runs any of them
//! with Newmark (β = 1/2, γ = 1) steps and open-close iterations, calling
//! [`ContactLaw`]s in the contacts' local frames. [`planar`] holds the
//! polygon geometry a 2D block's outline and a 3D block's face share.

pub mod assembly;
pub mod block_set;
mod by_block;
pub mod constitutive;
pub mod contact;
pub mod contacts;
pub mod driver;
pub mod error;
pub mod loads;
pub mod motion;
pub mod overlap;
pub mod planar;
pub mod settings;
pub mod solve;
pub mod statistics;
pub mod system;

/// Blocks a parallel task over the blocks (their masses, terms, commits,
/// the matrix's column blocks) takes at least: fewer would cost more in
/// scheduling than they save.
const BLOCKS_PER_TASK: usize = 128;

/// Contacts a parallel task over the contacts (their loads, decisions,
/// commits, copies) takes at least, for the same reason.
const CONTACTS_PER_TASK: usize = 256;

/// Block pairs a narrow-phase task takes at least: fewer would cost more
/// in scheduling than they save.
const PAIRS_PER_TASK: usize = 64;

pub use block_set::{BlockSet, Element, RotationUpdate};
pub use constitutive::ConstitutiveLaw;
pub use contact::{ContactLaw, ContactResponse, ContactState, DynContactLaw, LocalKinematics};
pub use contacts::{BlockVector, Contact, ContactKey, ContactRecord, Entrance, EntranceRows};
pub use driver::settle::Settling;
pub use driver::Driver;
pub use error::DdaError;
pub use loads::{FixedPoint, Force, MeasuredPoint, PointLoad};
pub use motion::{GroundMotion, Quantity, Record};
pub use settings::{Integrator, Settings, Solver};
pub use statistics::{Cycle, PhaseTimes, Statistics};
pub use system::{BlockKind, BlockMatrix, BlockState, BlockSystem, SystemState};
