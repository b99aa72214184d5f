//! Three-dimensional DDA with polyhedral blocks (12 DOF: translation,
//! rotation, uniform strain).
//!
//! Not implemented yet: this crate holds the place of the 3D dimension in the
//! workspace. The core driver, contact laws and scene format are already
//! dimension-agnostic and will run it unchanged.
