//! The attitude node's tile bus on the MSP430FG4619: the satellite's
//! [`TileBus`](crate::hal::TileBus) as a [`DeviceBus`] of [`super::super::drivers`] devices over
//! the part's peripherals, and the I²C address map of the tiles.
//!
//! # What is where
//! - The tiles' sensors and the wheels' speed controllers are I²C slaves on the one tile bus,
//!   USCI_B0 ([`super::usci_i2c`], 100 kHz; SDA P3.1, SCL P3.2): one
//!   [`UsciI2c::attach`]ed handle per device (the bus is configured once, [`UsciI2c::new`]).
//! - The three magnetorquer coils are driven by the node itself: Timer_B PWM ([`super::pwm`],
//!   19 988 Hz) into an H-bridge per coil, with a direction pin ([`super::gpio`]).
//!
//! Timer_B7 has six PWM outputs, fewer than three coils and five wheels: the wheels take their
//! set-point over I²C from their own controller on the tile, through the drivers'
//! [`PwmReactionWheel`] (a duty of full scale and a direction), here over two registers of the
//! controller ([`WheelSetpoint`], [`WheelDirection`]).
//!
//! # I²C address map (7-bit addresses; tile `i` = 0…5 in the configuration's order)
//! One block of eight addresses per device kind, the tile's index in the low three bits, all
//! outside the reserved 0x00–0x07 and 0x78–0x7F (NXP UM10204, "I²C-bus specification",
//! table "Reserved addresses"):
//!
//! | device (driver) | address | register | words (big-endian `i16`) |
//! |---|---|---|---|
//! | sun sensor ([`I2cSunSensor`]) | `0x20 + i` ([`SUN_SENSOR_BASE`]) | 0x00 | status (0: no spot), angle a, angle b (1e-4 rad) |
//! | magnetometer ([`I2cMagnetometer`]) | `0x28 + i` ([`MAGNETOMETER_BASE`]) | 0x03 | x, y (10 nT) |
//! | gyro ([`I2cGyro`]) | `0x30 + i` ([`GYRO_BASE`]) | 0x10 | rate about tile z (1e-4 rad/s) |
//! | wheel controller ([`PwmReactionWheel`]) | `0x38 + i` ([`WHEEL_BASE`]) | 0x20 write | set-point, 0 … [`WHEEL_FULL_SCALE`] of [`crate::flight::WHEEL_LIMIT_NMS`] (`u16`) |
//! | (same) | (same) | 0x22 write | direction: 1 positive (momentum along +tile z), 0 negative (one byte) |
//!
//! The telecom tile (tile 0 of the flight cube) has no ACS device: its addresses are
//! reserved and never addressed (the loop reads only the devices its configuration gives a
//! tile). A part with another register layout or resolution changes the constructors' register
//! and the driver's `Scale` ([`super::super::drivers::Scale`]), not the map.
//!
//! # Coils
//! | coil (body axis) | PWM | direction pin |
//! |---|---|---|
//! | 0 (x) | TB3, P3.4 | P5.0 |
//! | 1 (y) | TB4, P3.5 | P5.1 |
//! | 2 (z) | TB5, P3.6 | P5.2 |
//!
//! Full duty is [`crate::flight::COIL_LIMIT_AM2`] (0.2 A·m²); a command beyond it, or not
//! finite, is refused and the coil switched off ([`PwmMagnetorquer`]).
//!
//! Tested on the host against the register models of `tests/msp430_drivers.rs`
//! (`the_attitude_tile_bus_follows_its_address_map`): every device of every tile read or
//! commanded through the modelled USCI_B0 and Timer_B at its address.

use embedded_hal::i2c::I2c;
use embedded_hal::pwm::SetDutyCycle;

use super::gpio::{OutputPin, Pin, P5};
use super::pwm::{PwmChannel, PwmConfig, TbOutput, TimerBPwm};
use super::usci_i2c::{I2cConfig, UsciI2c};
use super::Registers;
use crate::flight::{COIL_LIMIT_AM2, TILES, WHEEL_LIMIT_NMS};
use crate::hal::bus::{DeviceBus, TileDevices};
use crate::hal::drivers::{
    I2cGyro, I2cMagnetometer, I2cSunSensor, PwmMagnetorquer, PwmReactionWheel,
};

