//! Uniform sampling of the solid angle a rectangle subtends from a point, and its inverse
//! (Ureña, Fajardo & King 2013, "An Area-Preserving Parametrization for Spherical Rectangles",
//! Computer Graphics Forum 32(4); pbrt-v4 samples rectangular bilinear-patch lights so).
//!
//! In a frame at the reference point o with x, y along the rectangle's edges and z toward it,
//! the rectangle is [x₀, x₁] × [y₀, y₁] at depth z₀ < 0 (its plane is z = z₀ after flipping z to
//! the far side). The planes through o and its four edges have normals n₀…n₃; the spherical
//! rectangle's interior angles are γᵢ = acos(−nᵢ·nᵢ₊₁) and its solid angle
//! S = γ₀ + γ₁ + γ₂ + γ₃ − 2π (Girard). The sub-rectangle [x₀, x] × [y₀, y₁] shares γ₂ and γ₃,
//! so its solid angle γ₀(x) + γ₁(x) − k with k = 2π − γ₂ − γ₃ grows monotonically with x:
//! drawing u S = γ₀(x) + γ₁(x) − k and solving for x (the paper's closed form) gives the column
//! of the direction with the right marginal, and within that column the height
//! h = y/√(d² + y²), d² = x² + z₀², is uniform in solid angle, so v picks h linearly.

use crate::math::{Vec2, Vec3, PI};

/// The solid angle a rectangle subtends from a point, prepared for sampling.
#[derive(Clone, Copy, Debug)]
pub struct SphericalRectangle {
    /// The reference point [world space].
    o: Vec3,
    /// Unit edge directions and the unit normal pointing away from `o`.
    x: Vec3,
    y: Vec3,
    z: Vec3,
    /// The rectangle in the frame at `o`: [x0, x1] × [y0, y1] at depth z0 < 0.
    x0: f32,
    x1: f32,
    y0: f32,
    y1: f32,
    z0: f32,
    /// z components of n₀ and n₂, and k = 2π − γ₂ − γ₃.
    b0: f32,
    b1: f32,
    k: f32,
    /// The normal of the plane through `o` and the edge x = x0 (shared by every sub-rectangle).
    n0: Vec3,
    n2: Vec3,
    /// Solid angle S [sr].
    solid_angle: f32,
}

impl SphericalRectangle {
    /// The rectangle with corner `corner` and perpendicular edges `ex`, `ey`, seen from `o`.
    /// `None` when `o` lies in its plane or an edge has no length.
    pub fn new(o: Vec3, corner: Vec3, ex: Vec3, ey: Vec3) -> Option<Self> {
        let (exl, eyl) = (ex.length(), ey.length());
        if !(exl > 0.0 && eyl > 0.0) {
            return None;
        }
        let (x, y) = (ex / exl, ey / eyl);
        let mut z = x.cross(y);
        let d = corner - o;
        let mut z0 = d.dot(z);
        if z0 > 0.0 {
            z = -z;
            z0 = -z0;
        }
        if z0 >= 0.0 || z0.is_nan() {
            return None;
        }
        let (x0, y0) = (d.dot(x), d.dot(y));
        let (x1, y1) = (x0 + exl, y0 + eyl);
        let n0 = Vec3::new(0.0, z0, -y0).normalize();
        let n1 = Vec3::new(-z0, 0.0, x1).normalize();
        let n2 = Vec3::new(0.0, -z0, y1).normalize();
        let n3 = Vec3::new(z0, 0.0, -x0).normalize();
        let angle = |a: Vec3, b: Vec3| (-a.dot(b)).clamp(-1.0, 1.0).acos();
        let (g0, g1, g2, g3) = (angle(n0, n1), angle(n1, n2), angle(n2, n3), angle(n3, n0));
        let k = 2.0 * PI - g2 - g3;
        let solid_angle = g0 + g1 - k;
        Some(Self { o, x, y, z, x0, x1, y0, y1, z0, b0: n0.z, b1: n2.z, k, n0, n2, solid_angle })
    }

