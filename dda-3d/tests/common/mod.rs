//! Shared builders for the 3D verification tests.
#![allow(dead_code)]

use dda_3d::polyhedron::cuboid;
use dda_3d::{Block, Driver3d, IsotropicElastic, Polyhedra};
use dda_contact::Coulomb;
use dda_core::{ConstitutiveLaw, Settings};
use nalgebra::{Point3, Rotation3, Vector3};

pub const G: f64 = 9.81;
pub const ROCK: f64 = 2700.0;

/// Rock-like elasticity: E = 10 GPa, ν = 0.25.
pub fn rock() -> Vec<Box<dyn ConstitutiveLaw<6>>> {
    vec![Box::new(IsotropicElastic {
        young: 1e10,
        poisson: 0.25,
    })]
}

pub fn boxed(center: Point3<f64>, size: Vector3<f64>, rotation: Rotation3<f64>) -> Block {
    let (v, f) = cuboid(center, size, rotation);
    Block::new(&v, &f, 0, ROCK).expect("a valid box")
}

/// A driver with one Coulomb joint law of friction angle `phi` (degrees).
pub fn driver(system: Polyhedra, phi: f64, settings: Settings) -> Driver3d {
    Driver3d::new(system, vec![Box::new(Coulomb::frictional(phi))], settings)
        .expect("valid settings")
}

/// Angle in degrees between two vectors.
pub fn angle(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    a.normalize()
        .dot(&b.normalize())
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}
