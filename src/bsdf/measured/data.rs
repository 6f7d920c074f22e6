//! A measured BRDF in Dupuy & Jakob's adaptive parameterisation, read from the fields of an RGL
//! tensor file (pbrt-v4 `MeasuredBxDFData`, Mitsuba 3 `measured`).
//!
//! Fields (C order, φ_i slowest): `theta_i` [n_θ], `phi_i` [n_φ] (radians; isotropic when
//! n_φ ≤ 2), `ndf` and `sigma` [rows, columns] over (u_θ, u_φ) of the half vector and of the
//! incident direction, `vndf` and `luminance` [n_φ, n_θ, rows, columns], `wavelengths` [n_λ]
//! (nm), `spectra` [n_φ, n_θ, n_λ, rows, columns] (the `vndf`'s sample space), `jacobian` [1]
//! (u8) and `description` (u8 text). The (u_θ, u_φ) coordinates are θ = u_θ² π/2 and
//! φ = (2u_φ − 1)π, so the grid is denser near the pole, where glossy lobes live.

use super::tensor_file::{TensorError, TensorFile};
use crate::sampling::piecewise_linear::{PiecewiseLinear2D, TableError};
use std::fmt;
use std::path::Path;

/// Why a `.bsdf` file cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum MeasuredError {
    /// The file could not be read.
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// The container is malformed or a field has the wrong type or number of dimensions.
    #[error("{0}")]
    Tensor(#[from] TensorError),
    /// A table the fields describe is not a valid grid.
    #[error("field \"{field}\": {source}")]
    Table {
        /// The field.
        field: &'static str,
        /// Why.
        source: TableError,
    },
    /// A file with `rgb` but no `spectra`.
    #[error(
        "the file has RGB data only (field \"rgb\"); pbrt-v4 and prism read the spectral files (field \"spectra\")"
    )]
    RgbOnly,
    /// An anisotropic file tabulating only a fraction of the azimuths.
    #[error("an anisotropic file whose φ_i spans 2π/{0}; only the full circle is supported (as in pbrt-v4)")]
    Reduction(i64),
}

/// The tables of one measured material, shared by every hit that uses it.
pub struct MeasuredBrdf {
    /// The distribution of normals D(ω_m) [1/sr] over (u_θ, u_φ).
    pub(super) ndf: PiecewiseLinear2D<0>,
    /// Projected microfacet area σ(ω) = ∫ D(ω_m) ⟨ω·ω_m⟩ dω_m over (u_θ, u_φ).
    pub(super) sigma: PiecewiseLinear2D<0>,
    /// The visible normals' density over (u_θ, u_φ) of ω_m, given (φ_i, θ_i).
    pub(super) vndf: PiecewiseLinear2D<2>,
    /// Luminance over the vndf's sample space, given (φ_i, θ_i): what sampling follows first.
    pub(super) luminance: PiecewiseLinear2D<2>,
    /// The reflectance factor R over the sample space, given (φ_i, θ_i, λ).
    pub(super) spectra: PiecewiseLinear2D<3>,
    /// True when the data do not depend on φ_i (half vectors' azimuths relative to it).
    pub(super) isotropic: bool,
    /// True when `spectra` holds R, to be multiplied by D / (4σ); false when it holds f cos θ.
    pub(super) jacobian: bool,
    /// The file's `description`.
    pub description: String,
    /// Tabulated wavelengths [nm] (first, last).
    pub wavelength_range: (f32, f32),
}

impl fmt::Debug for MeasuredBrdf {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (x, y) = self.spectra.resolution();
        f.debug_struct("MeasuredBrdf")
            .field("description", &self.description)
            .field("isotropic", &self.isotropic)
            .field("sample_grid", &(x, y))
            .field("wavelength_range", &self.wavelength_range)
            .finish()
    }
}

fn shape_error(field: &str, shape: &[usize], expected: String) -> MeasuredError {
    TensorError::WrongShape { field: field.into(), shape: shape.to_vec(), expected }.into()
}

