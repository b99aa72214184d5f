//! Contact laws for DDA.
//!
//! Every law works in the contact's local frame (see [`dda_core::contact`]),
//! so it serves 2D and 3D alike.

pub mod coulomb;

pub use coulomb::{Coulomb, CoulombHistory};
