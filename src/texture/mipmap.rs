//! MIP-maps (Williams 1983) and the filters pbrt-v4 looks them up with (§10.4.3): a pyramid of
//! box-filtered half-resolution levels, a level chosen from the footprint's width, then a
//! point, bilinear or trilinear lookup, or elliptically weighted averaging (EWA; Heckbert
//! 1989) of the texels under the footprint's ellipse with a Gaussian, for anisotropic
//! footprints.

use super::wrap::WrapMode;
use super::Sample;
use glam::Vec2;
use rayon::prelude::*;

/// How lookups average texels (the imagemap "filter" parameter).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilterFunction {
    /// The nearest texel of the level the footprint selects.
    Point,
    /// Bilinear interpolation within the level the footprint selects (pbrt-v4's default).
    Bilinear,
    /// Bilinear lookups in the two levels around the footprint's width, blended.
    Trilinear,
    /// Elliptically weighted average over the footprint.
    Ewa,
}

impl FilterFunction {
    /// Parses pbrt-v4's names: "point", "bilinear", "trilinear", "ewa" (any case).
    pub fn parse(s: &str) -> Option<Self> {
        Some(match s.to_ascii_lowercase().as_str() {
            "point" => FilterFunction::Point,
            "bilinear" => FilterFunction::Bilinear,
            "trilinear" => FilterFunction::Trilinear,
            "ewa" => FilterFunction::Ewa,
            _ => return None,
        })
    }
}

/// How a MIP-map is looked up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MipOptions {
    /// The filter.
    pub filter: FilterFunction,
    /// Outside the image.
    pub wrap: WrapMode,
    /// Largest ratio of the EWA ellipse's axes; longer footprints are widened (blurred) to it.
    pub max_anisotropy: f32,
}

impl Default for MipOptions {
    /// pbrt-v4's defaults: bilinear, repeat, anisotropy 8.
    fn default() -> Self {
        Self { filter: FilterFunction::Bilinear, wrap: WrapMode::Repeat, max_anisotropy: 8.0 }
    }
}

/// One level: `width` × `height` texels, row-major, row 0 at the top (t = 0).
#[derive(Clone, Debug)]
struct Level<T> {
    width: usize,
    height: usize,
    texels: Vec<T>,
}

/// A MIP pyramid of texels of type `T`, finest first; the coarsest is 1 × 1.
#[derive(Clone, Debug)]
pub struct MipMap<T> {
    levels: Vec<Level<T>>,
    /// Lookup settings.
    pub options: MipOptions,
}

impl MipMap<[f32; 3]> {
    /// The pyramid of a `width` × `height` RGB image (row-major, top row first). Sizes that
    /// are not powers of two are first resampled up to the next ones bilinearly (pbrt-v4 uses
    /// a windowed sinc there); each further level averages 2 × 2 texels.
    pub fn build(width: usize, height: usize, texels: Vec<[f32; 3]>, options: MipOptions) -> Self {
        assert_eq!(texels.len(), width * height, "texel count must match the size");
        let mut level = Level { width, height, texels };
        let (pw, ph) = (width.next_power_of_two(), height.next_power_of_two());
        if (pw, ph) != (width, height) {
            level = resample_up(&level, pw, ph, options.wrap);
        }
        let mut levels = Vec::new();
        while level.width > 1 || level.height > 1 {
            let next = halve(&level);
            levels.push(level);
            level = next;
        }
        levels.push(level);
        Self { levels, options }
    }
}

/// `src` resampled to `w` × `h` texels by bilinear interpolation at the new texel centres.
fn resample_up(src: &Level<[f32; 3]>, w: usize, h: usize, wrap: WrapMode) -> Level<[f32; 3]> {
    let m = MipMap { levels: vec![src.clone()], options: MipOptions { wrap, ..Default::default() } };
    let texels = (0..w * h)
        .map(|i| {
            let st = Vec2::new(((i % w) as f32 + 0.5) / w as f32, ((i / w) as f32 + 0.5) / h as f32);
            let rgb = m.bilerp(0, st, &|t: &[f32; 3]| glam::Vec3::from_array(*t));
            rgb.to_array()
        })
        .collect();
    Level { width: w, height: h, texels }
}