impl MeasuredBrdf {
    /// Reads and checks a `.bsdf` file.
    pub fn read(path: &Path) -> Result<Self, MeasuredError> {
        Self::from_tensor(&TensorFile::parse(&std::fs::read(path)?)?)
    }

    /// The material of a parsed tensor file: every field checked against the others (pbrt-v4's
    /// conditions), every failure an error.
    pub fn from_tensor(t: &TensorFile) -> Result<Self, MeasuredError> {
        if !t.fields.contains_key("spectra") && t.fields.contains_key("rgb") {
            return Err(MeasuredError::RgbOnly);
        }
        let description = String::from_utf8_lossy(t.bytes("description", 1)?).into_owned();
        let (theta_i, _) = t.f32s("theta_i", 1)?;
        let (phi_i, _) = t.f32s("phi_i", 1)?;
        let (wavelengths, _) = t.f32s("wavelengths", 1)?;
        let (ndf, ndf_shape) = t.f32s("ndf", 2)?;
        let (sigma, sigma_shape) = t.f32s("sigma", 2)?;
        let (vndf, vndf_shape) = t.f32s("vndf", 4)?;
        let (luminance, lum_shape) = t.f32s("luminance", 4)?;
        let (spectra, spec_shape) = t.f32s("spectra", 5)?;
        let jacobian = t.bytes("jacobian", 1)?;
        let [jacobian] = jacobian else {
            return Err(shape_error("jacobian", &[jacobian.len()], "one value is required".into()));
        };
        let (n_phi, n_theta) = (phi_i.len(), theta_i.len());
        if vndf_shape[..2] != [n_phi, n_theta] {
            return Err(shape_error("vndf", vndf_shape, format!("[{n_phi}, {n_theta}, …] (φ_i, θ_i) is required")));
        }
        if lum_shape[..2] != [n_phi, n_theta] || lum_shape[2] != lum_shape[3] {
            let expected = format!("[{n_phi}, {n_theta}, n, n] is required");
            return Err(shape_error("luminance", lum_shape, expected));
        }
        if spec_shape[..3] != [n_phi, n_theta, wavelengths.len()] || spec_shape[3..] != lum_shape[2..] {
            let expected =
                format!("[{n_phi}, {n_theta}, {}, {}, {}] is required", wavelengths.len(), lum_shape[2], lum_shape[3]);
            return Err(shape_error("spectra", spec_shape, expected));
        }
        let isotropic = n_phi <= 2;
        if !isotropic {
            let span = phi_i[n_phi - 1] - phi_i[0];
            let reduction = (std::f32::consts::TAU / span).round() as i64;
            if reduction != 1 {
                return Err(MeasuredError::Reduction(reduction));
            }
        }
        let table = |field: &'static str| move |source| MeasuredError::Table { field, source };
        let pt = [phi_i.clone(), theta_i.clone()];
        Ok(Self {
            ndf: PiecewiseLinear2D::new(&ndf, ndf_shape[1], ndf_shape[0], [], false, false).map_err(table("ndf"))?,
            sigma: PiecewiseLinear2D::new(&sigma, sigma_shape[1], sigma_shape[0], [], false, false)
                .map_err(table("sigma"))?,
            vndf: PiecewiseLinear2D::new(&vndf, vndf_shape[3], vndf_shape[2], pt.clone(), true, true)
                .map_err(table("vndf"))?,
            luminance: PiecewiseLinear2D::new(&luminance, lum_shape[3], lum_shape[2], pt, true, true)
                .map_err(table("luminance"))?,
            spectra: PiecewiseLinear2D::new(
                &spectra,
                spec_shape[4],
                spec_shape[3],
                [phi_i, theta_i, wavelengths.clone()],
                false,
                false,
            )
            .map_err(table("spectra"))?,
            isotropic,
            jacobian: *jacobian != 0,
            description,
            wavelength_range: (wavelengths[0], wavelengths[wavelengths.len() - 1]),
        })
    }
}
