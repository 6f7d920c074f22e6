//! The samplers chosen by name, with the parameters pbrt-v4's `Sampler` directive gives them.

use super::pattern::{GlobalSobol, Halton, PaddedSobol, Pattern, Pmj02bn, Randomize, Stratified, ZSobol};
use super::Sampler;
use crate::named::{self, UnknownName};

/// Which sampler generates the sample dimensions, and how.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplerKind {
    /// Independent uniform random numbers.
    Independent,
    /// prism's padded Owen-scrambled Sobol (Burley 2020), stratified in 4D groups.
    Sobol,
    /// pbrt-v4's `zsobol` (its default): Sobol' points over a Morton order of the pixels.
    ZSobol(Randomize),
    /// pbrt-v4's `sobol`: one Sobol' sequence over the whole image, each pixel's samples the
    /// sequence's points in it.
    GlobalSobol(Randomize),
    /// pbrt-v4's `paddedsobol`.
    PaddedSobol(Randomize),
    /// pbrt-v4's `halton` (randomised by `none`, `permutedigits` or `owen`).
    Halton(Randomize),
    /// pbrt-v4's `pmj02bn`: progressive multi-jittered (0,2) sequences.
    Pmj02bn,
    /// pbrt-v4's `stratified`: an `x` × `y` grid of strata per pixel, jittered or centred.
    Stratified {
        /// Strata per pixel row and column (used when their product is the samples per pixel,
        /// else the grid closest to square for that count, as pbrt-v4 with `--spp`).
        x: u32,
        y: u32,
        /// Random positions in the strata (else their centres).
        jitter: bool,
    },
}

impl SamplerKind {
    /// Each name with its kind and pbrt-v4's default parameters; the first is canonical.
    pub const NAMES: &'static [(&'static str, SamplerKind)] = &[
        ("sobol", SamplerKind::Sobol),
        ("independent", SamplerKind::Independent),
        ("zsobol", SamplerKind::ZSobol(Randomize::FastOwen)),
        ("globalsobol", SamplerKind::GlobalSobol(Randomize::FastOwen)),
        ("paddedsobol", SamplerKind::PaddedSobol(Randomize::FastOwen)),
        ("halton", SamplerKind::Halton(Randomize::PermuteDigits)),
        ("pmj02bn", SamplerKind::Pmj02bn),
        ("stratified", SamplerKind::Stratified { x: 4, y: 4, jitter: true }),
    ];

    /// The kind a name from [`Self::NAMES`] stands for, with its default parameters.
    pub fn parse(name: &str) -> Result<Self, UnknownName> {
        named::parse(Self::NAMES, "sampler", name)
    }

    /// The sampler's name.
    pub fn name(self) -> &'static str {
        match self {
            SamplerKind::Independent => "independent",
            SamplerKind::Sobol => "sobol",
            SamplerKind::ZSobol(_) => "zsobol",
            SamplerKind::GlobalSobol(_) => "globalsobol",
            SamplerKind::PaddedSobol(_) => "paddedsobol",
            SamplerKind::Halton(_) => "halton",
            SamplerKind::Pmj02bn => "pmj02bn",
            SamplerKind::Stratified { .. } => "stratified",
        }
    }

    /// The names, comma-separated, for messages.
    pub fn valid_names() -> String {
        named::valid(Self::NAMES)
    }

    /// A new sampler of this kind for renders of `spp` samples per pixel of an image of
    /// `resolution` pixels, seeded by `seed` (pbrt-v4's samplers depend on all three; prism's
    /// Sobol and the independent sampler take the seed per pixel sample).
    pub(crate) fn make(self, spp: u64, resolution: (u32, u32), seed: u64) -> Sampler {
        let pattern = match self {
            SamplerKind::Independent => return Sampler::independent(),
            SamplerKind::Sobol => return Sampler::sobol(),
            SamplerKind::ZSobol(r) => Pattern::ZSobol(ZSobol::new(r, seed, spp, resolution)),
            SamplerKind::GlobalSobol(r) => Pattern::GlobalSobol(GlobalSobol::new(r, seed, resolution)),
            SamplerKind::PaddedSobol(r) => Pattern::PaddedSobol(PaddedSobol::new(r, seed, spp)),
            SamplerKind::Halton(r) => Pattern::Halton(Halton::new(r, seed, resolution)),
            SamplerKind::Pmj02bn => Pattern::Pmj02bn(Pmj02bn::new(seed, spp)),
            SamplerKind::Stratified { x, y, jitter } => {
                let (x, y) = if u64::from(x) * u64::from(y) == spp { (x, y) } else { near_square(spp) };
                Pattern::Stratified(Stratified::new(x, y, jitter, seed))
            }
        };
        Sampler::Pattern(Box::new(pattern))
    }
}

/// The factors x ≥ y of `n` closest to √n (pbrt-v4's grid for a stratified sampler told its
/// sample count).
fn near_square(n: u64) -> (u32, u32) {
    let n = n.clamp(1, u32::MAX as u64) as u32;
    let mut y = (n as f64).sqrt() as u32;
    while !n.is_multiple_of(y) {
        y -= 1;
    }
    (n / y, y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_stratified_grids_fit_the_count() {
        for (name, kind) in SamplerKind::NAMES {
            assert_eq!(SamplerKind::parse(name), Ok(*kind));
            assert_eq!(kind.name(), *name);
        }
        assert_eq!(near_square(16), (4, 4));
        assert_eq!(near_square(8), (4, 2));
        assert_eq!(near_square(7), (7, 1));
        assert_eq!(near_square(1), (1, 1));
    }
}
