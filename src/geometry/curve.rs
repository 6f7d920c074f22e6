//! pbrt-v4's curves (Pharr, Jakob & Humphreys, *Physically Based Rendering*, 4th ed., §6.7):
//! cubic Bézier segments whose width varies linearly along the segment, of three kinds — flat
//! ribbons that always face the ray, "cylinders" (the same ribbons with the normal turned across
//! the width so that they shade like a tube), and ribbons oriented by normals given at the segment
//! ends. B-splines and quadratic curves are turned into cubic Bézier segments as pbrt-v4 does.
//!
//! Segments are stored in world space, or in an object instance's space inside an object
//! definition (the control points carried by the shape's transform: a Bézier curve is affine
//! invariant, so this is the transformed curve exactly; its width is scaled by the transform's
//! scale, exact under a similarity).

use glam::{Mat3, Mat4, Vec3};

use super::quadric::similarity_scale;
use super::Bounds3;

/// How a curve meets a ray (pbrt-v4 `CurveType`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveKind {
    /// A ribbon facing the ray; its normal faces the ray too.
    Flat,
    /// A ribbon facing the ray whose normal is turned from −90° to 90° across the width.
    Cylinder,
    /// A ribbon oriented by normals given at the segment ends (spherically interpolated).
    Ribbon,
}

/// One cubic Bézier segment of a curve shape (pbrt-v4 `CurveCommon`), world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveSegment {
    /// Control points [scene units].
    pub cp: [Vec3; 4],
    /// Width at u = 0 and u = 1 [scene units]; linear in between.
    pub width: [f32; 2],
    /// Unit normals at u = 0 and u = 1 (ribbons only; zero otherwise).
    pub n: [Vec3; 2],
    /// Angle between the two normals [radians].
    pub normal_angle: f32,
    /// The kind of curve.
    pub kind: CurveKind,
}

/// The segments of one curve shape and how finely each is split into BVH primitives.
#[derive(Clone, Debug, PartialEq)]
pub struct Curves {
    /// The segments (a hit's `prim_id` indexes them).
    pub segments: Vec<CurveSegment>,
    /// Each segment becomes 2^split_depth primitives of equal u range (pbrt-v4 "splitdepth").
    pub split_depth: u32,
    /// The normal ∂p/∂u × ∂p/∂v is reversed (pbrt-v4: `ReverseOrientation` differing from
    /// whether the transform to world space swaps handedness).
    pub flip_normal: bool,
}

impl CurveSegment {
    /// A segment of `kind` with control points `cp`, widths `width` at its ends and, for a
    /// ribbon, the normals `n` at its ends (normalised here).
    pub fn new(cp: [Vec3; 4], width: [f32; 2], kind: CurveKind, n: [Vec3; 2]) -> Self {
        let n = if kind == CurveKind::Ribbon { n.map(Vec3::normalize_or_zero) } else { [Vec3::ZERO; 2] };
        let normal_angle = n[0].dot(n[1]).clamp(-1.0, 1.0).acos();
        Self { cp, width, n, normal_angle, kind }
    }

    /// Width at `u` [scene units].
    #[inline]
    pub fn width_at(&self, u: f32) -> f32 {
        lerp(u, self.width[0], self.width[1])
    }

    /// A ribbon's normal at `u`: the spherical interpolation of the end normals.
    #[inline]
    pub fn ribbon_normal(&self, u: f32) -> Vec3 {
        if self.normal_angle == 0.0 {
            return self.n[0];
        }
        let inv_sin = 1.0 / self.normal_angle.sin();
        let s0 = ((1.0 - u) * self.normal_angle).sin() * inv_sin;
        let s1 = (u * self.normal_angle).sin() * inv_sin;
        s0 * self.n[0] + s1 * self.n[1]
    }

    /// Bounds of the part with u in [u0, u1]: its control hull grown by half its largest width.
    pub fn bounds(&self, u0: f32, u1: f32) -> Bounds3 {
        let cp = sub_curve(&self.cp, u0, u1);
        let half = 0.5 * self.width_at(u0).max(self.width_at(u1));
        let b = cp.iter().fold(Bounds3::EMPTY, |b, &p| b.union_point(p));
        Bounds3 { min: b.min - Vec3::splat(half), max: b.max + Vec3::splat(half) }
    }
}

