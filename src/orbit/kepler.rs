//! Two-body Kepler propagator (seed 000 §4.1).
