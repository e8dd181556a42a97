//! Tiny XML scanner (not written yet).
