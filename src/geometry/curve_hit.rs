//! Ray–curve intersection as pbrt-v4's `Curve::IntersectRay` (PBR 4th ed. §6.7.2): the segment
//! is carried into a frame whose z axis is the ray, split recursively at u = ½ (to a depth set by
//! how far the control polygon is from straight, relative to the width) while its hull, grown by
//! half its width, still overlaps the ray, and each final piece is treated as a line segment
//! whose closest point to the ray gives u and the distance across the width. And the surface
//! at a hit — position, normal, ∂p/∂u along the curve, ∂p/∂v across the width, (u, v) — which
//! depends only on the ray and u, so that hits found by any backend shade alike.

use glam::{Vec2, Vec3};

use super::curve::{bezier_point, sub_curve, subdivide, CurveKind, CurveSegment};
use super::Ray;

/// A ray–curve hit: ray parameter and u along the segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveHit {
    /// Ray parameter (units of |d|).
    pub t: f32,
    /// Curve parameter in [0, 1] along the segment.
    pub u: f32,
}

/// The surface of a curve at a hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveSurface {
    /// Hit point, on the ray.
    pub p: Vec3,
    /// Per-axis error bound of `p`: the width at the hit (pbrt-v4's bound; it also keeps a
    /// spawned ray from meeting the curve it leaves). For a ribbon, its width before the
    /// foreshortening that narrowed it for the ray that found it (pbrt-v4 takes the narrowed
    /// width): a ray leaving at another angle sees the ribbon wider.
    pub p_err: Vec3,
    /// Unit normal, ∂p/∂u × ∂p/∂v normalised.
    pub n: Vec3,
    /// Tangent along the curve.
    pub dpdu: Vec3,
    /// Across the width, |∂p/∂v| = the width.
    pub dpdv: Vec3,
    /// (u along the segment, v across the width in [0, 1]).
    pub uv: Vec2,
}

/// An orthonormal right-handed frame with z along the ray direction, origin at the ray origin
/// (pbrt-v4's `LookAt(o, o + d, up)`; any rotation about z gives the same results here).
#[derive(Clone, Copy, Debug)]
struct RayFrame {
    o: Vec3,
    x: Vec3,
    y: Vec3,
    z: Vec3,
}

impl RayFrame {
    /// The frame of `ray` whose x axis is perpendicular to `chord` (the curve's end-to-end
    /// direction) when it can be.
    fn new(ray: &Ray, chord: Vec3) -> Option<Self> {
        let z = ray.d.normalize_or_zero();
        if z == Vec3::ZERO {
            return None;
        }
        let up = ray.d.cross(chord);
        let x = up.cross(z).normalize_or_zero();
        let x = if x == Vec3::ZERO { z.any_orthonormal_vector() } else { x };
        Some(Self { o: ray.o, x, y: z.cross(x), z })
    }

    #[inline]
    fn point(&self, p: Vec3) -> Vec3 {
        let q = p - self.o;
        Vec3::new(self.x.dot(q), self.y.dot(q), self.z.dot(q))
    }

    #[inline]
    fn vector(&self, v: Vec3) -> Vec3 {
        Vec3::new(self.x.dot(v), self.y.dot(v), self.z.dot(v))
    }

    #[inline]
    fn world(&self, v: Vec3) -> Vec3 {
        self.x * v.x + self.y * v.y + self.z * v.z
    }
}

/// Whether the box of `cp` grown by `half_width` meets the ray segment from the origin to
/// z = `z_max` along the z axis.
#[inline]
fn overlaps(cp: &[Vec3], half_width: f32, z_max: f32) -> bool {
    let lo = cp.iter().fold(Vec3::INFINITY, |b, &p| b.min(p)) - Vec3::splat(half_width);
    let hi = cp.iter().fold(Vec3::NEG_INFINITY, |b, &p| b.max(p)) + Vec3::splat(half_width);
    lo.x <= 0.0 && hi.x >= 0.0 && lo.y <= 0.0 && hi.y >= 0.0 && hi.z >= 0.0 && lo.z <= z_max
}