impl Curves {
    /// The BVH primitives: (segment index, u range) for every piece of every segment.
    pub fn pieces(&self) -> impl Iterator<Item = (u32, [f32; 2])> + '_ {
        let n = 1u32 << self.split_depth.min(16);
        (0..self.segments.len() as u32)
            .flat_map(move |s| (0..n).map(move |i| (s, [i as f32 / n as f32, (i + 1) as f32 / n as f32])))
    }

    /// Bounds of every segment.
    pub fn bounds(&self) -> Bounds3 {
        self.segments.iter().fold(Bounds3::EMPTY, |b, s| b.union(s.bounds(0.0, 1.0)))
    }

    /// The curves carried by the affine `m`: control points transformed, ribbon normals by the
    /// inverse transpose, widths scaled by m's scale (a similarity's, else the cube root of
    /// |det|), and the normal reversed once more when `m` swaps handedness (pbrt-v4 reverses it
    /// for `ReverseOrientation` differing from the transform's handedness).
    pub fn transformed(&self, m: &Mat4) -> Self {
        let linear = Mat3::from_mat4(*m);
        let scale = similarity_scale(m).unwrap_or_else(|| linear.determinant().abs().cbrt());
        let normal_matrix = linear.inverse().transpose();
        let segments = self
            .segments
            .iter()
            .map(|seg| {
                let cp = seg.cp.map(|p| m.transform_point3(p));
                let n = seg.n.map(|n| normal_matrix * n);
                CurveSegment::new(cp, seg.width.map(|w| w * scale), seg.kind, n)
            })
            .collect();
        let flip_normal = self.flip_normal ^ (linear.determinant() < 0.0);
        Self { segments, split_depth: self.split_depth, flip_normal }
    }
}

/// The basis the control points of a curve shape are given in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveBasis {
    /// Bézier: segments share their end points.
    Bezier,
    /// Uniform B-spline: each run of degree + 1 points is one segment.
    BSpline,
}

/// Control points that make no curve.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum CurveError {
    /// A degree other than 2 or 3.
    #[error("degree {0}: only degree 2 and 3 curves are supported")]
    Degree(usize),
    /// A Bézier curve's point count that is not degree + 1 + n·degree.
    #[error("{points} control points: a degree {degree} Bézier curve needs {} + n·{degree}", .degree + 1)]
    BezierPoints {
        /// Control points given.
        points: usize,
        /// The curve's degree.
        degree: usize,
    },
    /// Fewer than degree + 1 points of a B-spline.
    #[error("{points} control points: a degree {degree} B-spline needs at least {}", .degree + 1)]
    BSplinePoints {
        /// Control points given.
        points: usize,
        /// The curve's degree.
        degree: usize,
    },
}

/// The cubic Bézier segments of a curve of `degree` 2 or 3 through control points `p` in
/// `basis` (pbrt-v4 `Curve::Create`); an error when the count does not fit.
pub fn bezier_segments(p: &[Vec3], basis: CurveBasis, degree: usize) -> Result<Vec<[Vec3; 4]>, CurveError> {
    if degree != 2 && degree != 3 {
        return Err(CurveError::Degree(degree));
    }
    match basis {
        CurveBasis::Bezier => {
            if p.len() < degree + 1 || !(p.len() - 1 - degree).is_multiple_of(degree) {
                return Err(CurveError::BezierPoints { points: p.len(), degree });
            }
            Ok((0..(p.len() - 1) / degree)
                .map(|s| {
                    let c = &p[s * degree..];
                    if degree == 2 {
                        elevate_quadratic([c[0], c[1], c[2]])
                    } else {
                        [c[0], c[1], c[2], c[3]]
                    }
                })
                .collect())
        }
        CurveBasis::BSpline => {
            if p.len() < degree + 1 {
                return Err(CurveError::BSplinePoints { points: p.len(), degree });
            }
            Ok((0..p.len() - degree)
                .map(|s| {
                    let c = &p[s..];
                    if degree == 2 {
                        // The quadratic uniform B-spline's Bézier points: the two midpoints and
                        // the middle point.
                        elevate_quadratic([(c[0] + c[1]) * 0.5, c[1], (c[1] + c[2]) * 0.5])
                    } else {
                        cubic_bspline_to_bezier([c[0], c[1], c[2], c[3]])
                    }
                })
                .collect())
        }
    }
}

