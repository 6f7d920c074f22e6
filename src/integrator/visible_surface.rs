//! The first surface a camera ray sees, recorded for the geometry buffers (AOVs) of pbrt-v4's
//! `GBufferFilm`: position, normals, (u, v), the pixel footprint ∂p/∂x, ∂p/∂y, and the
//! BSDF's albedo. Recorded at the path's first vertex with a BSDF (interfaces between media are
//! looked through; a camera ray that first scatters in a medium records nothing), as pbrt-v4's
//! `VisibleSurface`.

use crate::bsdf::{Bsdf, TransportMode};
use crate::film::VisibleSurface;
use crate::scene::SurfaceInteraction;
use crate::spectrum::SampledSpectrum;
use crate::texture::Footprint;
use glam::{Vec2, Vec3};

/// Samples of the albedo estimate [`albedo`].
const ALBEDO_SAMPLES: u32 = 16;

/// The record of `si` with BSDF `bsdf`; `footprint` gives the pixel's footprint there (zero
/// without one).
pub fn visible_surface(si: &SurfaceInteraction, bsdf: &Bsdf, footprint: Option<Footprint>) -> VisibleSurface {
    let (dpdx, dpdy) = footprint.map_or((Vec3::ZERO, Vec3::ZERO), |f| f.dp_dxy(si.p, si.shading.ng, si.time));
    VisibleSurface {
        p: si.p,
        n: si.shading.ng,
        ns: bsdf.ns(),
        uv: si.uv,
        dpdx,
        dpdy,
        time: si.time,
        albedo: albedo(bsdf, si.wo),
    }
}

/// ρ(ω_o) by Monte Carlo with a fixed set of [`ALBEDO_SAMPLES`] BSDF samples (a Hammersley set
/// shifted to cell centres, and stratified lobe choices): (1/N) Σ f |cos θ_i| / pdf. The same
/// points at every pixel, so the albedo image carries no sampling noise of its own; exact for a
/// Lambertian BSDF, whose every sample weighs its reflectance.
pub fn albedo(bsdf: &Bsdf, wo: Vec3) -> SampledSpectrum {
    let n = ALBEDO_SAMPLES as f32;
    let mut sum = SampledSpectrum::zero();
    for i in 0..ALBEDO_SAMPLES {
        let uc = (i as f32 + 0.5) / n;
        // Van der Corput's radical inverse of i in base 2, over 16 points: bit-reversed i.
        let u = Vec2::new((i as f32 + 0.5) / n, ((i.reverse_bits() >> 28) as f32 + 0.5) / n);
        if let Some(bs) = bsdf.sample_f(wo, uc, u, TransportMode::Radiance) {
            if bs.pdf > 0.0 {
                sum += bs.f * (bs.wi.dot(bsdf.ns()).abs() / bs.pdf);
            }
        }
    }
    sum * (1.0 / n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::{Conductor, Diffuse, TrowbridgeReitz};

    #[test]
    fn the_albedo_of_a_lambertian_bsdf_is_its_reflectance_and_of_a_mirror_its_fresnel() {
        let n = Vec3::Z;
        let wo = Vec3::new(0.3, -0.2, 0.9).normalize();
        let r = SampledSpectrum::new([0.2, 0.4, 0.6, 0.8]);
        let diffuse = Bsdf::new(n, Vec3::X, n, Diffuse::new(r).into());
        let a = albedo(&diffuse, wo);
        for i in 0..4 {
            assert!((a[i] - r[i]).abs() < 1e-5, "{a:?} vs {r:?}");
        }
        // A smooth conductor seen head-on: ρ is its normal-incidence Fresnel reflectance,
        // ((η − 1)² + k²) / ((η + 1)² + k²), all of it sent back along the normal.
        let (eta, k) = (0.2, 3.0);
        let smooth = TrowbridgeReitz::new(0.0, 0.0);
        let conductor = Conductor::new(smooth, SampledSpectrum::splat(eta), SampledSpectrum::splat(k));
        let mirror = Bsdf::new(n, Vec3::X, n, conductor.into());
        let fresnel = ((eta - 1.0f32).powi(2) + k * k) / ((eta + 1.0f32).powi(2) + k * k);
        let a = albedo(&mirror, Vec3::Z);
        assert!((a[0] - fresnel).abs() < 1e-4, "{} vs {fresnel}", a[0]);
    }
}
