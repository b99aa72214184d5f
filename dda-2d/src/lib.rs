//! Shi's two-dimensional DDA: polygonal blocks (convex or concave) with six
//! degrees of freedom (u0, v0, r0, εx, εy, γxy) about the centroid.
//!
//! [`Polygons`] implements the core's block system; run it with
//! [`Driver2d`].

pub mod block;
pub mod broad_phase;
pub mod contact;
pub mod cut;
pub mod kinematics;
pub mod material;
pub mod polygon;
pub mod system;

pub use block::Block;
pub use kinematics::RotationUpdate;
pub use material::{Plane, PlaneElastic};
pub use system::{FixedPoint, Force, PointLoad, Polygons};

/// The core driver running polygons: 6 DOF per block, one tangent per contact.
pub type Driver2d = dda_core::Driver<Polygons, 6, 1>;
