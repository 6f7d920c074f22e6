//! Why an accelerator could not be built.

/// Why an accelerator could not be built.
#[derive(Debug, thiserror::Error)]
pub enum AccelError {
    /// Embree failed (device creation, scene commit).
    #[cfg(embree)]
    #[error(transparent)]
    Embree(#[from] super::embree::EmbreeError),
    /// An Embree backend was asked of a build without Embree.
    #[error("this prism was built without Embree (feature `embree` or `embree4`); use --accel obvhs")]
    NoEmbree,
}
