//! Command-line front end.

/// Runs the CLI on the process arguments; returns the exit code.
pub fn main() -> i32 {
    0
}
