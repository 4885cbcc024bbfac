//! Reference tile drivers on `embedded-hal` 1.0: an I²C magnetometer (with an optional
//! set/reset pulse), an I²C gyro and sun sensor, and PWM + direction-pin drivers for a
//! magnetorquer coil and a reaction wheel's speed controller.
//!
//! The register maps are those of a generic tile sensor board (the thesis does not fix the
//! parts): each sensor answers a one-byte register address with big-endian `i16` words. A real
//! part needs only its own address and registers in the constructors, and its resolution in
//! the driver's [`Scale`] (`with_scale`) when it is not the bus's raw unit
//! ([`crate::hal`], "Raw formats"): the driver converts its part's words into the bus's units,
//! so a team with another magnetometer configures its driver and leaves the flight library
//! (and its raw-unit constants in [`crate::tiles`]) alone.
//!
//! Actuator drivers refuse commands beyond their limit or not finite with
//! [`ErrorKind::OutOfRange`] and switch the device off (the safe state) when they do: a driver
//! never leaves an actuator on a value it did not accept.

use embedded_hal::delay::DelayNs;
use embedded_hal::digital::OutputPin;
use embedded_hal::i2c::{self, I2c};
use embedded_hal::pwm::SetDutyCycle;

use super::{ErrorKind, ErrorType, Gyro, Magnetometer, Magnetorquer, ReactionWheel, SunSensor};
use crate::tiles::{GYRO_LSB_RADPS, MAGNETOMETER_LSB_NT, SUN_LSB_RAD};

/// Maps an I²C error to a device error kind (NACK of the address: the device is absent).
fn i2c_kind<E: i2c::Error>(e: &E) -> ErrorKind {
    match e.kind() {
        i2c::ErrorKind::NoAcknowledge(i2c::NoAcknowledgeSource::Address) => ErrorKind::DeviceAbsent,
        _ => ErrorKind::Bus,
    }
}

/// Reads `words.len()` (at most 4) big-endian `i16` words starting at `register` into `words`
/// and converts them by `scale` in place, after refusing a saturated one
/// ([`check_saturation`]); with `status`, the first word is a status word, not converted: 0
/// (nothing to read) returns `Ok(false)` without checking the others. Out of line on the
/// MSP430: one copy for the sun sensor's, magnetometer's and gyro's reads.
#[cfg_attr(target_arch = "msp430", inline(never))]
fn read_converted<I: I2c>(
    i2c: &mut I,
    address: u8,
    register: u8,
    scale: &Scale,
    words: &mut [i16],
    status: bool,
) -> Result<bool, ErrorKind> {
    read_words_into(i2c, address, register, words)?;
    let data = if status {
        match words.split_first_mut() {
            Some((&mut 0, _)) => return Ok(false),
            Some((_, rest)) => rest,
            None => return Err(ErrorKind::Other),
        }
    } else {
        words
    };
    check_saturation(data)?;
    for w in data.iter_mut() {
        *w = scale.convert(*w)?;
    }
    Ok(true)
}

/// Reads `words.len()` (at most 4) big-endian `i16` words starting at `register` into `words`.
/// Out of line on the MSP430: one copy for the sun sensor's, magnetometer's and gyro's reads
/// instead of one inlined per word count.
#[cfg_attr(target_arch = "msp430", inline(never))]
fn read_words_into<I: I2c>(
    i2c: &mut I,
    address: u8,
    register: u8,
    words: &mut [i16],
) -> Result<(), ErrorKind> {
    let mut bytes = [0u8; 8];
    let buf = bytes.get_mut(..2 * words.len()).ok_or(ErrorKind::Other)?;
    i2c.write_read(address, &[register], buf)
        .map_err(|e| i2c_kind(&e))?;
    for (w, pair) in words.iter_mut().zip(buf.chunks_exact(2)) {
        if let [hi, lo] = pair {
            *w = i16::from_be_bytes([*hi, *lo]);
        }
    }
    Ok(())
}

/// A raw word at either end of the `i16` range means the sensor saturated. Out of line on the
/// MSP430, as [`read_words_into`]: one copy for the three sensors' reads.
#[cfg_attr(target_arch = "msp430", inline(never))]
fn check_saturation(words: &[i16]) -> Result<(), ErrorKind> {
    if words.iter().any(|w| *w == i16::MIN || *w == i16::MAX) {
        Err(ErrorKind::OutOfRange)
    } else {
        Ok(())
    }
}

