//! Errors of the core.

use thiserror::Error;

#[derive(Debug, Error)]
pub enum DdaError {
    #[error("the system matrix is not positive definite ({0}); check for blocks with zero mass or negative stiffness")]
    Factorization(String),
    #[error("a step produced a non-finite displacement at time {time}: the model is unstable (try a smaller time step or penalty)")]
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
