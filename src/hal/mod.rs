//! Hardware abstraction: what a tile can do, behind small fallible traits (STYLE.md §5–6).
//!
//! The flight algorithms never see these types: the ACS loop ([`crate::acs_loop`]) reads raw
//! values through a [`TileBus`] (tile sensors and wheels by tile index, coils by coil index,
//! errors reduced to an [`ErrorKind`]) and converts them with [`crate::tiles`].
//!
//! # Layers
//! | layer | what | where |
//! |---|---|---|
//! | device traits | one device: [`SunSensor`], [`Magnetometer`], [`Gyro`], [`ReactionWheel`], [`Magnetorquer`] (each with its own error type, with `&mut T` forwarding impls) | this module |
//! | drivers | the devices on `embedded-hal` 1.0 (I²C sensors, PWM + direction-pin actuators), each with its part's address, registers and scale in its own configuration | [`drivers`] |
//! | MSP430 peripherals | USCI I²C master and UART, Timer_A period, Timer_B PWM, port pins, flash controller and the element store of the MSP430FG4619, over a register-access trait (tested on the host against register models) | [`msp430`] |
//! | adapter | [`bus::DeviceBus`]: the satellite's [`TileBus`] built from per-tile device drivers (any type implementing the device traits, each tile's devices optional) and the coils | [`bus`] |
//! | bus | [`TileBus`]: what the loop calls | this module |
//! | node link | [`link::NodeLink`]: one packet out, one packet in, between the two nodes; [`link::FramedLink`] over any [`link::ByteStream`] (a UART driver) | [`link`] |
//!
//! # Who implements [`TileBus`] how
//! - **A board** builds its drivers (from [`drivers`] or its own types implementing the device
//!   traits) and hands them to [`bus::DeviceBus`]; `examples/board.rs` runs the flight loop this
//!   way on the host against stand-in peripherals, and `tests/hal_adapter.rs` against
//!   `embedded-hal-mock` devices.
//! - **The host simulator** (`crate::host::sim`, `Simulator`) implements [`TileBus`] directly:
//!   its simulated devices are computed per tile index from the truth state, with faults
//!   injected at the bus (a failed tile, a stuck reading), so it does not go through
//!   per-device drivers.
//! - **The MSP430 firmware**: the attitude node's flight image (feature `pil` off) flies
//!   [`msp430::tile_bus::AttitudeBus`], a [`bus::DeviceBus`] of [`drivers`] over
//!   [`msp430::usci_i2c::UsciI2c`] (the tiles' sensors and wheel controllers at the I²C address
//!   map of [`msp430::tile_bus`]), [`msp430::pwm::PwmChannel`] and [`msp430::gpio::OutputPin`]
//!   (the coils), tested on the host against register models. Its processor-in-the-loop image
//!   (feature `pil`) implements [`TileBus`] directly over RAM mailboxes that the PIL host
//!   writes (`firmware/src/tiles.rs`, `MailboxBus`).
//!
//! All three feed the same loop through the same trait and the same raw formats below, so a
//! board that works over [`bus::DeviceBus`] runs the loop the simulator and the processor in the
//! loop test.
//!
//! # Raw formats (note 000 §1.3)
//! | device | raw value | unit |
//! |---|---|---|
//! | sun sensor | two `i16` angles `(a, b)` | [`SUN_LSB_RAD`] = 1e-4 rad |
//! | magnetometer | two `i16` components along tile x, y | [`MAGNETOMETER_LSB_NT`] = 10 nT |
//! | gyro | one `i16` rate about tile z | [`GYRO_LSB_RADPS`] = 1e-4 rad/s |
//! | reaction wheel | momentum command along tile z | kg·m²/s |
//! | reaction wheel read-back | one `i16` momentum along tile z (the tachometer) | [`WHEEL_LSB_NMS`] = 1e-7 kg·m²/s |
//! | magnetorquer | dipole command along the coil's axis | A·m² |
//! | magnetorquer read-back | one `i16` dipole along the coil's axis (its current) | [`COIL_LSB_AM2`] = 1e-5 A·m² |
//!
//! These units are the bus's contract, fixed in [`crate::tiles`]: the flight loop converts with
//! them (units per tile in the loop's configuration would change the flight loop and its image,
//! which is at its flash limit). A part with another resolution is configured in its driver, not in the library: the
//! driver's scale ([`drivers::Scale`]) converts the part's words into these units
//! ([`drivers::I2cMagnetometer::with_scale`]). The device traits also give each reading in
//! physical units ([`Magnetometer::read_field_nt`], [`SunSensor::read_sun_angles`],
//! [`Gyro::read_rate_radps`]).
//!
//! Every call returns a `Result` whose error has a [`ErrorKind`] (device absent, timeout,
//! value out of range, bus error): the loop marks a tile failed when its devices keep
//! failing and never uses a value that did not arrive.
//!
//! [`SUN_LSB_RAD`]: crate::tiles::SUN_LSB_RAD
//! [`MAGNETOMETER_LSB_NT`]: crate::tiles::MAGNETOMETER_LSB_NT
//! [`GYRO_LSB_RADPS`]: crate::tiles::GYRO_LSB_RADPS
//! [`WHEEL_LSB_NMS`]: crate::tiles::WHEEL_LSB_NMS
//! [`COIL_LSB_AM2`]: crate::tiles::COIL_LSB_AM2