/// The Bézier control points of one span of a uniform cubic B-spline (change of basis:
/// b₀ = (p₀ + 4p₁ + p₂)/6, b₁ = (2p₁ + p₂)/3, b₂ = (p₁ + 2p₂)/3, b₃ = (p₁ + 4p₂ + p₃)/6).
pub fn cubic_bspline_to_bezier(p: [Vec3; 4]) -> [Vec3; 4] {
    [
        (p[0] + 4.0 * p[1] + p[2]) / 6.0,
        (2.0 * p[1] + p[2]) / 3.0,
        (p[1] + 2.0 * p[2]) / 3.0,
        (p[1] + 4.0 * p[2] + p[3]) / 6.0,
    ]
}

/// The cubic with the same curve as the quadratic Bézier `q` (degree elevation).
pub fn elevate_quadratic(q: [Vec3; 3]) -> [Vec3; 4] {
    [q[0], q[0] + (q[1] - q[0]) * (2.0 / 3.0), q[2] + (q[1] - q[2]) * (2.0 / 3.0), q[2]]
}

/// Point of the cubic Bézier `cp` at `u` and its derivative d/du (de Casteljau). Where the
/// derivative vanishes (coincident control points) the chord cp₃ − cp₀ stands in for it.
#[inline]
pub fn bezier_point(cp: &[Vec3; 4], u: f32) -> (Vec3, Vec3) {
    let a = [cp[0].lerp(cp[1], u), cp[1].lerp(cp[2], u), cp[2].lerp(cp[3], u)];
    let b = [a[0].lerp(a[1], u), a[1].lerp(a[2], u)];
    let d = b[1] - b[0];
    let deriv = if d.length_squared() > 0.0 { 3.0 * d } else { cp[3] - cp[0] };
    (b[0].lerp(b[1], u), deriv)
}

/// The blossom B(u₀, u₁, u₂) of the cubic Bézier `cp` (PBR 4th ed. §6.7.1).
#[inline]
fn blossom(cp: &[Vec3; 4], u0: f32, u1: f32, u2: f32) -> Vec3 {
    let a = [cp[0].lerp(cp[1], u0), cp[1].lerp(cp[2], u0), cp[2].lerp(cp[3], u0)];
    let b = [a[0].lerp(a[1], u1), a[1].lerp(a[2], u1)];
    b[0].lerp(b[1], u2)
}

/// Control points of the part of `cp` with u in [u0, u1], from its blossoms.
#[inline]
pub fn sub_curve(cp: &[Vec3; 4], u0: f32, u1: f32) -> [Vec3; 4] {
    [blossom(cp, u0, u0, u0), blossom(cp, u0, u0, u1), blossom(cp, u0, u1, u1), blossom(cp, u1, u1, u1)]
}

/// The two halves of `cp` split at u = ½: points 0–3 and 3–6.
#[inline]
pub fn subdivide(cp: &[Vec3; 4]) -> [Vec3; 7] {
    let m01 = (cp[0] + cp[1]) * 0.5;
    let m12 = (cp[1] + cp[2]) * 0.5;
    let m23 = (cp[2] + cp[3]) * 0.5;
    let a = (m01 + m12) * 0.5;
    let b = (m12 + m23) * 0.5;
    [cp[0], m01, a, (a + b) * 0.5, b, m23, cp[3]]
}