/// The closest hit of `ray` with t in (0, t_max] on the part of `seg` with u in [u0, u1], or
/// with `any`, the first found.
pub fn intersect_curve(seg: &CurveSegment, u0: f32, u1: f32, ray: &Ray, t_max: f32, any: bool) -> Option<CurveHit> {
    let piece = sub_curve(&seg.cp, u0, u1);
    let frame = RayFrame::new(ray, piece[3] - piece[0])?;
    let cp = piece.map(|p| frame.point(p));
    let ray_len = ray.d.length();
    let max_width = seg.width_at(u0).max(seg.width_at(u1));
    if !overlaps(&cp, 0.5 * max_width, ray_len * t_max) {
        return None;
    }
    let depth = refinement_depth(&cp, seg.width);
    let mut search = Search { seg, dir: frame.z, ray_len, t_max, any, best: None };
    search.recurse(&cp, u0, u1, depth);
    search.best
}

/// How many times to halve the piece with control points `cp` (ray frame) so that each part is
/// straight to within a twentieth of the larger of the `width`s: the control polygon's second
/// differences L₀ bound the deviation from the chord (PBR 4th ed. §6.7.2), and pbrt-v4 takes
/// log₄ of √2 · 6 L₀ / (8 ε) as half of the nearest integer log₂, from 0 to 10.
fn refinement_depth(cp: &[Vec3; 4], width: [f32; 2]) -> i32 {
    let l0 = (0..2).map(|i| (cp[i] - 2.0 * cp[i + 1] + cp[i + 2]).abs().max_element()).fold(0.0f32, f32::max);
    if l0 <= 0.0 {
        return 0;
    }
    let eps = width[0].max(width[1]) * 0.05;
    let x = std::f32::consts::SQRT_2 * 6.0 * l0 / (8.0 * eps);
    if x.is_finite() {
        (log2_nearest(x) / 2).clamp(0, 10)
    } else {
        10
    }
}

/// log₂ `x` rounded to the nearest integer in the log domain (up from √2 times a power of two),
/// as pbrt-v4's `Log2Int(float)`: read off the bits of `x` > 0, and for `x` < 1, −log2_nearest(1/x).
fn log2_nearest(x: f32) -> i32 {
    if x < 1.0 {
        return -log2_nearest(1.0 / x);
    }
    /// The significand bits of √2.
    const SQRT_2_SIGNIFICAND: u32 = 0x0035_04f3;
    let bits = x.to_bits();
    let exponent = ((bits >> 23) & 0xff) as i32 - 127;
    exponent + i32::from(bits & 0x007f_ffff >= SQRT_2_SIGNIFICAND)
}

/// The state of one recursive search.
struct Search<'a> {
    seg: &'a CurveSegment,
    /// The unit ray direction, world space.
    dir: Vec3,
    ray_len: f32,
    t_max: f32,
    any: bool,
    best: Option<CurveHit>,
}

impl Search<'_> {
    /// Searches the piece `cp` (ray frame) spanning [u0, u1]; true to stop (an any-hit found).
    fn recurse(&mut self, cp: &[Vec3; 4], u0: f32, u1: f32, depth: i32) -> bool {
        if depth > 0 {
            let split = subdivide(cp);
            let u = [u0, 0.5 * (u0 + u1), u1];
            for half in 0..2 {
                let piece: [Vec3; 4] = split[3 * half..3 * half + 4].try_into().expect("four points");
                let half_width = 0.5 * self.seg.width_at(u[half]).max(self.seg.width_at(u[half + 1]));
                let z_max = self.ray_len * self.best.map_or(self.t_max, |b| b.t);
                if overlaps(&piece, half_width, z_max) && self.recurse(&piece, u[half], u[half + 1], depth - 1) {
                    return true;
                }
            }
            return false;
        }
        // The ray must lie between the perpendiculars to the tangents at the two ends.
        if (cp[1].y - cp[0].y) * -cp[0].y + cp[0].x * (cp[0].x - cp[1].x) < 0.0 {
            return false;
        }
        if (cp[2].y - cp[3].y) * -cp[3].y + cp[3].x * (cp[3].x - cp[2].x) < 0.0 {
            return false;
        }
        // w: the parameter of the chord's point closest to the ray.
        let chord = Vec2::new(cp[3].x - cp[0].x, cp[3].y - cp[0].y);
        let denom = chord.length_squared();
        if denom == 0.0 {
            return false;
        }
        let w = -Vec2::new(cp[0].x, cp[0].y).dot(chord) / denom;
        let u = (u0 + (u1 - u0) * w).clamp(u0, u1);
        let mut hit_width = self.seg.width_at(u);
        if self.seg.kind == CurveKind::Ribbon {
            // A ribbon seen at an angle is narrower by |n · d̂|.
            hit_width *= ribbon_foreshortening(self.seg, u, self.dir);
        }
        let (pc, _) = bezier_point(cp, w.clamp(0.0, 1.0));
        if pc.x * pc.x + pc.y * pc.y > hit_width * hit_width * 0.25 {
            return false;
        }
        let limit = self.ray_len * self.best.map_or(self.t_max, |b| b.t);
        if pc.z <= 0.0 || pc.z > limit {
            return false;
        }
        self.best = Some(CurveHit { t: pc.z / self.ray_len, u });
        self.any
    }
}

