//! A camera sample: the sampler positioned at (pixel, sample index), the film position and
//! wavelengths drawn jointly, the pixel filter's weight, the time and lens sample, the camera
//! ray and its differentials. The scalar render loop and the wavefront loop both start every
//! path here, so both draw the sampler's first dimensions alike.

use crate::camera::{Camera, CameraRay};
use crate::filter::Filter;
use crate::sampling::Sampler;
use crate::scene::Scene;
use crate::spectrum::SampledWavelengths;
use crate::texture::{RayDifferentials, TextureFootprint};
use glam::Vec2;

/// What a camera sample starts a path with.
pub struct CameraSample {
    /// The path's wavelengths.
    pub lambdas: SampledWavelengths,
    /// The pixel filter's weight of the film position.
    pub filter_weight: f32,
    /// The camera ray and its weight (`None`: the camera sees nothing there).
    pub ray: Option<CameraRay>,
    /// The camera ray's differentials, when `differentials` asked for them.
    pub differentials: Option<RayDifferentials>,
    /// The film position [pixels, full image].
    pub p_film: Vec2,
}

/// Sample `s` of pixel `(x, y)` (in the full image) for the render seed `seed`: positions
/// `sampler` there and draws the film position and wavelength (`wavelengths` turns the latter's
/// uniform into wavelengths), then, as pbrt-v4's camera sample, a time uniform over the shutter
/// interval (only in a scene where something moves) and the lens sample.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn camera_sample(
    scene: &Scene,
    camera: &Camera,
    filter: &Filter,
    differentials: Option<&TextureFootprint>,
    sampler: &mut Sampler,
    wavelengths: impl Fn(f32) -> SampledWavelengths,
    (x, y): (u32, u32),
    s: u64,
    seed: u64,
) -> CameraSample {
    sampler.start_pixel_sample((x, y), s, seed);
    let u = sampler.get_pixel_3d();
    let lambdas = wavelengths(u.z);
    let (offset, filter_weight) = filter.sample(u.truncate());
    let p_film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset;
    // A scene where nothing (camera included) moves draws no time sample, so its sampler
    // dimensions (and image) stay as without motion blur.
    let time = scene.shutter.map_or(0.0, |(open, close)| {
        let u = sampler.get_1d();
        open + (close - open) * u
    });
    let u_lens = sampler.get_2d();
    let ray = camera.sample_ray(p_film, u_lens, time);
    let differentials =
        differentials.zip(ray.as_ref()).and_then(|(f, r)| f.camera_ray_differentials(camera, &r.ray, p_film, u_lens));
    CameraSample { lambdas, filter_weight, ray, differentials, p_film }
}
