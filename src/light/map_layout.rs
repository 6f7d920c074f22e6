//! How an environment image covers the sphere of directions (light space, +z up): pbrt-v4's
//! square equal-area octahedral maps, or prism's latitude–longitude maps for other shapes.
//! Texel (x, y) is column x, row y counted from the top row of the file; (u, v) ∈ [0, 1]² runs
//! across and down, texel centres at ((x + ½)/w, (y + ½)/h).

use crate::math::equal_area::{self, SPHERE_PER_SQUARE};
use crate::math::PI;
use glam::{Vec2, Vec3};

/// The parameterisation of an environment map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapLayout {
    /// pbrt-v4's layout for every image infinite light (it rejects other shapes): Clarberg's
    /// equal-area octahedral mapping of a square image, (u, v) = (½, ½) at the zenith +z, the
    /// corners at the nadir, (1, ½) at +x and (½, 1) at +y (`math::equal_area`). Constant
    /// Jacobian dω = 4π du dv.
    EqualArea,
    /// prism's extension for images that are not square (pbrt-v3's layout): u = φ/2π with
    /// φ = atan2(y, x), v = θ/π with θ from +z, so row 0 is the zenith. Jacobian
    /// dω = 2π² sin θ du dv.
    LatLong,
}

impl MapLayout {
    /// Equal-area for a square image (pbrt-v4's maps), latitude–longitude otherwise.
    pub fn for_size(width: u32, height: u32) -> Self {
        if width == height {
            MapLayout::EqualArea
        } else {
            MapLayout::LatLong
        }
    }

    /// The unit direction at `uv` and the Jacobian dω/(du dv) there [sr] (0 at the poles of a
    /// latitude–longitude map, whose rows shrink to a point).
    pub fn direction(self, uv: Vec2) -> (Vec3, f32) {
        match self {
            MapLayout::EqualArea => (equal_area::square_to_sphere(uv), SPHERE_PER_SQUARE),
            MapLayout::LatLong => {
                let (theta, phi) = (uv.y * PI, uv.x * 2.0 * PI);
                let sin_theta = theta.sin().max(0.0);
                let d = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), theta.cos());
                (d, 2.0 * PI * PI * sin_theta)
            }
        }
    }

    /// The (u, v) of the unit direction `d` and the Jacobian dω/(du dv) there [sr].
    pub fn uv(self, d: Vec3) -> (Vec2, f32) {
        match self {
            MapLayout::EqualArea => (equal_area::sphere_to_square(d), SPHERE_PER_SQUARE),
            MapLayout::LatLong => {
                // sin θ from x, y rather than sin(acos z): near the poles acos loses precision,
                // and sin(π as f32) is negative.
                let sin_theta = (d.x * d.x + d.y * d.y).sqrt();
                let theta = sin_theta.atan2(d.z);
                let phi = d.y.atan2(d.x);
                let phi = if phi < 0.0 { phi + 2.0 * PI } else { phi };
                (Vec2::new(phi / (2.0 * PI), theta / PI), 2.0 * PI * PI * sin_theta)
            }
        }
    }

    /// Index (row-major) of the texel of a `width` × `height` image nearest to `uv`, i.e. the
    /// one containing it. An equal-area map's upper edges u = 1, v = 1 belong, by the
    /// octahedral wrap, to the mirrored texels of the last column and row.
    pub fn texel(self, uv: Vec2, width: usize, height: usize) -> usize {
        let (x, y) = ((uv.x * width as f32).floor() as i64, (uv.y * height as f32).floor() as i64);
        let (x, y) = match self {
            MapLayout::EqualArea => equal_area::wrap_pixel(x, y, width),
            MapLayout::LatLong => (x.clamp(0, width as i64 - 1) as usize, y.clamp(0, height as i64 - 1) as usize),
        };
        y * width + x
    }

    /// Solid angle [sr] of row `y`'s texels in a `width` × `height` map (every texel of an
    /// equal-area map has 4π/(w h); a latitude–longitude row spans θ₀..θ₁ and each of its
    /// texels (2π/w)(cos θ₀ − cos θ₁)).
    pub fn texel_solid_angle(self, y: usize, width: usize, height: usize) -> f64 {
        use std::f64::consts::PI;
        match self {
            MapLayout::EqualArea => 4.0 * PI / (width * height) as f64,
            MapLayout::LatLong => {
                let (t0, t1) = (PI * y as f64 / height as f64, PI * (y + 1) as f64 / height as f64);
                2.0 * PI / width as f64 * (t0.cos() - t1.cos())
            }
        }
    }

    /// ∫ max(cos θ, 0) dω over texel (x, y) [sr]: the weight of its radiance in the irradiance
    /// of a patch facing +z. Exact for a latitude–longitude row, (2π/w)·½(sin²θ₁ − sin²θ₀)
    /// clipped at the horizon. On an equal-area map cos θ = 1 − (|u'| + |v'|)² inside the
    /// horizon diamond (u' = 2u − 1, v' = 2v − 1): [`diamond_cosine_integral`].
    pub fn texel_cosine_weight(self, x: usize, y: usize, width: usize, height: usize) -> f64 {
        use std::f64::consts::{FRAC_PI_2, PI};
        match self {
            MapLayout::EqualArea => {
                let (n_u, n_v) = (width as f64, height as f64);
                let u = (2.0 * x as f64 / n_u - 1.0, 2.0 * (x + 1) as f64 / n_u - 1.0);
                let v = (2.0 * y as f64 / n_v - 1.0, 2.0 * (y + 1) as f64 / n_v - 1.0);
                let area = (u.1 - u.0) * (v.1 - v.0);
                self.texel_solid_angle(y, width, height) * diamond_cosine_integral(u, v, 8) / area
            }
            MapLayout::LatLong => {
                let t0 = PI * y as f64 / height as f64;
                let t1 = (PI * (y + 1) as f64 / height as f64).min(FRAC_PI_2);
                if t1 <= t0 {
                    return 0.0;
                }
                0.5 * (t1.sin().powi(2) - t0.sin().powi(2)) * 2.0 * PI / width as f64
            }
        }
    }
}

