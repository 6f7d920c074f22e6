//! The film: per-pixel sums of filter-weighted XYZ estimates, turned into the output colour
//! space once at the end, and, when asked for, the geometry buffers ([`gbuffer`]) or the
//! spectral buckets ([`spectral`]) beside them. Sums are f64 so long renders and merged parts
//! lose nothing.

mod adaptive;
pub mod gbuffer;
pub mod spectral;
mod splat;
mod strategy_images;
mod visible_surface;

pub use adaptive::AdaptivePixel;
pub use gbuffer::{AovPixel, AovSettings, AovSpace};
pub use spectral::{SpectralSettings, SpectralSums};
pub use splat::{Splat, SplatBuffer};
pub use strategy_images::StrategyImages;
pub use visible_surface::VisibleSurface;

use crate::image::Image;
use crate::sensor::Sensor;
use crate::spectrum::ColorSpace;
use glam::{DVec3, Vec3};

/// The pixels of the full image that are rendered: [x0, x1) × [y0, y1) (pbrt-v4's pixel bounds).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelBounds {
    /// First column.
    pub x0: u32,
    /// One past the last column.
    pub x1: u32,
    /// First row.
    pub y0: u32,
    /// One past the last row.
    pub y1: u32,
}

/// How a crop is asked for, before the resolution is known.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Crop {
    /// pbrt-v4's "cropwindow" [x0, x1, y0, y1] in fractions of the image (0 = left/top).
    Window([f32; 4]),
    /// pbrt-v4's "pixelbounds" [x0, x1, y0, y1] in pixels.
    Pixels([i64; 4]),
}

impl Crop {
    /// The pixels this crop selects from an image of `resolution`, as pbrt-v4 computes them
    /// (a window's corners are sorted, clamped to [0, 1] and rounded up to pixels; pixel bounds
    /// are clipped to the image). An empty selection is an error.
    pub fn bounds(&self, resolution: (u32, u32)) -> Result<PixelBounds, CropError> {
        let (w, h) = (resolution.0 as i64, resolution.1 as i64);
        let [x0, x1, y0, y1] = match *self {
            Crop::Window(c) => {
                if c.iter().any(|v| !v.is_finite()) {
                    return Err(CropError::NotFinite(*self));
                }
                // In f32 as pbrt-v4 computes it, so the same window selects the same pixels.
                let px = |v: f32, n: i64| (v.clamp(0.0, 1.0) * n as f32).ceil() as i64;
                [px(c[0].min(c[1]), w), px(c[0].max(c[1]), w), px(c[2].min(c[3]), h), px(c[2].max(c[3]), h)]
            }
            Crop::Pixels(p) => [p[0].clamp(0, w), p[1].clamp(0, w), p[2].clamp(0, h), p[3].clamp(0, h)],
        };
        if x0 >= x1 || y0 >= y1 {
            return Err(CropError::Empty { crop: *self, width: w, height: h });
        }
        Ok(PixelBounds { x0: x0 as u32, x1: x1 as u32, y0: y0 as u32, y1: y1 as u32 })
    }
}

/// A crop that selects no pixels.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum CropError {
    /// A window with a NaN or infinite corner.
    #[error("{0} is not finite")]
    NotFinite(Crop),
    /// Nothing of the image lies inside it.
    #[error("{crop} selects no pixels of a {width}x{height} image")]
    Empty {
        /// The crop as asked for.
        crop: Crop,
        /// The image's width [pixels].
        width: i64,
        /// The image's height [pixels].
        height: i64,
    },
}

impl std::fmt::Display for Crop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Crop::Window([a, b, c, d]) => write!(f, "cropwindow [{a} {b} {c} {d}]"),
            Crop::Pixels([a, b, c, d]) => write!(f, "pixelbounds [{a} {b} {c} {d}]"),
        }
    }
}

/// What the film records of the full image: which pixels, through which sensor.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FilmSettings {
    /// Only these pixels (the film is their size); `None`: the whole image.
    pub crop: Option<PixelBounds>,
    /// The sensor's response (ISO, exposure, white balance).
    pub sensor: Sensor,
    /// The geometry buffers, when they are recorded (pbrt-v4's `gbuffer` film).
    pub aov: Option<AovSettings>,
    /// The spectral buckets, when they are recorded (pbrt-v4's `spectral` film).
    pub spectral: Option<SpectralSettings>,
}

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
    /// Row-major geometry-buffer sums, when they are recorded.
    pub aov: Option<Vec<AovPixel>>,
    /// Spectral bucket sums, when they are recorded.
    pub spectral: Option<SpectralSums>,
    /// Light splatted onto the film by estimators that trace from the lights, when the
    /// integrator does ([`SplatBuffer`]).
    pub splats: Option<SplatBuffer>,
    /// The bidirectional estimator's per-strategy images, when they are asked for. They hold
    /// the samples of one render call: parts and checkpoints do not carry them.
    pub strategies: Option<StrategyImages>,
}

