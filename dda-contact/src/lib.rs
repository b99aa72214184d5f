//! Contact laws for DDA.
//!
//! Every law works in the contact's local frame (see [`dda_core::contact`]),
//! so it serves 2D and 3D alike. The penalty springs, Shi's open-close rules
//! and the Mohr-Coulomb strength are shared ([`springs`]); a law supplies its
//! strength and its history ([`StrengthLaw`]). [`LawRegistry`] names laws for scene files,
//! including laws written in other crates.
#![doc = include_str!("../../docs/contact-laws.md")]

pub mod coulomb;
pub mod rate_friction;
pub mod registry;
pub mod slip_weakening;
pub mod springs;
pub mod strength;
pub mod threshold;
pub mod weakening;

pub use coulomb::{Coulomb, CoulombHistory};
pub use rate_friction::RateFriction;
pub use registry::{LawRegistry, Params};
pub use slip_weakening::{SlipHistory, SlipWeakening};
pub use springs::{mohr_coulomb, Springs, SHEAR_RATIO};
pub use strength::{Strength, StrengthLaw};
pub use threshold::{BondHistory, ThresholdBond};
pub use weakening::Weakening;

/// The core's contact types, for [`strength_law!`].
#[doc(hidden)]
pub use dda_core as core;