/// ∫∫ max(1 − (|u'| + |v'|)², 0) du' dv' over the rectangle `u` × `v`: 2 × 2 Gauss–Legendre
/// points, exact for the quadratic, on rectangles inside the diamond and one quadrant; those the
/// horizon |u'| + |v'| = 1 or an axis crosses are split in four, `depth` times, then take their
/// midpoint.
fn diamond_cosine_integral(u: (f64, f64), v: (f64, f64), depth: u32) -> f64 {
    let nearest = |a: f64, b: f64| if a * b <= 0.0 { 0.0 } else { a.abs().min(b.abs()) };
    let near = nearest(u.0, u.1) + nearest(v.0, v.1);
    let far = u.0.abs().max(u.1.abs()) + v.0.abs().max(v.1.abs());
    let area = (u.1 - u.0) * (v.1 - v.0);
    let cosine = |a: f64, b: f64| (1.0 - (a.abs() + b.abs()).powi(2)).max(0.0);
    let mid = |(a, b): (f64, f64)| 0.5 * (a + b);
    if near >= 1.0 {
        0.0
    } else if far <= 1.0 && u.0 * u.1 >= 0.0 && v.0 * v.1 >= 0.0 {
        let g = 0.5 / 3f64.sqrt();
        let at = |t: f64, (a, b): (f64, f64)| 0.5 * (a + b) + t * (b - a);
        let sum: f64 = [(-g, -g), (-g, g), (g, -g), (g, g)].iter().map(|&(s, t)| cosine(at(s, u), at(t, v))).sum();
        area * sum / 4.0
    } else if depth == 0 {
        area * cosine(mid(u), mid(v))
    } else {
        let (um, vm) = (mid(u), mid(v));
        [((u.0, um), (v.0, vm)), ((um, u.1), (v.0, vm)), ((u.0, um), (vm, v.1)), ((um, u.1), (vm, v.1))]
            .iter()
            .map(|&(a, b)| diamond_cosine_integral(a, b, depth - 1))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texel_solid_angles_cover_the_sphere() {
        for (layout, w, h) in [(MapLayout::EqualArea, 16, 16), (MapLayout::LatLong, 24, 12)] {
            let total: f64 = (0..h).map(|y| layout.texel_solid_angle(y, w, h) * w as f64).sum();
            assert!((total - 4.0 * std::f64::consts::PI).abs() < 1e-9, "{layout:?}: {total}");
        }
    }

    fn weight_sum(
        layout: MapLayout,
        w: usize,
        h: usize,
        weight: fn(MapLayout, usize, usize, usize, usize) -> f64,
    ) -> f64 {
        (0..h).flat_map(|y| (0..w).map(move |x| weight(layout, x, y, w, h))).sum()
    }

    #[test]
    fn cosine_weights_sum_to_pi_over_the_upper_hemisphere() {
        // ∫_{H²} cos θ dω = π, for even and odd sizes (an odd one has texels on the axes).
        let pi = std::f64::consts::PI;
        assert!((weight_sum(MapLayout::LatLong, 20, 10, MapLayout::texel_cosine_weight) - pi).abs() < 1e-12);
        for n in [1, 5, 16, 33] {
            let sum = weight_sum(MapLayout::EqualArea, n, n, MapLayout::texel_cosine_weight);
            assert!((sum - pi).abs() < 1e-4 * pi, "{n}²: {sum}");
        }
    }

    #[test]
    fn texel_of_a_direction_is_the_texel_whose_region_maps_there() {
        let (w, h) = (8, 8);
        let layout = MapLayout::EqualArea;
        for y in 0..h {
            for x in 0..w {
                let centre = Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                let (d, _) = layout.direction(centre);
                let (uv, _) = layout.uv(d);
                assert_eq!(layout.texel(uv, w, h), y * w + x, "texel ({x}, {y})");
            }
        }
        // The edges u = 1 and v = 1 wrap to the mirrored texel of the last column or row.
        assert_eq!(layout.texel(Vec2::new(1.0, 0.1), w, h), (h - 1) * w + (w - 1));
        assert_eq!(layout.texel(Vec2::new(0.1, 1.0), w, h), (h - 1) * w + (w - 1));
        assert_eq!(layout.texel(Vec2::new(1.0, 1.0), w, h), 0);
    }
}
