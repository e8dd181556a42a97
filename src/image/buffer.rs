//! Floating-point linear-RGB pixel buffer.

use crate::{Error, Result};

/// A linear-light RGB image: row-major, top row first, `width * height` pixels.
///
/// Values are scene-referred (unbounded); encoding to 8-bit happens in
/// [`to_srgb8`](super::to_srgb8). Memory: 12 bytes per pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbImage {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Pixels, index `y * width + x`.
    pub data: Vec<[f32; 3]>,
}

impl RgbImage {
    /// A black image of `width x height` pixels. Allocates `12 * width * height` bytes.
    pub fn new(width: usize, height: usize) -> Self {
        Self::filled(width, height, [0.0; 3])
    }

    /// An image of `width x height` pixels all set to `colour` (linear RGB).
    pub fn filled(width: usize, height: usize, colour: [f32; 3]) -> Self {
        RgbImage {
            width,
            height,
            data: vec![colour; width * height],
        }
    }

    /// Wraps existing pixel data; fails if `data.len() != width * height`.
    pub fn from_data(width: usize, height: usize, data: Vec<[f32; 3]>) -> Result<Self> {
        if width.checked_mul(height) != Some(data.len()) {
            return Err(Error::invalid(format!(
                "image data has {} pixels, expected {width} x {height}",
                data.len()
            )));
        }
        Ok(RgbImage {
            width,
            height,
            data,
        })
    }

    /// Index of pixel `(x, y)` into [`data`](Self::data). Panics if out of bounds.
    #[inline]
    fn index(&self, x: usize, y: usize) -> usize {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside {}x{} image",
            self.width,
            self.height
        );
        y * self.width + x
    }

    /// The pixel at column `x`, row `y` (0 = top). Panics if out of bounds.
    #[inline]
    pub fn get(&self, x: usize, y: usize) -> [f32; 3] {
        self.data[self.index(x, y)]
    }

    /// Sets the pixel at `(x, y)`. Panics if out of bounds.
    #[inline]
    pub fn set(&mut self, x: usize, y: usize, v: [f32; 3]) {
        let i = self.index(x, y);
        self.data[i] = v;
    }

    /// Mutable access to the pixel at `(x, y)`. Panics if out of bounds.
    #[inline]
    pub fn pixel_mut(&mut self, x: usize, y: usize) -> &mut [f32; 3] {
        let i = self.index(x, y);
        &mut self.data[i]
    }

    /// The pixel at signed coordinates, or `None` outside the image.
    #[inline]
    pub fn get_checked(&self, x: i64, y: i64) -> Option<[f32; 3]> {
        if x < 0 || y < 0 || x as usize >= self.width || y as usize >= self.height {
            return None;
        }
        Some(self.data[y as usize * self.width + x as usize])
    }

    /// Mutable access at signed coordinates, or `None` outside the image (for clipped drawing).
    #[inline]
    pub fn pixel_mut_checked(&mut self, x: i64, y: i64) -> Option<&mut [f32; 3]> {
        if x < 0 || y < 0 || x as usize >= self.width || y as usize >= self.height {
            return None;
        }
        let w = self.width;
        Some(&mut self.data[y as usize * w + x as usize])
    }

    /// Number of pixels (`width * height`).
    pub fn len(&self) -> usize {
        self.data.len()
    }

    /// True if the image has no pixels.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn get_set_row_major() {
        let mut im = RgbImage::new(3, 2);
        im.set(2, 1, [1.0, 2.0, 3.0]);
        assert_eq!(im.data[5], [1.0, 2.0, 3.0]);
        assert_eq!(im.get(2, 1), [1.0, 2.0, 3.0]);
        im.pixel_mut(0, 1)[1] = 7.0;
        assert_eq!(im.data[3], [0.0, 7.0, 0.0]);
        assert_eq!(im.get_checked(3, 0), None);
        assert_eq!(im.get_checked(-1, 0), None);
        assert_eq!(im.get_checked(2, 1), Some([1.0, 2.0, 3.0]));
    }

    #[test]
    fn from_data_checks_length() {
        assert!(RgbImage::from_data(2, 2, vec![[0.0; 3]; 3]).is_err());
        assert!(RgbImage::from_data(2, 2, vec![[0.0; 3]; 4]).is_ok());
    }
}
