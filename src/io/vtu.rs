//! VTK XML reader (not written yet).

use std::path::Path;

use super::{ReadOptions, format_error};
use crate::error::Result;
use crate::pointcloud::PointCloud;

/// Reads a VTK XML file (not supported yet: always an error).
///
/// # Errors
/// Always [`crate::Error::Format`].
pub fn read(path: &Path, opts: &ReadOptions) -> Result<PointCloud> {
    opts.check()?;
    Err(format_error(path, "VTK XML", "reader not written yet"))
}
