//! Scene errors and warnings, each at a [`Location`].
//!
//! Every message a person reads starts with `file:line:col` so editors can jump to it, and names
//! the offending token (pbrt-v4 `ErrorExit(&loc, ...)`, Mitsuba's parser errors).

use std::fmt;
use std::path::PathBuf;

pub use super::location::Location;

/// Everything that stops a scene from loading.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// Malformed input at a token.
    #[error("{loc}: {message} (at \"{token}\")")]
    Syntax {
        /// Where.
        loc: Location,
        /// The offending token as written.
        token: String,
        /// What is wrong.
        message: String,
    },
    /// A type name (shape, material, light, ...) that neither prism nor pbrt-v4 knows.
    #[error("{loc}: unknown {kind} type \"{name}\"; valid {kind} types: {valid}")]
    UnknownType {
        /// Where.
        loc: Location,
        /// "shape", "material", ...
        kind: &'static str,
        /// The name as written.
        name: String,
        /// Comma-separated valid names.
        valid: String,
    },
    /// A pbrt-v4 feature prism does not render, in strict mode (`ParseOptions::strict`).
    #[error("{loc}: unsupported feature: {feature} (strict mode; without --strict prism {fallback})")]
    Unsupported {
        /// Where.
        loc: Location,
        /// What the file asked for.
        feature: String,
        /// What prism does without `--strict`.
        fallback: String,
    },
    /// Input pbrt-v4 itself stops on (a parameter nothing reads, several values for one), in
    /// strict mode.
    #[error("{loc}: {message} (strict mode; pbrt-v4 stops here too)")]
    Refused {
        /// Where.
        loc: Location,
        /// What is wrong.
        message: String,
    },
    /// A file that could not be read (scene, include, mesh).
    #[error("{loc}: cannot read \"{path}\": {reason}")]
    Io {
        /// The directive that named the file.
        loc: Location,
        /// The resolved path.
        path: PathBuf,
        /// The OS error text.
        reason: String,
    },
    /// Include/Import of a file that is already being read.
    #[error("{loc}: include cycle: {chain}")]
    IncludeCycle {
        /// The Include directive that closes the cycle.
        loc: Location,
        /// The files in the cycle, ` -> `-separated.
        chain: String,
    },
    /// A malformed mesh file (PLY/OBJ) named by a shape.
    #[error("{loc}: mesh file \"{path}\": {message}")]
    Mesh {
        /// The Shape directive that named the file.
        loc: Location,
        /// The mesh file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

impl SceneError {
    /// A syntax error at `loc` about `token`.
    pub fn syntax(loc: &Location, token: &str, message: impl Into<String>) -> Self {
        Self::Syntax { loc: loc.clone(), token: token.to_string(), message: message.into() }
    }

    /// The location the error points at.
    pub fn location(&self) -> &Location {
        match self {
            Self::Syntax { loc, .. }
            | Self::UnknownType { loc, .. }
            | Self::Unsupported { loc, .. }
            | Self::Refused { loc, .. }
            | Self::Io { loc, .. }
            | Self::IncludeCycle { loc, .. }
            | Self::Mesh { loc, .. } => loc,
        }
    }
}

/// Something a person should know about that does not stop loading.
#[derive(Clone, Debug, PartialEq)]
pub struct Warning {
    /// Where.
    pub loc: Location,
    /// What.
    pub message: String,
    /// Whether it reports a feature prism does not render.
    pub kind: WarningKind,
}

/// What a warning reports.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum WarningKind {
    /// Something worth knowing (deprecated syntax, a repeated parameter, an empty mesh file); the
    /// scene renders as written.
    Note,
    /// A pbrt-v4 feature prism does not render and what prism does instead: an error in strict
    /// mode ([`check_strict`]).
    Unsupported {
        /// What the file asked for.
        feature: String,
        /// What prism does instead ("ignores it").
        fallback: String,
    },
    /// Input pbrt-v4 stops on but prism reads past: a parameter nothing reads (often a
    /// misspelling), or several values where one is read. An error in strict mode.
    Refused,
}

impl Warning {
    /// A warning that is never an error.
    pub fn note(loc: &Location, message: impl Into<String>) -> Self {
        Self { loc: loc.clone(), message: message.into(), kind: WarningKind::Note }
    }

    /// Input pbrt-v4 stops on and prism reads past ([`WarningKind::Refused`]).
    pub fn refused(loc: &Location, message: impl Into<String>) -> Self {
        Self { loc: loc.clone(), message: message.into(), kind: WarningKind::Refused }
    }

    /// A pbrt-v4 feature prism does not render: "unsupported feature: {feature}; prism {fallback}".
    pub fn unsupported(loc: &Location, feature: impl Into<String>, fallback: impl Into<String>) -> Self {
        let (feature, fallback) = (feature.into(), fallback.into());
        let message = format!("unsupported feature: {feature}; prism {fallback}");
        Self { loc: loc.clone(), message, kind: WarningKind::Unsupported { feature, fallback } }
    }

    /// The error this warning is in strict mode, if it is one.
    pub fn strict_error(&self) -> Option<SceneError> {
        match &self.kind {
            WarningKind::Note => None,
            WarningKind::Unsupported { feature, fallback } => Some(SceneError::Unsupported {
                loc: self.loc.clone(),
                feature: feature.clone(),
                fallback: fallback.clone(),
            }),
            WarningKind::Refused => Some(SceneError::Refused { loc: self.loc.clone(), message: self.message.clone() }),
        }
    }
}

/// Strict mode: the first warning about an unsupported feature or input pbrt-v4 stops on, as
/// an error.
pub fn check_strict(warnings: &[Warning]) -> Result<(), SceneError> {
    match warnings.iter().find_map(Warning::strict_error) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: warning: {}", self.loc, self.message)
    }
}
