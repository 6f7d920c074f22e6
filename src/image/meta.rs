//! What an image file says about itself: the colour space of its RGB values and how it was
//! rendered. OpenEXR carries it as header attributes (the standard `chromaticities`, pbrt-v4's
//! names `renderTimeSeconds` and `samplesPerPixel`, and prism's own `prism:*`, among them an
//! adaptive render's `prism:estimatedError`); PNG carries the
//! colour space as a cICP chunk (ITU-T H.273 code points), which only the spaces H.273 names
//! can use.

use crate::spectrum::ColorSpace;

/// Chromaticities (CIE 1931 xy) of a colour space's primaries and white point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chromaticities {
    /// The space's name as [`ColorSpace::by_name`] knows it.
    pub name: &'static str,
    /// Red, green, blue primaries (x, y).
    pub primaries: [[f32; 2]; 3],
    /// White point (x, y).
    pub white: [f32; 2],
}

impl Chromaticities {
    /// The chromaticities of `space`.
    pub fn of(space: &ColorSpace) -> Self {
        let xy = |p: [f64; 2]| [p[0] as f32, p[1] as f32];
        Self { name: space.name, primaries: space.primaries.map(xy), white: xy(space.white) }
    }
}

/// Metadata written alongside an image; every field is optional.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImageMeta {
    /// The colour space of the RGB values.
    pub color_space: Option<Chromaticities>,
    /// Samples per pixel actually taken.
    pub samples_per_pixel: Option<u64>,
    /// Wall-clock rendering time [s].
    pub render_time_seconds: Option<f64>,
    /// The sampler's seed.
    pub seed: Option<u64>,
    /// The sampler's name.
    pub sampler: Option<String>,
    /// World space → camera space (pbrt-v4's `worldToCamera`), rows of the matrix that maps a
    /// point as a column vector, as pbrt-v4 writes them.
    pub world_to_camera: Option<[[f32; 4]; 4]>,
    /// World space → NDC (pbrt-v4's `worldToNDC`, see [`crate::camera::ndc`]), rows likewise.
    pub world_to_ndc: Option<[[f32; 4]; 4]>,
    /// The file holds spectral channels in the layout of Fichet et al. (JCGT 2021): say so as
    /// pbrt-v4 does (`spectralLayoutVersion` "1.0", `emissiveUnits` "W.m^-2.sr^-1").
    pub spectral_layout: bool,
    /// An adaptive render's estimated error when it stopped (`prism:estimatedError`, a float): RMSE of
    /// x/(1+x)-mapped RGB against the converged image ([`crate::adaptive`]).
    pub estimated_error: Option<f64>,
}

/// prism's version, written into every OpenEXR file as `prism:version`.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

impl ImageMeta {
    /// The (name, value) text attributes of an OpenEXR header besides the chromaticities and the
    /// numeric ones: prism's version and sampler, the seed (as text: OpenEXR has no 64-bit
    /// integer attribute).
    pub(crate) fn exr_strings(&self) -> Vec<(&'static str, String)> {
        let mut v = vec![("prism:version", VERSION.to_string())];
        if let Some(s) = &self.sampler {
            v.push(("prism:sampler", s.clone()));
        }
        if let Some(s) = self.seed {
            v.push(("prism:seed", s.to_string()));
        }
        if self.spectral_layout {
            v.push(("spectralLayoutVersion", "1.0".to_string()));
            v.push(("emissiveUnits", "W.m^-2.sr^-1".to_string()));
        }
        v
    }

    /// The cICP chunk's four bytes for the colour space with the sRGB transfer curve prism
    /// encodes 8- and 16-bit files with (ITU-T H.273: colour primaries, transfer characteristics
    /// = 13 (IEC 61966-2-1), matrix coefficients = 0 (RGB), full range = 1); `None` for a space
    /// H.273 has no primaries code for (ACES AP0 and AP1).
    pub fn cicp(&self) -> Option<[u8; 4]> {
        let primaries = match self.color_space?.name {
            "srgb" => 1,    // ITU-R BT.709
            "rec2020" => 9, // ITU-R BT.2020
            "dci-p3" => 12, // SMPTE EG 432-1 (P3 primaries, D65 white)
            _ => return None,
        };
        Some([primaries, 13, 0, 1])
    }

    /// A one-line note when a file of `format` cannot say this image's colour space (and so will
    /// be read as sRGB): JPEG and TIFF for any space but sRGB, PNG for the ACES spaces.
    pub fn untagged_warning(&self, format: super::FileFormat) -> Option<String> {
        use super::FileFormat::*;
        let space = self.color_space?;
        let tagged = match format {
            Exr | Hdr => return None,
            Png => self.cicp().is_some(),
            Jpeg | Tiff => space.name == "srgb",
        };
        (!tagged).then(|| {
            format!("this file format cannot record colour space {}: readers will take it as sRGB", space.name)
        })
    }
}

