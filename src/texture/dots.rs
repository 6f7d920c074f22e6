//! Polka dots (pbrt-v4 §10.6.1): one dot of radius 0.35 in about half of the unit cells of
//! (s, t) centred on integer points, the cells with a dot and each dot's jitter chosen by noise
//! so the pattern looks irregular yet is fixed.

use super::noise::noise_2d;
use glam::Vec2;

/// Dot radius [cells].
const RADIUS: f32 = 0.35;

/// True when (s, t) lies inside a dot.
pub fn inside_polka_dot(st: Vec2) -> bool {
    let (s_cell, t_cell) = ((st.x + 0.5).floor(), (st.y + 0.5).floor());
    if noise_2d(s_cell + 0.5, t_cell + 0.5) <= 0.0 {
        return false;
    }
    // The centre may move by up to the margin between the dot and its cell's edge.
    let max_shift = 0.5 - RADIUS;
    let centre = Vec2::new(
        s_cell + max_shift * noise_2d(s_cell + 1.5, t_cell + 2.8),
        t_cell + max_shift * noise_2d(s_cell + 4.5, t_cell + 9.8),
    );
    (st - centre).length_squared() < RADIUS * RADIUS
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dots_lie_in_cells_noise_selects() {
        let (mut with, mut cells) = (0, 0);
        for i in -20..20 {
            for j in -20..20 {
                let (s, t) = (i as f32, j as f32);
                let selected = noise_2d(s + 0.5, t + 0.5) > 0.0;
                let centre = Vec2::new(s + 0.15 * noise_2d(s + 1.5, t + 2.8), t + 0.15 * noise_2d(s + 4.5, t + 9.8));
                // The dot's centre and a point 0.3 from it are inside exactly when the cell
                // has a dot; a point of the same cell 0.36 away (towards the cell's middle, so
                // it stays in the cell) never is.
                assert_eq!(inside_polka_dot(centre), selected, "cell ({i}, {j})");
                assert_eq!(inside_polka_dot(centre + Vec2::new(0.3, 0.0)), selected);
                let away = if centre.y >= t { -0.36 } else { 0.36 };
                assert!(!inside_polka_dot(centre + Vec2::new(0.0, away)));
                cells += 1;
                with += selected as i32;
            }
        }
        // Noise at cell centres is positive about half the time.
        let frac = with as f64 / cells as f64;
        assert!((0.3..0.7).contains(&frac), "{frac}");
    }
}
