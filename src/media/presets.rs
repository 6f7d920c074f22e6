//! Measured scattering properties of named materials, for `"string preset"` of a medium:
//! Jensen, Marschner, Levoy & Hanrahan 2001, "A Practical Model for Subsurface Light
//! Transport", Table 1: the reduced scattering coefficient σ'_s and the absorption coefficient
//! σ_a in 1/mm at the red, green and blue of their measurement. As pbrt-v4 does, σ'_s is used as
//! σ_s (with the medium's own g, 0 by default).

/// (name, σ'_s RGB [1/mm], σ_a RGB [1/mm]).
const JENSEN_2001: &[(&str, [f32; 3], [f32; 3])] = &[
    ("Apple", [2.29, 2.39, 1.97], [0.0030, 0.0034, 0.046]),
    ("Chicken1", [0.15, 0.21, 0.38], [0.015, 0.077, 0.19]),
    ("Chicken2", [0.19, 0.25, 0.32], [0.018, 0.088, 0.20]),
    ("Cream", [7.38, 5.47, 3.15], [0.0002, 0.0028, 0.0163]),
    ("Ketchup", [0.18, 0.07, 0.03], [0.061, 0.97, 1.45]),
    ("Marble", [2.19, 2.62, 3.00], [0.0021, 0.0041, 0.0071]),
    ("Potato", [0.68, 0.70, 0.55], [0.0024, 0.0090, 0.12]),
    ("Skimmilk", [0.70, 1.22, 1.90], [0.0014, 0.0025, 0.0142]),
    ("Skin1", [0.74, 0.88, 1.01], [0.032, 0.17, 0.48]),
    ("Skin2", [1.09, 1.59, 1.79], [0.013, 0.070, 0.145]),
    ("Spectralon", [11.6, 20.4, 14.9], [0.00, 0.00, 0.00]),
    ("Wholemilk", [2.55, 3.21, 3.77], [0.0011, 0.0024, 0.014]),
];

/// σ_s and σ_a (RGB, 1/mm) of the named measured material, if the table has it.
pub fn measured_medium(name: &str) -> Option<([f32; 3], [f32; 3])> {
    JENSEN_2001.iter().find(|(n, _, _)| *n == name).map(|&(_, s, a)| (s, a))
}

/// The names [`measured_medium`] knows, for error messages.
pub fn measured_media_names() -> Vec<&'static str> {
    JENSEN_2001.iter().map(|(n, _, _)| *n).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whole_milk_is_the_published_row_and_unknown_names_are_none() {
        let (s, a) = measured_medium("Wholemilk").unwrap();
        assert_eq!(s, [2.55, 3.21, 3.77]);
        assert_eq!(a, [0.0011, 0.0024, 0.014]);
        assert!(measured_medium("Unobtainium").is_none());
        assert_eq!(measured_media_names().len(), 12);
    }
}
