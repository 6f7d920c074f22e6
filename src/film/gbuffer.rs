//! Geometry buffers (AOVs) beside the image, as pbrt-v4's `GBufferFilm` writes them: per pixel
//! the filter-weighted means of the first visible surface's albedo, position, normals, depth
//! slopes and (u, v), and the variance of the samples. Positions and normals are in camera space
//! (pbrt-v4's default: x right, y up, z along the view) or world space.

use super::VisibleSurface;
use crate::spectrum::{ColorSpace, SampledWavelengths};
use glam::{DVec2, DVec3, Mat3, Mat4, Vec3};

/// The space positions and normals are written in (pbrt-v4's `coordinatesystem`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AovSpace {
    /// The camera's space at the sample's time (pbrt-v4's default).
    #[default]
    Camera,
    /// World space.
    World,
}

crate::named::name_table!(AovSpace, "coordinate system", {
    "camera" => AovSpace::Camera,
    "world" => AovSpace::World,
});

/// What the film records besides the image: the geometry buffers' space, and the colour space
/// whose white lights the albedo (pbrt-v4 multiplies the albedo by the space's illuminant, so a
/// white surface has albedo (1, 1, 1)).
#[derive(Clone, Copy)]
pub struct AovSettings {
    /// Where positions and normals are expressed.
    pub coordinates: AovSpace,
    /// The output colour space.
    pub space: &'static ColorSpace,
}

impl std::fmt::Debug for AovSettings {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "AovSettings {{ coordinates: {}, space: {} }}", self.coordinates.name(), self.space.name)
    }
}

impl PartialEq for AovSettings {
    fn eq(&self, other: &Self) -> bool {
        self.coordinates == other.coordinates && self.space.name == other.space.name
    }
}

/// The channels of a geometry-buffer image, in pbrt-v4's names and order.
pub const CHANNELS: [&str; 25] = [
    "R",
    "G",
    "B",
    "Albedo.R",
    "Albedo.G",
    "Albedo.B",
    "P.X",
    "P.Y",
    "P.Z",
    "dzdx",
    "dzdy",
    "N.X",
    "N.Y",
    "N.Z",
    "Ns.X",
    "Ns.Y",
    "Ns.Z",
    "u",
    "v",
    "Variance.R",
    "Variance.G",
    "Variance.B",
    "RelativeVariance.R",
    "RelativeVariance.G",
    "RelativeVariance.B",
];

/// Running mean and sum of squared deviations of a 3-vector (Welford 1962), merged by Chan
/// et al.'s pairwise rule (1979).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Moments {
    /// Samples.
    pub n: u64,
    /// Their mean.
    pub mean: DVec3,
    /// Σ (x − mean)².
    pub m2: DVec3,
}

impl Moments {
    /// Adds one sample.
    pub fn add(&mut self, x: DVec3) {
        self.n += 1;
        let delta = x - self.mean;
        self.mean += delta / self.n as f64;
        self.m2 += delta * (x - self.mean);
    }

    /// Adds another set of samples.
    pub fn merge(&mut self, o: &Moments) {
        if o.n == 0 {
            return;
        }
        let n = (self.n + o.n) as f64;
        let delta = o.mean - self.mean;
        self.m2 += o.m2 + delta * delta * (self.n as f64 * o.n as f64 / n);
        self.mean += delta * (o.n as f64 / n);
        self.n += o.n;
    }

    /// The unbiased sample variance (0 below two samples).
    pub fn variance(&self) -> DVec3 {
        if self.n > 1 {
            self.m2 / (self.n - 1) as f64
        } else {
            DVec3::ZERO
        }
    }

    /// Variance over mean, per component (0 where the mean is 0), as pbrt-v4 defines it.
    pub fn relative_variance(&self) -> DVec3 {
        let v = self.variance();
        let rel = |v: f64, m: f64| if m == 0.0 { 0.0 } else { v / m };
        DVec3::new(rel(v.x, self.mean.x), rel(v.y, self.mean.y), rel(v.z, self.mean.z))
    }
}

