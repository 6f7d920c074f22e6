//! Composing images: panels placed side by side, for reports.

use super::{Image, ImageError};

/// The RGB of `images` placed left to right with `gap` black pixels between them, every panel
/// top-aligned; the result is as tall as the tallest. Panels need at least three channels
/// (extra channels are dropped).
pub fn side_by_side(images: &[&Image], gap: u32) -> Result<Image, ImageError> {
    for img in images {
        img.validate()?;
        if img.channels < 3 {
            return Err(ImageError::InvalidImage(format!("{} channels; a panel needs RGB", img.channels)));
        }
    }
    let height = images.iter().map(|i| i.height).max().unwrap_or(0);
    let gaps = gap * (images.len() as u32).saturating_sub(1);
    let width = images.iter().map(|i| i.width).sum::<u32>() + gaps;
    let mut out = Image::new(width, height, 3);
    let mut x0 = 0usize;
    for img in images {
        let c = img.channels as usize;
        for y in 0..img.height as usize {
            for x in 0..img.width as usize {
                let src = (y * img.width as usize + x) * c;
                let dst = (y * width as usize + x0 + x) * 3;
                out.data[dst..dst + 3].copy_from_slice(&img.data[src..src + 3]);
            }
        }
        x0 += (img.width + gap) as usize;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panels_keep_their_pixels_and_gaps_are_black() {
        let a = Image { width: 1, height: 2, channels: 3, data: vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0] };
        let b = Image { width: 1, height: 1, channels: 4, data: vec![7.0, 8.0, 9.0, 0.5] };
        let s = side_by_side(&[&a, &b], 1).unwrap();
        assert_eq!((s.width, s.height, s.channels), (3, 2, 3));
        assert_eq!(s.pixel(0, 0).unwrap(), [1.0, 2.0, 3.0]);
        assert_eq!(s.pixel(0, 1).unwrap(), [4.0, 5.0, 6.0]);
        assert_eq!(s.pixel(1, 0).unwrap(), [0.0; 3]);
        assert_eq!(s.pixel(2, 0).unwrap(), [7.0, 8.0, 9.0]);
        assert_eq!(s.pixel(2, 1).unwrap(), [0.0; 3]);
        assert!(side_by_side(&[&Image::new(1, 1, 1)], 0).is_err());
    }
}
