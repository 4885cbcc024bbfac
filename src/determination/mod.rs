//! Attitude determination.