/// Sums of one pixel's geometry buffers.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AovPixel {
    /// Σ w·XYZ of the albedo lit by the colour space's white (over samples that saw a surface;
    /// divided by the pixel's whole weight, as pbrt-v4, so misses darken it).
    pub albedo_sum: DVec3,
    /// Σ w over samples that saw a surface.
    pub weight_sum: f64,
    /// Σ w·p.
    pub p_sum: DVec3,
    /// Σ w·n (normalised at the end).
    pub n_sum: DVec3,
    /// Σ w·n_s (normalised at the end).
    pub ns_sum: DVec3,
    /// Σ w·(∂z/∂x, ∂z/∂y).
    pub dz_sum: DVec2,
    /// Σ w·(u, v).
    pub uv_sum: DVec2,
    /// Moments of the samples' sensor response (XYZ for the CIE 1931 sensor, as pbrt-v4's
    /// sensor RGB is), unweighted, over samples that saw a surface.
    pub moments: Moments,
}

impl AovPixel {
    /// Adds a sample that saw `v` at wavelengths `w`, with filter weight `weight` and sensor
    /// response `response`; `out_from_world` is the output space at the sample's time.
    pub fn add(
        &mut self,
        v: &VisibleSurface,
        w: &SampledWavelengths,
        settings: &AovSettings,
        out_from_world: &Mat4,
        response: Vec3,
        weight: f32,
    ) {
        let wt = f64::from(weight);
        let normal_matrix = Mat3::from_mat4(*out_from_world).inverse().transpose();
        let lit = v.albedo * settings.space.illuminant.sample(w);
        self.albedo_sum += lit.to_xyz(w).as_dvec3() * wt;
        self.weight_sum += wt;
        self.p_sum += out_from_world.transform_point3(v.p).as_dvec3() * wt;
        self.n_sum += (normal_matrix * v.n).as_dvec3() * wt;
        self.ns_sum += (normal_matrix * v.ns).as_dvec3() * wt;
        let dz = |d: Vec3| f64::from(out_from_world.transform_vector3(d).z);
        self.dz_sum += DVec2::new(dz(v.dpdx), dz(v.dpdy)) * wt;
        self.uv_sum += v.uv.as_dvec2() * wt;
        self.moments.add(response.as_dvec3());
    }

    /// Adds another film's sums of the same pixel.
    pub fn merge(&mut self, o: &AovPixel) {
        self.albedo_sum += o.albedo_sum;
        self.weight_sum += o.weight_sum;
        self.p_sum += o.p_sum;
        self.n_sum += o.n_sum;
        self.ns_sum += o.ns_sum;
        self.dz_sum += o.dz_sum;
        self.uv_sum += o.uv_sum;
        self.moments.merge(&o.moments);
    }

    /// Bytes of one pixel in a film file ([`Self::write_le`]).
    pub const FILE_BYTES: usize = 24 * 8;

    /// Appends the sums as 23 little-endian f64 and the sample count as a u64.
    pub fn write_le(&self, out: &mut Vec<u8>) {
        let (m, d) = (&self.moments, [self.dz_sum, self.uv_sum]);
        let v3 = [self.albedo_sum, self.p_sum, self.n_sum, self.ns_sum, m.mean, m.m2];
        let words = v3.iter().flat_map(|v| v.to_array()).chain(d.iter().flat_map(|v| v.to_array()));
        for w in words.chain([self.weight_sum]) {
            out.extend_from_slice(&w.to_le_bytes());
        }
        out.extend_from_slice(&m.n.to_le_bytes());
    }

    /// Reads what [`Self::write_le`] wrote (`bytes` is [`Self::FILE_BYTES`] long); `None` when
    /// a sum is not finite.
    pub fn read_le(bytes: &[u8]) -> Option<Self> {
        let word = |i: usize| f64::from_le_bytes(bytes[i * 8..i * 8 + 8].try_into().expect("8 bytes"));
        let v3 = |k: usize| DVec3::new(word(3 * k), word(3 * k + 1), word(3 * k + 2));
        let v2 = |k: usize| DVec2::new(word(18 + 2 * k), word(19 + 2 * k));
        let p = AovPixel {
            albedo_sum: v3(0),
            p_sum: v3(1),
            n_sum: v3(2),
            ns_sum: v3(3),
            moments: Moments {
                n: u64::from_le_bytes(bytes[184..192].try_into().expect("8 bytes")),
                mean: v3(4),
                m2: v3(5),
            },
            dz_sum: v2(0),
            uv_sum: v2(1),
            weight_sum: word(22),
        };
        let finite =
            [p.albedo_sum, p.p_sum, p.n_sum, p.ns_sum, p.moments.mean, p.moments.m2].iter().all(|v| v.is_finite())
                && p.dz_sum.is_finite()
                && p.uv_sum.is_finite()
                && p.weight_sum.is_finite();
        finite.then_some(p)
    }