/// |n · d̂| for a ribbon at `u` seen along `dir`.
fn ribbon_foreshortening(seg: &CurveSegment, u: f32, dir: Vec3) -> f32 {
    seg.ribbon_normal(u).dot(dir).abs()
}

/// The surface of `seg` where `ray` hit it at parameter `t` and curve parameter `u` (pbrt-v4's
/// interaction for a curve hit): v from the signed distance of the ray to the curve's centre
/// line relative to the width; ∂p/∂v across the width — perpendicular to the tangent in the
/// plane facing the ray, or along n × ∂p/∂u for a ribbon — and for a cylinder turned about the
/// tangent by θ = 180°·v − 90°, so the normal sweeps the half-tube facing the ray.
pub fn curve_surface(seg: &CurveSegment, ray: &Ray, t: f32, u: f32) -> Option<CurveSurface> {
    let frame = RayFrame::new(ray, seg.cp[3] - seg.cp[0])?;
    let u = u.clamp(0.0, 1.0);
    let local = seg.cp.map(|p| frame.point(p));
    let (pc, dpc) = bezier_point(&local, u);
    let (_, dpdu) = bezier_point(&seg.cp, u);
    let mut hit_width = seg.width_at(u);
    let ribbon_n = (seg.kind == CurveKind::Ribbon).then(|| seg.ribbon_normal(u));
    if ribbon_n.is_some() {
        hit_width *= ribbon_foreshortening(seg, u, frame.z);
    }
    let dist = (pc.x * pc.x + pc.y * pc.y).sqrt();
    let edge = dpc.x * -pc.y + pc.x * dpc.y;
    let offset = if hit_width > 0.0 { dist / hit_width } else { 0.0 };
    let v = (if edge > 0.0 { 0.5 + offset } else { 0.5 - offset }).clamp(0.0, 1.0);
    let dpdv = match ribbon_n {
        Some(n) => n.cross(dpdu).normalize_or_zero() * hit_width,
        None => {
            let dpdu_plane = frame.vector(dpdu);
            let across = Vec3::new(-dpdu_plane.y, dpdu_plane.x, 0.0).normalize_or_zero() * hit_width;
            let across = if seg.kind == CurveKind::Cylinder {
                let theta = (180.0 * v - 90.0).to_radians();
                rotate(across, dpdu_plane.normalize_or_zero(), -theta)
            } else {
                across
            };
            frame.world(across)
        }
    };
    let n = dpdu.cross(dpdv).normalize_or_zero();
    if n == Vec3::ZERO {
        return None;
    }
    let p_err = Vec3::splat(seg.width_at(u));
    Some(CurveSurface { p: ray.at(t), p_err, n, dpdu, dpdv, uv: Vec2::new(u, v) })
}

/// `v` rotated by `angle` [radians] about the unit `axis` (Rodrigues' formula).
#[inline]
fn rotate(v: Vec3, axis: Vec3, angle: f32) -> Vec3 {
    let (s, c) = angle.sin_cos();
    v * c + axis.cross(v) * s + axis * axis.dot(v) * (1.0 - c)
}

#[cfg(test)]
#[path = "curve_hit_tests.rs"]
mod tests;