/// The next level: each texel the mean of the 2 × 2 texels above it (of 2 × 1 or 1 × 2 where a
/// side is already 1).
fn halve(src: &Level<[f32; 3]>) -> Level<[f32; 3]> {
    let (w, h) = ((src.width / 2).max(1), (src.height / 2).max(1));
    let texels = (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let mut sum = [0.0f32; 3];
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let (sx, sy) = ((2 * x + dx).min(src.width - 1), (2 * y + dy).min(src.height - 1));
                let t = src.texels[sy * src.width + sx];
                for c in 0..3 {
                    sum[c] += 0.25 * t[c];
                }
            }
            sum
        })
        .collect();
    Level { width: w, height: h, texels }
}

/// exp(−α r²) − exp(−α) with α = 2: the Gaussian EWA weight, zero on the ellipse's edge.
fn ewa_weight(r2: f32) -> f32 {
    const ALPHA: f32 = 2.0;
    (-ALPHA * r2).exp() - (-ALPHA).exp()
}

impl<T: Sync> MipMap<T> {
    /// Number of levels.
    pub fn levels(&self) -> usize {
        self.levels.len()
    }

    /// Size of level `i` [texels].
    pub fn resolution(&self, i: usize) -> (usize, usize) {
        (self.levels[i].width, self.levels[i].height)
    }

    /// Every texel of every level, finest level first.
    pub fn texels(&self) -> impl Iterator<Item = &T> {
        self.levels.iter().flat_map(|l| &l.texels)
    }

    /// The same pyramid with every texel converted by `f` (in parallel).
    pub fn map<U: Send>(&self, f: impl Fn(&T) -> U + Sync) -> MipMap<U> {
        let levels = self
            .levels
            .iter()
            .map(|l| Level { width: l.width, height: l.height, texels: l.texels.par_iter().map(&f).collect() })
            .collect();
        MipMap { levels, options: self.options }
    }

    /// The value of texel (x, y) of `level` (wrapped; zero where black).
    fn texel<S: Sample>(&self, level: usize, x: i64, y: i64, value: &impl Fn(&T) -> S) -> S {
        let l = &self.levels[level];
        match self.options.wrap.texel(x, y, l.width, l.height) {
            Some((x, y)) => value(&l.texels[y * l.width + x]),
            None => S::zero(),
        }
    }

    /// Bilinear interpolation of `level` at `st` ∈ [0, 1]² (texel centres at (i + ½)/width).
    fn bilerp<S: Sample>(&self, level: usize, st: Vec2, value: &impl Fn(&T) -> S) -> S {
        let (w, h) = self.resolution(level);
        let (x, y) = (st.x * w as f32 - 0.5, st.y * h as f32 - 0.5);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (xi, yi) = (x0 as i64, y0 as i64);
        self.texel(level, xi, yi, value) * ((1.0 - fx) * (1.0 - fy))
            + self.texel(level, xi + 1, yi, value) * (fx * (1.0 - fy))
            + self.texel(level, xi, yi + 1, value) * ((1.0 - fx) * fy)
            + self.texel(level, xi + 1, yi + 1, value) * (fx * fy)
    }

