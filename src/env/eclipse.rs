//! Eclipse geometry.