    /// The solid angle S [sr]. In single precision it is a difference of angles near π, so
    /// its absolute error is a few 10⁻⁵ sr: below ~10⁻³ sr the rectangle is better sampled by
    /// area (pbrt-v4 does so below 3·10⁻⁴ sr).
    pub fn solid_angle(&self) -> f32 {
        self.solid_angle
    }

    /// The point of the rectangle in the direction drawn uniformly over its solid angle by
    /// `u` ∈ [0, 1)²: u.x picks the column x, u.y the height within it. The density of its
    /// direction is 1/S.
    pub fn sample(&self, u: Vec2) -> Vec3 {
        let au = u.x * self.solid_angle + self.k;
        let (sin_au, cos_au) = au.sin_cos();
        let fu = (cos_au * self.b0 - self.b1) / sin_au;
        let cu = ((fu * fu + self.b0 * self.b0).sqrt().recip()).copysign(fu).clamp(-1.0, 1.0);
        let xu = -(cu * self.z0) / (1.0 - cu * cu).max(0.0).sqrt();
        // At the ends of the range the quotient can round past the edge (or be 0/0 at a
        // vanishing S): keep the column on the rectangle.
        let xu = if xu.is_nan() { self.x0 + u.x * (self.x1 - self.x0) } else { xu.clamp(self.x0, self.x1) };
        let d2 = xu * xu + self.z0 * self.z0;
        let (h0, h1) = (self.height(self.y0, d2), self.height(self.y1, d2));
        let hv = h0 + u.y * (h1 - h0);
        let hv2 = hv * hv;
        let yv = if hv2 < 1.0 - 1e-6 { (hv * d2.sqrt() / (1.0 - hv2).sqrt()).clamp(self.y0, self.y1) } else { self.y1 };
        self.o + xu * self.x + yv * self.y + self.z0 * self.z
    }

    /// The `u` ∈ [0, 1]² that [`Self::sample`] maps to the point `p` of the rectangle.
    pub fn invert(&self, p: Vec3) -> Vec2 {
        let d = p - self.o;
        let (xu, yv) = (d.dot(self.x).clamp(self.x0, self.x1), d.dot(self.y).clamp(self.y0, self.y1));
        // The solid angle of the sub-rectangle [x0, xu] × [y0, y1], over S.
        let n1 = Vec3::new(-self.z0, 0.0, xu).normalize();
        let angle = |a: Vec3, b: Vec3| (-a.dot(b)).clamp(-1.0, 1.0).acos();
        let sub = angle(self.n0, n1) + angle(n1, self.n2) - self.k;
        let u = if self.solid_angle > 0.0 { (sub / self.solid_angle).clamp(0.0, 1.0) } else { 0.5 };
        let d2 = xu * xu + self.z0 * self.z0;
        let (h0, h1, hv) = (self.height(self.y0, d2), self.height(self.y1, d2), self.height(yv, d2));
        let v = if h1 > h0 { ((hv - h0) / (h1 - h0)).clamp(0.0, 1.0) } else { 0.5 };
        Vec2::new(u, v)
    }