    /// The filtered value at `st` (row 0 of the image at t = 0) for the footprint spanned by
    /// the change of `st` per pixel step along x, `dst0`, and along y, `dst1`. `value` turns
    /// a texel into what is averaged.
    pub fn filter<S: Sample>(&self, st: Vec2, dst0: Vec2, dst1: Vec2, value: impl Fn(&T) -> S) -> S {
        let top = self.levels() - 1;
        if self.options.filter != FilterFunction::Ewa {
            // The level whose texels are as wide as the footprint: level 0 has 2^top texels
            // across (along the longer side), so width w needs level top + log₂ w.
            let width = 2.0 * dst0.abs().max(dst1.abs()).max_element();
            let level = top as f32 + width.max(1e-8).log2();
            if level >= top as f32 {
                return self.texel(top, 0, 0, &value);
            }
            let lower = level.floor().max(0.0) as usize;
            return match self.options.filter {
                FilterFunction::Point => {
                    let (w, h) = self.resolution(lower);
                    let x = (st.x * w as f32 - 0.5).round() as i64;
                    let y = (st.y * h as f32 - 0.5).round() as i64;
                    self.texel(lower, x, y, &value)
                }
                FilterFunction::Bilinear => self.bilerp(lower, st, &value),
                _ if level <= 0.0 => self.bilerp(0, st, &value),
                _ => {
                    let f = level - lower as f32;
                    self.bilerp(lower, st, &value) * (1.0 - f) + self.bilerp(lower + 1, st, &value) * f
                }
            };
        }
        // EWA: the longer axis first; clamp the eccentricity.
        let (mut major, mut minor) = (dst0, dst1);
        if major.length_squared() < minor.length_squared() {
            std::mem::swap(&mut major, &mut minor);
        }
        let (longer, mut shorter) = (major.length(), minor.length());
        if shorter * self.options.max_anisotropy < longer && shorter > 0.0 {
            let scale = longer / (shorter * self.options.max_anisotropy);
            minor *= scale;
            shorter *= scale;
        }
        if shorter == 0.0 || !shorter.is_finite() {
            return self.bilerp(0, st, &value);
        }
        // The level where the minor axis spans about one texel, blended with the next.
        let lod = (top as f32 + shorter.log2()).max(0.0);
        let lower = lod.floor() as usize;
        let f = lod - lower as f32;
        self.ewa(lower, st, major, minor, &value) * (1.0 - f) + self.ewa(lower + 1, st, major, minor, &value) * f
    }

