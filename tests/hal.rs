//! Reference drivers against embedded-hal-mock: register reads, saturation, absent devices,
//! set/reset pulse, PWM + direction actuators and their refusal of bad commands, parts with
//! another resolution (a driver's `Scale`), readings in physical units.

use acs::hal::drivers::{
    I2cGyro, I2cMagnetometer, I2cSunSensor, PwmMagnetorquer, PwmReactionWheel, Scale,
    SetResetMagnetometer,
};
use acs::hal::{ErrorKind, Gyro, Magnetometer, Magnetorquer, ReactionWheel, SunSensor};
use embedded_hal::i2c::{ErrorKind as I2cErrorKind, NoAcknowledgeSource};
use embedded_hal_mock::eh1::delay::{CheckedDelay, Transaction as DelayTx};
use embedded_hal_mock::eh1::digital::{Mock as PinMock, State, Transaction as PinTx};
use embedded_hal_mock::eh1::i2c::{Mock as I2cMock, Transaction as I2cTx};
use embedded_hal_mock::eh1::pwm::{Mock as PwmMock, Transaction as PwmTx};

#[test]
fn magnetometer_reads_big_endian_words() {
    // x = 1603 (16 030 nT), y = −467 (−4 670 nT)
    let x = 1603i16.to_be_bytes();
    let y = (-467i16).to_be_bytes();
    let i2c = I2cMock::new(&[I2cTx::write_read(
        0x1e,
        vec![0x03],
        vec![x[0], x[1], y[0], y[1]],
    )]);
    let mut mag = I2cMagnetometer::new(i2c, 0x1e, 0x03);
    assert_eq!(mag.read_field_raw(), Ok([1603, -467]));
    mag.release().done();
}

#[test]
fn magnetometer_saturation_and_absent_device() {
    let max = i16::MAX.to_be_bytes();
    let i2c = I2cMock::new(&[
        I2cTx::write_read(0x1e, vec![0x03], vec![max[0], max[1], 0, 5]),
        I2cTx::write_read(0x1e, vec![0x03], vec![0, 0, 0, 0])
            .with_error(I2cErrorKind::NoAcknowledge(NoAcknowledgeSource::Address)),
        I2cTx::write_read(0x1e, vec![0x03], vec![0, 0, 0, 0]).with_error(I2cErrorKind::Bus),
    ]);
    let mut mag = I2cMagnetometer::new(i2c, 0x1e, 0x03);
    assert_eq!(mag.read_field_raw(), Err(ErrorKind::OutOfRange));
    assert_eq!(mag.read_field_raw(), Err(ErrorKind::DeviceAbsent));
    assert_eq!(mag.read_field_raw(), Err(ErrorKind::Bus));
    mag.release().done();
}

#[test]
fn set_reset_pulse_precedes_the_reading() {
    let i2c = I2cMock::new(&[I2cTx::write_read(0x1e, vec![0x03], vec![0, 10, 0, 20])]);
    let pin = PinMock::new(&[PinTx::set(State::High), PinTx::set(State::Low)]);
    let delay = CheckedDelay::new(&[DelayTx::delay_us(1), DelayTx::delay_us(50)]);
    let mut mag = SetResetMagnetometer::new(
        I2cMagnetometer::new(i2c.clone(), 0x1e, 0x03),
        pin.clone(),
        delay.clone(),
        1,
        50,
    );
    assert_eq!(mag.read_field_raw(), Ok([10, 20]));
    i2c.clone().done();
    pin.clone().done();
    delay.clone().done();
}

#[test]
fn gyro_and_sun_sensor() {
    let w = (-10000i16).to_be_bytes();
    let i2c = I2cMock::new(&[I2cTx::write_read(0x68, vec![0x10], vec![w[0], w[1]])]);
    let mut gyro = I2cGyro::new(i2c.clone(), 0x68, 0x10);
    assert_eq!(gyro.read_rate_raw(), Ok(-10000));
    i2c.clone().done();

    let a = 6903i16.to_be_bytes();
    let b = 4074i16.to_be_bytes();
    let i2c = I2cMock::new(&[
        I2cTx::write_read(0x40, vec![0x00], vec![0, 1, a[0], a[1], b[0], b[1]]),
        I2cTx::write_read(0x40, vec![0x00], vec![0, 0, 0, 0, 0, 0]),
    ]);
    let mut sun = I2cSunSensor::new(i2c.clone(), 0x40, 0x00);
    assert_eq!(sun.read_sun_raw(), Ok(Some([6903, 4074])));
    assert_eq!(sun.read_sun_raw(), Ok(None)); // no spot: not lit
    i2c.clone().done();
}

