//! SPD files: two columns, wavelength [nm] and value, separated by whitespace or a comma;
//! `#` starts a comment; spacing may be irregular. The file means the piecewise-linear
//! function through its samples, zero outside them (as pbrt-v4's PiecewiseLinearSpectrum);
//! samples outside 360–830 nm are kept and simply fall outside the matching functions.

use super::spd::Spectrum;
use std::path::Path;

/// What is wrong with an SPD file; line numbers start at 1.
#[derive(Debug, thiserror::Error)]
pub enum SpdError {
    /// The file could not be read.
    // The cause is part of the message, not a `source` (which the CLI would print a second
    // time when it joins an error's chain).
    #[error("cannot read {path}: {cause}")]
    Io {
        /// The path given.
        path: String,
        /// The OS error.
        cause: std::io::Error,
    },
    /// A file's contents are malformed: the error, named by the file.
    #[error("{path}: {error}")]
    InFile {
        /// The path given.
        path: String,
        /// What is wrong with its contents.
        error: Box<SpdError>,
    },
    /// A line does not have exactly two fields.
    #[error("line {line}: expected 2 fields (wavelength, value), found {found}")]
    FieldCount {
        /// Line number.
        line: usize,
        /// Number of fields found.
        found: usize,
    },
    /// A field is not a number.
    #[error("line {line}: '{field}' is not a number")]
    NotNumeric {
        /// Line number.
        line: usize,
        /// The offending text.
        field: String,
    },
    /// NaN or infinity.
    #[error("line {line}: {what} is not finite")]
    NotFinite {
        /// Line number.
        line: usize,
        /// "wavelength" or "value".
        what: &'static str,
    },
    /// A wavelength that is not positive.
    #[error("line {line}: wavelength {lambda} nm is not positive")]
    BadWavelength {
        /// Line number.
        line: usize,
        /// The wavelength [nm].
        lambda: f64,
    },
    /// A wavelength not larger than the previous one.
    #[error("line {line}: wavelength {lambda} nm is not above the previous {previous} nm (wavelengths must increase strictly)")]
    Unsorted {
        /// Line number.
        line: usize,
        /// This wavelength [nm].
        lambda: f64,
        /// The previous one [nm].
        previous: f64,
    },
    /// A wavelength given twice.
    #[error("line {line}: duplicate wavelength {lambda} nm")]
    Duplicate {
        /// Line number.
        line: usize,
        /// The wavelength [nm].
        lambda: f64,
    },
    /// A negative value where the quantity cannot be negative.
    #[error("line {line}: negative value {value} (an SPD cannot be negative)")]
    Negative {
        /// Line number.
        line: usize,
        /// The value.
        value: f64,
    },
    /// Fewer than two samples.
    #[error("need at least 2 samples, found {found}")]
    TooFewSamples {
        /// Samples found.
        found: usize,
    },
}

/// Parses SPD text into (wavelengths [nm], values). `allow_negative` admits negative values
/// (for signed quantities such as basis functions); SPDs of light or reflectance forbid them.
pub fn parse_spd(text: &str, allow_negative: bool) -> Result<(Vec<f64>, Vec<f64>), SpdError> {
    let mut lambdas: Vec<f64> = Vec::new();
    let mut values = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.split('#').next().unwrap_or("");
        let fields: Vec<&str> =
            content.split(|c: char| c.is_whitespace() || c == ',' || c == ';').filter(|f| !f.is_empty()).collect();
        if fields.is_empty() {
            continue;
        }
        if fields.len() != 2 {
            return Err(SpdError::FieldCount { line, found: fields.len() });
        }
        let num = |f: &str| f.parse::<f64>().map_err(|_| SpdError::NotNumeric { line, field: f.to_string() });
        let (l, v) = (num(fields[0])?, num(fields[1])?);
        if !l.is_finite() {
            return Err(SpdError::NotFinite { line, what: "wavelength" });
        }
        if !v.is_finite() {
            return Err(SpdError::NotFinite { line, what: "value" });
        }
        if l <= 0.0 {
            return Err(SpdError::BadWavelength { line, lambda: l });
        }
        if let Some(&prev) = lambdas.last() {
            if l == prev {
                return Err(SpdError::Duplicate { line, lambda: l });
            }
            if l < prev {
                return Err(SpdError::Unsorted { line, lambda: l, previous: prev });
            }
        }
        if v < 0.0 && !allow_negative {
            return Err(SpdError::Negative { line, value: v });
        }
        lambdas.push(l);
        values.push(v);
    }
    if lambdas.len() < 2 {
        return Err(SpdError::TooFewSamples { found: lambdas.len() });
    }
    Ok((lambdas, values))
}

