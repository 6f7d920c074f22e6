//! The area lights of an emissive mesh, as pbrt-v4 makes them: one light per triangle, except
//! that a face made of two triangles whose four corners are a rectangle (a rectangular bilinear
//! patch, a rectangular quad of a PLY file) is one [`RectangleLight`], sampled by the solid
//! angle it subtends as pbrt-v4 samples such patches. An emission image keeps the triangles,
//! whose corners carry its (u, v).

use super::Emission;
use crate::geometry::Mesh;
use crate::light::{is_rectangle, AreaLight, EmissionImage, ImageEmission, Light, RectangleLight};
use glam::{Vec2, Vec3};
use std::sync::Arc;

/// Which of the scene's lights a primitive's triangle is, counted from its first light.
#[derive(Clone, Debug, Default)]
pub enum LightsOf {
    /// Triangle `i` is light `first + i`.
    #[default]
    Triangles,
    /// The whole primitive is light `first` (a quadric).
    Whole,
    /// Triangle `i` is light `first + table[i]` (rectangles among the triangles).
    Table(Box<[u32]>),
}

impl LightsOf {
    /// The light of triangle `prim`, for a primitive whose lights start at `first`.
    #[inline]
    pub fn of(&self, first: u32, prim: u32) -> u32 {
        match self {
            LightsOf::Triangles => first + prim,
            LightsOf::Whole => first,
            LightsOf::Table(table) => first + table[prim as usize],
        }
    }
}

/// Pushes the lights of `mesh` emitting `em` onto `lights`: each face's radiance scale divided
/// by its area when `per_face_area` (pbrt-v4's `power` given to each face), the image's texels
/// at the triangles' (u, v) in place of the spectrum when there is one.
pub fn push_mesh_lights(
    mesh: &Mesh,
    em: &Emission,
    image: Option<&Arc<EmissionImage>>,
    per_face_area: bool,
    lights: &mut Vec<Light>,
) -> LightsOf {
    let first = lights.len();
    let spectrum = Arc::new(em.spectrum.clone());
    let face_areas = if per_face_area { mesh.face_areas() } else { Vec::new() };
    let scale = |prim: usize| if per_face_area { em.scale / face_areas[prim] } else { em.scale };
    let mut table = Vec::with_capacity(mesh.len());
    let mut prim = 0;
    while prim < mesh.len() {
        let rectangle = if image.is_none() { rectangle_face(mesh, prim) } else { None };
        if let Some([p00, p10, _, p01]) = rectangle {
            let n = (p10 - p00).cross(p01 - p00).normalize();
            let (ex, ey) = (p10 - p00, p01 - p00);
            let (spectrum, two_sided) = (spectrum.clone(), em.two_sided);
            let light = RectangleLight { corner: p00, ex, ey, n, spectrum, scale: scale(prim), two_sided };
            lights.push(Light::Rectangle(Box::new(light)));
            table.extend([(lights.len() - 1 - first) as u32; 2]);
            prim += 2;
            continue;
        }
        let p = mesh.triangle(prim);
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let image = image.map(|image| {
            let tri = mesh.indices[prim];
            // pbrt-v4's default (u, v) of a triangle's corners, as the surface uses.
            let uv = std::array::from_fn(|k| match &mesh.uvs {
                Some(uvs) => uvs[tri[k] as usize],
                None => [Vec2::ZERO, Vec2::X, Vec2::ONE][k],
            });
            Box::new(ImageEmission { image: image.clone(), uv })
        });
        lights.push(Light::Area(AreaLight {
            p,
            n: n.normalize_or_zero(),
            area: 0.5 * n.length(),
            spectrum: spectrum.clone(),
            scale: scale(prim),
            two_sided: em.two_sided,
            image,
        }));
        table.push((lights.len() - 1 - first) as u32);
        prim += 1;
    }
    if table.iter().enumerate().all(|(i, &l)| l == i as u32) {
        LightsOf::Triangles
    } else {
        LightsOf::Table(table.into())
    }
}