pub mod bus;
pub mod drivers;
pub mod link;
pub mod msp430;

use core::fmt;

use crate::linalg::Vec2;
use crate::tiles::{RawGyro, RawMagnetometer, RawSunAngles, SunAngles};

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

impl ErrorKind {
    /// The kind as a telemetry code ([`crate::telemetry`]): 1 absent, 2 timeout, 3 out of
    /// range, 4 bus, 5 other.
    pub fn code(self) -> u8 {
        match self {
            Self::DeviceAbsent => 1,
            Self::Timeout => 2,
            Self::OutOfRange => 3,
            Self::Bus => 4,
            Self::Other => 5,
        }
    }

    /// The kind of telemetry code `code` ([`ErrorKind::code`]), `None` for another value.
    pub fn from_code(code: u8) -> Option<Self> {
        Some(match code {
            1 => Self::DeviceAbsent,
            2 => Self::Timeout,
            3 => Self::OutOfRange,
            4 => Self::Bus,
            5 => Self::Other,
            _ => return None,
        })
    }
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

    /// The two angles in radians ([`crate::tiles::RawSunAngles::to_rad`]), or `None` when the
    /// detector sees no Sun.
    fn read_sun_angles(&mut self) -> Result<Option<SunAngles>, Self::Error> {
        Ok(self
            .read_sun_raw()?
            .map(|[a, b]| RawSunAngles { a, b }.to_rad()))
    }
}

/// A tile's two-axis magnetometer.
pub trait Magnetometer: ErrorType {
    /// Field components along tile x and y, in 10 nT.
    fn read_field_raw(&mut self) -> Result<[i16; 2], Self::Error>;

    /// Field components along tile x and y in nT ([`crate::tiles::RawMagnetometer::to_nt`]).
    fn read_field_nt(&mut self) -> Result<Vec2, Self::Error> {
        let [x, y] = self.read_field_raw()?;
        Ok(RawMagnetometer { x, y }.to_nt())
    }
}

/// A tile's one-axis gyro.
pub trait Gyro: ErrorType {
    /// Rate about tile z, in 1e-4 rad/s.
    fn read_rate_raw(&mut self) -> Result<i16, Self::Error>;

    /// Rate about tile z in rad/s ([`crate::tiles::RawGyro::to_radps`]).
    fn read_rate_radps(&mut self) -> Result<f32, Self::Error> {
        Ok(RawGyro(self.read_rate_raw()?).to_radps())
    }
}

/// A tile's reaction wheel (spin axis = tile z).
pub trait ReactionWheel: ErrorType {
    /// Commands the wheel's angular momentum along tile z, kg·m²/s.
    fn set_momentum(&mut self, h_nms: f32) -> Result<(), Self::Error>;

    /// Stops the wheel (the safe state). Default: a zero momentum command.
    fn stop(&mut self) -> Result<(), Self::Error> {
        self.set_momentum(0.0)
    }