impl Spectrum {
    /// Reads an SPD file (see the module docs) as a piecewise-linear spectrum.
    pub fn from_spd_file(path: impl AsRef<Path>) -> Result<Spectrum, SpdError> {
        let path = path.as_ref();
        let text =
            std::fs::read_to_string(path).map_err(|cause| SpdError::Io { path: path.display().to_string(), cause })?;
        Spectrum::from_spd_str(&text)
            .map_err(|e| SpdError::InFile { path: path.display().to_string(), error: Box::new(e) })
    }

    /// Parses SPD text (see the module docs) as a piecewise-linear spectrum.
    pub fn from_spd_str(text: &str) -> Result<Spectrum, SpdError> {
        let (l, v) = parse_spd(text, false)?;
        let found = l.len();
        Spectrum::piecewise_linear_f64(l, v).ok_or(SpdError::TooFewSamples { found })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_malformed_file_is_named_in_its_error() {
        let dir = std::env::temp_dir().join(format!("prism-spd-name-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("lamp.spd");
        std::fs::write(&path, "400 1\n500 x\n").unwrap();
        let e = Spectrum::from_spd_file(&path).unwrap_err().to_string();
        let _ = std::fs::remove_dir_all(&dir);
        assert!(e.contains("lamp.spd") && e.contains("line 2"), "{e}");
    }

    fn err(text: &str) -> SpdError {
        Spectrum::from_spd_str(text).unwrap_err()
    }

    #[test]
    fn parses_comments_commas_and_irregular_spacing() {
        let s = Spectrum::from_spd_str("# header\n400 1.0\n\n  410.5, 2 # note\n500\t0\n").unwrap();
        assert_eq!(s.knots(), vec![400.0, 410.5, 500.0]);
        assert_eq!(s.eval(410.5), 2.0);
    }

    #[test]
    fn errors_name_the_line() {
        assert!(matches!(err("400 1\n410 x\n"), SpdError::NotNumeric { line: 2, .. }));
        assert!(matches!(err("400 1\n390 1\n"), SpdError::Unsorted { line: 2, .. }));
        assert!(matches!(err("400 1\n# c\n400 2\n"), SpdError::Duplicate { line: 3, .. }));
        assert!(matches!(err("400 1\n410 -0.5\n"), SpdError::Negative { line: 2, .. }));
        assert!(matches!(err("400 1\n410 NaN\n"), SpdError::NotFinite { line: 2, what: "value" }));
        assert!(matches!(err("400 1 3\n"), SpdError::FieldCount { line: 1, found: 3 }));
        assert!(matches!(err("-5 1\n"), SpdError::BadWavelength { line: 1, .. }));
        assert!(matches!(err("# only\n400 1\n"), SpdError::TooFewSamples { found: 1 }));
        assert!(matches!(Spectrum::from_spd_file("/nonexistent/x.spd").unwrap_err(), SpdError::Io { .. }));
        let msg = err("400 1\n410 x\n").to_string();
        assert!(msg.contains("line 2") && msg.contains("'x'"), "{msg}");
    }

    #[test]
    fn negatives_allowed_on_request() {
        let (_, v) = parse_spd("400 -1\n500 1\n", true).unwrap();
        assert_eq!(v, vec![-1.0, 1.0]);
    }
}
