//! A lens prescription as pbrt-v4 reads it (pbrt-v4 §5.3.1): per element interface, from the
//! scene side to the film side, the curvature radius, the thickness to the next interface (the
//! last one's to the film), the index of refraction behind it and the aperture diameter, all
//! lengths in millimetres. A radius of 0 marks the aperture stop. `#` starts a comment.

/// One spherical interface of a lens system, or the aperture stop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LensInterface {
    /// Signed radius of curvature [m]: positive when the centre lies on the film side; 0 for the
    /// aperture stop (a plane).
    pub curvature_radius: f32,
    /// Axial distance to the next interface toward the film, or to the film for the last [m].
    pub thickness: f32,
    /// Index of refraction of the medium behind the interface (film side); 0 at the stop (air).
    pub eta: f32,
    /// Radius of the clear aperture [m].
    pub aperture_radius: f32,
}

impl LensInterface {
    /// Whether this is the aperture stop.
    pub fn is_stop(&self) -> bool {
        self.curvature_radius == 0.0
    }
}

/// A value of a lens file: the number and its 1-based line and column.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LensValue {
    /// The number as written [mm, or an index of refraction].
    pub value: f32,
    /// Line, from 1.
    pub line: u32,
    /// Column in characters, from 1.
    pub col: u32,
}

/// Why a lens file could not be read.
#[derive(Debug, PartialEq, thiserror::Error)]
pub enum LensFileError {
    /// A token that is not a number.
    #[error("lens file value \"{token}\" is not a number")]
    NotNumber {
        /// The token as written.
        token: String,
        /// Its line.
        line: u32,
        /// Its column.
        col: u32,
    },
    /// The values do not come in fours.
    #[error("lens file has {count} values; each element needs 4 (radius, thickness, eta, aperture)")]
    Incomplete {
        /// How many values there are.
        count: usize,
        /// The line of the first value of the incomplete element.
        line: u32,
        /// Its column.
        col: u32,
    },
    /// No values at all.
    #[error("lens file has no lens elements")]
    Empty,
}

impl LensFileError {
    /// The (line, column) the error points at (line 1 for an empty file).
    pub fn position(&self) -> (u32, u32) {
        match self {
            Self::NotNumber { line, col, .. } | Self::Incomplete { line, col, .. } => (*line, *col),
            Self::Empty => (1, 1),
        }
    }
}

/// The numbers of a lens file in order, with where each was written.
fn values(text: &str) -> Result<Vec<LensValue>, LensFileError> {
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("");
        let mut chars = line.char_indices().peekable();
        while let Some(&(start, c)) = chars.peek() {
            if c.is_whitespace() {
                chars.next();
                continue;
            }
            let mut end = start;
            while let Some(&(j, c)) = chars.peek() {
                if c.is_whitespace() {
                    break;
                }
                end = j + c.len_utf8();
                chars.next();
            }
            let token = &line[start..end];
            let (line_no, col) = (i as u32 + 1, line[..start].chars().count() as u32 + 1);
            match token.parse::<f32>() {
                Ok(value) if value.is_finite() => out.push(LensValue { value, line: line_no, col }),
                _ => return Err(LensFileError::NotNumber { token: token.to_string(), line: line_no, col }),
            }
        }
    }
    Ok(out)
}

/// The interfaces a lens file describes, scene side first, in metres.
pub fn parse_lens_file(text: &str) -> Result<Vec<LensInterface>, LensFileError> {
    let v = values(text)?;
    if v.is_empty() {
        return Err(LensFileError::Empty);
    }
    if v.len() % 4 != 0 {
        let first = v[v.len() - v.len() % 4];
        return Err(LensFileError::Incomplete { count: v.len(), line: first.line, col: first.col });
    }
    const MM: f32 = 1e-3;
    Ok(v.chunks_exact(4)
        .map(|e| LensInterface {
            curvature_radius: e[0].value * MM,
            thickness: e[1].value * MM,
            eta: e[2].value,
            aperture_radius: e[3].value * MM / 2.0,
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elements_are_read_in_metres_with_comments_skipped() {
        let text = "# radius thickness eta aperture\n29.475\t3.76 1.67 25.2 # front\n\n0 4.5 0 17.1\n";
        let e = parse_lens_file(text).unwrap();
        assert_eq!(e.len(), 2);
        let front = e[0];
        assert!((front.curvature_radius - 0.029475).abs() < 1e-8 && (front.thickness - 0.00376).abs() < 1e-8);
        assert!((front.eta - 1.67).abs() < 1e-7 && (front.aperture_radius - 0.0126).abs() < 1e-8);
        assert!(e[1].is_stop() && !front.is_stop());
    }

    #[test]
    fn malformed_files_name_the_line_and_column() {
        let bad = parse_lens_file("1 2 3 4\n5 6 x7 8\n").unwrap_err();
        assert_eq!(bad, LensFileError::NotNumber { token: "x7".into(), line: 2, col: 5 });
        let short = parse_lens_file("1 2 3 4\n# c\n  5 6 7\n").unwrap_err();
        assert_eq!(short.position(), (3, 3));
        assert!(matches!(short, LensFileError::Incomplete { count: 7, .. }));
        assert_eq!(parse_lens_file("# nothing\n"), Err(LensFileError::Empty));
        assert!(matches!(parse_lens_file("1 2 inf 4"), Err(LensFileError::NotNumber { .. })));
    }
}
