//! Orbit propagation: SGP4 (near-Earth) and the two-body Kepler propagator.

pub mod kepler;
pub mod sgp4;
