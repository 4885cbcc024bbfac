//! Hardware abstraction: what a tile can do, behind small fallible traits (STYLE.md §5–6).
//!
//! The flight algorithms never see these types: the ACS loop ([`crate::acs_loop`]) reads raw
//! values through a [`TileBus`] and converts them with [`crate::tiles`]. Two implementations
//! exist for every trait: the real drivers ([`drivers`], on `embedded-hal` 1.0) and the
//! simulated tiles of the host simulator (`crate::host::sim`), and the same loop runs on both.
//!
//! # Raw formats (note 000 §1.3)
//! | device | raw value | unit |
//! |---|---|---|
//! | sun sensor | two `i16` angles `(a, b)` | 1e-4 rad |
//! | magnetometer | two `i16` components along tile x, y | 10 nT |
//! | gyro | one `i16` rate about tile z | 1e-4 rad/s |
//! | reaction wheel | momentum along tile z (command and readback) | kg·m²/s |
//! | magnetorquer | dipole along tile z | A·m² |
//!
//! Every call returns a `Result` whose error has a [`ErrorKind`] (device absent, timeout,
//! value out of range, bus error): the loop marks a tile's device failed when it keeps
//! failing and never uses a value that did not arrive.

pub mod drivers;

use core::fmt;

/// What went wrong with a device, whatever its driver.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ErrorKind {
    /// The tile has no such device, or it does not answer.
    DeviceAbsent,
    /// The device did not answer in time.
    Timeout,
    /// The device answered with a value outside its range (saturated, or a command beyond its
    /// limit was refused).
    OutOfRange,
    /// A bus error (I²C NACK, SPI fault, ...).
    Bus,
    /// Any other failure.
    Other,
}

impl fmt::Display for ErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = match self {
            Self::DeviceAbsent => "device absent",
            Self::Timeout => "device timeout",
            Self::OutOfRange => "value out of range",
            Self::Bus => "bus error",
            Self::Other => "device failure",
        };
        f.write_str(s)
    }
}

/// A device error: anything that can say which [`ErrorKind`] it is.
pub trait Error: fmt::Debug {
    /// The kind of the error.
    fn kind(&self) -> ErrorKind;
}

impl Error for ErrorKind {
    fn kind(&self) -> ErrorKind {
        *self
    }
}

/// The error type of a device.
pub trait ErrorType {
    /// The driver's error.
    type Error: Error;
}

/// A tile's sun sensor (pinhole over a position-sensitive detector, note 000 §1.2).
pub trait SunSensor: ErrorType {
    /// The two raw angles `(a, b)` in 1e-4 rad, or `None` when the detector sees no Sun
    /// (not lit, or in eclipse).
    fn read_sun_raw(&mut self) -> Result<Option<[i16; 2]>, Self::Error>;
}

/// A tile's two-axis magnetometer.
pub trait Magnetometer: ErrorType {
    /// Field components along tile x and y, in 10 nT.
    fn read_field_raw(&mut self) -> Result<[i16; 2], Self::Error>;
}

/// A tile's one-axis gyro.
pub trait Gyro: ErrorType {
    /// Rate about tile z, in 1e-4 rad/s.
    fn read_rate_raw(&mut self) -> Result<i16, Self::Error>;
}

/// A tile's reaction wheel (spin axis = tile z).
pub trait ReactionWheel: ErrorType {
    /// Commands the wheel's angular momentum along tile z, kg·m²/s.
    fn set_momentum(&mut self, h_nms: f32) -> Result<(), Self::Error>;

    /// Stops the wheel (the safe state). Default: a zero momentum command.
    fn stop(&mut self) -> Result<(), Self::Error> {
        self.set_momentum(0.0)
    }
}

/// A tile's magnetorquer coil (dipole along tile z).
pub trait Magnetorquer: ErrorType {
    /// Commands the coil's dipole along tile z, A·m².
    fn set_dipole(&mut self, m_am2: f32) -> Result<(), Self::Error>;

    /// Switches the coil off (the safe state; also before magnetometer reads).
    fn off(&mut self) -> Result<(), Self::Error> {
        self.set_dipole(0.0)
    }
}

/// The set of tiles of a satellite, addressed by tile index (the order of
/// [`crate::tiles::Tiles`]). Errors are reduced to their [`ErrorKind`].
pub trait TileBus {
    /// Raw sun-sensor angles of a tile (`None`: no Sun).
    fn read_sun(&mut self, tile: usize) -> Result<Option<[i16; 2]>, ErrorKind>;
    /// Raw magnetometer components of a tile.
    fn read_magnetometer(&mut self, tile: usize) -> Result<[i16; 2], ErrorKind>;
    /// Raw gyro rate of a tile.
    fn read_gyro(&mut self, tile: usize) -> Result<i16, ErrorKind>;
    /// Commands a tile's wheel momentum, kg·m²/s.
    fn set_wheel_momentum(&mut self, tile: usize, h_nms: f32) -> Result<(), ErrorKind>;
    /// Commands a tile's magnetorquer dipole, A·m².
    fn set_dipole(&mut self, tile: usize, m_am2: f32) -> Result<(), ErrorKind>;
}