/// Sun sensor of tile `i`: address `SUN_SENSOR_BASE + i`.
pub const SUN_SENSOR_BASE: u8 = 0x20;
/// Magnetometer of tile `i`: `MAGNETOMETER_BASE + i`.
pub const MAGNETOMETER_BASE: u8 = 0x28;
/// Gyro of tile `i`: `GYRO_BASE + i`.
pub const GYRO_BASE: u8 = 0x30;
/// Wheel controller of tile `i`: `WHEEL_BASE + i`.
pub const WHEEL_BASE: u8 = 0x38;

/// The sun sensor's status and angle words.
pub const SUN_SENSOR_REGISTER: u8 = 0x00;
/// The magnetometer's field words.
pub const MAGNETOMETER_REGISTER: u8 = 0x03;
/// The gyro's rate word.
pub const GYRO_REGISTER: u8 = 0x10;
/// The wheel controller's set-point word.
pub const WHEEL_SETPOINT_REGISTER: u8 = 0x20;
/// The wheel controller's direction byte.
pub const WHEEL_DIRECTION_REGISTER: u8 = 0x22;
/// The set-point of the wheel's full momentum ([`WHEEL_LIMIT_NMS`]).
pub const WHEEL_FULL_SCALE: u16 = 10_000;

/// Number of magnetorquer coils.
pub const COILS: usize = 3;

/// The coils' Timer_B outputs and direction pins, coil 0 (x) to 2 (z).
pub const COIL_OUTPUTS: [(TbOutput, Pin); COILS] = [
    (TbOutput::TB3, Pin::new(P5, 0)),
    (TbOutput::TB4, Pin::new(P5, 1)),
    (TbOutput::TB5, Pin::new(P5, 2)),
];

/// The I²C address of a device of tile `tile` whose kind's block starts at `base`; `None`
/// beyond the eight tiles a block holds.
pub const fn address(base: u8, tile: usize) -> Option<u8> {
    if tile >= 8 {
        None
    } else {
        Some(base + tile as u8)
    }
}

/// A wheel controller's set-point register as a PWM channel: a duty of `d` of
/// [`WHEEL_FULL_SCALE`] is written as the `u16` `d` (big-endian) to
/// [`WHEEL_SETPOINT_REGISTER`]. A failed write is reported (an `embedded_hal` PWM error of kind
/// `Other`), and the wheel driver then reports the command refused.
pub struct WheelSetpoint<I> {
    i2c: I,
    address: u8,
}

impl<I: I2c> WheelSetpoint<I> {
    /// The set-point of the controller at `address`.
    pub fn new(i2c: I, address: u8) -> Self {
        Self { i2c, address }
    }
}

/// A wheel controller's direction register as an output pin: high writes 1 to
/// [`WHEEL_DIRECTION_REGISTER`], low 0.
pub struct WheelDirection<I> {
    i2c: I,
    address: u8,
}

impl<I: I2c> WheelDirection<I> {
    /// The direction of the controller at `address`.
    pub fn new(i2c: I, address: u8) -> Self {
        Self { i2c, address }
    }
}

/// Writes `bytes` (a register and its value) to the wheel controller at `address`. Out of line
/// on the MSP430: one copy for the set-point's and the direction's writes.
#[cfg_attr(target_arch = "msp430", inline(never))]
fn write_wheel<I: I2c>(i2c: &mut I, address: u8, bytes: &[u8]) -> Result<(), WheelWriteError> {
    i2c.write(address, bytes).map_err(|_| WheelWriteError)
}

/// A write to a wheel controller failed (its I²C error's kind is not kept: the wheel driver
/// reports any failure as [`crate::hal::ErrorKind::Other`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct WheelWriteError;

impl embedded_hal::pwm::Error for WheelWriteError {
    fn kind(&self) -> embedded_hal::pwm::ErrorKind {
        embedded_hal::pwm::ErrorKind::Other
    }
}

impl embedded_hal::digital::Error for WheelWriteError {
    fn kind(&self) -> embedded_hal::digital::ErrorKind {
        embedded_hal::digital::ErrorKind::Other
    }
}

impl<I: I2c> embedded_hal::pwm::ErrorType for WheelSetpoint<I> {
    type Error = WheelWriteError;
}

impl<I: I2c> SetDutyCycle for WheelSetpoint<I> {
    fn max_duty_cycle(&self) -> u16 {
        WHEEL_FULL_SCALE
    }

    /// Writes `duty` (at most [`WHEEL_FULL_SCALE`]) to the set-point register.
    fn set_duty_cycle(&mut self, duty: u16) -> Result<(), WheelWriteError> {
        let [hi, lo] = core::cmp::min(duty, WHEEL_FULL_SCALE).to_be_bytes();
        write_wheel(
            &mut self.i2c,
            self.address,
            &[WHEEL_SETPOINT_REGISTER, hi, lo],
        )
    }
}

