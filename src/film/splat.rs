//! Light arriving at the film through estimators that start at the lights (light tracing,
//! bidirectional strategies with one camera vertex): each contribution lands at a film position
//! of its own, not at the pixel whose sample made it, and is spread over the pixels the
//! reconstruction filter reaches there (pbrt-v4 `RGBFilm::AddSplat`).
//!
//! A pixel's splatted value estimates I_j = ∫ h_j(p) L(p) dp with h_j the filter about pixel j
//! normalised to unit integral: with N light paths traced for an image of M pixels and the
//! camera's importance W_e normalised over the whole image (Veach 1997, §10.3.4), that is
//! (M / N) Σ h_j W_e L G / pdf, so the buffer keeps Σ h_j · (contribution) per pixel, the number
//! of paths N, and scales by M / N on output.
//!
//! Splats are gathered per band of rows in the order the band's samples make them and added
//! here band by band in a fixed order, so the sums are the same for any thread count.

use crate::filter::Filter;
use glam::{DVec3, Vec2, Vec3};

/// One contribution at a film position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Splat {
    /// Position in the full image [pixels, origin at the top-left corner].
    pub p_raster: Vec2,
    /// The contribution's XYZ (the sensor's response to it, before the 1/N scale).
    pub xyz: Vec3,
}

/// The film's buffer of splatted light.
#[derive(Clone, Debug, PartialEq)]
pub struct SplatBuffer {
    /// Per film pixel, Σ h_j · XYZ of the splats (h_j normalised to unit integral).
    pub xyz_sum: Vec<DVec3>,
    /// Light paths traced (over the whole film), N.
    pub paths: u64,
    /// Pixels of the full image, M (the film may be a crop of it).
    pub full_pixels: u64,
}

impl SplatBuffer {
    /// An empty buffer for `pixels` film pixels of an image of `full_pixels`.
    pub fn new(pixels: usize, full_pixels: u64) -> Self {
        Self { xyz_sum: vec![DVec3::ZERO; pixels], paths: 0, full_pixels }
    }

    /// Adds `splat` to the pixels of a film `width × height` whose pixel (0, 0) is the full
    /// image's `origin` that `filter` reaches from it.
    pub fn add(&mut self, splat: &Splat, filter: &Filter, width: u32, height: u32, origin: (u32, u32)) {
        // Film coordinates: pixel (i, j) has its centre at (i + ½, j + ½).
        let p = splat.p_raster - Vec2::new(origin.0 as f32, origin.1 as f32);
        let r = filter.radius();
        let norm = 1.0 / filter.integral() as f64;
        // Pixels whose centre c lies in [p − r, p + r): half-open, so that a splat on a pixel
        // edge is not given to both pixels by a box filter.
        let x0 = (p.x - 0.5 - r.x).ceil().max(0.0) as i64;
        let x1 = ((p.x - 0.5 + r.x).ceil() as i64 - 1).min(width as i64 - 1);
        let y0 = (p.y - 0.5 - r.y).ceil().max(0.0) as i64;
        let y1 = ((p.y - 0.5 + r.y).ceil() as i64 - 1).min(height as i64 - 1);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let h = filter.eval(p - Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
                if h != 0.0 {
                    self.xyz_sum[(y * width as i64 + x) as usize] += splat.xyz.as_dvec3() * (h as f64 * norm);
                }
            }
        }
    }

    /// The splatted XYZ of film pixel `i`: its sum times M / N.
    pub fn xyz(&self, i: usize) -> DVec3 {
        if self.paths == 0 {
            return DVec3::ZERO;
        }
        self.xyz_sum[i] * (self.full_pixels as f64 / self.paths as f64)
    }

    /// Adds another buffer's sums and paths (a part of a split render).
    pub fn merge(&mut self, o: &SplatBuffer) {
        for (a, b) in self.xyz_sum.iter_mut().zip(&o.xyz_sum) {
            *a += *b;
        }
        self.paths += o.paths;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_splat_spreads_its_whole_weight_over_the_pixels_the_filter_reaches() {
        // Far from the edges the weights h_j sum to the filter's integral over the pixel
        // lattice, ≈ 1 after normalisation; a box filter of radius ½ puts it all in one pixel.
        for name in ["gaussian", "triangle", "mitchell"] {
            let f = Filter::by_name(name).unwrap();
            let mut b = SplatBuffer::new(32 * 32, 1024);
            b.add(&Splat { p_raster: Vec2::new(15.3, 16.8), xyz: Vec3::ONE }, &f, 32, 32, (0, 0));
            let total: f64 = b.xyz_sum.iter().map(|v| v.y).sum();
            assert!((total - 1.0).abs() < 0.03, "{name}: {total}");
        }
        let boxf = Filter::by_name("box").unwrap();
        let mut b = SplatBuffer::new(16, 16);
        b.add(&Splat { p_raster: Vec2::new(2.7, 1.2), xyz: Vec3::splat(2.0) }, &boxf, 4, 4, (0, 0));
        assert_eq!(b.xyz_sum[4 + 2], DVec3::splat(2.0));
        assert_eq!(b.xyz_sum.iter().filter(|v| v.y != 0.0).count(), 1);
        // A crop: the full image's pixel (5, 3) is the film's (2, 1) when the film starts at (3, 2).
        let mut c = SplatBuffer::new(16, 100);
        c.add(&Splat { p_raster: Vec2::new(5.5, 3.5), xyz: Vec3::ONE }, &boxf, 4, 4, (3, 2));
        assert_eq!(c.xyz_sum[4 + 2], DVec3::ONE);
        // On the edge between four pixels, a box filter gives it to one of them.
        let mut e = SplatBuffer::new(16, 16);
        e.add(&Splat { p_raster: Vec2::new(2.0, 3.0), xyz: Vec3::ONE }, &boxf, 4, 4, (0, 0));
        assert_eq!(e.xyz_sum.iter().map(|v| v.x).sum::<f64>(), 1.0);
        // Out of the film: nothing.
        c.add(&Splat { p_raster: Vec2::new(0.5, 0.5), xyz: Vec3::ONE }, &boxf, 4, 4, (3, 2));
        assert_eq!(c.xyz_sum.iter().map(|v| v.x).sum::<f64>(), 1.0);
        c.paths = 50;
        assert_eq!(c.xyz(6), DVec3::splat(2.0));
    }
}