    /// sin of the elevation of height `y` in the column at squared distance `d2`.
    #[inline]
    fn height(&self, y: f32, d2: f32) -> f32 {
        y / (d2 + y * y).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::chi2::{Chi2Test, Domain};
    use crate::sampling::Rng;

    /// The solid angle of an a × b rectangle seen from height h above one corner:
    /// Ω = atan(ab / (h √(a² + b² + h²))) (the classical form factor integral).
    fn corner_solid_angle(a: f64, b: f64, h: f64) -> f64 {
        (a * b / (h * (a * a + b * b + h * h).sqrt())).atan()
    }

    #[test]
    fn the_solid_angle_is_the_closed_form() {
        for (a, b, h) in [(1.0, 1.0, 1.0), (3.0, 0.5, 0.1), (0.3, 0.2, 5.0), (10.0, 10.0, 0.01)] {
            // Seen from above a corner, and from above the centre (four corner rectangles).
            let r = SphericalRectangle::new(
                Vec3::new(0.0, 0.0, h as f32),
                Vec3::ZERO,
                Vec3::X * a as f32,
                Vec3::Y * b as f32,
            )
            .unwrap();
            // Angles near π summed and differenced in single precision: a few 10⁻⁵ sr at most.
            let want = corner_solid_angle(a, b, h);
            let tol = 5e-5f64.min(1e-3 * want).max(2e-5 * want);
            assert!((r.solid_angle() as f64 - want).abs() < tol, "{a} {b} {h}: {} vs {want}", r.solid_angle());
            let c = Vec3::new(0.5 * a as f32, 0.5 * b as f32, -(h as f32));
            let r = SphericalRectangle::new(c, Vec3::ZERO, Vec3::X * a as f32, Vec3::Y * b as f32).unwrap();
            let want = 4.0 * corner_solid_angle(a / 2.0, b / 2.0, h);
            let tol = 5e-5f64.min(1e-3 * want).max(2e-5 * want);
            assert!((r.solid_angle() as f64 - want).abs() < tol, "centre {a} {b} {h}: {} vs {want}", r.solid_angle());
        }
        assert!(SphericalRectangle::new(Vec3::new(0.3, 0.2, 0.0), Vec3::ZERO, Vec3::X, Vec3::Y).is_none());
    }

    /// A rectangle tilted and offset from the point, in world space.
    fn tilted() -> (Vec3, Vec3, Vec3, Vec3) {
        let ex = Vec3::new(1.5, 0.3, -0.2);
        let ey = ex.cross(Vec3::new(0.1, 0.2, 1.0)).normalize() * 0.8;
        (Vec3::new(0.2, -0.4, 0.3), Vec3::new(-0.9, 0.6, 1.1), ex, ey)
    }

    #[test]
    fn samples_land_on_the_rectangle_and_invert_to_their_uniforms() {
        let (o, c, ex, ey) = tilted();
        let r = SphericalRectangle::new(o, c, ex, ey).unwrap();
        let n = ex.cross(ey).normalize();
        let mut rng = Rng::new(1, 2);
        for _ in 0..20_000 {
            let u = Vec2::new(rng.uniform(), rng.uniform());
            let p = r.sample(u);
            let q = p - c;
            assert!(q.dot(n).abs() < 1e-5, "off the plane: {}", q.dot(n));
            let (s, t) = (q.dot(ex) / ex.length_squared(), q.dot(ey) / ey.length_squared());
            assert!((-1e-5..=1.0 + 1e-5).contains(&s) && (-1e-5..=1.0 + 1e-5).contains(&t), "{s} {t}");
            let back = r.invert(p);
            assert!((back - u).abs().max_element() < 2e-4, "{u} → {back}");
        }
    }

    #[test]
    fn directions_are_uniform_over_the_solid_angle() {
        let (o, c, ex, ey) = tilted();
        let r = SphericalRectangle::new(o, c, ex, ey).unwrap();
        let n = ex.cross(ey).normalize();
        let inside = |w: Vec3| {
            // The ray o + t w meets the rectangle.
            let t = (c - o).dot(n) / w.dot(n);
            if t <= 0.0 || t.is_nan() {
                return false;
            }
            let q = o + t * w - c;
            let (s, v) = (q.dot(ex) / ex.length_squared(), q.dot(ey) / ey.length_squared());
            (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&v)
        };
        let axis = (c + 0.5 * (ex + ey) - o).normalize();
        let test = Chi2Test { domain: Domain::Cap { axis, theta_max: 1.2 }, ..Chi2Test::default() };
        let s = r.solid_angle();
        let result = test.run(|_, u| Some((r.sample(u) - o).normalize()), |w| if inside(w) { 1.0 / s } else { 0.0 });
        assert!(result.passed, "{result}");
        // A density that is not uniform (the area density's shape) fails.
        let wrong =
            test.run(|_, u| Some((c + u.x * ex + u.y * ey - o).normalize()), |w| if inside(w) { 1.0 / s } else { 0.0 });
        assert!(!wrong.passed, "area sampling passed as uniform in solid angle: {wrong}");
    }
}
