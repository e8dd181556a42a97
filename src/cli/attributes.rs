//! The attribute-mapping flags shared by `info` and `convert`.

use crate::Result;
use crate::io::ReadOptions;
use clap::Args;

/// Which attributes of a particle file hold thickness, normals and radius, and the thickness
/// unit.
#[derive(Debug, Args)]
pub struct AttributeArgs {
    /// Unit of the file's thickness values: nm, um, mm or m (default: the format's unit, m for
    /// frame folders, nm otherwise).
    #[arg(long)]
    thickness_unit: Option<String>,
    /// Name of the thickness attribute.
    #[arg(long)]
    thickness_attr: Option<String>,
    /// Prefix of the normal attributes (n for nx ny nz, normal for normal_x ...).
    #[arg(long)]
    normal_attr: Option<String>,
    /// Name of the radius attribute.
    #[arg(long)]
    radius_attr: Option<String>,
}

impl AttributeArgs {
    /// The reader options these flags ask for.
    pub fn read_options(&self) -> Result<ReadOptions> {
        ReadOptions {
            thickness_attr: self.thickness_attr.clone(),
            normal_attr: self.normal_attr.clone(),
            radius_attr: self.radius_attr.clone(),
            ..ReadOptions::default()
        }
        .with_unit(self.thickness_unit.as_deref())
    }
}
