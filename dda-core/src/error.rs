//! Errors of the core.

use thiserror::Error;

#[derive(Debug, Error)]
pub enum DdaError {
    #[error("the system matrix is not positive definite ({0}); check for blocks with zero mass or negative stiffness")]
    Factorization(String),
    #[error("a step produced a non-finite displacement at time {time}: the model is unstable (try a smaller time step or penalty)")]
    NotFinite { time: f64 },
    #[error("invalid analysis setting: {0}")]
    Settings(String),
}
