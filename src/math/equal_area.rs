//! Clarberg's equal-area octahedral mapping between the unit square and the unit sphere
//! (P. Clarberg, "Fast Equal-Area Mapping of the (Hemi)Sphere using SIMD", JGT 13(3), 2008; PBR
//! 4th ed. §3.8.3), in pbrt-v4's orientation: the centre of the square is +z, its four corners
//! are −z, and the midpoints of the edges u = 1 and v = 1 are +x and +y. Each quadrant of the
//! square is one octant pair: the inner diamond |u'| + |v'| ≤ 1 (u' = 2u − 1, v' = 2v − 1) is the
//! upper hemisphere, the four corner triangles are the lower one folded outwards.
//!
//! Any region of the square maps onto a region of the sphere 4π times its area, so a density
//! p(u, v) over the square is p / (4π) per steradian.

use super::{Vec2, Vec3, PI};

/// Solid angle covered by the unit square [sr]: the mapping's constant Jacobian dω/(du dv).
pub const SPHERE_PER_SQUARE: f32 = 4.0 * PI;

/// The unit direction of point `p` in [0, 1]².
///
/// With r = 1 − | 1 − |u'| − |v'| | the distance from the diamond's edge (0 at its centre and
/// the corners, 1 on the diamond), z = ±(1 − r²) and the azimuth within the quadrant
/// φ = (π/4)((|v'| − |u'|)/r + 1): the area of the square within r is 2r², and that of the
/// spherical cap with z ≥ 1 − r² is 2π r², the same fraction of the whole.
pub fn square_to_sphere(p: Vec2) -> Vec3 {
    let (u, v) = (2.0 * p.x - 1.0, 2.0 * p.y - 1.0);
    let (au, av) = (u.abs(), v.abs());
    let signed_distance = 1.0 - (au + av);
    let r = 1.0 - signed_distance.abs();
    let phi = if r == 0.0 { PI / 4.0 } else { (PI / 4.0) * ((av - au) / r + 1.0) };
    let z = (1.0 - r * r).copysign(signed_distance);
    let sin_theta = r * (2.0 - r * r).max(0.0).sqrt();
    let (sin_phi, cos_phi) = phi.sin_cos();
    Vec3::new(sin_theta * cos_phi.copysign(u), sin_theta * sin_phi.copysign(v), z)
}

/// The point of the square whose direction is the unit vector `d` (the inverse of
/// [`square_to_sphere`]).
///
/// r = √(1 − |z|), computed as √((x² + y²)/(1 + |z|)) to keep its precision near the poles; in
/// the first quadrant |v'| = r · φ/(π/2) and |u'| = r − |v'|; the lower hemisphere reflects that
/// point across the diamond's edge, (|u'|, |v'|) → (1 − |v'|, 1 − |u'|).
pub fn sphere_to_square(d: Vec3) -> Vec2 {
    let (ax, ay, az) = (d.x.abs(), d.y.abs(), d.z.abs());
    let r = ((ax * ax + ay * ay) / (1.0 + az)).sqrt().min(1.0);
    let t = quadrant_angle(ax, ay);
    let (mut u, mut v) = (r - t * r, t * r);
    if d.z < 0.0 {
        (u, v) = (1.0 - v, 1.0 - u);
    }
    Vec2::new(0.5 * (u.copysign(d.x) + 1.0), 0.5 * (v.copysign(d.y) + 1.0))
}

/// atan2(y, x) / (π/2) for x, y ≥ 0: the azimuth within the first quadrant as a fraction of
/// it, in [0, 1]. atan(q) for q = min/max ∈ [0, 1] is q·P(q²) with P of degree 7, fitted here to
/// atan on [0, 1] (weighted least squares on Chebyshev nodes): |error| < 1.5·10⁻⁷ rad in single
/// precision, against a library atan2 that is a call and several times the instructions (the
/// mapping runs at every environment-map lookup).
#[inline]
fn quadrant_angle(x: f32, y: f32) -> f32 {
    const C: [f32; 8] = [
        0.999_999_34,
        -0.333_298_6,
        0.199_465_66,
        -0.139_086_3,
        0.096_421_98,
        -0.055_912_325,
        0.021_862_949,
        -0.004_054_563,
    ];
    let (a, b) = (x.max(y), x.min(y));
    let q = if a > 0.0 { b / a } else { 0.0 };
    let z = q * q;
    let p = C.iter().rev().fold(0.0f32, |acc, &c| acc * z + c);
    let t = q * p * (2.0 / PI);
    if y > x {
        1.0 - t
    } else {
        t
    }
}

