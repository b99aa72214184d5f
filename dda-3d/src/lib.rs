//! Three-dimensional DDA (Shi 2001): polyhedral blocks, convex or not, with
//! twelve degrees of freedom (u0, v0, w0, rx, ry, rz, εx, εy, εz, γyz, γzx,
//! γxy) about the centroid.
//!
//! [`Polyhedra`] implements the core's block system; run it with
//! [`Driver3d`]. Blocks are validated closed surfaces ([`polyhedron`]); the
//! end-of-step motion applies the strain first and then the exact rotation of
//! the step's rotation vector, so a spinning block keeps its volume. Contacts
//! are vertex-face and edge-edge entrances, grouped at corners and edges so
//! the driver can choose among them ([`contact`] explains the rules,
//! including how non-convex blocks are handled).

mod area;
pub mod block;
pub mod broad_phase;
pub mod contact;
pub mod cut;
pub mod entrance;
pub mod face;
pub mod features;
pub mod kinematics;
pub mod material;
pub mod polyhedron;
pub mod system;

pub use block::Block;
pub use contact::contact_label;
pub use kinematics::RotationUpdate;
pub use material::IsotropicElastic;
pub use polyhedron::{Polyhedron, PolyhedronError};
pub use system::{FixedPoint, Force, PointLoad, Polyhedra};

/// The core driver running polyhedra: 12 DOF per block, two tangents per contact.
pub type Driver3d = dda_core::Driver<Polyhedra, 12, 2>;

/// A property-test runner with a fixed seed: the same cases on every run.
#[cfg(test)]
pub(crate) fn seeded_runner(cases: u32) -> proptest::test_runner::TestRunner {
    use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
    TestRunner::new_with_rng(
        Config::with_cases(cases),
        TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    )
}
