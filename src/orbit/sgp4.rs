//! SGP4 near-Earth propagator (Vallado et al. 2006), f32 propagation.
