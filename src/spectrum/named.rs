//! The names of pbrt-v4's built-in spectra (file-format reference, "Spectra") with prism's
//! additions: the illuminants [`super::Spectrum::named`] gives, and metals' η and k and
//! glasses' η (`bsdf::named_spectra`).

/// pbrt-v4's built-in named spectra (file-format reference, "Spectra"); any other string
/// given to a "spectrum" parameter is a file name.
pub const NAMED_SPECTRA: &[&str] = &[
    // prism's own additions (Sellmeier glasses, more measured metals).
    "glass-diamond",
    "glass-fused-silica",
    "glass-water",
    "metal-Cr-eta",
    "metal-Cr-k",
    "metal-Ti-eta",
    "metal-Ti-k",
    // pbrt-v4's names.
    "glass-BK7",
    "glass-BAF10",
    "glass-FK51A",
    "glass-LASF9",
    "glass-F5",
    "glass-F10",
    "glass-F11",
    "metal-Ag-eta",
    "metal-Ag-k",
    "metal-Al-eta",
    "metal-Al-k",
    "metal-Au-eta",
    "metal-Au-k",
    "metal-Cu-eta",
    "metal-Cu-k",
    "metal-CuZn-eta",
    "metal-CuZn-k",
    "metal-MgO-eta",
    "metal-MgO-k",
    "metal-TiO2-eta",
    "metal-TiO2-k",
    "stdillum-A",
    "stdillum-D50",
    "stdillum-D65",
    "stdillum-F1",
    "stdillum-F2",
    "stdillum-F3",
    "stdillum-F4",
    "stdillum-F5",
    "stdillum-F6",
    "stdillum-F7",
    "stdillum-F8",
    "stdillum-F9",
    "stdillum-F10",
    "stdillum-F11",
    "stdillum-F12",
    "illum-acesD60",
];
