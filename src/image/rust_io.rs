//! The pure-Rust image path: OpenEXR through the `exr` crate, everything else through `image`.
//!
//! Errors come back as [`RustIoError`], one line each; `super` wraps them with the path.

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use ::image::{DynamicImage, ImageBuffer, ImageFormat};
use exr::prelude::{self as exr_p, f16, SmallVec, WritableImage};

use super::format::FileFormat;
use super::{srgb, ExrSample, Image, WriteOptions};

/// Why the pure-Rust path could not encode or decode a file.
#[derive(Debug, thiserror::Error)]
pub(crate) enum RustIoError {
    /// The sample vector does not fill the image's width·height·channels.
    #[error("pixel buffer does not match the image size")]
    BufferMismatch,
    /// A file could not be created or opened.
    #[error(transparent)]
    Io(#[from] std::io::Error),
    /// The `image` crate failed to encode or decode.
    #[error(transparent)]
    Image(#[from] ::image::ImageError),
    /// The `exr` crate failed to encode or decode.
    #[error(transparent)]
    Exr(#[from] exr::error::Error),
    /// A crop origin beyond OpenEXR's signed 32-bit data window.
    #[error("crop origin {0} is too large for OpenEXR")]
    CropOriginTooLarge(u32),
    /// The file's first layer is empty.
    #[error("the first layer has no pixels")]
    NoPixels,
    /// A channel sampled more coarsely than the layer (OpenEXR x/y sampling).
    #[error("channel {0} is subsampled")]
    Subsampled(String),
    /// The PNG encoder's output does not begin with the signature and IHDR, so no cICP chunk
    /// can be placed after it.
    #[error("the PNG encoder wrote no IHDR chunk first")]
    PngHeader,
    /// A decoded layout prism has no conversion for.
    #[error("unsupported pixel layout {0:?}")]
    PixelLayout(::image::ColorType),
}

/// Conventional channel names for 1–4 channels, the same ones the OIIO shim writes.
pub(crate) fn channel_names(channels: usize) -> &'static [&'static str] {
    match channels {
        1 => &["Y"],
        2 => &["Y", "A"],
        3 => &["R", "G", "B"],
        _ => &["R", "G", "B", "A"],
    }
}

/// Writes `img` (already validated for `format`) to `path`.
pub(crate) fn write(path: &Path, format: FileFormat, img: &Image, opts: &WriteOptions) -> Result<(), RustIoError> {
    match format {
        FileFormat::Exr => write_exr(path, img, channel_names(img.channels as usize), opts),
        FileFormat::Hdr => {
            let buf =
                ImageBuffer::from_raw(img.width, img.height, img.data.clone()).ok_or(RustIoError::BufferMismatch)?;
            Ok(DynamicImage::ImageRgb32F(buf).save_with_format(path, ImageFormat::Hdr)?)
        }
        FileFormat::Png | FileFormat::Jpeg | FileFormat::Tiff => {
            let wide = format == FileFormat::Tiff && opts.tiff_16bit;
            let dynimg = encoded_dynamic_image(img, wide)?;
            if format == FileFormat::Jpeg {
                let file = File::create(path)?;
                let encoder = ::image::codecs::jpeg::JpegEncoder::new_with_quality(
                    BufWriter::new(file),
                    opts.jpeg_quality.clamp(1, 100),
                );
                Ok(dynimg.write_with_encoder(encoder)?)
            } else if let (FileFormat::Png, Some(code)) = (format, opts.meta.cicp()) {
                let mut png = std::io::Cursor::new(Vec::new());
                dynimg.write_to(&mut png, ImageFormat::Png)?;
                let tagged = super::meta::png_with_cicp(png.get_ref(), code).ok_or(RustIoError::PngHeader)?;
                Ok(std::fs::write(path, tagged)?)
            } else {
                let fmt = if format == FileFormat::Png { ImageFormat::Png } else { ImageFormat::Tiff };
                Ok(dynimg.save_with_format(path, fmt)?)
            }
        }
    }
}

/// sRGB-encodes and quantises `img` into an 8- or 16-bit `DynamicImage`.
fn encoded_dynamic_image(img: &Image, sixteen_bit: bool) -> Result<DynamicImage, RustIoError> {
    let c = img.channels as usize;
    let (w, h) = (img.width, img.height);
    let mismatch = || RustIoError::BufferMismatch;
    if sixteen_bit {
        let codes: Vec<u16> = srgb::encode_to_codes(&img.data, c, 65535).into_iter().map(|v| v as u16).collect();
        Ok(match c {
            1 => DynamicImage::ImageLuma16(ImageBuffer::from_raw(w, h, codes).ok_or_else(mismatch)?),
            2 => DynamicImage::ImageLumaA16(ImageBuffer::from_raw(w, h, codes).ok_or_else(mismatch)?),
            3 => DynamicImage::ImageRgb16(ImageBuffer::from_raw(w, h, codes).ok_or_else(mismatch)?),
            _ => DynamicImage::ImageRgba16(ImageBuffer::from_raw(w, h, codes).ok_or_else(mismatch)?),
        })
    } else {
        let codes: Vec<u8> = srgb::encode_to_codes(&img.data, c, 255).into_iter().map(|v| v as u8).collect();
        Ok(match c {
            1 => DynamicImage::ImageLuma8(ImageBuffer::from_raw(w, h, codes).ok_or_else(mismatch)?),
            2 => DynamicImage::ImageLumaA8(ImageBuffer::from_raw(w, h, codes).ok_or_else(mismatch)?),
            3 => DynamicImage::ImageRgb8(ImageBuffer::from_raw(w, h, codes).ok_or_else(mismatch)?),
            _ => DynamicImage::ImageRgba8(ImageBuffer::from_raw(w, h, codes).ok_or_else(mismatch)?),
        })
    }
}

/// Writes `img` as OpenEXR with channels called `names`.
pub(crate) fn write_exr(path: &Path, img: &Image, names: &[&str], opts: &WriteOptions) -> Result<(), RustIoError> {
    let c = img.channels as usize;
    let list: SmallVec<[exr_p::AnyChannel<exr_p::FlatSamples>; 4]> = (0..c)
        .map(|ch| {
            let plane = img.data.iter().skip(ch).step_by(c).copied();
            let samples = match opts.exr_sample {
                ExrSample::Float => exr_p::FlatSamples::F32(plane.collect()),
                ExrSample::Half => exr_p::FlatSamples::F16(plane.map(f16::from_f32).collect()),
            };
            exr_p::AnyChannel::new(names[ch], samples)
        })
        .collect();
    let mut layer = exr_p::Layer::new(
        (img.width as usize, img.height as usize),
        exr_p::LayerAttributes::default(),
        exr_p::Encoding::SMALL_LOSSLESS, // ZIP, as OIIO writes
        exr_p::AnyChannels::sort(list),
    );
    let display = match opts.window {
        Some(w) => {
            let origin = |v: u32| i32::try_from(v).map_err(|_| RustIoError::CropOriginTooLarge(v));
            layer.attributes.layer_position = exr_p::Vec2(origin(w.x0)?, origin(w.y0)?);
            exr_p::IntegerBounds::new((0, 0), (w.full_width as usize, w.full_height as usize))
        }
        None => exr_p::IntegerBounds::new((0, 0), layer.size),
    };
    // OpenEXR's standard `worldToCamera` and `worldToNDC` (m44f, 16 floats row by row) are the
    // layer's.
    let flat = |m: [[f32; 4]; 4]| -> [f32; 16] { std::array::from_fn(|i| m[i / 4][i % 4]) };
    layer.attributes.world_to_camera = opts.meta.world_to_camera.map(flat);
    layer.attributes.world_to_normalized_device = opts.meta.world_to_ndc.map(flat);
    let mut attributes = exr_p::ImageAttributes::new(display);
    exr_attributes(&mut attributes, &opts.meta);
    Ok(exr_p::Image::new(attributes, layer).write().to_file(path)?)
}

/// Sets the OpenEXR header attributes `meta` describes.
fn exr_attributes(a: &mut exr_p::ImageAttributes, meta: &super::ImageMeta) {
    use exr::meta::attribute::{AttributeValue, Chromaticities, Text};
    if let Some(c) = meta.color_space {
        let v = |p: [f32; 2]| exr_p::Vec2(p[0], p[1]);
        let [r, g, b] = c.primaries;
        a.chromaticities = Some(Chromaticities { red: v(r), green: v(g), blue: v(b), white: v(c.white) });
    }
    if let Some(t) = meta.render_time_seconds {
        a.other.insert(Text::from("renderTimeSeconds"), AttributeValue::F32(t as f32));
    }
    if let Some(n) = meta.samples_per_pixel {
        a.other.insert(Text::from("samplesPerPixel"), AttributeValue::I32(i32::try_from(n).unwrap_or(i32::MAX)));
    }
    if let Some(e) = meta.estimated_error {
        a.other.insert(Text::from("prism:estimatedError"), AttributeValue::F32(e as f32));
    }
    for (name, value) in meta.exr_strings() {
        a.other.insert(Text::from(name), AttributeValue::Text(Text::from(value.as_str())));
    }
}

/// Reads `path` as `format` into linear floats.
pub(crate) fn read(path: &Path, format: FileFormat) -> Result<Image, RustIoError> {
    match format {
        FileFormat::Exr => read_exr(path),
        _ => read_other(path),
    }
}

/// The size of the image in `path` from its header alone (for OpenEXR the largest layer's),
/// `None` when the header cannot be read (decoding then reports why).
pub(crate) fn dimensions(path: &Path, format: FileFormat) -> Option<(u64, u64)> {
    match format {
        FileFormat::Exr => {
            let meta = exr::meta::MetaData::read_from_file(path, false).ok()?;
            let sizes = meta.headers.iter().map(|h| (h.layer_size.width() as u64, h.layer_size.height() as u64));
            sizes.max_by_key(|&(w, h)| w.saturating_mul(h))
        }
        _ => {
            let reader = ::image::ImageReader::open(path).ok()?.with_guessed_format().ok()?;
            reader.into_dimensions().ok().map(|(w, h)| (u64::from(w), u64::from(h)))
        }
    }
}

/// Position of an EXR channel in prism's interleaved order: R G B A, or Y A, then the rest.
fn canonical_rank(name: &str) -> usize {
    match name {
        "R" | "Y" => 0,
        "G" => 1,
        "B" => 2,
        "A" => 3,
        _ => 4,
    }
}

/// The indices, in [`read_exr`]'s channel order, of the first three channels of the OpenEXR
/// file at `path` in the order OpenEXR lists them (`Imf::ChannelList`: by name, bytewise): B,
/// G, R for an RGB file, A, B, G with alpha. `None` if the header cannot be read or holds fewer
/// than three channels.
pub(crate) fn exr_channels_in_file_order(path: &Path) -> Option<[usize; 3]> {
    let meta = exr::meta::MetaData::read_from_file(path, false).ok()?;
    let names = meta.headers.first()?.channels.list.iter().map(|c| c.name.to_string()).collect();
    first_channels_in_file_order(names)
}

/// [`exr_channels_in_file_order`] for the channel names `names`.
fn first_channels_in_file_order(mut names: Vec<String>) -> Option<[usize; 3]> {
    names.sort();
    let mut ours = names.clone();
    ours.sort_by_key(|n| canonical_rank(n));
    let index = |k: usize| ours.iter().position(|n| names.get(k) == Some(n));
    Some([index(0)?, index(1)?, index(2)?])
}

fn read_exr(path: &Path) -> Result<Image, RustIoError> {
    let image = exr_p::read_first_flat_layer_from_file(path)?;
    let layer = image.layer_data;
    let (w, h) = (layer.size.width(), layer.size.height());
    let mut channels: Vec<&exr_p::AnyChannel<exr_p::FlatSamples>> = layer.channel_data.list.iter().collect();
    // Stable sort keeps the file's alphabetical order among non-canonical names.
    channels.sort_by_key(|ch| canonical_rank(&ch.name.to_string()));
    let c = channels.len();
    if c == 0 || w == 0 || h == 0 {
        return Err(RustIoError::NoPixels);
    }
    let mut data = vec![0.0f32; w * h * c];
    for (k, ch) in channels.iter().enumerate() {
        let count = match &ch.sample_data {
            exr_p::FlatSamples::F16(v) => v.len(),
            exr_p::FlatSamples::F32(v) => v.len(),
            exr_p::FlatSamples::U32(v) => v.len(),
        };
        if count != w * h {
            return Err(RustIoError::Subsampled(ch.name.to_string()));
        }
        let dst = data.iter_mut().skip(k).step_by(c);
        match &ch.sample_data {
            exr_p::FlatSamples::F16(v) => dst.zip(v).for_each(|(d, s)| *d = s.to_f32()),
            exr_p::FlatSamples::F32(v) => dst.zip(v).for_each(|(d, s)| *d = *s),
            exr_p::FlatSamples::U32(v) => dst.zip(v).for_each(|(d, s)| *d = *s as f32),
        }
    }
    Ok(Image { width: w as u32, height: h as u32, channels: c as u32, data })
}

fn read_other(path: &Path) -> Result<Image, RustIoError> {
    let decoded = ::image::ImageReader::open(path)?.with_guessed_format()?.decode()?;
    let (width, height) = (decoded.width(), decoded.height());
    let channels = u32::from(decoded.color().channel_count());
    // `max_code` 0 marks linear float data.
    let (mut data, max_code): (Vec<f32>, u32) = match decoded {
        DynamicImage::ImageLuma8(b) => (normalise(b.as_raw(), 255.0), 255),
        DynamicImage::ImageLumaA8(b) => (normalise(b.as_raw(), 255.0), 255),
        DynamicImage::ImageRgb8(b) => (normalise(b.as_raw(), 255.0), 255),
        DynamicImage::ImageRgba8(b) => (normalise(b.as_raw(), 255.0), 255),
        DynamicImage::ImageLuma16(b) => (normalise(b.as_raw(), 65535.0), 65535),
        DynamicImage::ImageLumaA16(b) => (normalise(b.as_raw(), 65535.0), 65535),
        DynamicImage::ImageRgb16(b) => (normalise(b.as_raw(), 65535.0), 65535),
        DynamicImage::ImageRgba16(b) => (normalise(b.as_raw(), 65535.0), 65535),
        DynamicImage::ImageRgb32F(b) => (b.into_raw(), 0),
        DynamicImage::ImageRgba32F(b) => (b.into_raw(), 0),
        other => return Err(RustIoError::PixelLayout(other.color())),
    };
    if max_code > 0 {
        srgb::decode_normalised_in_place(&mut data, channels as usize, max_code);
    }
    Ok(Image { width, height, channels, data })
}

fn normalise<T: Copy + Into<f32>>(raw: &[T], max_code: f32) -> Vec<f32> {
    raw.iter().map(|&v| v.into() / max_code).collect()
}

#[cfg(test)]
mod tests {
    use super::first_channels_in_file_order;

    fn order(names: &[&str]) -> Option<[usize; 3]> {
        first_channels_in_file_order(names.iter().map(|n| n.to_string()).collect())
    }

    #[test]
    fn openexr_lists_channels_by_name() {
        // prism reads R G B (A), then the rest; OpenEXR lists A B G R Z.
        assert_eq!(order(&["R", "G", "B"]), Some([2, 1, 0]));
        assert_eq!(order(&["B", "G", "R"]), Some([2, 1, 0]));
        assert_eq!(order(&["A", "B", "G", "R"]), Some([3, 2, 1]));
        assert_eq!(order(&["R", "G", "B", "Z"]), Some([2, 1, 0]));
        assert_eq!(order(&["Y", "A"]), None);
    }
}
