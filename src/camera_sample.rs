//! A camera sample of a pixel, as both render loops draw it: film position through the pixel
//! filter, wavelength uniform, shutter time, lens point, and the ray they give.

use crate::camera::{Camera, CameraRay};
use crate::filter::Filter;
use crate::sampling::Sampler;
use crate::scene::Scene;
use crate::texture::{RayDifferentials, TextureFootprint};
use glam::Vec2;

/// A camera sample: the film position drawn through the pixel filter, the shutter time, the
/// lens point, and what they give.
pub(crate) struct CameraSample {
    /// The uniform [0, 1) the sample's wavelengths are drawn with.
    pub u_lambda: f32,
    /// The filter's weight of the film position.
    pub weight: f32,
    /// The ray (`None`: the lens lets none through).
    pub ray: Option<CameraRay>,
    /// The ray's differentials, when `differentials` asks for them.
    pub differentials: Option<RayDifferentials>,
}

/// Camera sample `s` of full-image pixel `(x, y)` for the render seed `seed`: the sampler started there, then the film
/// position and wavelength uniform (one stratified 3D draw), the time, the lens.
#[allow(clippy::too_many_arguments)]
pub(crate) fn camera_sample(
    scene: &Scene,
    seed: u64,
    filter: &Filter,
    camera: &Camera,
    differentials: Option<&TextureFootprint>,
    sampler: &mut Sampler,
    (x, y): (u32, u32),
    s: u64,
) -> CameraSample {
    sampler.start_pixel_sample((x, y), s, seed);
    let u = sampler.get_pixel_3d();
    let (offset, weight) = filter.sample(u.truncate());
    let p_film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset;
    // pbrt-v4's camera sample: a time uniform over the shutter interval, then the lens. A
    // scene where nothing (camera included) moves draws no time sample, so its sampler
    // dimensions (and image) stay as without motion blur.
    let time = scene.shutter.map_or(0.0, |(open, close)| {
        let u = sampler.get_1d();
        open + (close - open) * u
    });
    let u_lens = sampler.get_2d();
    let ray = camera.sample_ray(p_film, u_lens, time);
    let differentials =
        differentials.zip(ray.as_ref()).and_then(|(f, r)| f.camera_ray_differentials(camera, &r.ray, p_film, u_lens));
    CameraSample { u_lambda: u.z, weight, ray, differentials }
}