    /// The EWA average over `level` of the ellipse with axes `a0`, `a1` centred at `st`.
    fn ewa<S: Sample>(&self, level: usize, st: Vec2, a0: Vec2, a1: Vec2, value: &impl Fn(&T) -> S) -> S {
        if level >= self.levels() {
            return self.texel(self.levels() - 1, 0, 0, value);
        }
        let (w, h) = self.resolution(level);
        let res = Vec2::new(w as f32, h as f32);
        let c = st * res - Vec2::splat(0.5);
        let (a0, a1) = (a0 * res, a1 * res);
        // The ellipse A s² + B s t + C t² = F through the axes' ends, widened by one texel so
        // it always covers some texel centre, normalised to F = 1.
        let a = a0.y * a0.y + a1.y * a1.y + 1.0;
        let b = -2.0 * (a0.x * a0.y + a1.x * a1.y);
        let cc = a0.x * a0.x + a1.x * a1.x + 1.0;
        let inv_f = 1.0 / (a * cc - 0.25 * b * b);
        let (a, b, cc) = (a * inv_f, b * inv_f, cc * inv_f);
        // Its bounding box: |s| ≤ 2√(C/det), |t| ≤ 2√(A/det) with det = 4AC − B².
        let det = 4.0 * a * cc - b * b;
        let (hs, ht) = (2.0 * (cc / det).max(0.0).sqrt(), 2.0 * (a / det).max(0.0).sqrt());
        let (s0, s1) = ((c.x - hs).ceil() as i64, (c.x + hs).floor() as i64);
        let (t0, t1) = ((c.y - ht).ceil() as i64, (c.y + ht).floor() as i64);
        let (mut sum, mut weights) = (S::zero(), 0.0f32);
        for it in t0..=t1 {
            let tt = it as f32 - c.y;
            for is in s0..=s1 {
                let ss = is as f32 - c.x;
                let r2 = a * ss * ss + b * ss * tt + cc * tt * tt;
                if r2 < 1.0 {
                    let wgt = ewa_weight(r2);
                    sum = sum + self.texel(level, is, it, value) * wgt;
                    weights += wgt;
                }
            }
        }
        if weights > 0.0 {
            sum * (1.0 / weights)
        } else {
            self.bilerp(level, st, value)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `n` × `n` checkerboard of 0 and 1 texels.
    fn checks(n: usize, options: MipOptions) -> MipMap<[f32; 3]> {
        let texels = (0..n * n).map(|i| [((i % n + i / n) % 2) as f32; 3]).collect();
        MipMap::build(n, n, texels, options)
    }

    fn red(t: &[f32; 3]) -> f32 {
        t[0]
    }

    #[test]
    fn the_pyramid_halves_down_to_one_texel_and_keeps_the_mean() {
        let texels: Vec<[f32; 3]> = (0..8 * 4).map(|i| [i as f32, 0.0, 1.0]).collect();
        let mean = (0..32).sum::<usize>() as f32 / 32.0;
        let m = MipMap::build(8, 4, texels, MipOptions::default());
        let sizes: Vec<_> = (0..m.levels()).map(|i| m.resolution(i)).collect();
        assert_eq!(sizes, vec![(8, 4), (4, 2), (2, 1), (1, 1)]);
        assert!((m.levels[3].texels[0][0] - mean).abs() < 1e-5);
        // Level 1 texel (0, 0) averages texels (0,0), (1,0), (0,1), (1,1) = 0, 1, 8, 9.
        assert_eq!(m.levels[1].texels[0][0], 4.5);
    }

    #[test]
    fn a_non_power_of_two_image_is_resampled_up() {
        let m = MipMap::build(3, 1, vec![[1.0; 3], [1.0; 3], [1.0; 3]], MipOptions::default());
        assert_eq!(m.resolution(0), (4, 1));
        assert!(m.levels[0].texels.iter().all(|t| (t[0] - 1.0).abs() < 1e-6));
    }

    #[test]
    fn a_zero_footprint_reads_the_finest_level() {
        for filter in [FilterFunction::Point, FilterFunction::Bilinear, FilterFunction::Trilinear, FilterFunction::Ewa]
        {
            let m = checks(8, MipOptions { filter, ..Default::default() });
            // Texel (2, 1) centre is odd: 1; texel (3, 1) even: 0.
            let at =
                |x: f32, y: f32| m.filter(Vec2::new((x + 0.5) / 8.0, (y + 0.5) / 8.0), Vec2::ZERO, Vec2::ZERO, red);
            assert_eq!(at(2.0, 1.0), 1.0, "{filter:?}");
            assert_eq!(at(3.0, 1.0), 0.0, "{filter:?}");
        }
    }

    #[test]
    fn a_footprint_covering_the_image_gives_its_mean() {
        for filter in [FilterFunction::Point, FilterFunction::Bilinear, FilterFunction::Trilinear, FilterFunction::Ewa]
        {
            let m = checks(16, MipOptions { filter, ..Default::default() });
            let v = m.filter(Vec2::new(0.3, 0.6), Vec2::new(0.7, 0.0), Vec2::new(0.0, 0.7), red);
            assert!((v - 0.5).abs() < 1e-4, "{filter:?}: {v}");
        }
    }

    #[test]
    fn ewa_averages_an_anisotropic_footprint_along_its_long_axis() {
        // Stripes 4 texels wide along s: a footprint long along s averages them to about ½;
        // one as long but along t, at a stripe's middle, sees only that stripe.
        let n = 64;
        let texels = (0..n * n).map(|i| [((i % n / 4) % 2) as f32; 3]).collect();
        let m = MipMap::build(n, n, texels, MipOptions { filter: FilterFunction::Ewa, ..Default::default() });
        let st = Vec2::new(6.0 / n as f32, 0.5);
        let along_s = m.filter(st, Vec2::new(16.0 / n as f32, 0.0), Vec2::new(0.0, 0.25 / n as f32), red);
        assert!((along_s - 0.5).abs() < 0.1, "{along_s}");
        let along_t = m.filter(st, Vec2::new(0.0, 16.0 / n as f32), Vec2::new(0.25 / n as f32, 0.0), red);
        assert!(along_t > 0.95, "{along_t}");
    }

    #[test]
    fn black_wrap_fades_to_zero_outside() {
        let m = checks(4, MipOptions { wrap: WrapMode::Black, ..Default::default() });
        assert_eq!(m.filter(Vec2::new(-0.5, 0.5), Vec2::ZERO, Vec2::ZERO, red), 0.0);
        let clamp = checks(4, MipOptions { wrap: WrapMode::Clamp, ..Default::default() });
        // Left of texel (0, 1) (odd: 1) a clamped lookup stays 1.
        assert_eq!(clamp.filter(Vec2::new(-0.5, 1.5 / 4.0), Vec2::ZERO, Vec2::ZERO, red), 1.0);
    }
}
