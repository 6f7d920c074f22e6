//! Tests of the texture combinations and of filtering over a camera's footprint.

use super::*;
use crate::camera::Camera;
use crate::spectrum::SampledWavelengths;
use glam::Vec2;

fn constant(v: f32) -> Arc<FloatTexture> {
    Arc::new(Texture::Constant(v))
}

fn uv(u: f32, v: f32) -> TextureEvalContext {
    TextureEvalContext::uv(Vec2::new(u, v))
}

#[test]
fn bilerp_has_its_corner_values_and_their_mean_at_the_centre() {
    let t: FloatTexture = Texture::Bilerp { mapping: Mapping2D::UV, corners: Box::new([1.0, 2.0, 4.0, 8.0]) };
    assert_eq!(t.eval(&uv(0.0, 0.0)), 1.0);
    assert_eq!(t.eval(&uv(1.0, 0.0)), 2.0);
    assert_eq!(t.eval(&uv(0.0, 1.0)), 4.0);
    assert_eq!(t.eval(&uv(1.0, 1.0)), 8.0);
    assert_eq!(t.eval(&uv(0.5, 0.5)), 15.0 / 4.0);
    // Along the edge v = 0: linear between v00 and v10.
    assert_eq!(t.eval(&uv(0.25, 0.0)), 1.25);
}

#[test]
fn mix_gives_its_endpoints_and_blends_linearly() {
    let mix = |a: f32| -> FloatTexture { Texture::Mix { tex: [constant(2.0), constant(10.0)], amount: constant(a) } };
    assert_eq!(mix(0.0).eval(&uv(0.3, 0.3)), 2.0);
    assert_eq!(mix(1.0).eval(&uv(0.3, 0.3)), 10.0);
    assert_eq!(mix(0.25).eval(&uv(0.3, 0.3)), 4.0);
    // The amount may be a texture: a checkerboard selects the endpoints cell by cell.
    let board = Arc::new(Texture::Checkerboard {
        pattern: Checkerboard::Planar(Mapping2D::Uv { scale: Vec2::splat(2.0), delta: Vec2::ZERO }),
        tex: [constant(0.0), constant(1.0)],
    });
    let t: FloatTexture = Texture::Mix { tex: [constant(2.0), constant(10.0)], amount: board };
    assert_eq!(t.eval(&uv(0.2, 0.2)), 2.0);
    assert_eq!(t.eval(&uv(0.7, 0.2)), 10.0);
}

#[test]
fn direction_mix_weights_by_the_normal() {
    let t: FloatTexture = Texture::DirectionMix { tex: [constant(1.0), constant(0.0)], dir: -Vec3::Y };
    let at = |n: Vec3| t.eval(&TextureEvalContext::at(Vec3::ZERO, n, Vec2::ZERO));
    // Facing dir (either way round): tex1; perpendicular: tex2; at 60°: cos 60° = ½.
    assert_eq!(at(-Vec3::Y), 1.0);
    assert_eq!(at(Vec3::Y), 1.0);
    assert_eq!(at(Vec3::X), 0.0);
    assert!((at(Vec3::new(3f32.sqrt() / 2.0, 0.5, 0.0)) - 0.5).abs() < 1e-6);
}

#[test]
fn scale_multiplies_textures() {
    let s: FloatTexture = Texture::Scale { tex: constant(3.0), scale: constant(0.5) };
    assert_eq!(s.eval(&uv(0.0, 0.0)), 1.5);
    let w = SampledWavelengths::sample_uniform(0.4);
    let spectral: SpectrumTexture =
        Texture::Scale { tex: Arc::new(Texture::Constant(Spectrum::constant(0.8))), scale: constant(0.25) };
    let v = spectral.eval(&uv(0.0, 0.0), &w);
    assert!((0..4).all(|k| (v[k] - 0.2).abs() < 1e-6), "{v:?}");
}

#[test]
fn dots_show_their_textures_inside_and_around() {
    let t: FloatTexture = Texture::Dots { mapping: Mapping2D::UV, dots: constant(1.0), background: constant(0.0) };
    let (mut inside, mut n) = (0, 0);
    for i in 0..100 {
        for j in 0..100 {
            let st = Vec2::new(i as f32 * 0.173, j as f32 * 0.119);
            let v = t.eval(&TextureEvalContext::uv(st));
            assert_eq!(v, if inside_polka_dot(st) { 1.0 } else { 0.0 });
            inside += v as i32;
            n += 1;
        }
    }
    // About half the cells have a dot covering π 0.35² ≈ 0.385 of the cell: ~19 % of the plane.
    let frac = inside as f64 / n as f64;
    assert!((0.1..0.3).contains(&frac), "{frac}");
}

