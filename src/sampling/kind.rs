//! The samplers chosen by name: which one generates a render's sample dimensions.

use super::Sampler;

/// Which sampler generates the sample dimensions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplerKind {
    /// Independent uniform random numbers.
    Independent,
    /// Owen-scrambled Sobol (low discrepancy).
    Sobol,
}

// pbrt-v4's "zsobol" and "paddedsobol" are read as prism's Sobol sampler.
crate::named::name_table!(SamplerKind, "sampler", {
    "independent" => SamplerKind::Independent,
    "sobol" => SamplerKind::Sobol,
    "zsobol" => SamplerKind::Sobol,
    "paddedsobol" => SamplerKind::Sobol,
});

impl SamplerKind {
    /// A new sampler of this kind.
    pub(crate) fn make(self) -> Sampler {
        match self {
            SamplerKind::Independent => Sampler::independent(),
            SamplerKind::Sobol => Sampler::sobol(),
        }
    }
}
