//! What the image I/O does with and without OpenImageIO compiled in: the pure-Rust build runs
//! this suite too, so both answers are checked.

use crate::common::tmpdir;
use prism::image::{read, read_with, write_with, Backend, Image, ImageError, WriteOptions};
use std::path::Path;

#[test]
fn backend_availability_matches_the_build() {
    let img = Image::new(2, 2, 3);
    let path = tmpdir("image-backend").join("x.exr");
    let result = write_with(&path, &img, &WriteOptions { backend: Backend::Oiio, ..WriteOptions::default() });
    if cfg!(feature = "oiio") {
        assert!(result.is_ok(), "{result:?}");
    } else {
        assert!(matches!(result, Err(ImageError::BackendUnavailable)), "{result:?}");
    }
}

/// A TIFF of 64-bit float samples (16×8 RGB: R = 0.25, G = 0.5, B = 2 for x < 8 and 0.125
/// beyond), written by OpenImageIO 3.2 from PyPI (scripts/make-image-fixtures.py), which the
/// `image` crate does not decode: `read` falls back to OpenImageIO when it is built in.
#[test]
fn read_falls_back_to_openimageio_for_what_the_rust_path_cannot_decode() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/images/float64.tif");
    let rust = read_with(&path, Backend::Rust);
    assert!(matches!(rust, Err(ImageError::Decode { .. })), "the image crate reads float64 TIFF now: {rust:?}");
    let read = read(&path);
    if !cfg!(feature = "oiio") {
        assert!(matches!(read, Err(ImageError::Decode { .. })), "{read:?}");
        return;
    }
    let img = read.unwrap();
    assert_eq!((img.width, img.height, img.channels), (16, 8, 3));
    for y in 0..8 {
        for x in 0..16 {
            let expected = [0.25, 0.5, if x < 8 { 2.0 } else { 0.125 }];
            assert_eq!(img.pixel(x, y).unwrap(), expected, "({x}, {y})");
        }
    }
}