#[test]
fn magnetorquer_pwm_and_direction() {
    // max duty 1000: 0.05 of 0.2 A·m² = 25 % = 250, positive = direction high
    let pwm = PwmMock::new(&[
        PwmTx::max_duty_cycle(1000),
        PwmTx::set_duty_cycle(250),
        PwmTx::max_duty_cycle(1000),
        PwmTx::set_duty_cycle(1000),
        PwmTx::set_duty_cycle(0), // refused command: off
        PwmTx::set_duty_cycle(0), // NaN: off
        PwmTx::max_duty_cycle(1000),
        PwmTx::set_duty_cycle(0), // off()
    ]);
    let dir = PinMock::new(&[
        PinTx::set(State::High),
        PinTx::set(State::Low),
        PinTx::set(State::High),
    ]);
    let mut coil = PwmMagnetorquer::new(pwm.clone(), dir.clone(), 0.2);
    assert_eq!(coil.set_dipole(0.05), Ok(()));
    assert_eq!(coil.set_dipole(-0.2), Ok(()));
    assert_eq!(coil.set_dipole(0.3), Err(ErrorKind::OutOfRange));
    assert_eq!(coil.set_dipole(f32::NAN), Err(ErrorKind::OutOfRange));
    assert_eq!(coil.off(), Ok(()));
    pwm.clone().done();
    dir.clone().done();
}

#[test]
fn wheel_pwm_and_direction() {
    let pwm = PwmMock::new(&[
        PwmTx::max_duty_cycle(2000),
        PwmTx::set_duty_cycle(500),
        PwmTx::set_duty_cycle(0),
    ]);
    let dir = PinMock::new(&[PinTx::set(State::Low)]);
    let mut wheel = PwmReactionWheel::new(pwm.clone(), dir.clone(), 0.01);
    assert_eq!(wheel.set_momentum(-0.0025), Ok(()));
    assert_eq!(wheel.set_momentum(0.02), Err(ErrorKind::OutOfRange));
    pwm.clone().done();
    dir.clone().done();
}

#[test]
fn a_part_with_another_resolution_is_configured_in_its_driver() {
    // a magnetometer counting 0.1 µT = 100 nT: 1603 counts = 160 300 nT = 16 030 bus words;
    // 4000 counts = 400 000 nT is beyond the bus's ±327 670 nT: refused, not wrapped
    let i2c = I2cMock::new(&[
        I2cTx::write_read(
            0x1e,
            vec![0x03],
            [1603i16, -467].map(i16::to_be_bytes).concat(),
        ),
        I2cTx::write_read(
            0x1e,
            vec![0x03],
            [4000i16, 0].map(i16::to_be_bytes).concat(),
        ),
        I2cTx::write_read(0x1e, vec![0x03], [-3i16, 7].map(i16::to_be_bytes).concat()),
    ]);
    let scale = Scale::magnetometer_lsb_nt(100.0).unwrap();
    let mut mag = I2cMagnetometer::new(i2c, 0x1e, 0x03).with_scale(scale);
    assert_eq!(mag.read_field_raw(), Ok([16_030, -4_670]));
    assert_eq!(mag.read_field_raw(), Err(ErrorKind::OutOfRange));
    // in physical units
    let b = mag.read_field_nt().unwrap();
    assert_eq!((b.x, b.y), (-300.0, 700.0));
    mag.release().done();

    // a gyro counting 1/131 °/s (a common MEMS range): 131 counts = 1 °/s = 174.53 bus words
    // (1e-4 rad/s), rounded to 175
    let i2c = I2cMock::new(&[I2cTx::write_read(0x68, vec![0x10], vec![0, 131])]);
    let lsb = (1.0f32 / 131.0).to_radians();
    let mut gyro = I2cGyro::new(i2c, 0x68, 0x10).with_scale(Scale::gyro_lsb_radps(lsb).unwrap());
    assert_eq!(gyro.read_rate_raw(), Ok(175));
    gyro.release().done();

    // a sun sensor counting 0.5 mrad: 100 counts = 50 mrad = 500 bus words
    let i2c = I2cMock::new(&[I2cTx::write_read(
        0x40,
        vec![0x00],
        [1i16, 100, -20].map(i16::to_be_bytes).concat(),
    )]);
    let mut sun = I2cSunSensor::new(i2c, 0x40, 0x00).with_scale(Scale::sun_lsb_rad(5e-4).unwrap());
    assert_eq!(sun.read_sun_raw(), Ok(Some([500, -100])));
    sun.release().done();

    // a scale must be finite and positive
    assert_eq!(Scale::magnetometer_lsb_nt(0.0), None);
    assert_eq!(Scale::magnetometer_lsb_nt(-1.0), None);
    assert_eq!(Scale::magnetometer_lsb_nt(f32::NAN), None);
    assert_eq!(Scale::magnetometer_lsb_nt(f32::INFINITY), None);
    assert_eq!(Scale::IDENTITY.convert(i16::MAX - 1), Ok(i16::MAX - 1));
}