    /// The wheel's momentum read back (its tachometer) along tile z, in
    /// [`crate::tiles::WHEEL_LSB_NMS`]; `Ok(None)`: the driver has no read-back (the default),
    /// and the loop cannot check this wheel.
    fn read_momentum_raw(&mut self) -> Result<Option<i16>, Self::Error> {
        Ok(None)
    }
}

/// A magnetorquer coil (dipole along its axis).
pub trait Magnetorquer: ErrorType {
    /// Commands the coil's dipole along its axis, A·m².
    fn set_dipole(&mut self, m_am2: f32) -> Result<(), Self::Error>;

    /// Switches the coil off (the safe state; also before magnetometer reads).
    fn off(&mut self) -> Result<(), Self::Error> {
        self.set_dipole(0.0)
    }

    /// The coil's dipole read back (its current times its turns-area) along its axis, in
    /// [`crate::tiles::COIL_LSB_AM2`]; `Ok(None)`: the driver has no read-back (the default),
    /// and the loop cannot check this coil.
    fn read_dipole_raw(&mut self) -> Result<Option<i16>, Self::Error> {
        Ok(None)
    }
}

// A driver borrowed mutably is a driver (what embedded-hal does for its traits): a board can
// lend its drivers to a [`bus::DeviceBus`] and keep them, and `&mut dyn SunSensor<Error = E>`
// mixes parts of different types on one bus. Every method forwards, so a driver's own `stop`,
// `off` or physical-unit read is the one called.

impl<T: ErrorType + ?Sized> ErrorType for &mut T {
    type Error = T::Error;
}

impl<T: SunSensor + ?Sized> SunSensor for &mut T {
    fn read_sun_raw(&mut self) -> Result<Option<[i16; 2]>, Self::Error> {
        T::read_sun_raw(self)
    }
    fn read_sun_angles(&mut self) -> Result<Option<SunAngles>, Self::Error> {
        T::read_sun_angles(self)
    }
}

impl<T: Magnetometer + ?Sized> Magnetometer for &mut T {
    fn read_field_raw(&mut self) -> Result<[i16; 2], Self::Error> {
        T::read_field_raw(self)
    }
    fn read_field_nt(&mut self) -> Result<Vec2, Self::Error> {
        T::read_field_nt(self)
    }
}

impl<T: Gyro + ?Sized> Gyro for &mut T {
    fn read_rate_raw(&mut self) -> Result<i16, Self::Error> {
        T::read_rate_raw(self)
    }
    fn read_rate_radps(&mut self) -> Result<f32, Self::Error> {
        T::read_rate_radps(self)
    }
}

impl<T: ReactionWheel + ?Sized> ReactionWheel for &mut T {
    fn set_momentum(&mut self, h_nms: f32) -> Result<(), Self::Error> {
        T::set_momentum(self, h_nms)
    }
    fn stop(&mut self) -> Result<(), Self::Error> {
        T::stop(self)
    }
    fn read_momentum_raw(&mut self) -> Result<Option<i16>, Self::Error> {
        T::read_momentum_raw(self)
    }
}

impl<T: Magnetorquer + ?Sized> Magnetorquer for &mut T {
    fn set_dipole(&mut self, m_am2: f32) -> Result<(), Self::Error> {
        T::set_dipole(self, m_am2)
    }
    fn off(&mut self) -> Result<(), Self::Error> {
        T::off(self)
    }
    fn read_dipole_raw(&mut self) -> Result<Option<i16>, Self::Error> {
        T::read_dipole_raw(self)
    }
}

/// The index of a tile: its place in the configuration's tiles ([`crate::tiles::Tiles`],
/// `AcsConfig::tiles`). A tile's sensors and its reaction wheel are addressed by it (the loop
/// has at most one wheel per tile, spinning about the tile's normal).
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TileIndex(pub usize);

/// The index of a magnetorquer coil: its place in `AcsConfig::coils` (coils are the
/// satellite's, not a tile's: the flight configuration has three along the body axes).
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CoilIndex(pub usize);

