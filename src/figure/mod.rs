//! Figures: the interference colour chart and other annotated images.

pub mod chart;

pub use chart::{ChartParams, interference_chart};
