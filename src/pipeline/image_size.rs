//! The one rule for a scene's image size when it gives none.

use crate::render::{DEFAULT_HEIGHT, DEFAULT_WIDTH};
use crate::scene::SceneDesc;

/// The image size a scene renders at, (width, height) pixels: `[render]`'s,
/// [`DEFAULT_WIDTH`]×[`DEFAULT_HEIGHT`] where unset (checked by `SceneDesc::resolve`). Every
/// way in (render, info, the viewer, Python) takes its default size from here.
pub fn image_size(d: &SceneDesc) -> (usize, usize) {
    (
        d.render.width.unwrap_or(DEFAULT_WIDTH),
        d.render.height.unwrap_or(DEFAULT_HEIGHT),
    )
}
