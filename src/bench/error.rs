//! Why a bench run stopped.

use crate::film::FilmAllocError;
use crate::image::ImageError;
use crate::named::UnknownName;
use crate::pbrt::SceneError;
use crate::scene::BuildError;
use std::path::PathBuf;

/// Why a bench run stopped.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// The scene file could not be read.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The scene could not be built.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// The film could not be allocated.
    #[error(transparent)]
    Film(#[from] FilmAllocError),
    /// An image could not be read, written or compared.
    #[error(transparent)]
    Image(#[from] ImageError),
    /// An output could not be written.
    #[error(transparent)]
    Io(#[from] std::io::Error),
    /// An output could not be serialised.
    #[error(transparent)]
    Json(#[from] serde_json::Error),
    /// A `builtin:` scene that does not exist.
    #[error(transparent)]
    UnknownScene(UnknownName),
    /// The given reference image could not be read.
    #[error("reading the reference {}", path.display())]
    ReadReference {
        /// The reference's path.
        path: PathBuf,
        /// Why.
        source: ImageError,
    },
    /// The given reference image is not the size the bench renders.
    #[error("the reference {} is {}x{}, but the bench renders {}x{} (--resolution)", path.display(), size.0, size.1, renders.0, renders.1)]
    ReferenceSize {
        /// The reference's path.
        path: PathBuf,
        /// Its size [pixels].
        size: (u32, u32),
        /// The size the bench renders [pixels].
        renders: (u32, u32),
    },
    /// The output directory could not be created.
    #[error("creating {}", path.display())]
    CreateDir {
        /// The directory.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A plot could not be drawn.
    #[error("plotting: {0}")]
    Plot(String),
}
