//! geometry stage (see the crate docs for its place).
