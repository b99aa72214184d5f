//! A contact law written outside the library, and a `dda` command that
//! knows it.
//!
//! The law is a Barton–Bandis rock joint: rough joints are stronger under
//! low normal stress,
//!
//! `φ(σn) = φr + JRC·log10(JCS / σn)`, capped at `max_friction_angle`,
//!
//! with φr the residual (smooth-joint) friction angle, JRC the joint
//! roughness coefficient (0 smooth to 20 very rough), JCS the joint wall
//! compressive strength and σn the contact's normal stress (its normal force
//! over the boundary length it stands for). The penalty springs and Shi's
//! open-close rules are the library's (`StrengthLaw`); the law only supplies
//! the shear strength.
//!
//! `main` is the `dda` command with this law registered, so from the
//! repository root
//!
//! ```sh
//! cargo run --release --example custom_law -- run examples/custom_law.ron
//! ```
//!
//! runs `examples/custom_law.ron` (a block on a 30° incline whose joint is
//! `Custom(name: "barton_bandis", ...)`) and writes `out/custom_law/`.

use dda_contact::{mohr_coulomb, LawRegistry, Params, Strength, StrengthLaw};
use dda_core::LocalKinematics;

/// Barton–Bandis joint friction with penalty springs.
#[derive(Debug, Clone, PartialEq)]
pub struct BartonBandis {
    /// φr, degrees.
    pub residual_friction_angle: f64,
    /// Joint roughness coefficient.
    pub jrc: f64,
    /// Joint wall compressive strength, Pa.
    pub jcs: f64,
    /// Cap on φ at vanishing normal stress, degrees.
    pub max_friction_angle: f64,
}

impl BartonBandis {
    /// φ in degrees at normal stress `sigma` (Pa, compression positive).
    pub fn friction_angle(&self, sigma: f64) -> f64 {
        if sigma <= 0.0 {
            return self.max_friction_angle;
        }
        let phi = self.residual_friction_angle + self.jrc * (self.jcs / sigma).log10();
        phi.clamp(self.residual_friction_angle, self.max_friction_angle)
    }
}

impl StrengthLaw for BartonBandis {
    /// Nothing to remember between steps.
    type History = ();

    fn new_history(&self, _at_start: bool) {}

    fn strength(&self, normal: f64, kin: &LocalKinematics, _: &()) -> Strength {
        let phi = self.friction_angle(normal / kin.length);
        Strength {
            shear: mohr_coulomb(phi, 0.0, normal, kin),
            tension: 0.0,
        }
    }
}

dda_contact::strength_law!(BartonBandis);

/// Builds the law from a scene's `params`; a parameter left unused is
/// reported by the registry.
pub fn build_barton_bandis(p: &mut Params) -> Result<BartonBandis, String> {
    let law = BartonBandis {
        residual_friction_angle: p.take("residual_friction_angle")?,
        jrc: p.take("jrc")?,
        jcs: p.take("jcs")?,
        max_friction_angle: p.take_or("max_friction_angle", 70.0)?,
    };
    let (phi_r, phi_max) = (law.residual_friction_angle, law.max_friction_angle);
    if !(law.jcs > 0.0 && law.jrc >= 0.0 && 0.0 <= phi_r && phi_r <= phi_max && phi_max < 90.0) {
        return Err(
            "need jcs > 0, jrc >= 0, 0 <= residual_friction_angle <= max_friction_angle < 90"
                .into(),
        );
    }
    Ok(law)
}

/// The built-in laws plus `barton_bandis`.
pub fn registry() -> LawRegistry {
    let mut registry = LawRegistry::with_builtin();
    registry.register("barton_bandis", build_barton_bandis);
    registry
}

/// `dda run`, `dda check`, … with `barton_bandis` known.
fn main() -> std::process::ExitCode {
    dda::cli::main_with(registry())
}
