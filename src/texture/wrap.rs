//! What an image lookup finds outside the image (the imagemap "wrap" parameter).

/// Wrap mode of texel coordinates outside [0, width) × [0, height).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WrapMode {
    /// The image tiles the plane.
    Repeat,
    /// Zero outside.
    Black,
    /// The nearest edge texel.
    Clamp,
    /// An equal-area octahedral sphere map (Clarberg 2008): crossing an edge continues on the
    /// mirrored edge of the same square, so the four edge halves that meet on the sphere join.
    OctahedralSphere,
}

impl WrapMode {
    /// Parses pbrt-v4's names: "repeat", "black", "clamp", "octahedralsphere".
    pub fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "repeat" => WrapMode::Repeat,
            "black" => WrapMode::Black,
            "clamp" => WrapMode::Clamp,
            "octahedralsphere" => WrapMode::OctahedralSphere,
            _ => return None,
        })
    }

    /// The texel that (x, y) stands for in a `w` × `h` image, or `None` for black.
    pub fn texel(self, x: i64, y: i64, w: usize, h: usize) -> Option<(usize, usize)> {
        let (wi, hi) = (w as i64, h as i64);
        let (x, y) = match self {
            WrapMode::Repeat => (x.rem_euclid(wi), y.rem_euclid(hi)),
            WrapMode::Clamp => (x.clamp(0, wi - 1), y.clamp(0, hi - 1)),
            WrapMode::Black => {
                if x < 0 || x >= wi || y < 0 || y >= hi {
                    return None;
                }
                (x, y)
            }
            WrapMode::OctahedralSphere => {
                // Mirror across the crossed edge and across the square's other midline; a
                // footprint more than one image away is clamped.
                let (mut x, mut y) = (x, y);
                if x < 0 {
                    (x, y) = (-x - 1, hi - 1 - y);
                } else if x >= wi {
                    (x, y) = (2 * wi - 1 - x, hi - 1 - y);
                }
                if y < 0 {
                    (x, y) = (wi - 1 - x, -y - 1);
                } else if y >= hi {
                    (x, y) = (wi - 1 - x, 2 * hi - 1 - y);
                }
                (x.clamp(0, wi - 1), y.clamp(0, hi - 1))
            }
        };
        Some((x as usize, y as usize))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_modes_find_the_right_texel() {
        assert_eq!(WrapMode::Repeat.texel(-1, 5, 4, 4), Some((3, 1)));
        assert_eq!(WrapMode::Clamp.texel(-1, 5, 4, 4), Some((0, 3)));
        assert_eq!(WrapMode::Black.texel(-1, 2, 4, 4), None);
        assert_eq!(WrapMode::Black.texel(1, 2, 4, 4), Some((1, 2)));
        // Octahedral: one step left of column 0 is column 0 mirrored top to bottom.
        assert_eq!(WrapMode::OctahedralSphere.texel(-1, 0, 4, 4), Some((0, 3)));
        assert_eq!(WrapMode::OctahedralSphere.texel(4, 1, 4, 4), Some((3, 2)));
        assert_eq!(WrapMode::OctahedralSphere.texel(1, -1, 4, 4), Some((2, 0)));
        assert_eq!(WrapMode::parse("octahedralsphere"), Some(WrapMode::OctahedralSphere));
        assert_eq!(WrapMode::parse("mirror"), None);
    }
}
