//! How a strength falls from its peak to its residual value as slip
//! accumulates.

use dda_core::settings::finite;
use dda_core::DdaError;
use serde::{Deserialize, Serialize};

/// The fraction of the peak-minus-residual strength left after a slip δ;
/// a scene writes `Step(at: 0.001)`, `Linear(start: 0.0, end: 0.01)` or
/// `Exponential(length: 100.0)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Weakening {
    /// All of it until δ reaches `at` (m), none after: a sharp drop.
    Step { at: f64 },
    /// All of it until `start`, falling linearly to none at `end` (m).
    Linear { start: f64, end: f64 },
    /// exp(−δ / `length`) (m): ntdda's form, with `length` = 1/k.
    Exponential { length: f64 },
}

impl Weakening {
    /// 1 at the peak, 0 at the residual strength.
    pub fn remaining(&self, slip: f64) -> f64 {
        match *self {
            Weakening::Step { at } => {
                if slip < at {
                    1.0
                } else {
                    0.0
                }
            }
            Weakening::Linear { start, end } => {
                if slip <= start {
                    1.0
                } else if slip >= end {
                    0.0
                } else {
                    (end - slip) / (end - start)
                }
            }
            Weakening::Exponential { length } => (-slip / length).exp(),
        }
    }

    /// Peak to residual at slip δ.
    pub fn between(&self, peak: f64, residual: f64, slip: f64) -> f64 {
        residual + (peak - residual) * self.remaining(slip)
    }

    /// Whether the parameters make sense; the error names `weakening`.
    pub fn check(&self) -> Result<(), DdaError> {
        let slips: &[f64] = match self {
            Weakening::Step { at } => &[*at],
            Weakening::Linear { start, end } => &[*start, *end],
            Weakening::Exponential { length } => &[*length],
        };
        for slip in slips {
            finite("weakening", "the weakening slip", *slip)?;
        }
        let reason = match *self {
            Weakening::Step { at } if at < 0.0 => {
                format!("the step slip `at` must be zero or positive, got {at}")
            }
            Weakening::Linear { start, end } if !(start >= 0.0 && end > start) => format!(
                "a linear weakening needs 0 <= start < end, got start {start} and end {end}"
            ),
            Weakening::Exponential { length } if length <= 0.0 => {
                format!("the exponential weakening length must be positive, got {length}")
            }
            _ => return Ok(()),
        };
        Err(DdaError::Setting {
            field: "weakening",
            message: format!(
                "{reason}; slips are in m, like Step(at: 0.001) or Linear(start: 0.0, end: 0.01)"
            ),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forms_fall_from_peak_to_residual() {
        let step = Weakening::Step { at: 0.05 };
        assert_eq!(step.between(25.0, 15.0, 0.0499), 25.0);
        assert_eq!(step.between(25.0, 15.0, 0.05), 15.0);
        let linear = Weakening::Linear {
            start: 0.01,
            end: 0.03,
        };
        assert_eq!(linear.between(4.0, 2.0, 0.0), 4.0);
        assert!((linear.between(4.0, 2.0, 0.02) - 3.0).abs() < 1e-12);
        assert_eq!(linear.between(4.0, 2.0, 1.0), 2.0);
        let exp = Weakening::Exponential { length: 100.0 };
        assert!((exp.between(12.0, 6.0, 100.0) - (6.0 + 6.0 / std::f64::consts::E)).abs() < 1e-12);
        assert!(Weakening::Linear {
            start: 0.1,
            end: 0.1
        }
        .check()
        .is_err());
        assert!(Weakening::Exponential { length: 0.0 }.check().is_err());
        assert!(step.check().is_ok());
    }
}
