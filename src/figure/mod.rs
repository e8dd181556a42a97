//! Figures: the interference colour chart, colour bars and other annotated images.

pub mod chart;
pub mod colour_bar;
pub mod compare;

pub use chart::{ChartParams, interference_chart};
pub use colour_bar::{add_colour_bar, colour_bar_width};
pub use compare::side_by_side;