    /// The 22 channels after R, G, B ([`CHANNELS`][3..]), given the pixel's whole filter
    /// weight `pixel_weight` and the output colour space.
    pub fn channels(&self, pixel_weight: f64, space: &ColorSpace) -> [f32; 22] {
        let albedo = if pixel_weight != 0.0 { self.albedo_sum / pixel_weight } else { DVec3::ZERO };
        let albedo = space.xyz_to_rgb(albedo.as_vec3());
        let mean = |s: DVec3| if self.weight_sum != 0.0 { s / self.weight_sum } else { DVec3::ZERO };
        let mean2 = |s: DVec2| if self.weight_sum != 0.0 { s / self.weight_sum } else { DVec2::ZERO };
        let (p, dz, uv) = (mean(self.p_sum), mean2(self.dz_sum), mean2(self.uv_sum));
        let (n, ns) = (self.n_sum.normalize_or_zero(), self.ns_sum.normalize_or_zero());
        let (var, rel) = (self.moments.variance(), self.moments.relative_variance());
        let f = |x: f64| x as f32;
        [
            albedo.x,
            albedo.y,
            albedo.z,
            f(p.x),
            f(p.y),
            f(p.z),
            f(dz.x.abs()),
            f(dz.y.abs()),
            f(n.x),
            f(n.y),
            f(n.z),
            f(ns.x),
            f(ns.y),
            f(ns.z),
            f(uv.x),
            f(uv.y),
            f(var.x),
            f(var.y),
            f(var.z),
            f(rel.x),
            f(rel.y),
            f(rel.z),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pixel_reads_back_as_written() {
        let mut p = AovPixel {
            albedo_sum: DVec3::new(0.1, 0.2, 0.3),
            weight_sum: 2.5,
            p_sum: DVec3::new(1.0, -2.0, 3.0),
            n_sum: DVec3::new(0.0, 0.6, 0.8),
            ns_sum: DVec3::new(0.6, 0.0, 0.8),
            dz_sum: DVec2::new(0.01, -0.02),
            uv_sum: DVec2::new(0.25, 0.75),
            moments: Moments::default(),
        };
        p.moments.add(DVec3::new(1.0, 2.0, 3.0));
        p.moments.add(DVec3::new(2.0, 2.0, 5.0));
        let mut bytes = Vec::new();
        p.write_le(&mut bytes);
        assert_eq!(bytes.len(), AovPixel::FILE_BYTES);
        assert_eq!(AovPixel::read_le(&bytes), Some(p));
        bytes[0..8].copy_from_slice(&f64::NAN.to_le_bytes());
        assert_eq!(AovPixel::read_le(&bytes), None);
    }

    #[test]
    fn moments_give_the_sample_variance_and_merge_as_if_added_in_one() {
        let xs = [1.0, 4.0, 2.0, 8.0, 5.0];
        let (mut all, mut a, mut b) = (Moments::default(), Moments::default(), Moments::default());
        for (i, &x) in xs.iter().enumerate() {
            let v = DVec3::new(x, 2.0 * x, 0.0);
            all.add(v);
            if i < 2 {
                a.add(v)
            } else {
                b.add(v)
            }
        }
        // mean 4, Σ(x − 4)² = 9 + 0 + 4 + 16 + 1 = 30, variance 30/4.
        assert!((all.variance().x - 7.5).abs() < 1e-12 && (all.variance().y - 30.0).abs() < 1e-12);
        assert!((all.relative_variance().x - 7.5 / 4.0).abs() < 1e-12 && all.relative_variance().z == 0.0);
        a.merge(&b);
        assert_eq!(a.n, 5);
        assert!((a.mean - all.mean).length() < 1e-12 && (a.m2 - all.m2).length() < 1e-9);
    }
}
