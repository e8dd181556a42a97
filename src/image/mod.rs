//! Image stage: linear-RGB pixel buffers, grading, exposure and tone mapping to sRGB8, atomic PNG and
//! EXR output, movies (frames piped to ffmpeg), EXR input (environment maps), and chart drawing (text, lines, rectangles,
//! viridis colour map), and image-comparison metrics (PSNR, SSIM, CIEDE2000).
//!
//! Everything here works on plain pixel arrays and imports nothing else from the crate except
//! the error type. Pixel buffers are row-major with the top row first; colours are linear RGB
//! unless a function says otherwise.

mod buffer;
mod colormap;
pub mod draw;
pub mod exr;
mod font;
pub mod grade;
pub mod metrics;
pub mod pinholes;
mod png;
pub mod stability;
pub mod text;
mod tonemap;
pub mod video;
pub mod visibility;

pub use crate::atomic::write_atomic;
pub use buffer::RgbImage;
pub use colormap::{ONE_VALUE_WIDTH, is_one_value, viridis};
pub use draw::{blend, draw_line, fill_rect, stroke_rect};
pub use exr::{ExrLayers, read_exr, read_exr_rgba, write_exr};
pub use grade::Grade;
pub use png::{Srgb8Image, read_png, read_png_srgb8, save_png, write_png, write_png_rgba};
pub use text::{
    Anchor, FontMetrics, HAlign, VAlign, draw_text, draw_text_vertical, font_metrics, text_width,
};
pub use tonemap::{ToneMap, encode_srgb8, linear_to_srgb, srgb_to_linear, to_srgb8};
