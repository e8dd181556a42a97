//! What the radius fit decided about each splat beyond its radius ([`Cut`]): whole, grown past
//! its cell for tilted neighbours, or cut at an open edge, and which kind of cut. The disks
//! take the half-planes ([`Cut::clip`]); the MLS surface, whose supports blend across
//! neighbours, reads the kind to choose each support's radius (`pipeline::build`).

use super::clip::{EdgeClip, NO_CLIP, cuts};

/// The fit's verdict on a splat besides its radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cut {
    /// A whole disk.
    None,
    /// A whole disk grown past its cell for neighbours whose planes lie apart from its own
    /// (`fan::shingle_overlap`); `flat` is its radius without that growth, which the MLS
    /// surface keeps.
    Grown {
        /// The radius without the growth.
        flat: f32,
    },
    /// A particle one row in from an open edge, cut at its distances to the two nearest edges
    /// of its neighbours' hull plus the reach ([`super::clip::inner_cut`]).
    Inner(EdgeClip),
    /// A particle on an open edge, cut by the lines past the two hull edges through it
    /// ([`super::clip::edge_cut`]).
    Edge(EdgeClip),
}

impl Cut {
    /// The half-planes that cut the disk ([`NO_CLIP`] for a whole one).
    pub fn clip(&self) -> EdgeClip {
        match self {
            Cut::Inner(c) | Cut::Edge(c) => *c,
            Cut::None | Cut::Grown { .. } => NO_CLIP,
        }
    }

    /// Whether the disk loses any part to its cut ([`cuts`]).
    pub fn cuts(&self) -> bool {
        cuts(&self.clip())
    }
}

/// The disks' half-planes of `cuts`, one a particle.
pub fn clips(cuts: &[Cut]) -> Vec<EdgeClip> {
    cuts.iter().map(Cut::clip).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    #[test]
    fn only_cuts_cut_the_disk() {
        let c = [
            Vec4::new(0.0, -1.0, 0.0, 0.5),
            Vec4::new(-1.0, 0.0, 0.0, 0.5),
        ];
        for (cut, cutting) in [
            (Cut::None, false),
            (Cut::Grown { flat: 0.3 }, false),
            (Cut::Inner(c), true),
            (Cut::Edge(c), true),
        ] {
            assert_eq!(cut.cuts(), cutting, "{cut:?}");
            assert_eq!(cut.clip() == c, cutting, "{cut:?}");
        }
        assert_eq!(
            clips(&[Cut::Grown { flat: 1.0 }, Cut::Edge(c)]),
            vec![NO_CLIP, c]
        );
    }
}