impl<I: I2c> embedded_hal::digital::ErrorType for WheelDirection<I> {
    type Error = WheelWriteError;
}

impl<I: I2c> embedded_hal::digital::OutputPin for WheelDirection<I> {
    fn set_low(&mut self) -> Result<(), WheelWriteError> {
        write_wheel(&mut self.i2c, self.address, &[WHEEL_DIRECTION_REGISTER, 0])
    }

    fn set_high(&mut self) -> Result<(), WheelWriteError> {
        write_wheel(&mut self.i2c, self.address, &[WHEEL_DIRECTION_REGISTER, 1])
    }
}

/// A tile device's I²C handle.
pub type Bus<R> = UsciI2c<R>;
/// A wheel: its controller's set-point and direction over I²C.
pub type Wheel<R> = PwmReactionWheel<WheelSetpoint<Bus<R>>, WheelDirection<Bus<R>>>;
/// A coil: a Timer_B channel and a direction pin.
pub type Coil<R> = PwmMagnetorquer<PwmChannel<R>, OutputPin<R>>;

/// One tile's devices.
pub type Tile<R> =
    TileDevices<I2cSunSensor<Bus<R>>, I2cMagnetometer<Bus<R>>, I2cGyro<Bus<R>>, Wheel<R>>;

/// The attitude node's tile bus (see the [module docs](self)), waiting on the timer `D`.
pub type AttitudeBus<R, D> = DeviceBus<
    I2cSunSensor<Bus<R>>,
    I2cMagnetometer<Bus<R>>,
    I2cGyro<Bus<R>>,
    Wheel<R>,
    Coil<R>,
    D,
    TILES,
    COILS,
>;

/// The devices of tile `tile` at their addresses of the map (tile < 8).
fn tile_devices<R: Registers + Clone>(regs: &R, config: &'static I2cConfig, tile: u8) -> Tile<R> {
    let bus = || UsciI2c::attach(regs.clone(), config);
    let t = tile & 7;
    TileDevices::new(
        I2cSunSensor::new(bus(), SUN_SENSOR_BASE + t, SUN_SENSOR_REGISTER),
        I2cMagnetometer::new(bus(), MAGNETOMETER_BASE + t, MAGNETOMETER_REGISTER),
        I2cGyro::new(bus(), GYRO_BASE + t, GYRO_REGISTER),
        PwmReactionWheel::new(
            WheelSetpoint::new(bus(), WHEEL_BASE + t),
            WheelDirection::new(bus(), WHEEL_BASE + t),
            WHEEL_LIMIT_NMS,
        ),
    )
}

/// Sets up USCI_B0 as the tile bus's I²C master (`i2c`), starts Timer_B's PWM period (`pwm`),
/// the coils' channels and direction pins (all off, low), and returns the tile bus over them:
/// every tile's devices at the map's addresses, and `delay`, the image's timer for the wait
/// before the reads ([`crate::hal::TileBus::delay_us`]). Touches no device: the first bus traffic
/// is the loop's first read.
pub fn attitude_bus<R: Registers + Clone, D>(
    regs: R,
    i2c: &'static I2cConfig,
    pwm: PwmConfig,
    delay: D,
) -> AttitudeBus<R, D> {
    drop(UsciI2c::new(regs.clone(), i2c));
    let timer = TimerBPwm::start(regs.clone(), pwm);
    let coils = COIL_OUTPUTS.map(|(out, pin)| {
        Some(PwmMagnetorquer::new(
            timer.channel(out),
            OutputPin::new(regs.clone(), pin),
            COIL_LIMIT_AM2,
        ))
    });
    let tiles = [0u8, 1, 2, 3, 4, 5].map(|t| tile_devices(&regs, i2c, t));
    DeviceBus::new(tiles, coils, delay)
}

/// The flight coils' safe state without the bus (a fault handler's): the coils' Timer_B
/// channels (TB3–TB5, [`COIL_OUTPUTS`]) to output mode 0, low (no pulse), whatever state the
/// bus is in. Three constant register writes.
pub fn coils_off<R: Registers>(regs: &mut R) {
    regs.write16(TbOutput::TB3.control_register(), 0);
    regs.write16(TbOutput::TB4.control_register(), 0);
    regs.write16(TbOutput::TB5.control_register(), 0);
}
