//! Properties every one of pbrt-v4's samplers shares, through [`SamplerKind::make`]: values are
//! a function of (pixel, sample index, seed) whatever was drawn before, stay in [0, 1), and are
//! uniform over many pixels (Pearson's χ²).

use crate::sampling::chi2::chi2_survival;
use crate::sampling::{Randomize, Sampler, SamplerKind};

fn kinds() -> Vec<SamplerKind> {
    let mut v = vec![SamplerKind::Sobol, SamplerKind::Independent, SamplerKind::Pmj02bn];
    for r in [Randomize::None, Randomize::PermuteDigits, Randomize::FastOwen, Randomize::Owen] {
        v.extend([SamplerKind::ZSobol(r), SamplerKind::GlobalSobol(r), SamplerKind::PaddedSobol(r)]);
        if r != Randomize::FastOwen {
            v.push(SamplerKind::Halton(r));
        }
    }
    v.extend([true, false].map(|jitter| SamplerKind::Stratified { x: 4, y: 4, jitter }));
    v
}

/// The values one camera sample draws: the film position and wavelength, then 1D and 2D draws.
fn draws(s: &mut Sampler, pixel: (u32, u32), index: u64, seed: u64) -> Vec<f32> {
    s.start_pixel_sample(pixel, index, seed);
    let mut v = s.get_pixel_3d().to_array().to_vec();
    for _ in 0..3 {
        v.push(s.get_1d());
        v.extend(s.get_2d().to_array());
    }
    v
}

#[test]
fn values_depend_only_on_pixel_index_and_seed() {
    for kind in kinds() {
        let mut s = kind.make(16, (64, 48), 3);
        let a = draws(&mut s, (7, 9), 5, 3);
        draws(&mut s, (60, 1), 11, 3);
        assert_eq!(draws(&mut kind.make(16, (64, 48), 3), (7, 9), 5, 3), a, "{kind:?}: another sampler");
        assert_eq!(draws(&mut s, (7, 9), 5, 3), a, "{kind:?}: after other work");
        assert_ne!(draws(&mut s, (8, 9), 5, 3), a, "{kind:?}: another pixel");
        assert_ne!(draws(&mut s, (7, 9), 6, 3), a, "{kind:?}: another sample");
        assert!(a.iter().all(|x| (0.0..1.0).contains(x)), "{kind:?}: {a:?}");
        // Past the samples per pixel (a render extended later): still defined and in range.
        let far = draws(&mut s, (7, 9), 16 * 5 + 3, 3);
        assert!(far.iter().all(|x| (0.0..1.0).contains(x)), "{kind:?}: {far:?}");
    }
}

#[test]
fn every_dimension_is_uniform_over_the_image() {
    // One sample of each of 128×128 pixels (the samples of one pixel are not independent: a
    // pixel's strata share their offsets); each 2D draw binned in 16×16 cells (expected count
    // 64 each), each 1D draw in 256 strata. Pearson's statistic against χ² with 255 degrees of
    // freedom; significance 0.01 split over all the tests (Šidák). Patterns that stratify across
    // pixels give statistics below the mean: only too large a one (non-uniform) fails.
    // Unrandomised padded Sobol' and unjittered strata give every pixel the same 16 points (in
    // shuffled orders): uniform only at the resolution of 16 strata, so they are left out. The
    // global Sobol' sampler's film positions are uniform over the image, not within the pixel
    // (one index block's in-pixel offsets lie on a lattice; its own tests check them).
    let fixed = [SamplerKind::PaddedSobol(Randomize::None), SamplerKind::Stratified { x: 4, y: 4, jitter: false }];
    let kinds: Vec<SamplerKind> = kinds().into_iter().filter(|k| !fixed.contains(k)).collect();
    let dims = 6;
    let alpha = 1.0 - 0.99f64.powf(1.0 / (kinds.len() * dims) as f64);
    for kind in kinds {
        let mut s = kind.make(16, (128, 128), 1);
        let mut counts = vec![vec![0u32; 256]; dims];
        for (px, py) in (0..128).flat_map(|y| (0..128).map(move |x| (x, y))) {
            {
                s.start_pixel_sample((px, py), u64::from(px * 7 + py * 3) % 16, 1);
                let p = s.get_pixel_3d();
                let cell2 = |u: glam::Vec2| (u.x * 16.0) as usize * 16 + (u.y * 16.0) as usize;
                counts[0][cell2(p.truncate())] += 1;
                counts[1][(p.z * 256.0) as usize] += 1;
                counts[2][cell2(s.get_2d())] += 1;
                counts[3][(s.get_1d() * 256.0) as usize] += 1;
                counts[4][cell2(s.get_2d())] += 1;
                counts[5][cell2(s.get_2d())] += 1;
            }
        }
        let global = matches!(kind, SamplerKind::GlobalSobol(_));
        for (d, c) in counts.iter().enumerate().skip(global as usize) {
            let expected = 128.0 * 128.0 / 256.0;
            // pmj02bn's film positions repeat every 64 pixels (as pbrt-v4's), and so do these
            // sample indices: the 128×128 pixels are four copies of 64×64 independent ones, which
            // multiplies the statistic by 4.
            let copies = if kind == SamplerKind::Pmj02bn && d == 0 { 4.0 } else { 1.0 };
            let stat: f64 = c.iter().map(|&o| (o as f64 - expected).powi(2) / expected).sum::<f64>() / copies;
            let p = chi2_survival(stat, 255.0);
            assert!(p >= alpha, "{kind:?}, draw {d}: χ² = {stat:.1}, p = {p:.2e} < {alpha:.2e}");
        }
    }
}