/// A sensor part's resolution against the bus's raw unit: the factor from a part's word to the
/// bus's word (`bus = round(part · part_lsb / bus_lsb)`), part of a driver's configuration.
///
/// A converted word that reaches either end of the `i16` range is refused as
/// [`ErrorKind::OutOfRange`] (the loop reads such a word as a saturated device); the part's own
/// saturated words are refused before conversion.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Scale {
    bus_per_part: f32,
}

impl Scale {
    /// The part's words are already in the bus's unit (the default of every driver).
    pub const IDENTITY: Self = Self { bus_per_part: 1.0 };

    /// A part whose word is `part_lsb` when the bus's is `bus_lsb` (both in the same unit);
    /// `None` unless both are finite and positive and their ratio is.
    pub fn from_lsb(part_lsb: f32, bus_lsb: f32) -> Option<Self> {
        let factor = part_lsb / bus_lsb;
        (factor.is_finite() && factor > 0.0 && part_lsb.is_finite()).then_some(Self {
            bus_per_part: factor,
        })
    }

    /// A magnetometer whose word is `lsb_nt` nT (the bus's unit: [`MAGNETOMETER_LSB_NT`]).
    pub fn magnetometer_lsb_nt(lsb_nt: f32) -> Option<Self> {
        Self::from_lsb(lsb_nt, MAGNETOMETER_LSB_NT)
    }

    /// A gyro whose word is `lsb_radps` rad/s (the bus's unit: [`GYRO_LSB_RADPS`]).
    pub fn gyro_lsb_radps(lsb_radps: f32) -> Option<Self> {
        Self::from_lsb(lsb_radps, GYRO_LSB_RADPS)
    }

    /// A sun sensor whose angle word is `lsb_rad` rad (the bus's unit: [`SUN_LSB_RAD`]).
    pub fn sun_lsb_rad(lsb_rad: f32) -> Option<Self> {
        Self::from_lsb(lsb_rad, SUN_LSB_RAD)
    }

    /// The bus's word for the part's word `word`, rounded to nearest;
    /// [`ErrorKind::OutOfRange`] if it reaches either end of the `i16` range.
    pub fn convert(&self, word: i16) -> Result<i16, ErrorKind> {
        if self.bus_per_part == 1.0 {
            return Ok(word);
        }
        let x = libm::roundf(f32::from(word) * self.bus_per_part);
        // NaN-explicit: a value outside (i16::MIN, i16::MAX) is refused
        if !(x > f32::from(i16::MIN) && f32::from(i16::MAX) > x) {
            return Err(ErrorKind::OutOfRange);
        }
        Ok(x as i16)
    }
}

impl Default for Scale {
    fn default() -> Self {
        Self::IDENTITY
    }
}

/// A two-axis magnetometer on I²C: register `data_register` holds x then y, in 10 nT unless
/// its [`Scale`] says otherwise.
pub struct I2cMagnetometer<I> {
    i2c: I,
    address: u8,
    data_register: u8,
    scale: Scale,
}

impl<I: I2c> I2cMagnetometer<I> {
    /// A magnetometer at `address` whose field words (in the bus's 10 nT) start at
    /// `data_register`.
    pub fn new(i2c: I, address: u8, data_register: u8) -> Self {
        Self {
            i2c,
            address,
            data_register,
            scale: Scale::IDENTITY,
        }
    }

    /// The same magnetometer with its part's resolution, e.g.
    /// `Scale::magnetometer_lsb_nt(100.0)` for a part counting 0.1 µT.
    pub fn with_scale(self, scale: Scale) -> Self {
        Self { scale, ..self }
    }

    /// Gives the bus back.
    pub fn release(self) -> I {
        self.i2c
    }
}

impl<I: I2c> ErrorType for I2cMagnetometer<I> {
    type Error = ErrorKind;
}

impl<I: I2c> Magnetometer for I2cMagnetometer<I> {
    fn read_field_raw(&mut self) -> Result<[i16; 2], ErrorKind> {
        let mut words = [0i16; 2];
        read_converted(
            &mut self.i2c,
            self.address,
            self.data_register,
            &self.scale,
            &mut words,
            false,
        )?;
        Ok(words)
    }
}

