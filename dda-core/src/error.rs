//! Errors of the core.

use thiserror::Error;

#[derive(Debug, Error)]
pub enum DdaError {
    /// A pivot of the step's matrix that is not positive: `detail` says
    /// where, `advice` what in the model usually makes one
    /// ([`DdaError::not_positive_definite`]; the driver names the penalty
    /// where it is far above the automatic one).
    #[error("the system matrix is not positive definite ({detail}); {advice}")]
    Factorization { detail: String, advice: String },
    #[error(
        "a step produced a non-finite displacement at time {time}: the model is unstable; {}",
        OVERFLOW_ADVICE
    )]
    NotFinite { time: f64 },
    /// A value outside its range: `field` names it (like `dt`, or
    /// `friction_angle` for a law's parameter), `message` says what to write.
    #[error("{field}: {message}")]
    Setting {
        field: &'static str,
        message: String,
    },
    /// A bad entry of a list value: `field[index]`, like a load history's
    /// sample.
    #[error("{field}[{index}]: {message}")]
    Entry {
        field: &'static str,
        index: usize,
        message: String,
    },
    #[error("invalid analysis setting: {0}")]
    Settings(String),
    /// A checkpoint that cannot be saved or does not fit the run.
    #[error("{0}")]
    Checkpoint(String),
}

/// What to check where a run's numbers stop being finite: the implicit
/// step is stable at any dt, so it is first an input out of all scale.
pub const OVERFLOW_ADVICE: &str = "a value of the scene far beyond any physical scale (a load, a velocity, a stiffness or a damping near 1e300) overflows a double; else a smaller dt or a softer penalty keeps the springs resolved";

/// A penalty at least this many times the automatic one is named as the
/// likely cause of a failed factorisation or an unexplained rise of the
/// energy: its springs' terms then swamp the blocks' own by all but the
/// last few of a double's 16 digits. A block resting on a base at dt 1 ms
/// (E 1e10 Pa, automatic penalty 2e10 N/m³) factorises up to 5e14 times
/// and fails from 5e15; the block sliding on its incline fails from
/// 2.5e15, and at 5e19 factorises but its energy check reads round-off as
/// a rise.
pub const STIFF_PENALTY: f64 = 1e12;

impl DdaError {
    /// A failed factorisation, `detail` saying where, with the advice that
    /// holds whatever the penalty: scene validation keeps masses and
    /// moduli positive, so what is left is a law's stiffness or a model
    /// whose scales span too much.
    pub fn not_positive_definite(detail: String) -> Self {
        Self::Factorization {
            detail,
            advice: "a contact law may give a negative stiffness, or the blocks' masses and stiffnesses and the contacts' springs span more orders of magnitude than double precision holds (blocks of very different sizes, a penalty far from the automatic one)".into(),
        }
    }
}

/// `penalty` (N/m³) against the `automatic` one, where it is at least
/// [`STIFF_PENALTY`] times as stiff: the words that name it, for advice.
pub fn stiff_penalty(penalty: f64, automatic: f64) -> Option<String> {
    let ratio = penalty / automatic;
    (ratio >= STIFF_PENALTY).then(|| {
        format!(
            "the penalty, {penalty:.3e} N/m³, is {ratio:.1e} times the automatic one ({automatic:.3e} N/m³: twice the stiffest Young's modulus over the median block size)"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The penalty is named from `STIFF_PENALTY` times the automatic one,
    /// with the ratio, and not below it.
    #[test]
    fn a_penalty_is_named_only_far_above_the_automatic_one() {
        assert_eq!(stiff_penalty(1e22, 2e10), None);
        let named = stiff_penalty(1e23, 2e10).unwrap();
        assert!(named.contains("1.000e23 N/m³"), "{named}");
        assert!(
            named.contains("is 5.0e12 times the automatic one (2.000e10 N/m³"),
            "{named}"
        );
    }

    /// Without the driver's knowledge of the penalty, the advice names
    /// what scene validation leaves possible, not zero masses.
    #[test]
    fn a_failed_factorisation_names_what_validation_leaves() {
        let e = DdaError::not_positive_definite("NonPositivePivot in supernode 3".into());
        let text = e.to_string();
        assert!(
            text.starts_with(
                "the system matrix is not positive definite (NonPositivePivot in supernode 3); "
            ),
            "{text}"
        );
        assert!(text.contains("negative stiffness"), "{text}");
        assert!(!text.contains("zero mass"), "{text}");
    }
}
