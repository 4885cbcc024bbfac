//! Tilted-dipole geomagnetic field.
