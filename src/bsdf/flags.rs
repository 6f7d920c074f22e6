//! Lobe classification flags and the transport direction.

use std::ops::{BitAnd, BitOr};

/// Which quantity a path carries: radiance from the camera side, or importance from lights.
/// Refraction scales radiance by 1/η² but not importance (Veach 1997 §5.2, pbrt-v4 §9.5.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransportMode {
    /// Camera paths (path tracing).
    Radiance,
    /// Light paths (light tracing, photon mapping).
    Importance,
}

impl TransportMode {
    /// The other quantity: a path traced from the other end carries it (pbrt-v4 `!mode`).
    #[inline]
    pub fn adjoint(self) -> Self {
        match self {
            TransportMode::Radiance => TransportMode::Importance,
            TransportMode::Importance => TransportMode::Radiance,
        }
    }
}

/// Which lobes a sampler may choose from (pbrt-v4 `BxDFReflTransFlags`): layered BSDFs ask
/// an interface only for its reflection or only for its transmission.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lobes {
    /// Reflection and transmission.
    All,
    /// Reflection only.
    Reflection,
    /// Transmission only.
    Transmission,
}

impl Lobes {
    /// The choice weights (reflection, transmission) of an interface that reflects the
    /// fraction `r` and transmits 1 − `r`, with the excluded lobe's weight 0; `None` when
    /// nothing is left to choose.
    #[inline]
    pub fn weights(self, r: f32) -> Option<(f32, f32)> {
        let (pr, pt) = match self {
            Lobes::All => (r, 1.0 - r),
            Lobes::Reflection => (r, 0.0),
            Lobes::Transmission => (0.0, 1.0 - r),
        };
        (pr + pt > 0.0).then_some((pr, pt))
    }

    /// True when reflection may be chosen.
    #[inline]
    pub fn reflection(self) -> bool {
        self != Lobes::Transmission
    }
}

/// Set of lobe kinds of a BxDF or of one sampled direction (pbrt-v4 `BxDFFlags`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct BxdfFlags(u8);

impl BxdfFlags {
    /// No lobe (black BxDF).
    pub const UNSET: Self = Self(0);
    /// Scatters into the hemisphere of `wo`.
    pub const REFLECTION: Self = Self(1);
    /// Scatters into the opposite hemisphere.
    pub const TRANSMISSION: Self = Self(2);
    /// Broad lobe.
    pub const DIFFUSE: Self = Self(4);
    /// Finite but peaked lobe.
    pub const GLOSSY: Self = Self(8);
    /// Dirac delta lobe.
    pub const SPECULAR: Self = Self(16);
    /// Diffuse reflection.
    pub const DIFFUSE_REFLECTION: Self = Self(1 | 4);
    /// Diffuse transmission.
    pub const DIFFUSE_TRANSMISSION: Self = Self(2 | 4);
    /// Glossy reflection.
    pub const GLOSSY_REFLECTION: Self = Self(1 | 8);
    /// Glossy transmission.
    pub const GLOSSY_TRANSMISSION: Self = Self(2 | 8);
    /// Perfect mirror reflection.
    pub const SPECULAR_REFLECTION: Self = Self(1 | 16);
    /// Perfect refraction.
    pub const SPECULAR_TRANSMISSION: Self = Self(2 | 16);
    /// Every lobe.
    pub const ALL: Self = Self(31);

    /// True when every flag of `other` is set.
    #[inline]
    pub fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }
    /// True when any flag of `other` is set.
    #[inline]
    pub fn intersects(self, other: Self) -> bool {
        self.0 & other.0 != 0
    }
    /// No flag set.
    #[inline]
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }
    /// Has a reflection lobe.
    #[inline]
    pub fn is_reflective(self) -> bool {
        self.intersects(Self::REFLECTION)
    }
    /// Has a transmission lobe.
    #[inline]
    pub fn is_transmissive(self) -> bool {
        self.intersects(Self::TRANSMISSION)
    }
    /// Has a diffuse lobe.
    #[inline]
    pub fn is_diffuse(self) -> bool {
        self.intersects(Self::DIFFUSE)
    }
    /// Has a glossy lobe.
    #[inline]
    pub fn is_glossy(self) -> bool {
        self.intersects(Self::GLOSSY)
    }
    /// Has a delta lobe.
    #[inline]
    pub fn is_specular(self) -> bool {
        self.intersects(Self::SPECULAR)
    }
    /// Has a lobe that light sampling can hit (diffuse or glossy): MIS applies.
    #[inline]
    pub fn is_non_specular(self) -> bool {
        self.intersects(Self(4 | 8))
    }
}

impl BitOr for BxdfFlags {
    type Output = Self;
    #[inline]
    fn bitor(self, o: Self) -> Self {
        Self(self.0 | o.0)
    }
}

impl BitAnd for BxdfFlags {
    type Output = Self;
    #[inline]
    fn bitand(self, o: Self) -> Self {
        Self(self.0 & o.0)
    }
}
