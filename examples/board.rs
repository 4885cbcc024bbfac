//! A board integration: the flight loop over `embedded-hal` drivers through the driver adapter
//! (`acs::hal::bus::DeviceBus`), runnable on the host.
//!
//! `cargo run --example board`
//!
//! What a board's firmware does: build one driver per device from the board's peripherals
//! (`acs::hal::drivers`, or the board's own types implementing the device traits), hand them to
//! a `DeviceBus` in the configuration's tile and coil order, and call `AcsLoop::step` once per
//! control period. Here the peripherals are host stand-ins (an I²C register file that serves the
//! words a satellite at a fixed attitude would measure, `common::raw_words`, and PWM channels and
//! direction pins that keep what they were set to): replace `peripherals()` with the board's
//! HAL. The stand-in does not move (no dynamics): the loop's commands are printed, not flown;
//! `acs sim` flies them on the simulator.
//!
//! Tile 5's magnetometer is a part counting 0.1 µT, not the bus's 10 nT: its driver is given
//! the part's resolution (`Scale::magnetometer_lsb_nt(100.0)`), and the loop is unchanged.
//!
//! Conventions (`acs::attitude`): attitudes map TEME of date to the body, quaternions are
//! scalar-first.

mod common;

use std::cell::{Cell, RefCell};
use std::collections::HashMap;
use std::convert::Infallible;
use std::rc::Rc;

use acs::acs_loop::Command;
use acs::attitude::Quaternion;
use acs::flight::{FlightLoop, CONFIG, TILES};
use acs::hal::bus::{DeviceBus, TileDevices};
use acs::hal::drivers::{
    I2cGyro, I2cMagnetometer, I2cSunSensor, PwmMagnetorquer, PwmReactionWheel, Scale,
};
use acs::linalg::Vec3;
use acs::time::TimeSpan;
use embedded_hal::delay::DelayNs;
use embedded_hal::digital::{self, OutputPin};
use embedded_hal::i2c::{self, I2c, NoAcknowledgeSource, Operation};
use embedded_hal::pwm::{self, SetDutyCycle};

/// The flight configuration's coils.
const COILS: usize = 3;
/// Full scale of the stand-in PWM channels.
const MAX_DUTY: u16 = 1000;
/// The tile sensor board's registers (the drivers' defaults: big-endian `i16` words).
const SUN_REGISTER: u8 = 0x00;
const MAG_REGISTER: u8 = 0x03;
const GYRO_REGISTER: u8 = 0x10;

/// I²C addresses of tile `i`'s sun sensor, magnetometer and gyro.
fn addresses(i: usize) -> (u8, u8, u8) {
    let i = i as u8;
    (0x20 + i, 0x30 + i, 0x40 + i)
}

// ---- host stand-ins for the board's peripherals -------------------------------------------

/// An I²C bus whose devices are a register file: `(address, register)` → the bytes it answers.
/// A clone is another handle on the same bus (on a board: `embedded-hal-bus`'s shared-bus
/// devices give each driver its handle).
#[derive(Clone, Default)]
struct StandInI2c(Rc<RefCell<Registers>>);

/// `(address, register)` → the bytes the device answers.
type Registers = HashMap<(u8, u8), Vec<u8>>;

impl StandInI2c {
    fn set_words(&self, address: u8, register: u8, words: &[i16]) {
        let bytes = words.iter().flat_map(|w| w.to_be_bytes()).collect();
        self.0.borrow_mut().insert((address, register), bytes);
    }
}

impl i2c::ErrorType for StandInI2c {
    type Error = i2c::ErrorKind;
}

impl I2c for StandInI2c {
    fn transaction(
        &mut self,
        address: u8,
        operations: &mut [Operation<'_>],
    ) -> Result<(), Self::Error> {
        let mut register = None;
        for op in operations {
            match op {
                Operation::Write(bytes) => register = bytes.first().copied(),
                Operation::Read(buffer) => {
                    let registers = self.0.borrow();
                    let data = register
                        .and_then(|r| registers.get(&(address, r)))
                        .ok_or(i2c::ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address))?;
                    let data = data.get(..buffer.len()).ok_or(i2c::ErrorKind::Overrun)?;
                    buffer.copy_from_slice(data);
                }
            }
        }
        Ok(())
    }
}

/// A PWM channel that keeps its duty cycle.
#[derive(Clone, Default)]
struct StandInPwm(Rc<Cell<u16>>);

impl pwm::ErrorType for StandInPwm {
    type Error = pwm::ErrorKind;
}

impl SetDutyCycle for StandInPwm {
    fn max_duty_cycle(&self) -> u16 {
        MAX_DUTY
    }
    fn set_duty_cycle(&mut self, duty: u16) -> Result<(), Self::Error> {
        self.0.set(duty);
        Ok(())
    }
}

/// A direction pin that keeps its level.
#[derive(Clone, Default)]
struct StandInPin(Rc<Cell<bool>>);

impl digital::ErrorType for StandInPin {
    type Error = Infallible;
}

impl OutputPin for StandInPin {
    fn set_low(&mut self) -> Result<(), Infallible> {
        self.0.set(false);
        Ok(())
    }
    fn set_high(&mut self) -> Result<(), Infallible> {
        self.0.set(true);
        Ok(())
    }
}

/// A timer: a board's HAL would wait on a hardware timer; this one adds up the waits, ns (the
/// attitude node waits 5 ms each step between switching the coils off and reading).
#[derive(Default)]
struct StandInTimer(u64);

impl DelayNs for StandInTimer {
    fn delay_ns(&mut self, ns: u32) {
        self.0 += u64::from(ns);
    }
}

