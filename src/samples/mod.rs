//! Sample scene generators: synthetic thin-film particle clouds (bubbles, films).

pub mod bubble;
pub mod fibonacci;
pub mod icosphere;
pub mod rng;

pub use bubble::{BubbleParams, bubble};
pub use fibonacci::{fibonacci_spacing, fibonacci_sphere};
pub use icosphere::icosphere;