/// A magnetoresistive magnetometer that needs a set/reset pulse before each reading (note 002
/// §8.6: a pulse of about 1 µs re-aligns the permalloy domains); wraps any [`Magnetometer`].
pub struct SetResetMagnetometer<M, P, D> {
    inner: M,
    set_pin: P,
    delay: D,
    pulse_us: u32,
    settle_us: u32,
}

impl<M: Magnetometer, P: OutputPin, D: DelayNs> SetResetMagnetometer<M, P, D> {
    /// Pulses `set_pin` high for `pulse_us`, waits `settle_us`, then reads.
    pub fn new(inner: M, set_pin: P, delay: D, pulse_us: u32, settle_us: u32) -> Self {
        Self {
            inner,
            set_pin,
            delay,
            pulse_us,
            settle_us,
        }
    }
}

impl<M: Magnetometer, P: OutputPin, D: DelayNs> ErrorType for SetResetMagnetometer<M, P, D> {
    type Error = ErrorKind;
}

impl<M: Magnetometer, P: OutputPin, D: DelayNs> Magnetometer for SetResetMagnetometer<M, P, D> {
    fn read_field_raw(&mut self) -> Result<[i16; 2], ErrorKind> {
        self.set_pin.set_high().map_err(|_| ErrorKind::Other)?;
        self.delay.delay_us(self.pulse_us);
        self.set_pin.set_low().map_err(|_| ErrorKind::Other)?;
        self.delay.delay_us(self.settle_us);
        self.inner
            .read_field_raw()
            .map_err(|e| super::Error::kind(&e))
    }
}

/// A one-axis gyro on I²C: one word at `data_register`, 1e-4 rad/s unless its [`Scale`] says
/// otherwise.
pub struct I2cGyro<I> {
    i2c: I,
    address: u8,
    data_register: u8,
    scale: Scale,
}

impl<I: I2c> I2cGyro<I> {
    /// A gyro at `address` whose rate word (in the bus's 1e-4 rad/s) is at `data_register`.
    pub fn new(i2c: I, address: u8, data_register: u8) -> Self {
        Self {
            i2c,
            address,
            data_register,
            scale: Scale::IDENTITY,
        }
    }

    /// The same gyro with its part's resolution ([`Scale::gyro_lsb_radps`]).
    pub fn with_scale(self, scale: Scale) -> Self {
        Self { scale, ..self }
    }

    /// Gives the bus back.
    pub fn release(self) -> I {
        self.i2c
    }
}

impl<I: I2c> ErrorType for I2cGyro<I> {
    type Error = ErrorKind;
}

impl<I: I2c> Gyro for I2cGyro<I> {
    fn read_rate_raw(&mut self) -> Result<i16, ErrorKind> {
        let mut words = [0i16; 1];
        read_converted(
            &mut self.i2c,
            self.address,
            self.data_register,
            &self.scale,
            &mut words,
            false,
        )?;
        let [w] = words;
        Ok(w)
    }
}

/// A sun sensor on I²C: at `data_register` a status word (non-zero when a spot is detected)
/// then the angles `a`, `b` in 1e-4 rad unless its [`Scale`] says otherwise.
pub struct I2cSunSensor<I> {
    i2c: I,
    address: u8,
    data_register: u8,
    scale: Scale,
}

impl<I: I2c> I2cSunSensor<I> {
    /// A sun sensor at `address` whose status and angle words (in the bus's 1e-4 rad) start at
    /// `data_register`.
    pub fn new(i2c: I, address: u8, data_register: u8) -> Self {
        Self {
            i2c,
            address,
            data_register,
            scale: Scale::IDENTITY,
        }
    }

    /// The same sun sensor with its part's resolution ([`Scale::sun_lsb_rad`]).
    pub fn with_scale(self, scale: Scale) -> Self {
        Self { scale, ..self }
    }

    /// Gives the bus back.
    pub fn release(self) -> I {
        self.i2c
    }
}

impl<I: I2c> ErrorType for I2cSunSensor<I> {
    type Error = ErrorKind;
}

impl<I: I2c> SunSensor for I2cSunSensor<I> {
    fn read_sun_raw(&mut self) -> Result<Option<[i16; 2]>, ErrorKind> {
        let mut words = [0i16; 3];
        if !read_converted(
            &mut self.i2c,
            self.address,
            self.data_register,
            &self.scale,
            &mut words,
            true,
        )? {
            return Ok(None);
        }
        let [_, a, b] = words;
        Ok(Some([a, b]))
    }
}

