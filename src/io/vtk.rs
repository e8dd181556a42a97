//! VTK legacy reader (not written yet).

use std::path::Path;

use super::{ReadOptions, format_error};
use crate::error::Result;
use crate::pointcloud::PointCloud;

/// Reads a VTK legacy file (not supported yet: always an error).
///
/// # Errors
/// Always [`crate::Error::Format`].
pub fn read(path: &Path, opts: &ReadOptions) -> Result<PointCloud> {
    opts.check()?;
    Err(format_error(path, "VTK legacy", "reader not written yet"))
}
