//! Scene errors: one readable line naming the file, the place and the fix.

use super::locate::{locate, Place};
use super::Source;

#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    // The io error is in the message rather than the source chain, so
    // `to_string()` alone says why.
    #[error("{file}: cannot read the scene file: {error}")]
    Read { file: String, error: std::io::Error },
    /// The text is not a scene (RON syntax, unknown or missing fields,
    /// wrong types); `at` is the file, line and column, like `a.ron:3:5`.
    #[error("{at}: {message}")]
    Syntax { at: String, message: String },
    /// The scene parses but a value is wrong; `at` is the file, and the
    /// line and column where they can be found.
    #[error("{at}: {place}: {message}")]
    Invalid {
        at: String,
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
            at: format!("{}:{}", self.origin, e.span.start),
            message,
        }
    }

    pub(super) fn invalid(&self, place: &Place, message: impl Into<String>) -> SceneError {
        let at = match locate(&self.text, place) {
            Some((line, column)) => format!("{}:{line}:{column}", self.origin),
            None => self.origin.clone(),
        };
        SceneError::Invalid {
            at,
            place: place.to_string(),
            message: message.into(),
        }
    }
}
