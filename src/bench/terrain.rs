//! A built-in scene of just over a million triangles for `prism bench builtin:terrain`: the
//! heightfield and the finely tessellated sphere of the ray benchmark (`benches/accel.rs`), lit
//! by a large emitting panel, so build time, memory per triangle and rays/s of each backend
//! can be measured inside the renderer without shipping a large mesh file.

use crate::geometry::shapes::{icosphere, quad, terrain};
use crate::material::Material;
use crate::scene::{Emission, SceneBuilder};
use crate::spectrum::Spectrum;
use glam::Vec3;

/// Heightfield cells per side: 2·600² = 720,000 triangles.
const TERRAIN_RESOLUTION: u32 = 600;
/// Icosphere subdivisions: 20·4⁷ = 327,680 triangles.
const SPHERE_SUBDIVISIONS: u32 = 7;
/// Triangles in the scene, besides the light's two.
pub const TERRAIN_TRIANGLES: u64 = 2 * (TERRAIN_RESOLUTION as u64).pow(2) + 20 * 4u64.pow(SPHERE_SUBDIVISIONS);
// Checked at compile time: the benchmark is about scenes of a million triangles and more.
const _: () = assert!(TERRAIN_TRIANGLES > 1_000_000);

/// The terrain scene (scene units are metres; 100 m × 100 m of ground).
pub fn terrain_scene() -> SceneBuilder {
    let mut b = SceneBuilder::new();
    let ground = b.add_material(Material::diffuse(Spectrum::constant(0.5)));
    let ball = b.add_material(Material::diffuse(Spectrum::constant(0.8)));
    let black = b.add_material(Material::diffuse(Spectrum::constant(0.0)));
    b.add_mesh(terrain(100.0, TERRAIN_RESOLUTION, 4.0, 1), ground, None);
    b.add_mesh(icosphere(Vec3::new(0.0, 12.0, 0.0), 8.0, SPHERE_SUBDIVISIONS), ball, None);
    // A 60 m × 60 m panel 60 m up, facing down: CIE D65 radiance of luminance Y = 5, which
    // makes the lit ground about 0.5 in linear sRGB.
    let panel = light_panel();
    let d65 = Spectrum::named("stdillum-D65").unwrap_or(Spectrum::constant(1.0));
    b.add_mesh(panel, black, Some(Emission { spectrum: d65, scale: 5.0, two_sided: false }));
    let eye = Vec3::new(0.0, 40.0, 80.0);
    b.set_camera(crate::camera::Camera::look_at(eye, Vec3::new(0.0, 5.0, 0.0), Vec3::Y), 45.0);
    b
}

/// The emitting panel: 60 m × 60 m, 60 m up, normal e1 × e2 = −y (down).
fn light_panel() -> crate::geometry::Mesh {
    quad(Vec3::new(-30.0, 60.0, -30.0), Vec3::new(60.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 60.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn has_over_a_million_triangles_and_a_downward_light() {
        let ground = terrain(100.0, TERRAIN_RESOLUTION, 4.0, 1);
        let ball = icosphere(Vec3::new(0.0, 12.0, 0.0), 8.0, SPHERE_SUBDIVISIONS);
        assert_eq!((ground.len() + ball.len()) as u64, TERRAIN_TRIANGLES);
        let p = light_panel();
        let [a, b, c] = p.indices[0].map(|i| p.positions[i as usize]);
        assert!((b - a).cross(c - a).y < 0.0, "the panel must face the ground");
    }
}