/// A point just outside the square moved to the point inside it with the same direction
/// (pbrt-v4's wrap rule): each edge of the square is glued to itself reversed about its
/// midpoint, so crossing the edge u = 0 at v re-enters at (−u, 1 − v), and likewise for the
/// other three edges.
pub fn wrap_square(p: Vec2) -> Vec2 {
    let mut p = p;
    if p.x < 0.0 {
        p = Vec2::new(-p.x, 1.0 - p.y);
    } else if p.x > 1.0 {
        p = Vec2::new(2.0 - p.x, 1.0 - p.y);
    }
    if p.y < 0.0 {
        p = Vec2::new(1.0 - p.x, -p.y);
    } else if p.y > 1.0 {
        p = Vec2::new(1.0 - p.x, 2.0 - p.y);
    }
    p
}

/// The pixel of an `n` × `n` equal-area image that holds pixel (x, y) of the unfolded plane
/// around it (the discrete form of [`wrap_square`]: column −1 is column 0 mirrored in y, column
/// n is column n − 1 mirrored, and likewise for rows). For pixels at most one image away.
pub fn wrap_pixel(x: i64, y: i64, n: usize) -> (usize, usize) {
    let n = n.max(1) as i64;
    let (mut x, mut y) = (x, y);
    if x < 0 {
        (x, y) = (-1 - x, n - 1 - y);
    } else if x >= n {
        (x, y) = (2 * n - 1 - x, n - 1 - y);
    }
    if y < 0 {
        (x, y) = (n - 1 - x, -1 - y);
    } else if y >= n {
        (x, y) = (n - 1 - x, 2 * n - 1 - y);
    }
    (x.clamp(0, n - 1) as usize, y.clamp(0, n - 1) as usize)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    fn random_point(rng: &mut Rng) -> Vec2 {
        Vec2::new(rng.uniform(), rng.uniform())
    }

    #[test]
    fn the_quadrant_angle_is_atan2_over_a_right_angle() {
        let mut rng = Rng::new(4, 4);
        let mut cases: Vec<(f32, f32)> = (0..200_000).map(|_| (rng.uniform(), rng.uniform())).collect();
        cases.extend([(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0), (1e-30, 1.0), (1.0, 1e-30), (3.0, 3.0)]);
        for (x, y) in cases {
            let want = (y as f64).atan2(x as f64) / std::f64::consts::FRAC_PI_2;
            let got = quadrant_angle(x, y) as f64;
            assert!((got - want).abs() < 1.2e-7, "({x}, {y}): {got} vs {want}");
        }
    }

    #[test]
    fn landmarks_sit_where_pbrt_v4_puts_them() {
        let at = |u: f32, v: f32| square_to_sphere(Vec2::new(u, v));
        let close = |a: Vec3, b: Vec3| (a - b).length() < 1e-6;
        assert!(close(at(0.5, 0.5), Vec3::Z));
        for corner in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
            assert!(close(at(corner.0, corner.1), -Vec3::Z), "corner {corner:?}: {}", at(corner.0, corner.1));
        }
        assert!(close(at(1.0, 0.5), Vec3::X));
        assert!(close(at(0.0, 0.5), -Vec3::X));
        assert!(close(at(0.5, 1.0), Vec3::Y));
        assert!(close(at(0.5, 0.0), -Vec3::Y));
        // The diamond |u'| + |v'| = 1 is the horizon.
        for t in [0.1f32, 0.3, 0.77] {
            let d = at(0.5 + 0.5 * t, 0.5 + 0.5 * (1.0 - t));
            assert!(d.z.abs() < 1e-6, "{d}");
        }
    }

    #[test]
    fn directions_are_unit_and_round_trip() {
        let mut rng = Rng::new(7, 1);
        for _ in 0..100_000 {
            let p = random_point(&mut rng);
            let d = square_to_sphere(p);
            assert!((d.length() - 1.0).abs() < 1e-5, "|{d}| at {p}");
            let q = sphere_to_square(d);
            assert!((q - p).abs().max_element() < 2e-5, "{p} → {d} → {q}");
        }
        // The other way round too, from directions uniform on the sphere.
        for _ in 0..100_000 {
            let d = crate::sampling::warp::sample_uniform_sphere(random_point(&mut rng));
            let back = square_to_sphere(sphere_to_square(d));
            assert!((back - d).length() < 2e-5, "{d} → {back}");
        }
        // Exact poles and axes.
        for d in [Vec3::Z, -Vec3::Z, Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y] {
            assert!((square_to_sphere(sphere_to_square(d)) - d).length() < 1e-6, "{d}");
        }
    }

    /// |∂d/∂u × ∂d/∂v| by central differences: the area of the sphere per unit area of the
    /// square at p.
    fn jacobian(p: Vec2, h: f32) -> f32 {
        let du = square_to_sphere(p + Vec2::new(h, 0.0)) - square_to_sphere(p - Vec2::new(h, 0.0));
        let dv = square_to_sphere(p + Vec2::new(0.0, h)) - square_to_sphere(p - Vec2::new(0.0, h));
        du.cross(dv).length() / (4.0 * h * h)
    }

    #[test]
    fn mapping_preserves_area_everywhere() {
        // The Jacobian is 4π away from the creases (the axes u' = 0, v' = 0 and the horizon
        // diamond, where the map is only continuous); sample points that keep a margin.
        let mut rng = Rng::new(11, 2);
        let h = 1e-3;
        let mut tested = 0;
        while tested < 2000 {
            let p = random_point(&mut rng);
            let (u, v) = (2.0 * p.x - 1.0, 2.0 * p.y - 1.0);
            let margin = 4.0 * h;
            if u.abs() < margin || v.abs() < margin || (u.abs() + v.abs() - 1.0).abs() < margin {
                continue;
            }
            if u.abs() > 1.0 - margin || v.abs() > 1.0 - margin {
                continue;
            }
            let j = jacobian(p, h);
            assert!((j - SPHERE_PER_SQUARE).abs() < 2e-3 * SPHERE_PER_SQUARE, "dω/dA = {j} at {p}");
            tested += 1;
        }
    }

    #[test]
    fn uniform_points_of_the_square_are_uniform_on_the_sphere() {
        // Equal areas: the fraction of uniform square points in the cap z > c is (1 − c)/2, and
        // in any octant 1/8.
        let mut rng = Rng::new(5, 3);
        let n = 400_000;
        let dirs: Vec<Vec3> = (0..n).map(|_| square_to_sphere(random_point(&mut rng))).collect();
        for c in [-0.6f32, 0.0, 0.5, 0.9] {
            let frac = dirs.iter().filter(|d| d.z > c).count() as f64 / n as f64;
            let p = (1.0 - c as f64) / 2.0;
            let sigma = (p * (1.0 - p) / n as f64).sqrt();
            assert!((frac - p).abs() < 4.0 * sigma, "cap z > {c}: {frac} vs {p}");
        }
        let octant = dirs.iter().filter(|d| d.x > 0.0 && d.y < 0.0 && d.z < 0.0).count() as f64 / n as f64;
        let sigma = (0.125 * 0.875 / n as f64).sqrt();
        assert!((octant - 0.125).abs() < 4.0 * sigma, "octant {octant}");
    }

    #[test]
    fn wrapping_across_an_edge_keeps_the_direction_continuous() {
        // A point ε outside the square has, after wrapping, the direction the map tends to at
        // the edge from inside: the directions of p ± ε across the edge are close.
        let eps = 1e-4;
        let mut rng = Rng::new(3, 4);
        for _ in 0..1000 {
            let t = rng.uniform();
            for (inside, outside) in [
                (Vec2::new(eps, t), Vec2::new(-eps, t)),
                (Vec2::new(1.0 - eps, t), Vec2::new(1.0 + eps, t)),
                (Vec2::new(t, eps), Vec2::new(t, -eps)),
                (Vec2::new(t, 1.0 - eps), Vec2::new(t, 1.0 + eps)),
            ] {
                let w = wrap_square(outside);
                assert!((0.0..=1.0).contains(&w.x) && (0.0..=1.0).contains(&w.y), "{outside} → {w}");
                let gap = (square_to_sphere(w) - square_to_sphere(inside)).length();
                assert!(gap < 1e-2, "{outside} → {w}: {gap}");
            }
        }
    }

    #[test]
    fn pixel_wrap_matches_the_continuous_wrap_at_pixel_centres() {
        let n = 8usize;
        for i in -1..=n as i64 {
            for j in -1..=n as i64 {
                let centre = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let w = wrap_square(centre);
                let expected = ((w.x * n as f32) as usize, (w.y * n as f32) as usize);
                assert_eq!(wrap_pixel(i, j, n), expected, "pixel ({i}, {j})");
            }
        }
    }
}