/// The corners, in order around, of the face that starts at triangle `prim` when that face is
/// exactly triangles `prim` and `prim + 1`, which share one edge (its diagonal), face the same
/// way, and whose four corners are a rectangle; `None` otherwise. The corners start at the
/// vertex of triangle `prim` off the diagonal and turn the way its normal does, so that
/// (c₁ − c₀) × (c₃ − c₀) is along it.
fn rectangle_face(mesh: &Mesh, prim: usize) -> Option<[Vec3; 4]> {
    let faces = mesh.faces.as_ref()?;
    let face = faces[prim];
    let run_starts = prim == 0 || faces[prim - 1] != face;
    let run_of_two = faces.get(prim + 1) == Some(&face) && faces.get(prim + 2) != Some(&face);
    if !(run_starts && run_of_two) {
        return None;
    }
    let (a, b) = (mesh.indices[prim], mesh.indices[prim + 1]);
    let shared = a.iter().filter(|v| b.contains(v)).count();
    let off_a = (0..3).find(|&k| !b.contains(&a[k]))?;
    let off_b = *b.iter().find(|v| !a.contains(v))?;
    if shared != 2 {
        return None;
    }
    // Around triangle a from its vertex off the diagonal: a[k], a[k+1], (b's), a[k+2].
    let v = |i: u32| mesh.positions[i as usize];
    let corners = [v(a[off_a]), v(a[(off_a + 1) % 3]), v(off_b), v(a[(off_a + 2) % 3])];
    let [pa, pb] = [mesh.triangle(prim), mesh.triangle(prim + 1)];
    let same_side = (pa[1] - pa[0]).cross(pa[2] - pa[0]).dot((pb[1] - pb[0]).cross(pb[2] - pb[0])) > 0.0;
    (same_side && is_rectangle(&corners)).then_some(corners)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::Spectrum;

    fn emission() -> Emission {
        Emission { spectrum: Spectrum::constant(1.0), scale: 2.0, two_sided: false }
    }

    /// A unit-square patch split either way, a parallelogram, and a square whose two triangles
    /// are not one face: one rectangle light for the first two only, facing as the triangles.
    #[test]
    fn rectangular_faces_of_two_triangles_become_rectangle_lights() {
        let square = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        let sheared = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.5, 1.0, 0.0), Vec3::new(0.5, 1.0, 0.0)];
        for (positions, indices, faces, rectangle) in [
            (square.clone(), vec![[0, 1, 2], [0, 2, 3]], Some(vec![0, 0]), true),
            (square.clone(), vec![[1, 2, 3], [1, 3, 0]], Some(vec![4, 4]), true),
            (sheared, vec![[0, 1, 2], [0, 2, 3]], Some(vec![0, 0]), false),
            (square, vec![[0, 1, 2], [0, 2, 3]], None, false),
        ] {
            let mut mesh = Mesh::new(positions, indices);
            mesh.faces = faces;
            let mut lights = vec![];
            let layout = push_mesh_lights(&mesh, &emission(), None, true, &mut lights);
            if rectangle {
                let [Light::Rectangle(r)] = &lights[..] else { panic!("{lights:?}") };
                assert!(matches!(layout, LightsOf::Table(ref t) if t[..] == [0, 0]));
                assert!((r.area() - 1.0).abs() < 1e-6 && (r.n - Vec3::Z).length() < 1e-6, "{r:?}");
                // The face's power over its area.
                assert_eq!(r.scale, 2.0);
            } else {
                assert!(lights.len() == 2 && lights.iter().all(|l| matches!(l, Light::Area(_))));
                assert!(matches!(layout, LightsOf::Triangles));
            }
        }
    }

    /// In a mesh of a rectangle, a triangle and a rectangle, each triangle maps to its light.
    #[test]
    fn triangles_map_to_their_lights() {
        let mut positions = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        positions.extend(positions.clone().iter().map(|p| *p + Vec3::Z));
        let mut mesh = Mesh::new(positions, vec![[0, 1, 2], [0, 2, 3], [0, 1, 3], [4, 5, 6], [4, 6, 7]]);
        mesh.faces = Some(vec![0, 0, 1, 2, 2]);
        let mut lights = vec![];
        let layout = push_mesh_lights(&mesh, &emission(), None, false, &mut lights);
        assert_eq!(lights.len(), 3);
        assert!(matches!(&lights[1], Light::Area(_)) && matches!(&lights[2], Light::Rectangle(_)));
        assert_eq!((0..5).map(|p| layout.of(7, p)).collect::<Vec<_>>(), [7, 7, 8, 9, 9]);
    }
}