/// Sets a PWM + direction-pin bridge to `value / limit` of full scale, positive = pin high.
/// Refuses (and switches off) a value beyond `limit` or not finite.
fn drive_bridge<P: SetDutyCycle, D: OutputPin>(
    pwm: &mut P,
    dir: &mut D,
    value: f32,
    limit: f32,
) -> Result<(), ErrorKind> {
    let Some(num) = bridge_fraction(value, limit) else {
        pwm.set_duty_cycle_fully_off()
            .map_err(|_| ErrorKind::Other)?;
        return Err(ErrorKind::OutOfRange);
    };
    if value >= 0.0 {
        dir.set_high().map_err(|_| ErrorKind::Other)?;
    } else {
        dir.set_low().map_err(|_| ErrorKind::Other)?;
    }
    pwm.set_duty_cycle_fraction(num, BRIDGE_SCALE)
        .map_err(|_| ErrorKind::Other)
}

/// The denominator of [`bridge_fraction`].
const BRIDGE_SCALE: u16 = 10_000;

/// [`drive_bridge`]'s rounded fraction of full scale of `value`, in `BRIDGE_SCALE`ths
/// (0..=`BRIDGE_SCALE`), `None` for a value beyond `limit` or not finite. Out of line on the
/// MSP430: one copy for the wheels' and the coils' bridges.
#[cfg_attr(target_arch = "msp430", inline(never))]
fn bridge_fraction(value: f32, limit: f32) -> Option<u16> {
    let magnitude = if value >= 0.0 { value } else { -value };
    if !value.is_finite() || magnitude > limit {
        return None;
    }
    // rounded fraction of full scale, 0..=SCALE (magnitude ≤ limit)
    let num = (magnitude / limit * f32::from(BRIDGE_SCALE) + 0.5) as u16;
    Some(core::cmp::min(num, BRIDGE_SCALE))
}

/// A magnetorquer coil driven by PWM through an H-bridge with a direction pin: the dipole is
/// proportional to the duty cycle (air core, `m = N I A`), full scale `max_dipole_am2`.
pub struct PwmMagnetorquer<P, D> {
    pwm: P,
    dir: D,
    max_dipole_am2: f32,
}

impl<P: SetDutyCycle, D: OutputPin> PwmMagnetorquer<P, D> {
    /// A coil whose full PWM duty gives `max_dipole_am2`.
    pub fn new(pwm: P, dir: D, max_dipole_am2: f32) -> Self {
        Self {
            pwm,
            dir,
            max_dipole_am2,
        }
    }

    /// Gives the PWM channel and the direction pin back.
    pub fn release(self) -> (P, D) {
        (self.pwm, self.dir)
    }
}

impl<P: SetDutyCycle, D: OutputPin> ErrorType for PwmMagnetorquer<P, D> {
    type Error = ErrorKind;
}

impl<P: SetDutyCycle, D: OutputPin> Magnetorquer for PwmMagnetorquer<P, D> {
    fn set_dipole(&mut self, m_am2: f32) -> Result<(), ErrorKind> {
        drive_bridge(&mut self.pwm, &mut self.dir, m_am2, self.max_dipole_am2)
    }
}

/// A reaction wheel whose speed controller takes a PWM set-point and a direction pin: the
/// set-point is proportional to the commanded momentum, full scale `max_momentum_nms`.
pub struct PwmReactionWheel<P, D> {
    pwm: P,
    dir: D,
    max_momentum_nms: f32,
}

impl<P: SetDutyCycle, D: OutputPin> PwmReactionWheel<P, D> {
    /// A wheel whose full PWM set-point is `max_momentum_nms`.
    pub fn new(pwm: P, dir: D, max_momentum_nms: f32) -> Self {
        Self {
            pwm,
            dir,
            max_momentum_nms,
        }
    }

    /// Gives the PWM channel and the direction pin back.
    pub fn release(self) -> (P, D) {
        (self.pwm, self.dir)
    }
}

impl<P: SetDutyCycle, D: OutputPin> ErrorType for PwmReactionWheel<P, D> {
    type Error = ErrorKind;
}

impl<P: SetDutyCycle, D: OutputPin> ReactionWheel for PwmReactionWheel<P, D> {
    fn set_momentum(&mut self, h_nms: f32) -> Result<(), ErrorKind> {
        drive_bridge(&mut self.pwm, &mut self.dir, h_nms, self.max_momentum_nms)
    }
}
