//! Environment models: the Sun, eclipses and the geomagnetic field.

pub mod albedo;
pub mod dipole;
pub mod eclipse;
pub mod igrf;
pub mod sun;
