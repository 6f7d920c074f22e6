//! File formats prism reads and writes, chosen by file extension.

use std::path::Path;

use super::ImageError;

/// Extensions accepted by [`super::write`] and [`super::read`], for error messages.
pub const SUPPORTED_EXTENSIONS: &str = ".exr, .png, .jpg, .jpeg, .tif, .tiff, .hdr";

/// An on-disk image format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileFormat {
    /// OpenEXR: linear half or float samples.
    Exr,
    /// PNG: 8-bit sRGB-encoded.
    Png,
    /// JPEG: 8-bit sRGB-encoded, lossy, no alpha.
    Jpeg,
    /// TIFF: 8- or 16-bit sRGB-encoded; Y, RGB or RGBA.
    Tiff,
    /// Radiance RGBE: linear, RGB only.
    Hdr,
}

impl FileFormat {
    /// The format named by `path`'s extension (case-insensitive).
    pub fn from_path(path: &Path) -> Result<Self, ImageError> {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        match ext.as_str() {
            "exr" => Ok(Self::Exr),
            "png" => Ok(Self::Png),
            "jpg" | "jpeg" => Ok(Self::Jpeg),
            "tif" | "tiff" => Ok(Self::Tiff),
            "hdr" => Ok(Self::Hdr),
            _ => Err(ImageError::UnsupportedExtension {
                path: path.to_path_buf(),
                ext: if ext.is_empty() { "(none)".to_string() } else { format!(".{ext}") },
                supported: SUPPORTED_EXTENSIONS,
            }),
        }
    }

    /// Display name for messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Exr => "OpenEXR",
            Self::Png => "PNG",
            Self::Jpeg => "JPEG",
            Self::Tiff => "TIFF",
            Self::Hdr => "Radiance HDR",
        }
    }

    /// Whether samples are stored linear (float) rather than sRGB-encoded integers.
    pub fn is_linear(self) -> bool {
        matches!(self, Self::Exr | Self::Hdr)
    }

    /// Checks the format's size limit. JPEG stops at 65500 (libjpeg's `JPEG_MAX_DIMENSION`);
    /// checking here matters because OIIO 2.4's JPEG writer lets libjpeg `exit()` the whole
    /// process on that error instead of returning it.
    pub(crate) fn check_size(self, path: &Path, width: u32, height: u32) -> Result<(), ImageError> {
        let max = match self {
            Self::Jpeg => 65_500,
            _ => return Ok(()),
        };
        if width <= max && height <= max {
            Ok(())
        } else {
            Err(ImageError::TooLarge { path: path.to_path_buf(), format: self.name(), width, height, max })
        }
    }

    /// Checks that this format can store `channels` channels.
    pub(crate) fn check_channels(self, path: &Path, channels: u32) -> Result<(), ImageError> {
        let (ok, accepted) = match self {
            Self::Exr | Self::Png => ((1..=4).contains(&channels), "1 to 4"),
            // The `image` crate's TIFF encoder has no grey+alpha layout.
            Self::Tiff => (matches!(channels, 1 | 3 | 4), "1, 3 or 4"),
            Self::Jpeg => (channels == 1 || channels == 3, "1 or 3"),
            Self::Hdr => (channels == 3, "3"),
        };
        if ok {
            Ok(())
        } else {
            Err(ImageError::UnsupportedChannels { path: path.to_path_buf(), format: self.name(), channels, accepted })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extension_is_case_insensitive() {
        assert_eq!(FileFormat::from_path(Path::new("a/b.EXR")).unwrap(), FileFormat::Exr);
        assert_eq!(FileFormat::from_path(Path::new("x.Jpeg")).unwrap(), FileFormat::Jpeg);
    }

    #[test]
    fn unknown_extension_lists_supported_ones() {
        let err = FileFormat::from_path(Path::new("out.bmp")).unwrap_err();
        let msg = err.to_string();
        assert!(msg.contains("\".bmp\""), "{msg}");
        assert!(msg.contains(SUPPORTED_EXTENSIONS), "{msg}");
        let err = FileFormat::from_path(Path::new("noext")).unwrap_err();
        assert!(err.to_string().contains("(none)"));
    }
}