/// The set of tiles and coils of a satellite: sensors and wheels addressed by tile index (the
/// order of [`crate::tiles::Tiles`], a [`TileIndex`]'s value), coils by coil index (the order of
/// `AcsConfig::coils`, a [`CoilIndex`]'s value). Errors are reduced to their [`ErrorKind`].
///
/// The indices are plain `usize` here because the flight firmware implements this trait and
/// its image is at its flash limit; [`bus::DeviceBus`] gives the typed view.
pub trait TileBus {
    /// Raw sun-sensor angles of tile `tile` (`None`: no Sun).
    fn read_sun(&mut self, tile: usize) -> Result<Option<[i16; 2]>, ErrorKind>;
    /// Raw magnetometer components of tile `tile`.
    fn read_magnetometer(&mut self, tile: usize) -> Result<[i16; 2], ErrorKind>;
    /// Raw gyro rate of tile `tile`.
    fn read_gyro(&mut self, tile: usize) -> Result<i16, ErrorKind>;
    /// Commands the momentum of tile `tile`'s reaction wheel, kg·m²/s along the tile normal.
    fn set_wheel_momentum(&mut self, tile: usize, h_nms: f32) -> Result<(), ErrorKind>;
    /// Commands the dipole of magnetorquer coil `coil` (an index into `AcsConfig::coils`,
    /// not a tile index), A·m² along the coil's axis.
    fn set_dipole(&mut self, coil: usize, m_am2: f32) -> Result<(), ErrorKind>;
    /// The momentum tile `tile`'s wheel reads back (its tachometer), in
    /// [`crate::tiles::WHEEL_LSB_NMS`] along the tile normal; `Ok(None)`: this wheel has no
    /// read-back, and the attitude node cannot check it (the default).
    fn read_wheel_momentum(&mut self, tile: usize) -> Result<Option<i16>, ErrorKind> {
        let _ = tile;
        Ok(None)
    }
    /// The dipole coil `coil` reads back (its current), in [`crate::tiles::COIL_LSB_AM2`]
    /// along its axis; `Ok(None)`: this coil has no read-back, and the attitude node cannot
    /// check it (the default). The node reads it at the start of a step, before it switches
    /// the coils off: the dipole of the previous step's command.
    fn read_coil_dipole(&mut self, coil: usize) -> Result<Option<i16>, ErrorKind> {
        let _ = coil;
        Ok(None)
    }
    /// Waits at least `us` microseconds before returning. The attitude node calls it once a
    /// step, between switching the coils off and reading the tiles
    /// ([`crate::attitude_node::COIL_DECAY_US`]): a board waits on its timer (the flight
    /// image: [`bus::DeviceBus`] over an `embedded_hal::delay::DelayNs`); a simulator, whose
    /// truth places the reads in time itself, may return at once.
    fn delay_us(&mut self, us: u32);
}

impl<T: TileBus + ?Sized> TileBus for &mut T {
    fn read_sun(&mut self, tile: usize) -> Result<Option<[i16; 2]>, ErrorKind> {
        T::read_sun(self, tile)
    }
    fn read_magnetometer(&mut self, tile: usize) -> Result<[i16; 2], ErrorKind> {
        T::read_magnetometer(self, tile)
    }
    fn read_gyro(&mut self, tile: usize) -> Result<i16, ErrorKind> {
        T::read_gyro(self, tile)
    }
    fn set_wheel_momentum(&mut self, tile: usize, h_nms: f32) -> Result<(), ErrorKind> {
        T::set_wheel_momentum(self, tile, h_nms)
    }
    fn set_dipole(&mut self, coil: usize, m_am2: f32) -> Result<(), ErrorKind> {
        T::set_dipole(self, coil, m_am2)
    }
    fn read_wheel_momentum(&mut self, tile: usize) -> Result<Option<i16>, ErrorKind> {
        T::read_wheel_momentum(self, tile)
    }
    fn read_coil_dipole(&mut self, coil: usize) -> Result<Option<i16>, ErrorKind> {
        T::read_coil_dipole(self, coil)
    }
    fn delay_us(&mut self, us: u32) {
        T::delay_us(self, us)
    }
}