#[inline]
fn lerp(t: f32, a: f32, b: f32) -> f32 {
    (1.0 - t) * a + t * b
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cubic polynomial through `cp` at u by the Bernstein form (independent of de Casteljau).
    fn bernstein(cp: &[Vec3; 4], u: f32) -> Vec3 {
        let s = 1.0 - u;
        cp[0] * s * s * s + cp[1] * 3.0 * s * s * u + cp[2] * 3.0 * s * u * u + cp[3] * u * u * u
    }

    #[test]
    fn bspline_segments_meet_with_matching_tangents() {
        let p: Vec<Vec3> = (0..6).map(|i| Vec3::new(i as f32, (i * i) as f32 * 0.3, (i as f32).sin())).collect();
        let segs = bezier_segments(&p, CurveBasis::BSpline, 3).unwrap();
        assert_eq!(segs.len(), 3);
        // The uniform cubic B-spline at a knot is (p_{i} + 4 p_{i+1} + p_{i+2}) / 6.
        assert!((segs[0][0] - (p[0] + 4.0 * p[1] + p[2]) / 6.0).length() < 1e-6);
        for w in segs.windows(2) {
            assert!((w[0][3] - w[1][0]).length() < 1e-5);
            assert!(((w[0][3] - w[0][2]) - (w[1][1] - w[1][0])).length() < 1e-5);
        }
        // The B-spline's value at a span midpoint: (p0 + 23 p1 + 23 p2 + p3) / 48.
        let mid = (p[0] + 23.0 * p[1] + 23.0 * p[2] + p[3]) / 48.0;
        assert!((bernstein(&segs[0], 0.5) - mid).length() < 1e-5);
    }

    #[test]
    fn bezier_counts_are_checked_and_quadratics_elevated() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::new(2.0, 1.0, 0.0), Vec3::Y, Vec3::Z, Vec3::ONE, Vec3::NEG_X];
        assert_eq!(bezier_segments(&p, CurveBasis::Bezier, 3).unwrap().len(), 2);
        assert!(bezier_segments(&p[..6], CurveBasis::Bezier, 3).is_err());
        assert!(bezier_segments(&p, CurveBasis::Bezier, 4).is_err());
        let q = bezier_segments(&p[..3], CurveBasis::Bezier, 2).unwrap()[0];
        // The quadratic (1−u)²a + 2u(1−u)b + u²c at u = 0.3.
        let u = 0.3f32;
        let expect = p[0] * (1.0 - u).powi(2) + p[1] * 2.0 * u * (1.0 - u) + p[2] * u * u;
        assert!((bernstein(&q, u) - expect).length() < 1e-6);
    }

    #[test]
    fn evaluation_splitting_and_sub_curves_agree_with_bernstein_form() {
        let cp = [Vec3::ZERO, Vec3::new(1.0, 2.0, 0.0), Vec3::new(3.0, -1.0, 1.0), Vec3::new(4.0, 0.0, 2.0)];
        for &u in &[0.0, 0.2, 0.5, 0.9, 1.0] {
            assert!((bezier_point(&cp, u).0 - bernstein(&cp, u)).length() < 1e-5);
        }
        for &u in &[0.2, 0.5, 0.9] {
            let d = bezier_point(&cp, u).1;
            let h = 1e-2;
            let fd = (bernstein(&cp, u + h) - bernstein(&cp, u - h)) / (2.0 * h);
            assert!((d - fd).length() < 1e-2 * d.length(), "u={u}: {d} vs {fd}");
        }
        let halves = subdivide(&cp);
        let sub = sub_curve(&cp, 0.25, 0.75);
        for &t in &[0.0, 0.3, 1.0] {
            let lo: [Vec3; 4] = halves[0..4].try_into().unwrap();
            let hi: [Vec3; 4] = halves[3..7].try_into().unwrap();
            assert!((bernstein(&lo, t) - bernstein(&cp, 0.5 * t)).length() < 1e-5);
            assert!((bernstein(&hi, t) - bernstein(&cp, 0.5 + 0.5 * t)).length() < 1e-5);
            assert!((bernstein(&sub, t) - bernstein(&cp, 0.25 + 0.5 * t)).length() < 1e-5);
        }
    }

    #[test]
    fn ribbon_normals_interpolate_on_the_sphere() {
        let s = CurveSegment::new([Vec3::ZERO; 4], [1.0, 1.0], CurveKind::Ribbon, [Vec3::Z, Vec3::X * 2.0]);
        let n = s.ribbon_normal(0.5);
        assert!((n - Vec3::new(1.0, 0.0, 1.0).normalize()).length() < 1e-6);
        assert!((s.ribbon_normal(0.0) - Vec3::Z).length() < 1e-6);
        let c = Curves { segments: vec![s; 2], split_depth: 2, flip_normal: false };
        assert_eq!(c.pieces().count(), 8);
        assert_eq!(c.pieces().nth(5), Some((1, [0.25, 0.5])));
    }
}
