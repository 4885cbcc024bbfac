//! Tile geometry and raw sensor formats.
