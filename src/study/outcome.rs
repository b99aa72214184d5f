//! How a run ended, for stability maps and searches. The first that applies
//! (a run's guards stop it at the first of the three failures of the method,
//! which then names its outcome):
//!
//! * `penetrated`: a step ended with a contact deeper than the allowed
//!   bound (`deep_penetration_steps > 0` in summary.json);
//! * `energy grew`: the total energy rose although nothing did work on the
//!   blocks (`energy_growth_steps > 0`);
//! * `cut`: steps were cut down to the smallest time step and accepted
//!   without open-close agreement (`unconverged_steps > 0`);
//! * `failed`: the run stopped with another error (or could not be built);
//! * with `held: (block, tolerance)` in the study: `held` when the block
//!   ended within `tolerance` of its start, else `slid`;
//! * otherwise `converged`.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::summary::{Status, Summary};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Outcome {
    Held,
    Slid,
    Converged,
    Cut,
    EnergyGrew,
    Penetrated,
    Failed,
}

impl Outcome {
    pub const ALL: [Outcome; 7] = [
        Outcome::Held,
        Outcome::Slid,
        Outcome::Converged,
        Outcome::Cut,
        Outcome::EnergyGrew,
        Outcome::Penetrated,
        Outcome::Failed,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Outcome::Held => "held",
            Outcome::Slid => "slid",
            Outcome::Converged => "converged",
            Outcome::Cut => "cut",
            Outcome::EnergyGrew => "energy grew",
            Outcome::Penetrated => "penetrated",
            Outcome::Failed => "failed",
        }
    }

    /// One colour each on the charts.
    pub fn colour(self) -> (u8, u8, u8) {
        match self {
            Outcome::Held => (46, 139, 87),
            Outcome::Slid => (230, 120, 20),
            Outcome::Converged => (70, 110, 200),
            Outcome::Cut => (150, 90, 180),
            Outcome::EnergyGrew => (200, 40, 40),
            Outcome::Penetrated => (120, 70, 40),
            Outcome::Failed => (40, 40, 40),
        }
    }

    /// The outcome of a run from its summary and (for held/slid) the
    /// farthest its watched block moved, m.
    pub fn judge(summary: &Summary, moved: Option<(f64, f64)>) -> Outcome {
        if summary.deep_penetration_steps > 0 {
            Outcome::Penetrated
        } else if summary.energy_growth_steps > 0 {
            Outcome::EnergyGrew
        } else if summary.unconverged_steps > 0 {
            Outcome::Cut
        } else if summary.status == Status::Failed {
            Outcome::Failed
        } else if let Some((moved, tolerance)) = moved {
            if moved < tolerance {
                Outcome::Held
            } else {
                Outcome::Slid
            }
        } else {
            Outcome::Converged
        }
    }
}

impl fmt::Display for Outcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Outcome {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Outcome::ALL
            .into_iter()
            .find(|o| o.name() == s)
            .ok_or_else(|| format!("`{s}` is not an outcome"))
    }
}
