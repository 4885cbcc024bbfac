//! Reference frames: TEME, Earth-fixed (GMST), geodetic WGS-84, NED, spherical, RSW, J2000.
