//! Helpers shared by the end-to-end tests.

use prism::film::Film;

/// Compares two films pixel by pixel on Y: the mean of the per-pixel differences, its standard
/// error (pixels are independent estimates), and the mean Y of `a`.
pub fn film_difference(a: &Film, b: &Film) -> (f64, f64, f64) {
    let y = |p: &prism::film::Pixel| p.xyz_sum.y / p.weight_sum;
    let d: Vec<f64> = a.pixels.iter().zip(&b.pixels).map(|(p, q)| y(p) - y(q)).collect();
    let n = d.len() as f64;
    let m = d.iter().sum::<f64>() / n;
    let se = (d.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (n - 1.0) / n).sqrt();
    (m, se, a.pixels.iter().map(y).sum::<f64>() / n)
}
