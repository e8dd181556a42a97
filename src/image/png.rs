//! 8-bit PNG output (via the `image` crate's encoder), written atomically.

use std::path::Path;

use ::image::codecs::png::PngEncoder;
use ::image::{ExtendedColorType, ImageEncoder};

use super::buffer::RgbImage;
use super::tonemap::{ToneMap, to_srgb8};
use crate::atomic::write_atomic;
use crate::{Error, Result};

/// Writes packed sRGB-encoded RGB8 pixels (`3 * width * height` bytes, top row first) as a PNG.
/// Atomic (see [`write_atomic`]): no partial file is left on error.
pub fn write_png(path: &Path, width: usize, height: usize, rgb8: &[u8]) -> Result<()> {
    write_png_impl(path, width, height, rgb8, 3, ExtendedColorType::Rgb8)
}

/// Writes packed RGBA8 pixels (`4 * width * height` bytes, straight alpha, sRGB colour) as a PNG.
pub fn write_png_rgba(path: &Path, width: usize, height: usize, rgba8: &[u8]) -> Result<()> {
    write_png_impl(path, width, height, rgba8, 4, ExtendedColorType::Rgba8)
}

/// Exposes, tone maps and encodes `img` (see [`to_srgb8`]) and writes it as an RGB PNG.
pub fn save_png(path: &Path, img: &RgbImage, exposure_ev: f32, tone: ToneMap) -> Result<()> {
    write_png(
        path,
        img.width,
        img.height,
        &to_srgb8(img, exposure_ev, tone),
    )
}

fn write_png_impl(
    path: &Path,
    width: usize,
    height: usize,
    bytes: &[u8],
    channels: usize,
    colour: ExtendedColorType,
) -> Result<()> {
    let fail = |message: String| Error::Format {
        path: path.into(),
        format: "PNG",
        message,
    };
    let (w, h) = match (u32::try_from(width), u32::try_from(height)) {
        (Ok(w), Ok(h)) if w > 0 && h > 0 => (w, h),
        _ => return Err(fail(format!("cannot write a {width} x {height} image"))),
    };
    let expected = width
        .checked_mul(height)
        .and_then(|n| n.checked_mul(channels));
    if expected != Some(bytes.len()) {
        return Err(fail(format!(
            "pixel buffer has {} bytes, expected {width} x {height} x {channels}",
            bytes.len()
        )));
    }
    write_atomic(path, |out| {
        PngEncoder::new(out)
            .write_image(bytes, w, h, colour)
            .map_err(|e| match e {
                ::image::ImageError::IoError(io) => Error::io(path, io),
                other => fail(other.to_string()),
            })
    })
}

/// Packed 8-bit sRGB pixels, as a PNG holds them: `3 * width * height` bytes, top row first.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Srgb8Image {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// R, G, B bytes of each pixel, row by row.
    pub data: Vec<u8>,
}

/// Decodes the PNG at `path` (any bit depth or colour type the `image` crate decodes); errors
/// name the file.
fn decode(path: &Path) -> Result<::image::DynamicImage> {
    ::image::ImageReader::open(path)
        .map_err(|e| Error::io(path, e))?
        .with_guessed_format()
        .map_err(|e| Error::io(path, e))?
        .decode()
        .map_err(|e| Error::Format {
            path: path.into(),
            format: "PNG",
            message: e.to_string(),
        })
}

/// Reads a PNG (any bit depth or colour type the `image` crate decodes) as its 8-bit sRGB
/// pixels; alpha is dropped (the second value says whether there was any).
pub fn read_png_srgb8(path: &Path) -> Result<(Srgb8Image, bool)> {
    let img = decode(path)?;
    let alpha = img.color().has_alpha();
    let img = img.to_rgb8();
    let (width, height) = (img.width() as usize, img.height() as usize);
    Ok((
        Srgb8Image {
            width,
            height,
            data: img.into_raw(),
        },
        alpha,
    ))
}

/// Reads a PNG (any bit depth or colour type the `image` crate decodes) as linear RGB: the
/// 8-bit sRGB values are decoded with the sRGB curve; alpha is ignored.
pub fn read_png(path: &Path) -> Result<RgbImage> {
    let bad = |e: String| Error::Format {
        path: path.into(),
        format: "PNG",
        message: e,
    };
    let img = decode(path)?.to_rgb8();
    let (w, h) = (img.width() as usize, img.height() as usize);
    // The decoder stops at its own limit (512 MiB); the linear copy is 4x the 8-bit image.
    crate::budget::check((w * h * 12) as u64, || {
        format!("a {w}x{h} image as linear RGB")
    })
    .map_err(bad)?;
    let data = img
        .pixels()
        .map(|p| {
            p.0.map(|v| super::tonemap::srgb_to_linear(v as f32 / 255.0))
        })
        .collect();
    Ok(RgbImage {
        width: w,
        height: h,
        data,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_a_valid_png_and_rejects_bad_sizes() {
        let dir = std::env::temp_dir().join(format!("filmsplat-png-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("t.png");
        let px: Vec<u8> = (0..2 * 3 * 3).map(|i| (i * 13) as u8).collect();
        write_png(&p, 3, 2, &px).unwrap();
        let back = ::image::open(&p).unwrap().to_rgb8();
        assert_eq!((back.width(), back.height()), (3, 2));
        assert_eq!(back.as_raw(), &px);
        // read_png decodes the sRGB bytes to linear values, which encode back to the bytes.
        let lin = read_png(&p).unwrap();
        assert_eq!((lin.width, lin.height), (3, 2));
        let again: Vec<u8> = lin
            .data
            .iter()
            .flat_map(|p| p.map(super::super::tonemap::encode_srgb8))
            .collect();
        assert_eq!(again, px);
        assert!(read_png(&dir.join("none.png")).is_err());

        let rgba: Vec<u8> = (0..4 * 4).map(|i| (i * 17) as u8).collect();
        write_png_rgba(&p, 2, 2, &rgba).unwrap();
        assert_eq!(::image::open(&p).unwrap().to_rgba8().as_raw(), &rgba);

        assert!(write_png(&p, 3, 3, &px).is_err());
        assert!(write_png(&p, 0, 0, &[]).is_err());
        assert!(write_png(&dir.join("missing/t.png"), 3, 2, &px).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