/// A floor at z = 0 seen by a camera 2 units up looking along +y, 64 × 64 pixels.
fn floor_camera() -> Camera {
    let m = Camera::look_at(Vec3::new(0.0, 0.0, 2.0), Vec3::new(0.0, 10.0, 0.0), Vec3::Z);
    Camera::perspective(m, (64, 64), 40.0, 0.0, 1e6, None)
}

/// The floor's texture context at `p`, with (u, v) = (x, y) and the camera's footprint.
fn floor_point(f: &TextureFootprint, p: Vec3) -> TextureEvalContext {
    let (dx, dy) = f.dp_dxy(p, Vec3::Z, 0.0);
    TextureEvalContext::at(p, Vec3::Z, Vec2::new(p.x, p.y)).with_footprint(dx, dy, Vec3::X, Vec3::Y)
}

#[test]
fn a_distant_checkerboard_filters_to_its_mean() {
    // Checks 0.05 wide in (u, v) = (x, y) on the floor; near the camera a pixel covers a
    // fraction of a check, 60 units away it covers dozens. The mean of the board is ½.
    let f = TextureFootprint::new(&floor_camera(), 1);
    let checks: Vec<[f32; 3]> = (0..256 * 256).map(|i| [((i % 256 + i / 256) % 2) as f32; 3]).collect();
    let image_at = |filter| {
        let pyramid = MipMap::build(256, 256, checks.clone(), MipOptions { filter, ..Default::default() });
        // 256 texels across 12.8 units: texels 0.05 wide.
        let scale = Vec2::splat(1.0 / 12.8);
        FloatImage::new(Mapping2D::Uv { scale, delta: Vec2::ZERO }, &pyramid, 1.0, false)
    };
    let procedural = Texture::<f32>::Checkerboard {
        pattern: Checkerboard::Planar(Mapping2D::Uv { scale: Vec2::splat(20.0), delta: Vec2::ZERO }),
        tex: [constant(0.0), constant(1.0)],
    };
    // Texel centres, (k + ½) · 0.05.
    let far = [Vec3::new(0.025, 60.025, 0.0), Vec3::new(-3.725, 75.025, 0.0), Vec3::new(5.025, 90.075, 0.0)];
    for filter in [FilterFunction::Bilinear, FilterFunction::Trilinear, FilterFunction::Ewa] {
        let img = image_at(filter);
        for p in far {
            let ctx = floor_point(&f, p);
            let v = img.eval(&ctx);
            assert!((v - 0.5).abs() < 0.05, "{filter:?} at {p}: {v}");
            // Without the footprint the lookup is the texel: 0 or 1.
            let raw = img.eval(&TextureEvalContext::at(p, Vec3::Z, ctx.uv));
            assert!(!(0.02..=0.98).contains(&raw), "{raw}");
        }
    }
    for p in far {
        let v = procedural.eval(&floor_point(&f, p));
        assert!((v - 0.5).abs() < 0.05, "procedural at {p}: {v}");
    }
    // Close to the camera (the floor is seen from y ≈ 3.3 on) checks half a unit wide are
    // resolved: at a check's centre the filter does not reach its edges.
    let coarse = Texture::<f32>::Checkerboard {
        pattern: Checkerboard::Planar(Mapping2D::Uv { scale: Vec2::splat(2.0), delta: Vec2::ZERO }),
        tex: [constant(0.0), constant(1.0)],
    };
    assert_eq!(coarse.eval(&floor_point(&f, Vec3::new(0.25, 3.75, 0.0))), 1.0);
    assert_eq!(coarse.eval(&floor_point(&f, Vec3::new(0.75, 3.75, 0.0))), 0.0);
}

#[test]
fn filtered_checkerboard_averages_converge_to_the_mean_over_the_image_of_distant_rows() {
    // The average of the filtered texture over many pixels of a distant row equals the mean
    // of the board (filtering preserves the average), while each value is near it too.
    let f = TextureFootprint::new(&floor_camera(), 1);
    let board = Texture::<f32>::Checkerboard {
        pattern: Checkerboard::Planar(Mapping2D::Uv { scale: Vec2::splat(20.0), delta: Vec2::ZERO }),
        tex: [constant(0.0), constant(1.0)],
    };
    let n = 400;
    let mean: f32 =
        (0..n).map(|i| board.eval(&floor_point(&f, Vec3::new(-4.0 + 0.0203 * i as f32, 70.0, 0.0)))).sum::<f32>()
            / n as f32;
    assert!((mean - 0.5).abs() < 0.01, "{mean}");
}