/// `png` (a complete PNG stream) with a cICP chunk holding `code` inserted after IHDR, which
/// the PNG specification (third edition, §11.3.2.6) places before PLTE and IDAT.
pub(crate) fn png_with_cicp(png: &[u8], code: [u8; 4]) -> Option<Vec<u8>> {
    // Signature (8 bytes), then IHDR: length (4), type (4), 13 data bytes, CRC (4).
    const IHDR_END: usize = 8 + 4 + 4 + 13 + 4;
    if png.len() < IHDR_END || &png[12..16] != b"IHDR" {
        return None;
    }
    let mut out = Vec::with_capacity(png.len() + 16);
    out.extend_from_slice(&png[..IHDR_END]);
    out.extend_from_slice(&4u32.to_be_bytes());
    let mut crc = flate2::Crc::new();
    crc.update(b"cICP");
    crc.update(&code);
    out.extend_from_slice(b"cICP");
    out.extend_from_slice(&code);
    out.extend_from_slice(&crc.sum().to_be_bytes());
    out.extend_from_slice(&png[IHDR_END..]);
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::super::{read, write_with, Backend, ExrSample, FileFormat, Image, WriteOptions};
    use super::*;
    use exr::meta::attribute::{AttributeValue, Text};

    /// Published chromaticities (xy of red, green, blue, white): sRGB and Rec. 2020 from
    /// ITU-R BT.709-6 and BT.2020-2 (white D65), ACES2065-1 from SMPTE ST 2065-1 (AP0, white
    /// ≈ D60).
    const PUBLISHED: [(&str, [[f32; 2]; 4]); 3] = [
        ("srgb", [[0.640, 0.330], [0.300, 0.600], [0.150, 0.060], [0.3127, 0.3290]]),
        ("rec2020", [[0.708, 0.292], [0.170, 0.797], [0.131, 0.046], [0.3127, 0.3290]]),
        ("aces2065-1", [[0.7347, 0.2653], [0.0, 1.0], [0.0001, -0.0770], [0.32168, 0.33767]]),
    ];

    fn meta(space: &str) -> ImageMeta {
        ImageMeta {
            color_space: Some(Chromaticities::of(ColorSpace::by_name(space).unwrap())),
            samples_per_pixel: Some(64),
            render_time_seconds: Some(1.5),
            seed: Some(7),
            sampler: Some("sobol".into()),
            world_to_camera: Some(WORLD_TO_CAMERA),
            world_to_ndc: Some([
                [0.5, 0.0, 0.5, 0.25],
                [0.0, 0.5, 0.5, -1.0],
                [0.0, 0.0, 1.0, 2.0],
                [0.0, 0.0, 1.0, 3.0],
            ]),
            estimated_error: Some(0.0125),
            spectral_layout: false,
        }
    }

    /// A world-to-camera matrix with every entry distinct, so a transposition shows.
    const WORLD_TO_CAMERA: [[f32; 4]; 4] =
        [[0.8, 0.0, -0.6, 1.0], [0.0, 1.0, 0.0, -2.0], [0.6, 0.0, 0.8, -3.0], [0.125, 0.25, 0.375, 1.5]];

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("prism-meta-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn write(path: &std::path::Path, meta: ImageMeta) {
        write_by(path, meta, Backend::Rust)
    }

    fn write_by(path: &std::path::Path, meta: ImageMeta, backend: Backend) {
        let img = Image { width: 4, height: 3, channels: 3, data: (0..36).map(|i| i as f32 / 36.0).collect() };
        let opts = WriteOptions { backend, exr_sample: ExrSample::Half, meta, ..Default::default() };
        write_with(path, &img, &opts).unwrap();
    }

    #[test]
    fn exr_header_names_the_colour_space_and_how_the_image_was_rendered() {
        let dir = scratch("exr");
        // Both writers, where OpenImageIO is available.
        for (backend, (space, [r, g, b, w])) in
            Backend::available().iter().copied().flat_map(|b| PUBLISHED.into_iter().map(move |p| (b, p)))
        {
            let path = dir.join(format!("{space}-{backend:?}.exr"));
            write_by(&path, meta(space), backend);
            let header = exr::meta::MetaData::read_from_file(&path, false).unwrap().headers.remove(0);
            let c = header.shared_attributes.chromaticities.expect("chromaticities");
            for (got, want) in [(c.red, r), (c.green, g), (c.blue, b), (c.white, w)] {
                assert!((got.0 - want[0]).abs() < 2e-4 && (got.1 - want[1]).abs() < 2e-4, "{space}: {got:?} {want:?}");
            }
            // A reader cannot tell image from layer attributes of a single-part file: either map.
            let attr = |n: &str| {
                let n = Text::from(n);
                header.own_attributes.other.get(&n).or(header.shared_attributes.other.get(&n)).cloned()
            };
            assert_eq!(attr("samplesPerPixel"), Some(AttributeValue::I32(64)));
            assert_eq!(attr("renderTimeSeconds"), Some(AttributeValue::F32(1.5)));
            assert_eq!(attr("prism:estimatedError"), Some(AttributeValue::F32(0.0125)));
            assert_eq!(attr("prism:seed"), Some(AttributeValue::Text(Text::from("7"))));
            assert_eq!(attr("prism:sampler"), Some(AttributeValue::Text(Text::from("sobol"))));
            assert_eq!(attr("prism:version"), Some(AttributeValue::Text(Text::from(VERSION))));
            // pbrt-v4's matrices: 16 floats, row by row.
            let flat = |m: [[f32; 4]; 4]| -> [f32; 16] { std::array::from_fn(|i| m[i / 4][i % 4]) };
            assert_eq!(header.own_attributes.world_to_camera, Some(flat(WORLD_TO_CAMERA)), "{backend:?}");
            assert_eq!(header.own_attributes.world_to_normalized_device, meta(space).world_to_ndc.map(flat));
            // R, G, B as half floats (OpenEXR lists channels sorted by name).
            let ch: Vec<(String, exr::meta::attribute::SampleType)> =
                header.channels.list.iter().map(|c| (c.name.to_string(), c.sample_type)).collect();
            let half = exr::meta::attribute::SampleType::F16;
            assert_eq!(ch, [("B".into(), half), ("G".into(), half), ("R".into(), half)]);
            // OpenImageIO reads the same header, where installed.
            if let Ok(o) = std::process::Command::new("oiiotool").arg("--info").arg("-v").arg(&path).output() {
                let info = String::from_utf8_lossy(&o.stdout);
                let xy = format!("chromaticities: {}, {}", r[0], r[1]);
                assert!(info.contains(&xy) && info.contains("samplesPerPixel: 64"), "{space}: {info}");
            }
        }
        let _ = std::fs::remove_dir_all(dir);
    }

    /// The chunk types of a PNG stream, in order, with their data.
    fn chunks(png: &[u8]) -> Vec<(String, Vec<u8>)> {
        let (mut v, mut i) = (Vec::new(), 8);
        while i + 8 <= png.len() {
            let len = u32::from_be_bytes(png[i..i + 4].try_into().unwrap()) as usize;
            v.push((String::from_utf8_lossy(&png[i + 4..i + 8]).into_owned(), png[i + 8..i + 8 + len].to_vec()));
            i += 12 + len;
        }
        v
    }

    #[test]
    fn png_has_a_cicp_chunk_where_h273_names_the_space() {
        let dir = scratch("png");
        // ITU-T H.273: primaries 1 = BT.709, 9 = BT.2020, 12 = P3 with D65; transfer 13 = sRGB
        // (IEC 61966-2-1); matrix 0 = RGB; full range 1.
        for (space, code) in [
            ("srgb", Some([1, 13, 0, 1])),
            ("rec2020", Some([9, 13, 0, 1])),
            ("dci-p3", Some([12, 13, 0, 1])),
            ("aces2065-1", None),
        ] {
            let path = dir.join(format!("{space}.png"));
            write(&path, meta(space));
            let c = chunks(&std::fs::read(&path).unwrap());
            assert_eq!(c[0].0, "IHDR");
            match code {
                Some(code) => assert_eq!(c[1], ("cICP".to_string(), code.to_vec()), "{space}"),
                None => assert!(c.iter().all(|(t, _)| t != "cICP"), "{space}"),
            }
            // The stream stays valid: the decoder checks every chunk's CRC.
            assert_eq!(read(&path).unwrap().width, 4);
            let warned = meta(space).untagged_warning(FileFormat::Png).is_some();
            assert_eq!(warned, code.is_none(), "{space}");
        }
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn jpeg_and_tiff_warn_for_any_space_but_srgb() {
        for f in [FileFormat::Jpeg, FileFormat::Tiff] {
            assert!(meta("srgb").untagged_warning(f).is_none());
            assert!(meta("rec2020").untagged_warning(f).is_some());
        }
        assert!(meta("aces2065-1").untagged_warning(FileFormat::Exr).is_none());
        assert!(ImageMeta::default().untagged_warning(FileFormat::Jpeg).is_none());
    }
}
