//! The film: per-pixel sums of filter-weighted XYZ estimates, turned into the output colour
//! space once at the end. Sums are f64 so long renders and merged parts lose nothing.

use glam::{DVec3, Vec3};

/// Accumulated samples of one pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pixel {
    /// Σ w·XYZ.
    pub xyz_sum: DVec3,
    /// Σ w.
    pub weight_sum: f64,
    /// Number of samples taken.
    pub samples: u64,
}

/// A rectangular film of `width × height` pixels.
#[derive(Clone, Debug)]
pub struct Film {
    /// Width [pixels].
    pub width: u32,
    /// Height [pixels].
    pub height: u32,
    /// Row-major pixels.
    pub pixels: Vec<Pixel>,
}

impl Film {
    /// An empty film.
    pub fn new(width: u32, height: u32) -> Self {
        Self { width, height, pixels: vec![Pixel::default(); width as usize * height as usize] }
    }

    /// Adds one sample's XYZ estimate with filter weight `w` to pixel (x, y).
    #[inline]
    pub fn add_sample(&mut self, x: u32, y: u32, xyz: Vec3, w: f32) {
        let p = &mut self.pixels[(y * self.width + x) as usize];
        p.xyz_sum += xyz.as_dvec3() * w as f64;
        p.weight_sum += w as f64;
        p.samples += 1;
    }

    /// Adds another film's sums (a tile, or a part of a split render).
    pub fn merge(&mut self, other: &Film) {
        for (a, b) in self.pixels.iter_mut().zip(&other.pixels) {
            a.xyz_sum += b.xyz_sum;
            a.weight_sum += b.weight_sum;
            a.samples += b.samples;
        }
    }

    /// Reconstructed XYZ of pixel (x, y).
    pub fn xyz(&self, x: u32, y: u32) -> Vec3 {
        let p = &self.pixels[(y * self.width + x) as usize];
        if p.weight_sum != 0.0 {
            (p.xyz_sum / p.weight_sum).as_vec3()
        } else {
            Vec3::ZERO
        }
    }

    /// Total samples taken over all pixels.
    pub fn total_samples(&self) -> u64 {
        self.pixels.iter().map(|p| p.samples).sum()
    }
}