/// The board's peripherals: the tiles' I²C bus, a PWM channel and a direction pin per wheel
/// (one per tile) and per coil.
struct Peripherals {
    i2c: StandInI2c,
    wheels: [(StandInPwm, StandInPin); TILES],
    coils: [(StandInPwm, StandInPin); COILS],
}

fn peripherals() -> Peripherals {
    Peripherals {
        i2c: StandInI2c::default(),
        wheels: Default::default(),
        coils: Default::default(),
    }
}

/// A bridge's output as a signed fraction of full scale.
fn output((pwm, dir): &(StandInPwm, StandInPin)) -> f32 {
    let fraction = f32::from(pwm.0.get()) / f32::from(MAX_DUTY);
    if dir.0.get() {
        fraction
    } else {
        -fraction
    }
}

// ---- the board's firmware -----------------------------------------------------------------

type Bus = DeviceBus<
    I2cSunSensor<StandInI2c>,
    I2cMagnetometer<StandInI2c>,
    I2cGyro<StandInI2c>,
    PwmReactionWheel<StandInPwm, StandInPin>,
    PwmMagnetorquer<StandInPwm, StandInPin>,
    StandInTimer,
    TILES,
    COILS,
>;

/// The satellite's tile bus from the board's drivers, in the flight configuration's order.
fn tile_bus(p: &Peripherals) -> Bus {
    let tiles = std::array::from_fn(|i| {
        let tile = &CONFIG.tiles[i];
        let (sun, mag, gyro) = addresses(i);
        let mut devices = TileDevices::none();
        if tile.equipment.sun_sensor {
            devices = devices.with_sun_sensor(I2cSunSensor::new(p.i2c.clone(), sun, SUN_REGISTER));
        }
        if tile.equipment.magnetometer {
            let mut driver = I2cMagnetometer::new(p.i2c.clone(), mag, MAG_REGISTER);
            if i == 5 {
                // a part counting 0.1 µT
                driver = driver.with_scale(Scale::magnetometer_lsb_nt(100.0).expect("positive"));
            }
            devices = devices.with_magnetometer(driver);
        }
        if tile.equipment.gyro {
            devices = devices.with_gyro(I2cGyro::new(p.i2c.clone(), gyro, GYRO_REGISTER));
        }
        if tile.equipment.reaction_wheel {
            let (pwm, dir) = p.wheels[i].clone();
            devices = devices.with_wheel(PwmReactionWheel::new(pwm, dir, CONFIG.wheel_limit_nms));
        }
        devices
    });
    let coils = std::array::from_fn(|c| {
        let (pwm, dir) = p.coils[c].clone();
        Some(PwmMagnetorquer::new(pwm, dir, CONFIG.coils[c].limit))
    });
    DeviceBus::new(tiles, coils, StandInTimer::default())
}

fn main() {
    let p = peripherals();
    let mut bus = tile_bus(&p);
    let (tle, orbit) = common::orbit();
    let mut acs = FlightLoop::new(&CONFIG, orbit.clone()).expect("valid configuration");

    // the stand-in satellite: a fixed attitude, at rest
    let truth = Quaternion::new_normalize(0.8, 0.3, -0.4, 0.33).expect("non-zero");
    let t0 = tle.epoch.add(TimeSpan::new(600, 0));
    // after a few steps, a ground command: track an attitude 10° away (a turn about z)
    let turn = Quaternion::from_axis_angle(&Vec3::z(), 10f32.to_radians()).expect("unit axis");
    let target = truth.mul(&turn);

    println!(
        "{:>3} {:>9} {:>9} {:>9} {:>6}  {:<40} coils",
        "t s", "mode", "meas. °", "filt. °", "faults", "wheels (tiles 1–5, of full scale)"
    );
    for k in 0..15 {
        let now = t0.add(TimeSpan::new(k, 0));
        // the stand-in tiles' registers for this instant
        let sky = common::sky(&orbit, &now);
        let raw = common::raw_words(&CONFIG.tiles, &truth, &Vec3::zeros(), &sky);
        for i in 0..TILES {
            let (sun, mag, gyro) = addresses(i);
            let [a, b] = raw.sun[i].unwrap_or([0, 0]);
            p.i2c
                .set_words(sun, SUN_REGISTER, &[i16::from(raw.sun[i].is_some()), a, b]);
            let [x, y] = raw.mag[i];
            // tile 5's part counts 100 nT: its words are a tenth of the bus's
            let part = if i == 5 {
                [x, y].map(|w| (f32::from(w) / 10.0).round() as i16)
            } else {
                [x, y]
            };
            p.i2c.set_words(mag, MAG_REGISTER, &part);
            p.i2c.set_words(gyro, GYRO_REGISTER, &[raw.gyro[i]]);
        }
        if k == 5 {
            acs.command(Command::Track { target }, None, now)
                .expect("tracking accepted");
        }

        let report = acs.step(&mut bus, now, 1.0);

        let error = |q: Option<Quaternion>| {
            q.map_or("-".to_string(), |q| {
                format!("{:.3}", common::angle_deg(&q, &truth))
            })
        };
        let wheels: Vec<String> = (1..TILES)
            .map(|i| format!("{:+.3}", output(&p.wheels[i])))
            .collect();
        let coils: Vec<String> = p
            .coils
            .iter()
            .map(|c| format!("{:+.2}", output(c)))
            .collect();
        println!(
            "{k:>3} {:>9} {:>9} {:>9} {:>#6x}  {:<40} {}",
            format!("{:?}", report.mode),
            error(report.measured_attitude),
            error(report.attitude),
            report.faults.bits(),
            wheels.join(" "),
            coils.join(" ")
        );
    }
    println!("(meas./filt.: the measured and filtered attitudes' angle to the stand-in's)");
}
