//! A finished picture for the page: display-ready sRGB bytes, encoded as PNG on the way out.

use ::image::codecs::png::{CompressionType, FilterType, PngEncoder};
use ::image::{ExtendedColorType, ImageEncoder};

/// An 8-bit sRGB picture and what it cost.
#[derive(Debug, Clone, PartialEq)]
pub struct Picture {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// Packed RGB, top row first (`3 * width * height` bytes).
    pub rgb8: Vec<u8>,
    /// Camera samples per pixel it was rendered with (1 for the scientific views).
    pub spp: u32,
    /// Seconds spent rendering (not encoding).
    pub seconds: f64,
}

impl Picture {
    /// The picture as a PNG file. `fast` uses the quickest compression (for pictures shown
    /// while the camera moves, a few times larger); otherwise the encoder's default, the same
    /// bytes `filmsplat render` writes.
    pub fn png(&self, fast: bool) -> Result<Vec<u8>, String> {
        let mut out = Vec::new();
        let encoder = if fast {
            PngEncoder::new_with_quality(&mut out, CompressionType::Fast, FilterType::Sub)
        } else {
            PngEncoder::new(&mut out)
        };
        encoder
            .write_image(
                &self.rgb8,
                self.width as u32,
                self.height as u32,
                ExtendedColorType::Rgb8,
            )
            .map_err(|e| format!("encoding the PNG: {e}"))?;
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_encodings_decode_to_the_same_pixels() {
        let (width, height) = (7, 3);
        let rgb8: Vec<u8> = (0..width * height * 3)
            .map(|i| (i * 37 % 256) as u8)
            .collect();
        let p = Picture {
            width,
            height,
            rgb8: rgb8.clone(),
            spp: 1,
            seconds: 0.0,
        };
        for fast in [false, true] {
            let png = p.png(fast).unwrap();
            let img = ::image::load_from_memory(&png).unwrap().to_rgb8();
            assert_eq!(img.dimensions(), (7, 3));
            assert_eq!(img.into_raw(), rgb8, "fast = {fast}");
        }
    }
}