/// A film (or a buffer of its size) that does not fit in memory.
#[derive(Clone, Debug, thiserror::Error)]
#[error("out of memory: a {width}x{height} film needs {gib:.1} GiB")]
pub struct FilmAllocError {
    /// Width [pixels].
    pub width: u32,
    /// Height [pixels].
    pub height: u32,
    /// Bytes asked for [GiB].
    pub gib: f64,
}

impl Film {
    /// An empty film; aborts like `vec!` if it does not fit in memory (see [`Film::try_new`]).
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![Pixel::default(); width as usize * height as usize],
            aov: None,
            spectral: None,
            splats: None,
            strategies: None,
        }
    }

    /// An empty film, or an error naming its size when the allocation fails.
    pub fn try_new(width: u32, height: u32) -> Result<Self, FilmAllocError> {
        let n = width as usize * height as usize;
        let mut pixels = Vec::new();
        pixels.try_reserve_exact(n).map_err(|_| Self::alloc_error(width, height, n * size_of::<Pixel>()))?;
        pixels.resize(n, Pixel::default());
        Ok(Self { width, height, pixels, aov: None, spectral: None, splats: None, strategies: None })
    }

    /// This film with a splat buffer, for an image of `full_pixels` pixels of which the film may
    /// be a crop, or an error naming its size when it does not fit.
    pub fn try_with_splats(mut self, full_pixels: u64) -> Result<Self, FilmAllocError> {
        let n = self.pixels.len();
        let mut sums = Vec::new();
        sums.try_reserve_exact(n).map_err(|_| Self::alloc_error(self.width, self.height, n * size_of::<DVec3>()))?;
        sums.resize(n, DVec3::ZERO);
        self.splats = Some(SplatBuffer { xyz_sum: sums, paths: 0, full_pixels });
        Ok(self)
    }

    /// This film with geometry buffers, or an error naming its size when they do not fit.
    pub fn try_with_aov(mut self) -> Result<Self, FilmAllocError> {
        let n = self.pixels.len();
        let mut aov = Vec::new();
        aov.try_reserve_exact(n).map_err(|_| Self::alloc_error(self.width, self.height, n * size_of::<AovPixel>()))?;
        aov.resize(n, AovPixel::default());
        self.aov = Some(aov);
        Ok(self)
    }

    /// This film with spectral buckets, or an error naming their size when they do not fit.
    pub fn try_with_spectral(mut self, settings: SpectralSettings) -> Result<Self, FilmAllocError> {
        let n = self.pixels.len().saturating_mul(settings.stride());
        let mut sums = Vec::new();
        sums.try_reserve_exact(n).map_err(|_| Self::alloc_error(self.width, self.height, n.saturating_mul(8)))?;
        sums.resize(n, 0.0);
        self.spectral = Some(SpectralSums { settings, sums });
        Ok(self)
    }

    /// An empty film with the buffers `settings` asks for.
    pub fn try_for(width: u32, height: u32, settings: &FilmSettings) -> Result<Self, FilmAllocError> {
        let mut film = Self::try_new(width, height)?;
        if settings.aov.is_some() {
            film = film.try_with_aov()?;
        }
        if let Some(s) = settings.spectral {
            film = film.try_with_spectral(s)?;
        }
        Ok(film)
    }

    /// The error for a `width × height` film whose buffer of `bytes` could not be allocated.
    pub fn alloc_error(width: u32, height: u32, bytes: usize) -> FilmAllocError {
        FilmAllocError { width, height, gib: bytes as f64 / (1u64 << 30) as f64 }
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
        if let (Some(a), Some(b)) = (self.aov.as_mut(), other.aov.as_ref()) {
            for (a, b) in a.iter_mut().zip(b) {
                a.merge(b);
            }
        }
        if let (Some(a), Some(b)) = (self.spectral.as_mut(), other.spectral.as_ref()) {
            for (a, b) in a.sums.iter_mut().zip(&b.sums) {
                *a += b;
            }
        }
        if let (Some(a), Some(b)) = (self.splats.as_mut(), other.splats.as_ref()) {
            a.merge(b);
        }
    }

    /// Reconstructed XYZ of pixel (x, y): the filter-weighted mean of its samples, plus the
    /// light splatted onto it.
    pub fn xyz(&self, x: u32, y: u32) -> Vec3 {
        let i = (y * self.width + x) as usize;
        let p = &self.pixels[i];
        let mean = if p.weight_sum != 0.0 { p.xyz_sum / p.weight_sum } else { DVec3::ZERO };
        match &self.splats {
            None => mean.as_vec3(),
            Some(s) => (mean + s.xyz(i)).as_vec3(),
        }
    }

    /// The image of bidirectional strategy (s, t) as a film of its own (its light held as
    /// splats), when the film records strategy images.
    pub fn strategy_film(&self, s: usize, t: usize) -> Option<Film> {
        let buffer = self.strategies.as_ref()?.images.get(StrategyImages::index(s, t))?;
        let mut film = Film::new(self.width, self.height);
        film.splats = Some(buffer.clone());
        Some(film)
    }

    /// Total samples taken over all pixels.
    pub fn total_samples(&self) -> u64 {
        self.pixels.iter().map(|p| p.samples).sum()
    }

    /// The film as a linear RGB image in `space` (3 channels, row-major), or an error naming
    /// its size when the image does not fit in memory.
    pub fn to_image(&self, space: &ColorSpace) -> Result<Image, FilmAllocError> {
        let n = self.pixels.len() * 3;
        let mut data = Vec::new();
        data.try_reserve_exact(n).map_err(|_| Self::alloc_error(self.width, self.height, n * 4))?;
        for y in 0..self.height {
            for x in 0..self.width {
                data.extend_from_slice(&space.xyz_to_rgb(self.xyz(x, y)).to_array());
            }
        }
        Ok(Image { width: self.width, height: self.height, channels: 3, data })
    }

    /// The names of the image's channels: R, G, B, then the geometry buffers' (when `aov` and
    /// the film holds them), then the spectral buckets' (when it holds them).
    pub fn channel_names(&self, aov: bool) -> Vec<String> {
        let aov = self.aov.iter().filter(|_| aov).flat_map(|_| gbuffer::CHANNELS[3..].iter().map(|c| c.to_string()));
        let spectral = self.spectral.iter().flat_map(|s| s.settings.channel_names());
        ["R", "G", "B"].map(String::from).into_iter().chain(aov).chain(spectral).collect()
    }

    /// The film as an image in `space` of its [`Self::channel_names`] (`None` when that is R,
    /// G, B only).
    pub fn to_layered_image(&self, space: &ColorSpace, aov: bool) -> Option<Result<Image, FilmAllocError>> {
        let aov = self.aov.as_ref().filter(|_| aov);
        if aov.is_none() && self.spectral.is_none() {
            return None;
        }
        let c = self.channel_names(aov.is_some()).len();
        let n = self.pixels.len() * c;
        let mut data = Vec::new();
        if data.try_reserve_exact(n).is_err() {
            return Some(Err(Self::alloc_error(self.width, self.height, n * 4)));
        }
        for (i, p) in self.pixels.iter().enumerate() {
            let (x, y) = (i as u32 % self.width, i as u32 / self.width);
            data.extend_from_slice(&space.xyz_to_rgb(self.xyz(x, y)).to_array());
            if let Some(a) = aov {
                data.extend_from_slice(&a[i].channels(p.weight_sum, space));
            }
            if let Some(s) = &self.spectral {
                let stride = s.settings.stride();
                data.extend(s.settings.means(&s.sums[i * stride..(i + 1) * stride]));
            }
        }
        Some(Ok(Image { width: self.width, height: self.height, channels: c as u32, data }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crops_select_pixels_as_pbrt_v4_does() {
        let b = |x0, x1, y0, y1| PixelBounds { x0, x1, y0, y1 };
        // Corners in either order, clamped to the image, rounded up.
        assert_eq!(Crop::Window([0.6, 0.25, 0.1, 0.5]).bounds((40, 30)), Ok(b(10, 24, 3, 15)));
        assert_eq!(Crop::Window([-1.0, 2.0, 0.0, 1.0]).bounds((7, 5)), Ok(b(0, 7, 0, 5)));
        assert_eq!(Crop::Window([0.0, 0.01, 0.0, 1.0]).bounds((40, 30)), Ok(b(0, 1, 0, 30)));
        // Pixel bounds are clipped to the image.
        assert_eq!(Crop::Pixels([-5, 10, 20, 99]).bounds((40, 30)), Ok(b(0, 10, 20, 30)));
        // Empty or non-finite: errors.
        assert!(Crop::Window([0.5, 0.5, 0.0, 1.0]).bounds((40, 30)).is_err());
        assert!(Crop::Window([f32::NAN, 0.5, 0.0, 1.0]).bounds((40, 30)).is_err());
        assert!(Crop::Pixels([50, 60, 0, 10]).bounds((40, 30)).is_err());
        assert!(Crop::Pixels([10, 5, 0, 10]).bounds((40, 30)).is_err());
    }
}
