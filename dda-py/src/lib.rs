//! Python bindings of `dda`: the `dda._native` extension module behind the
//! `dda` Python package (`python/dda`), built with maturin.
//!
//! The parts that need no Python are plain Rust and tested as such: the
//! scene as a tree of RON values changed by path ([`tree`], [`scene`]) and
//! result files as named columns ([`columns`]).

pub mod columns;
pub mod scene;
pub mod tree;

#[cfg(feature = "python")]
mod python;
