//! The checkerboard (pbrt-v4 §10.5.3), 2D in (s, t) or 3D in texture space, antialiased in
//! closed form: the ±1 square wave of each axis is convolved with a triangle filter as wide as
//! the footprint, and the filtered axes multiply.

use super::context::TextureEvalContext;
use super::mapping::{Mapping2D, Mapping3D};

/// Where the checks are laid out.
#[derive(Clone, Debug, PartialEq)]
pub enum Checkerboard {
    /// Unit squares in (s, t) ("dimension" 2).
    Planar(Mapping2D),
    /// Unit cubes in texture space ("dimension" 3).
    Solid(Mapping3D),
}

/// Second antiderivative D of the square wave c(x) = +1 where ⌊x⌋ is even, −1 where odd: the
/// first antiderivative is a triangle wave whose integral over a period (2) is 1, so
/// D(x) = ⌊x/2⌋ + G(x mod 2) with G(t) = t²/2 on [0, 1] and 1 − (2 − t)²/2 on [1, 2].
fn square_wave_second_integral(x: f64) -> f64 {
    let k = (x / 2.0).floor();
    let t = x - 2.0 * k;
    let g = if t < 1.0 { 0.5 * t * t } else { 1.0 - 0.5 * (2.0 - t) * (2.0 - t) };
    k + g
}

/// The square wave c at `x` averaged with a triangle filter of half-width `r`:
/// (1/r²) ∫ c(x + u)(r − |u|) du = (D(x + r) − 2D(x) + D(x − r))/r². Exact ±1 when the
/// filter does not reach a cell edge.
fn filtered_square_wave(x: f32, r: f32) -> f64 {
    let (x, r) = (x as f64, r as f64);
    if (x - r).floor() == (x + r).floor() {
        return if (x.floor() as i64) & 1 == 0 { 1.0 } else { -1.0 };
    }
    let d = square_wave_second_integral;
    (d(x + r) - 2.0 * d(x) + d(x - r)) / (r * r)
}

/// Half-width of the triangle filter per unit of footprint (pbrt-v4's factor).
const FILTER_SCALE: f32 = 1.5;

impl Checkerboard {
    /// The weight of the second texture at `ctx`: 0 on even cells (⌊s⌋ + ⌊t⌋ even, or the
    /// sum of the three cell indices), 1 on odd ones, in between where the footprint covers
    /// both.
    pub fn weight(&self, ctx: &TextureEvalContext) -> f32 {
        let product = match self {
            Checkerboard::Planar(m) => {
                let c = m.map(ctx);
                let w = FILTER_SCALE * c.dst_dx.abs().max(c.dst_dy.abs());
                filtered_square_wave(c.st.x, w.x) * filtered_square_wave(c.st.y, w.y)
            }
            Checkerboard::Solid(m) => {
                let c = m.map(ctx);
                let w = FILTER_SCALE * c.dpdx.abs().max(c.dpdy.abs());
                filtered_square_wave(c.p.x, w.x) * filtered_square_wave(c.p.y, w.y) * filtered_square_wave(c.p.z, w.z)
            }
        };
        (0.5 - 0.5 * product) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Mat4, Vec2, Vec3};

    #[test]
    fn unfiltered_parity_at_chosen_points() {
        let board = Checkerboard::Planar(Mapping2D::Uv { scale: Vec2::splat(4.0), delta: Vec2::ZERO });
        let w = |u: f32, v: f32| board.weight(&TextureEvalContext::uv(Vec2::new(u, v)));
        // (u, v) · 4 → cells (0, 0), (1, 0), (1, 1), (3, 2), (−1, 0).
        assert_eq!(w(0.1, 0.1), 0.0);
        assert_eq!(w(0.3, 0.1), 1.0);
        assert_eq!(w(0.3, 0.3), 0.0);
        assert_eq!(w(0.8, 0.6), 1.0);
        assert_eq!(w(-0.1, 0.1), 1.0);
        let solid = Checkerboard::Solid(Mapping3D { texture_from_world: Mat4::from_scale(Vec3::splat(5.0)) });
        let at = |p: Vec3| solid.weight(&TextureEvalContext::at(p, Vec3::Z, Vec2::ZERO));
        // Cells of 0.2: (0, 0, 0) even, (1, 0, 0) odd, (1, 1, 0) even, (1, 1, −1) odd.
        assert_eq!(at(Vec3::new(0.1, 0.1, 0.1)), 0.0);
        assert_eq!(at(Vec3::new(0.3, 0.1, 0.1)), 1.0);
        assert_eq!(at(Vec3::new(0.3, 0.3, 0.1)), 0.0);
        assert_eq!(at(Vec3::new(0.3, 0.3, -0.1)), 1.0);
    }

    #[test]
    fn the_second_integral_has_the_square_wave_as_second_derivative() {
        let h = 1e-3;
        for &x in &[0.3, 0.9, 1.4, 2.2, 3.7, -0.6, -1.5, 100.25] {
            let d = square_wave_second_integral;
            let second = (d(x + h) - 2.0 * d(x) + d(x - h)) / (h * h);
            let c = if (f64::floor(x) as i64) & 1 == 0 { 1.0 } else { -1.0 };
            assert!((second - c).abs() < 1e-6, "D''({x}) = {second}");
        }
    }

    #[test]
    fn filtering_at_an_edge_and_far_away() {
        // Centred on a cell edge the triangle filter sees half of each cell: 0.
        assert!(filtered_square_wave(1.0, 0.5).abs() < 1e-12);
        // A wide filter averages many cells: near 0 (exact value: a triangle of half-width r
        // over a ±1 wave leaves at most 1/(2r²)·... ≤ 1/r).
        assert!(filtered_square_wave(0.37, 20.0).abs() < 0.05);
        // Inside a cell and away from edges: exact.
        assert_eq!(filtered_square_wave(2.5, 0.2), 1.0);
        // The filtered value is continuous where the filter starts to reach an edge.
        let a = filtered_square_wave(0.7, 0.3 - 1e-5);
        let b = filtered_square_wave(0.7, 0.3 + 1e-5);
        assert!((a - b).abs() < 1e-3, "{a} vs {b}");
    }
}
