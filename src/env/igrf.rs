//! IGRF-14 geomagnetic field.
