//! The `analysis` section: the scene's own fields, then the driver's
//! [`Settings`] as they are written (declared once, with their docs and
//! defaults, by [`dda_core::with_settings!`]), all in one struct, so its
//! derive refuses unknown fields and names every field it reads.

use std::f64::consts::TAU;

use dda_core::settings::{non_negative, positive};
use dda_core::{DdaError, Settings};
use serde::{Deserialize, Serialize};

use dda_2d::{Plane, RotationUpdate};

use super::{is_default, Coords};
use crate::guard::OnFailure;

dda_core::with_settings! {
    /// The analysis: what the scene decides, then the driver's settings as
    /// written (see [`Settings`]), but for the velocity ratio and the mass
    /// damping, which the scene's fields give ([`Analysis::settings`]).
    /// `None` means automatic.
    #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
    #[serde(default, deny_unknown_fields)]
    pub struct Analysis {
        /// Simulated time, s; required (0 is rejected).
        duration: f64 = 0.0,
        /// `Dynamic` (default) carries velocities from step to step, `Static`
        /// starts each step at rest.
        mode: Mode = Mode::Dynamic,
        /// Fraction of the velocity carried into the next step, in [0, 1];
        /// default the mode's (1 dynamic, 0 static).
        velocity_ratio: Option<f64> = None,
        /// (gx, gy) in 2D, (gx, gy, gz) in 3D, m/s²; default (0, −9.81) or
        /// (0, 0, −9.81): see [`super::Scene::gravity`].
        #[serde(skip_serializing_if = "Option::is_none")]
        gravity: Option<Coords> = None,
        /// Plane strain (default) or plane stress: 2D scenes only.
        #[serde(skip_serializing_if = "is_default")]
        plane: Plane = Plane::Strain,
        /// `Exact` (default) turns blocks by the exact rotation, `Linear` by
        /// Shi's first-order update.
        rotation_update: RotationUpdate = RotationUpdate::Exact,
        /// Stiffness of the springs holding fixed points, N/m; default 10 × a
        /// typical contact's spring.
        fixed_penalty: Option<f64> = None,
        /// Mass-proportional viscous damping; default none.
        #[serde(skip_serializing_if = "Option::is_none")]
        damping: Option<Damping> = None,
        /// What a run does when a guard trips (energy growth in a scene nothing
        /// works on, a penetration past the bound or a step without open-close
        /// agreement, both at the smallest step): `Stop` (default) ends it,
        /// status "failed", with a report; `Continue` runs on and warns.
        #[serde(skip_serializing_if = "is_default")]
        on_failure: OnFailure = OnFailure::Stop,
        /// Bring the model to rest under its loads at t = 0 before the run
        /// (`settle: ()`), so gravity is on when the run's own loads begin;
        /// default none: gravity comes on at once and the model rings
        /// about its settlement. Implicit integrator only.
        #[serde(skip_serializing_if = "Option::is_none")]
        settle: Option<Settle> = None,
    }
}

impl Analysis {
    /// The driver settings the analysis asks for: as written, with the
    /// velocity ratio of the mode and the damping's coefficient.
    pub fn settings(&self) -> Settings {
        let carried = if self.mode == Mode::Static { 0.0 } else { 1.0 };
        let velocity_ratio = self.velocity_ratio.unwrap_or(carried);
        let mass_damping = self
            .damping
            .map_or(0.0, |d| 2.0 * d.ratio * TAU * d.frequency);
        self.settings_with(velocity_ratio, mass_damping)
    }
}

/// Mass-proportional damping giving the ratio `ratio` of critical damping
/// at `frequency` (Hz): α = 2·ratio·2π·frequency (1/s), a force −α·m·v on
/// every block. Lower frequencies are damped more, higher ones less.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Damping {
    /// Fraction of critical damping, like 0.05; required, not negative.
    pub ratio: f64,
    /// Where the ratio holds, Hz; required, positive.
    pub frequency: f64,
}

impl Damping {
    /// Whether the ratio and frequency make a damping: the first field at
    /// fault and what to change.
    pub fn check(&self) -> Result<(), DdaError> {
        let hint = "it is a fraction of critical damping, like 0.05";
        non_negative("ratio", "the damping ratio", self.ratio, hint)?;
        let hint =
            "give the frequency (Hz) at which the ratio holds, like the structure's first mode";
        positive("frequency", "the damping frequency", self.frequency, hint)
    }
}

/// Settling before the run: static steps that take no time
/// ([`dda_core::Driver::settle`]); the run starts at rest where they leave
/// the blocks, and its displacements are measured from there.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Settle {
    /// The most static steps, at least 1; default 20. A model that stands
    /// settles in a few (a wall in 2–4); one still moving after them
    /// cannot stand under its loads, and the summary says so.
    pub steps: usize,
}

impl Default for Settle {
    fn default() -> Self {
        Self { steps: 20 }
    }
}

/// Dynamic carries the velocity from step to step; static starts each step at rest.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Mode {
    #[default]
    Dynamic,
    Static,
}
