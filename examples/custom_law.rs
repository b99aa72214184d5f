//! A contact law written outside the library, registered by name and used
//! from a scene file.
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
//! open-close rules come from `dda_contact::Springs`; the law only supplies
//! the shear strength.
//!
//! Run it from the repository root:
//!
//! ```sh
//! cargo run --release --example custom_law
//! ```
//!
//! It runs `examples/custom_law.ron` (a block on a 30° incline whose joint
//! is `Custom(name: "barton_bandis", ...)`) and writes `out/custom_law/`.

use std::path::Path;

use dda::run::{run_with_registry, RunOptions};
use dda_contact::{mohr_coulomb, LawRegistry, Params, Springs};
use dda_core::{ContactLaw, ContactResponse, ContactState, LocalKinematics};

// ---- The law: everything a new law needs. ----

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
    /// Penalties; `None` takes the driver's (shear: normal / 2.5).
    pub normal_stiffness: Option<f64>,
    pub shear_stiffness: Option<f64>,
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

    /// The springs and the shear strength at the trial gap.
    fn springs_and_strength(&self, kin: &LocalKinematics) -> (Springs, f64) {
        let springs = Springs::new(self.normal_stiffness, self.shear_stiffness, kin);
        let normal = springs.normal_force(kin);
        let phi = self.friction_angle(normal / kin.length);
        (springs, mohr_coulomb(phi, 0.0, normal, kin))
    }
}

impl ContactLaw for BartonBandis {
    /// Nothing to remember between steps.
    type History = ();

    fn initial_history(&self, _at_start: bool) {}

    fn response(&self, state: ContactState, kin: &LocalKinematics, _: &()) -> ContactResponse {
        let (springs, strength) = self.springs_and_strength(kin);
        springs.response(state, kin, strength)
    }

    fn next_state(&self, state: ContactState, kin: &LocalKinematics, _: &()) -> ContactState {
        let (springs, strength) = self.springs_and_strength(kin);
        springs.next_state(state, kin, strength, 0.0)
    }

    fn commit(&self, _: ContactState, _: &LocalKinematics, _: &mut ()) {}
}

/// Builds the law from a scene's `params`; a parameter left unused is
/// reported by the registry.
pub fn build_barton_bandis(p: &mut Params) -> Result<BartonBandis, String> {
    let law = BartonBandis {
        residual_friction_angle: p.take("residual_friction_angle")?,
        jrc: p.take("jrc")?,
        jcs: p.take("jcs")?,
        max_friction_angle: p.take_or("max_friction_angle", 70.0)?,
        normal_stiffness: p.take_opt("normal_stiffness"),
        shear_stiffness: p.take_opt("shear_stiffness"),
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

// ---- Using it. ----

fn main() -> anyhow::Result<()> {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/custom_law.ron");
    let out = Path::new("out/custom_law");
    let summary = run_with_registry(&scene, out, RunOptions::default(), &registry())?;
    let files: Vec<String> = summary
        .outputs
        .iter()
        .map(|f| out.join(f).display().to_string())
        .collect();
    println!("wrote {}", files.join(", "));

    let history = dda::read_history(out.join("history.csv"))?;
    let block: Vec<_> = history.iter().filter(|r| r.block == 1).collect();
    let (first, last) = (block[0], block[block.len() - 1]);
    let travel = (last.x - first.x).hypot(last.y - first.y);
    println!(
        "the block slid {travel:.4} m down the incline in {} s",
        last.time
    );

    // The friction the joint mobilised at the end, atan(Σ shear / Σ normal),
    // and the travel a constant friction angle of that size gives.
    let contacts = dda::read_contacts(out.join("contacts.csv"))?;
    let end: Vec<_> = contacts
        .iter()
        .filter(|c| c.step == last.step && c.state.is_closed())
        .collect();
    let shear: f64 = end.iter().map(|c| c.shear_force).sum();
    let normal: f64 = end.iter().map(|c| c.normal_force).sum();
    let phi = (shear / normal).atan();
    let (g, slope, t) = (9.81, 30f64.to_radians(), last.time);
    let expected = 0.5 * g * (slope.sin() - slope.cos() * phi.tan()) * t * t;
    println!(
        "the joint mobilised a friction angle of {:.2}° (φr = 20°, JRC = 4), for which \
         ½ g (sin 30° − cos 30° tan φ) t² = {expected:.4} m",
        phi.to_degrees()
    );
    Ok(())
}
