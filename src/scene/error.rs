//! Scene errors: one readable line naming the file, the place and the fix.

use std::fmt;

use super::locate::{locate, Place};
use super::Source;

/// A place in a scene file: the file, and the line and column (1-based)
/// where they can be found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    pub file: String,
    pub line_column: Option<(usize, usize)>,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.file)?;
        match self.line_column {
            Some((line, column)) => write!(f, ":{line}:{column}"),
            None => Ok(()),
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    // The io error is in the message rather than the source chain, so
    // `to_string()` alone says why.
    #[error("{file}: cannot read the scene file: {error}")]
    Read { file: String, error: std::io::Error },
    /// The text is not a scene (RON syntax, unknown or missing fields, wrong types).
    #[error("{at}: {message}")]
    Syntax { at: Location, message: String },
    /// The scene parses but a value is wrong.
    #[error("{at}: {place}: {message}")]
    Invalid {
        at: Location,
        place: String,
        message: String,
    },
}

impl Source {
    pub(super) fn syntax(&self, e: &ron::error::SpannedError) -> SceneError {
        use ron::error::Error as E;
        let hint = match &e.code {
            E::NoSuchStructField { .. } => "remove the field or correct its spelling",
            E::NoSuchEnumVariant { .. } => "use one of the listed names",
            E::MissingStructField { .. } => "add the field",
            E::DuplicateStructField { .. } => "keep only one of them",
            E::ExpectedDifferentStructName { .. } => "use the expected name or leave the name out",
            E::ExpectedDifferentLength { expected, .. } if expected.contains("length 6") => {
                "a 3D block's velocity is (vx, vy, vz, wx, wy, wz) and its stress (sx, sy, sz, syz, szx, sxy)"
            }
            E::ExpectedDifferentLength { expected, .. } if expected.contains("length 3") => {
                "a 2D block's velocity is (vx, vy, omega) and its stress (sx, sy, sxy); 3D corners and sizes are (x, y, z)"
            }
            E::ExpectedDifferentLength { expected, .. } if expected.contains("length 2") => {
                "a 2D point or a prism's outline point is (x, y)"
            }
            E::Message(_) => "",
            _ => "fix the syntax there (RON: fields as `name: value`, separated by commas; see examples/)",
        };
        let mut message = e.code.to_string();
        if !hint.is_empty() {
            message = format!("{message}; {hint}");
        }
        SceneError::Syntax {
            at: Location {
                file: self.origin.clone(),
                line_column: Some((e.span.start.line, e.span.start.col)),
            },
            message,
        }
    }

    pub(super) fn invalid(&self, place: &Place, message: impl Into<String>) -> SceneError {
        SceneError::Invalid {
            at: Location {
                file: self.origin.clone(),
                line_column: locate(&self.text, place),
            },
            place: place.to_string(),
            message: message.into(),
        }
    }
}
