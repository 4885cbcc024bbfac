//! STK ephemeris files (`.e`, `EphemerisTimePosVel`): reader and writer.
