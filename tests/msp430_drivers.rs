//! The MSP430FG4619 peripheral drivers (`acs::hal::msp430`) against register models of their
//! peripherals (`tests/msp430/`): the protocol each driver performs, its errors, and the
//! project's device drivers (`acs::hal::drivers`, `acs::hal::bus::DeviceBus`) running over them.

mod msp430;

use acs::hal::bus::{DeviceBus, TileDevices};
use acs::hal::drivers::{I2cGyro, I2cMagnetometer, I2cSunSensor, PwmMagnetorquer};
use acs::hal::msp430::element_store::{
    crc16_ccitt, ElementStore, StoreError, FLIGHT_SEGMENTS, RECORD_MAGIC, RECORD_WORDS,
};
use acs::hal::msp430::flash::{FlashConfig, FlashController, FlashError};
use acs::hal::msp430::gpio::{OutputPin, Pin, P3, P5};
use acs::hal::msp430::pwm::{PwmChannel, PwmConfig, TbOutput, TimerBPwm};
use acs::hal::msp430::timer_a::{Period, PeriodTimer, TimerError};
use acs::hal::msp430::usci_i2c::{self, I2cConfig, I2cError, UsciI2c};
use acs::hal::msp430::usci_uart::{self, UartConfig, UartError, UsciUart};
use acs::hal::msp430::{Registers, ACLK_HZ, SMCLK_HZ};
use acs::hal::{ErrorKind, Magnetometer, Magnetorquer, TileBus};
use acs::orbit::sgp4::{Gravity, Sgp4, ELEMENT_WORDS};
use embedded_hal::digital::OutputPin as _;
use embedded_hal::i2c::{self, I2c, NoAcknowledgeSource, Operation};
use embedded_hal::pwm::SetDutyCycle;
use embedded_hal_mock::eh1::delay::NoopDelay;
use msp430::{Event, Handle, Slave};

const MAG: u8 = 0x1E;
const GYRO: u8 = 0x68;
const SUN: u8 = 0x30;

/// A part whose I²C bus has a magnetometer, a gyro and a sun sensor (the drivers' register
/// layout: big-endian `i16` words), and the bus driver on it.
fn sensor_bus() -> (Handle, UsciI2c<Handle>) {
    let h = Handle::new();
    {
        let mut mcu = h.mcu();
        mcu.i2c
            .slaves
            .push(Slave::new(MAG).with_words(0x03, &[1603, -467]));
        mcu.i2c
            .slaves
            .push(Slave::new(GYRO).with_words(0x10, &[-312]));
        mcu.i2c
            .slaves
            .push(Slave::new(SUN).with_words(0x00, &[1, 2500, -1200]));
    }
    let bus = UsciI2c::new(h.clone(), &I2cConfig::FLIGHT);
    (h, bus)
}

fn no_violations(h: &Handle) {
    let v = h.mcu().violations();
    assert!(v.is_empty(), "{v:#?}");
}

fn events(h: &Handle) -> Vec<Event> {
    std::mem::take(&mut h.mcu().i2c.events)
}

fn w(address: u8) -> Event {
    Event::Start {
        address,
        read: false,
    }
}

fn rs(address: u8) -> Event {
    Event::Restart {
        address,
        read: true,
    }
}

// ---- USCI_B0, I²C ----------------------------------------------------------------------------

#[test]
fn i2c_flight_configuration_is_100_khz_from_smclk() {
    assert_eq!(
        I2cConfig::new(SMCLK_HZ, 100_000, 1_000),
        Some(I2cConfig::FLIGHT)
    );
    assert_eq!(I2cConfig::FLIGHT.prescaler(), 80);
    assert_eq!(I2cConfig::FLIGHT.scl_hz(SMCLK_HZ), 99_942);
    // f_BRCLK / 4 at most, and a bounded wait
    assert_eq!(
        I2cConfig::new(SMCLK_HZ, 2_000_000, 10),
        Some(I2cConfig::new(SMCLK_HZ, 1_998_848, 10).unwrap())
    );
    assert_eq!(I2cConfig::new(SMCLK_HZ, 3_000_000, 10), None);
    assert_eq!(I2cConfig::new(SMCLK_HZ, 100_000, 0), None);
}

#[test]
fn i2c_initialisation_follows_the_ucswrst_sequence() {
    let (h, _bus) = sensor_bus();
    let mcu = h.mcu();
    use usci_i2c::bits::*;
    assert_eq!(mcu.i2c.ctl0, UCMST | UCMODE_I2C | UCSYNC);
    assert_eq!(mcu.i2c.ctl1, UCSSEL_SMCLK);
    assert_eq!(u16::from_le_bytes([mcu.i2c.br0, mcu.i2c.br1]), 80);
    assert_eq!(mcu.read_port(usci_i2c::P3SEL), P3_SDA_SCL);
    drop(mcu);
    no_violations(&h);
}

#[test]
fn magnetometer_gyro_and_sun_sensor_read_through_the_usci() {
    let (h, bus) = sensor_bus();
    let mut mag = I2cMagnetometer::new(bus, MAG, 0x03);
    assert_eq!(mag.read_field_raw(), Ok([1603, -467]));
    let mut expected = vec![w(MAG), Event::Write(0x03), rs(MAG)];
    expected.extend([0x06, 0x43, 0xFE, 0x2D].map(Event::Read));
    expected.push(Event::Stop);
    assert_eq!(events(&h), expected);

    let mut gyro = I2cGyro::new(UsciI2c::attach(h.clone(), &I2cConfig::FLIGHT), GYRO, 0x10);
    assert_eq!(acs::hal::Gyro::read_rate_raw(&mut gyro), Ok(-312));
    let e = events(&h);
    assert_eq!(e.len(), 3 + 2 + 1, "{e:?}");

    let mut sun = I2cSunSensor::new(UsciI2c::attach(h.clone(), &I2cConfig::FLIGHT), SUN, 0x00);
    assert_eq!(
        acs::hal::SunSensor::read_sun_raw(&mut sun),
        Ok(Some([2500, -1200]))
    );
    assert_eq!(events(&h).len(), 3 + 6 + 1);
    // no Sun: status word 0
    h.mcu().i2c.slaves[2].registers[1] = 0;
    assert_eq!(acs::hal::SunSensor::read_sun_raw(&mut sun), Ok(None));
    no_violations(&h);
}

#[test]
fn a_single_byte_read_stops_after_exactly_one_byte() {
    let (h, mut bus) = sensor_bus();
    h.mcu().i2c.slaves[0].pointer = 0x04;
    let mut buf = [0u8; 1];
    bus.read(MAG, &mut buf).unwrap();
    assert_eq!(buf, [0x43]);
    let read = Event::Start {
        address: MAG,
        read: true,
    };
    assert_eq!(events(&h), vec![read, Event::Read(0x43), Event::Stop]);
    // and after a write, a one-byte read with a repeated START
    let mut one = [0u8; 1];
    bus.write_read(GYRO, &[0x11], &mut one).unwrap();
    assert_eq!(one, [0xC8]); // low byte of -312 = 0xFEC8
    assert_eq!(
        events(&h),
        vec![
            w(GYRO),
            Event::Write(0x11),
            rs(GYRO),
            Event::Read(0xC8),
            Event::Stop
        ]
    );
    no_violations(&h);
}

/// The protocol does not depend on how fast the bus is against the CPU: the same events for
/// address phases of 1–5 polls and bytes of 2–9 polls (a poll is about 20 MCLK cycles; at
/// 100 kHz a byte is 720 cycles, about 36 polls, so the model runs the bus much faster than
/// the part does).
#[test]
fn the_protocol_holds_at_any_bus_speed() {
    for address_ticks in 1..=5 {
        for byte_ticks in 2..=9 {
            let (h, mut bus) = sensor_bus();
            h.mcu().i2c.address_ticks = address_ticks;
            h.mcu().i2c.byte_ticks = byte_ticks;
            let mut four = [0u8; 4];
            bus.write_read(MAG, &[0x03], &mut four).unwrap();
            assert_eq!(four, [0x06, 0x43, 0xFE, 0x2D]);
            let mut one = [0u8; 1];
            bus.write_read(GYRO, &[0x10], &mut one).unwrap();
            bus.write(MAG, &[0x30, 1, 2]).unwrap();
            bus.write(MAG, &[0x30]).unwrap();
            bus.read(MAG, &mut four).unwrap();
            assert_eq!(four[..2], [1, 2]);
            let e = events(&h);
            let reads = e.iter().filter(|e| matches!(e, Event::Read(_))).count();
            let stops = e.iter().filter(|e| **e == Event::Stop).count();
            assert_eq!(
                (reads, stops, e.len()),
                (9, 5, 8 + 5 + 5 + 3 + 6),
                "{address_ticks} {byte_ticks}: {e:?}"
            );
            no_violations(&h);
        }
    }
}

#[test]
fn writes_and_merged_operations_follow_the_transaction_contract() {
    let (h, mut bus) = sensor_bus();
    // an address-only write (a probe)
    bus.write(MAG, &[]).unwrap();
    assert_eq!(events(&h), vec![w(MAG), Event::Stop]);
    // a register write
    bus.write(MAG, &[0x20, 0xAB, 0xCD]).unwrap();
    assert_eq!(h.mcu().i2c.slaves[0].registers[0x20..0x22], [0xAB, 0xCD]);
    let _ = events(&h);
    // adjacent operations of one direction merged, a repeated START between directions
    let (mut a, mut b) = ([0u8; 2], [0u8; 1]);
    bus.transaction(
        MAG,
        &mut [
            Operation::Write(&[0x20]),
            Operation::Write(&[]),
            Operation::Read(&mut a),
            Operation::Read(&mut b),
        ],
    )
    .unwrap();
    assert_eq!((a, b), ([0xAB, 0xCD], [0x00]));
    assert_eq!(
        events(&h),
        vec![
            w(MAG),
            Event::Write(0x20),
            rs(MAG),
            Event::Read(0xAB),
            Event::Read(0xCD),
            Event::Read(0x00),
            Event::Stop
        ]
    );
    // read, then write: the repeated START is requested while the last byte is received
    let mut c = [0u8; 2];
    bus.transaction(
        MAG,
        &mut [Operation::Read(&mut c), Operation::Write(&[0x03])],
    )
    .unwrap();
    let e = events(&h);
    assert_eq!(e.len(), 6, "{e:?}");
    assert_eq!(
        e[3..],
        [
            Event::Restart {
                address: MAG,
                read: false
            },
            Event::Write(0x03),
            Event::Stop
        ]
    );
    no_violations(&h);
}

#[test]
fn an_absent_device_is_an_address_nack_and_the_bus_recovers() {
    let (h, mut bus) = sensor_bus();
    let e = bus.write_read(0x55, &[0x03], &mut [0u8; 4]).unwrap_err();
    assert_eq!(e, I2cError::AddressNack);
    assert_eq!(
        i2c::Error::kind(&e),
        i2c::ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address)
    );
    assert_eq!(acs::hal::Error::kind(&e), ErrorKind::DeviceAbsent);
    // the master released the bus with a STOP
    assert_eq!(events(&h), vec![w(0x55), Event::Nack, Event::Stop]);
    // and a read of an absent magnetometer is DeviceAbsent for the loop
    let mut absent = I2cMagnetometer::new(UsciI2c::attach(h.clone(), &I2cConfig::FLIGHT), 0x55, 3);
    assert_eq!(absent.read_field_raw(), Err(ErrorKind::DeviceAbsent));
    let _ = events(&h);
    // the next transaction works
    let mut buf = [0u8; 2];
    bus.write_read(MAG, &[0x03], &mut buf).unwrap();
    assert_eq!(buf, [0x06, 0x43]);
    assert_eq!(h.mcu().i2c.events.last(), Some(&Event::Stop));
    no_violations(&h);
}

#[test]
fn a_refused_data_byte_is_a_data_nack() {
    let (h, mut bus) = sensor_bus();
    h.mcu().i2c.slaves[0].nack_write_byte = Some(1);
    let e = bus.write(MAG, &[0x20, 0x01, 0x02]).unwrap_err();
    assert_eq!(
        i2c::Error::kind(&e),
        i2c::ErrorKind::NoAcknowledge(NoAcknowledgeSource::Data)
    );
    assert_eq!(acs::hal::Error::kind(&e), ErrorKind::Bus);
    assert_eq!(
        events(&h),
        vec![w(MAG), Event::Write(0x20), Event::Nack, Event::Stop]
    );
    // the register byte refused before a repeated START: the source is unknown (the byte's
    // NACK and the new address's come in the same window), a bus error for the loop
    h.mcu().i2c.slaves[0].nack_write_byte = Some(0);
    let e = bus.write_read(MAG, &[0x03], &mut [0u8; 2]).unwrap_err();
    assert_eq!(
        i2c::Error::kind(&e),
        i2c::ErrorKind::NoAcknowledge(NoAcknowledgeSource::Unknown)
    );
    let e = events(&h);
    assert_eq!(e[..3], [w(MAG), Event::Nack, rs(MAG)]);
    assert_eq!(e.last(), Some(&Event::Stop));
    let mut mag = I2cMagnetometer::new(bus, MAG, 0x03);
    assert_eq!(mag.read_field_raw(), Err(ErrorKind::Bus));
    assert_eq!(h.mcu().i2c.events.last(), Some(&Event::Stop));
    no_violations(&h);
}

#[test]
fn lost_arbitration_is_reported_and_master_mode_restored() {
    let (h, mut bus) = sensor_bus();
    h.mcu().i2c.lose_arbitration = true;
    let e = bus.write_read(MAG, &[0x03], &mut [0u8; 4]).unwrap_err();
    assert_eq!(e, I2cError::ArbitrationLost);
    assert_eq!(i2c::Error::kind(&e), i2c::ErrorKind::ArbitrationLoss);
    assert_eq!(events(&h), vec![w(MAG), Event::ArbitrationLost]);
    assert!(h.mcu().i2c.is_master());
    let mut buf = [0u8; 4];
    bus.write_read(MAG, &[0x03], &mut buf).unwrap();
    assert_eq!(buf, [0x06, 0x43, 0xFE, 0x2D]);
    no_violations(&h);
}

#[test]
fn a_stuck_bus_times_out_within_the_poll_limit() {
    let (h, mut bus) = sensor_bus();
    h.mcu().i2c.stuck = true;
    let before = h.mcu().accesses;
    let e = bus.write_read(MAG, &[0x03], &mut [0u8; 4]).unwrap_err();
    let accesses = h.mcu().accesses - before;
    assert_eq!(e, I2cError::Timeout);
    assert_eq!(i2c::Error::kind(&e), i2c::ErrorKind::Other);
    assert_eq!(acs::hal::Error::kind(&e), ErrorKind::Timeout);
    // two bounded waits (the transfer, the STOP of the recovery): at most 3 accesses a poll
    assert!(accesses <= 2 * 3 * 1_000 + 50, "{accesses} accesses");
    // the module was reset: the lines released
    assert_eq!(events(&h), vec![w(MAG), Event::Reset]);
    // through a device driver, embedded-hal has no timeout kind: a bus error
    let mut mag = I2cMagnetometer::new(bus, MAG, 0x03);
    assert_eq!(mag.read_field_raw(), Err(ErrorKind::Bus));
    // another master holding the bus: the START is never made
    let mut bus = mag.release();
    h.mcu().i2c.stuck = false;
    h.mcu().i2c.external_busy = true;
    let _ = events(&h);
    assert_eq!(bus.write(MAG, &[0x03]), Err(I2cError::Timeout));
    assert!(events(&h).is_empty());
    h.mcu().i2c.external_busy = false;
    assert_eq!(bus.write(MAG, &[0x03]), Ok(()));
    no_violations(&h);
}

#[test]
fn bad_requests_are_refused_before_the_bus_is_touched() {
    let (h, mut bus) = sensor_bus();
    assert_eq!(bus.read(MAG, &mut []), Err(I2cError::EmptyRead));
    assert_eq!(bus.write(0x80, &[1]), Err(I2cError::BadAddress));
    assert_eq!(bus.transaction(MAG, &mut []), Ok(()));
    assert!(events(&h).is_empty());
    no_violations(&h);
}

// ---- Timer_B PWM and the direction pins: the coils --------------------------------------------

#[test]
fn pwm_duty_cycles_and_output_modes() {
    let h = Handle::new();
    assert_eq!(PwmConfig::FLIGHT.period_counts(), 400);
    let timer = TimerBPwm::start(h.clone(), PwmConfig::FLIGHT);
    let mut ch = timer.channel(TbOutput::TB4);
    {
        let mut mcu = h.mcu();
        assert_eq!(mcu.timer_b.ccr(0), 399);
        assert_eq!(mcu.timer_b.duty(4), Some(0.0));
        // P3.5 given to TB4 as an output
        assert_eq!(mcu.read_port(P3.select) & 0x20, 0x20);
        assert_eq!(mcu.read_port(P3.direction) & 0x20, 0x20);
    }
    assert_eq!(ch.max_duty_cycle(), 400);
    for (duty, expected) in [
        (0, 0.0),
        (1, 0.0025),
        (200, 0.5),
        (399, 0.9975),
        (400, 1.0),
        (900, 1.0),
    ] {
        ch.set_duty_cycle(duty).unwrap();
        assert_eq!(h.mcu().timer_b.duty(4), Some(expected), "duty {duty}");
    }
    // mode 7 loads its compare latch at TBR = 0
    ch.set_duty_cycle(100).unwrap();
    assert_eq!(h.mcu().timer_b.cctl(4) & 0x0600, 0x0200);
    ch.set_duty_cycle_fraction(1, 4).unwrap();
    assert_eq!(h.mcu().timer_b.ccr(4), 100);
    no_violations(&h);
}

#[test]
fn direction_pins_touch_only_their_bit() {
    let h = Handle::new();
    h.mcu().ports[usize::from(P5.output)] = 0b1010_0000;
    h.mcu().ports[usize::from(P5.select)] = 0b0000_0010;
    let mut pin = OutputPin::new(h.clone(), Pin::new(P5, 1));
    {
        let mcu = h.mcu();
        assert_eq!(mcu.ports[usize::from(P5.select)], 0);
        assert_eq!(mcu.ports[usize::from(P5.direction)], 0b10);
        assert_eq!(mcu.ports[usize::from(P5.output)], 0b1010_0000);
    }
    pin.set_high().unwrap();
    assert_eq!(h.mcu().ports[usize::from(P5.output)], 0b1010_0010);
    pin.set_low().unwrap();
    assert_eq!(h.mcu().ports[usize::from(P5.output)], 0b1010_0000);
}

#[test]
fn the_pwm_coil_driver_commands_a_coil_through_timer_b() {
    let h = Handle::new();
    let timer = TimerBPwm::start(h.clone(), PwmConfig::FLIGHT);
    let dir = OutputPin::new(h.clone(), Pin::new(P5, 0));
    let mut coil = PwmMagnetorquer::new(timer.channel(TbOutput::TB3), dir, 0.2);
    let dir_high = |h: &Handle| h.mcu().ports[usize::from(P5.output)] & 1 == 1;
    coil.set_dipole(0.1).unwrap();
    assert_eq!(h.mcu().timer_b.duty(3), Some(0.5));
    assert!(dir_high(&h));
    coil.set_dipole(-0.05).unwrap();
    assert_eq!(h.mcu().timer_b.duty(3), Some(0.25));
    assert!(!dir_high(&h));
    // beyond the limit: refused, and the coil off
    assert_eq!(coil.set_dipole(0.3), Err(ErrorKind::OutOfRange));
    assert_eq!(h.mcu().timer_b.duty(3), Some(0.0));
    no_violations(&h);
}

/// The project's `DeviceBus` over the MSP430 drivers: a tile's three sensors on the USCI_B0,
/// three coils on Timer_B with their direction pins.
#[test]
fn device_bus_runs_on_the_msp430_drivers() {
    let (h, bus) = sensor_bus();
    let cfg = &I2cConfig::FLIGHT;
    let tile = TileDevices::none()
        .with_magnetometer(I2cMagnetometer::new(bus, MAG, 0x03))
        .with_gyro(I2cGyro::new(UsciI2c::attach(h.clone(), cfg), GYRO, 0x10))
        .with_sun_sensor(I2cSunSensor::new(
            UsciI2c::attach(h.clone(), cfg),
            SUN,
            0x00,
        ));
    let timer = TimerBPwm::start(h.clone(), PwmConfig::FLIGHT);
    let coil = |out: TbOutput, bit: u8| {
        Some(PwmMagnetorquer::new(
            timer.channel(out),
            OutputPin::new(h.clone(), Pin::new(P5, bit)),
            0.2,
        ))
    };
    type Coil = PwmMagnetorquer<PwmChannel<Handle>, OutputPin<Handle>>;
    let coils: [Option<Coil>; 3] = [
        coil(TbOutput::TB3, 0),
        coil(TbOutput::TB4, 1),
        coil(TbOutput::TB5, 2),
    ];
    let mut dbus: DeviceBus<_, _, _, acs::hal::bus::NoDevice, _, _, 2, 3> =
        DeviceBus::new([tile, TileDevices::none()], coils, NoopDelay::new());
    assert_eq!(dbus.read_magnetometer(0), Ok([1603, -467]));
    assert_eq!(dbus.read_gyro(0), Ok(-312));
    assert_eq!(dbus.read_sun(0), Ok(Some([2500, -1200])));
    assert_eq!(dbus.read_magnetometer(1), Err(ErrorKind::DeviceAbsent));
    assert_eq!(dbus.set_dipole(0, 0.05), Ok(()));
    assert_eq!(dbus.set_dipole(1, -0.2), Ok(()));
    assert_eq!(dbus.set_dipole(2, 0.0), Ok(()));
    {
        let mut mcu = h.mcu();
        assert_eq!(mcu.timer_b.duty(3), Some(0.25));
        assert_eq!(mcu.timer_b.duty(4), Some(1.0));
        assert_eq!(mcu.timer_b.duty(5), Some(0.0));
        assert_eq!(mcu.ports[usize::from(P5.output)] & 0b111, 0b101);
    }
    // a magnetometer that stops answering is a device error for the loop
    h.mcu().i2c.slaves[0].nack_address = true;
    assert_eq!(dbus.read_magnetometer(0), Err(ErrorKind::DeviceAbsent));
    assert_eq!(dbus.coils_off(), Ok(()));
    assert_eq!(h.mcu().timer_b.duty(4), Some(0.0));
    no_violations(&h);
}

// ---- USCI_A0, UART ---------------------------------------------------------------------------

#[test]
fn uart_flight_configuration_is_115200_baud() {
    assert_eq!(
        UartConfig::new(SMCLK_HZ, 115_200, 200),
        Some(UartConfig::FLIGHT)
    );
    let c = UartConfig::FLIGHT;
    assert_eq!((c.ucbr(), c.ucbrs()), (69, 3));
    assert_eq!(c.mean_baud(SMCLK_HZ), 115_248);
    // the user's guide's example rates (UCOS16 = 0): 1 048 576 Hz, 9 600 Bd → 109, 2
    let ex = UartConfig::new(1_048_576, 9_600, 1).unwrap();
    assert_eq!((ex.ucbr(), ex.ucbrs()), (109, 2));
    assert_eq!(UartConfig::new(1_000_000, 400_000, 1), None);

    let h = Handle::new();
    let _uart = UsciUart::new(h.clone(), UartConfig::FLIGHT);
    let mcu = h.mcu();
    use usci_uart::bits::*;
    assert_eq!((mcu.uart.ctl0, mcu.uart.ctl1), (0, UCSSEL_SMCLK | UCRXEIE));
    assert_eq!((mcu.uart.br0, mcu.uart.br1, mcu.uart.mctl), (69, 0, 3 << 1));
    assert_eq!(mcu.read_port(usci_uart::P2SEL), P2_TXD_RXD);
    drop(mcu);
    no_violations(&h);
}

/// SLAU056 "Transmit Bit Timing": bit j of a character lasts (UCBRx + m_j) BRCLK cycles, m_j
/// the UCBRSx modulation pattern's bit (table "BITCLK Modulation Pattern", UCBRSx = 3: bits 1,
/// 3, 5); the error of bit j's end is (Σ_{i≤j} t_i) · baud − (j + 1), in bit times.
#[test]
fn uart_baud_error_of_the_flight_setting() {
    let pattern3 = [0u32, 1, 0, 1, 0, 1, 0, 0];
    let c = UartConfig::FLIGHT;
    let mut cycles = 0u32;
    let mut errors = Vec::new();
    for j in 0..10 {
        cycles += u32::from(c.ucbr()) + pattern3[j % 8];
        let error = f64::from(cycles) * 115_200.0 / f64::from(SMCLK_HZ) - (j + 1) as f64;
        errors.push(100.0 * error);
    }
    let min = errors.iter().cloned().fold(f64::INFINITY, f64::min);
    let max = errors.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    assert!(
        (min - -0.922).abs() < 5e-4 && (max - 0.826).abs() < 5e-4,
        "{errors:?}"
    );
}

#[test]
fn a_100_byte_frame_goes_out_in_order() {
    let h = Handle::new();
    let mut uart = UsciUart::new(h.clone(), UartConfig::FLIGHT);
    let frame: Vec<u8> = (0..100u8).map(|i| i.wrapping_mul(37)).collect();
    assert_eq!(uart.write_bytes(&frame), Ok(100));
    // the last byte is in the shift register
    for _ in 0..10 {
        uart.write_bytes(&[]).unwrap();
        h.mcu().uart.tick();
    }
    assert_eq!(h.mcu().uart.tx_line, frame);
    no_violations(&h);
}

#[test]
fn a_stopped_transmitter_times_out() {
    let h = Handle::new();
    let mut uart = UsciUart::new(h.clone(), UartConfig::FLIGHT);
    h.mcu().uart.tx_stuck = true;
    // one byte to the shift register, one to the buffer, then nothing
    assert_eq!(uart.write_bytes(&[1, 2, 3, 4]), Ok(2));
    let before = h.mcu().accesses;
    assert_eq!(uart.write_bytes(&[3, 4]), Err(UartError::Timeout));
    assert!(h.mcu().accesses - before <= 200);
    no_violations(&h);
}

#[test]
fn reads_take_what_arrived_and_report_errors() {
    let h = Handle::new();
    let mut uart = UsciUart::new(h.clone(), UartConfig::FLIGHT);
    let mut buf = [0u8; 8];
    assert_eq!(uart.read_bytes(&mut buf), Ok(0));
    // bytes read as they arrive
    let mut got = Vec::new();
    h.mcu()
        .uart
        .rx_line
        .extend([(10, false), (11, false), (12, false)]);
    while h.mcu().uart.deliver() {
        let n = uart.read_bytes(&mut buf).unwrap();
        got.extend_from_slice(&buf[..n]);
    }
    assert_eq!(got, [10, 11, 12]);
    // two bytes without a read between: an overrun, the byte discarded
    h.mcu().uart.rx_line.extend([(20, false), (21, false)]);
    h.mcu().uart.deliver();
    h.mcu().uart.deliver();
    assert_eq!(uart.read_bytes(&mut buf), Err(UartError::Overrun));
    assert_eq!(uart.read_bytes(&mut buf), Ok(0));
    // a framing error: reported on its own, the bytes after it intact
    h.mcu().uart.rx_line.extend([(30, true), (31, false)]);
    h.mcu().uart.deliver();
    assert_eq!(uart.read_bytes(&mut buf), Err(UartError::Framing));
    h.mcu().uart.deliver();
    assert_eq!(uart.read_bytes(&mut buf), Ok(1));
    assert_eq!(buf[0], 31);
    no_violations(&h);
}

// ---- Timer_A, the control period -------------------------------------------------------------

#[test]
fn periods_from_aclk_ticks() {
    assert_eq!(Period::from_aclk_ticks(ACLK_HZ), Some(Period::ONE_SECOND));
    assert_eq!(Period::ONE_SECOND.ccr0(), 32_767);
    assert_eq!(Period::ONE_SECOND.aclk_ticks(), 32_768);
    // 4 s: 131 072 ticks, divider 2 (65 536 counts)
    let p = Period::from_aclk_ticks(4 * ACLK_HZ).unwrap();
    assert_eq!((p.ccr0(), p.aclk_ticks()), (65_535, 4 * ACLK_HZ));
    assert_eq!(Period::from_aclk_ticks(16 * ACLK_HZ + 8), None);
    assert_eq!(
        Period::from_aclk_ticks(3),
        Some(Period::from_aclk_ticks(3).unwrap())
    );
    assert_eq!(Period::from_aclk_ticks(0), None);
}

#[test]
fn the_period_timer_marks_each_32768_aclk_cycles() {
    let h = Handle::new();
    let mut timer = PeriodTimer::start(h.clone(), Period::ONE_SECOND, 1_000);
    {
        let mcu = h.mcu();
        use acs::hal::msp430::timer_a::bits::*;
        assert_eq!(mcu.timer_a.ctl, TASSEL_ACLK | MC_UP);
        assert_eq!((mcu.timer_a.ccr0, mcu.timer_a.tar), (32_767, 0));
    }
    h.mcu().timer_a.advance(32_766);
    assert!(!timer.period_elapsed());
    h.mcu().timer_a.advance(1);
    assert!(timer.period_elapsed());
    assert!(!timer.period_elapsed());
    h.mcu().timer_a.advance(32_767);
    assert!(!timer.period_elapsed());
    h.mcu().timer_a.advance(1);
    assert!(timer.period_elapsed());
    timer.enable_wakeup();
    assert_eq!(h.mcu().timer_a.cctl0 & 0x0010, 0x0010);
    timer.disable_wakeup();
    assert_eq!(h.mcu().timer_a.cctl0 & 0x0010, 0);
    no_violations(&h);
}

#[test]
fn waiting_for_a_period_is_bounded() {
    let h = Handle::new();
    // 100 ACLK cycles pass per poll: a period in 328 polls
    h.mcu().timer_a.ticks_per_poll = 100;
    let mut timer = PeriodTimer::start(h.clone(), Period::ONE_SECOND, 1_000);
    assert_eq!(timer.wait_period(), Ok(()));
    assert_eq!(h.mcu().timer_a.polls, 328);
    // the crystal stopped
    h.mcu().timer_a.ticks_per_poll = 0;
    assert_eq!(timer.wait_period(), Err(TimerError::Timeout));
    assert_eq!(h.mcu().timer_a.polls, 1_328);
    let _ = timer.stop();
    assert_eq!(h.mcu().timer_a.ctl & 0x0030, 0);
}

// ---- flash controller and element store ------------------------------------------------------

fn flash(h: &Handle) -> FlashController<Handle> {
    FlashController::new(h.clone(), FlashConfig::FLIGHT)
}

#[test]
fn flash_timing_generator_is_mclk_over_22() {
    assert_eq!(
        FlashConfig::from_mclk(SMCLK_HZ, 20_000),
        Some(FlashConfig::FLIGHT)
    );
    assert_eq!(FlashConfig::FLIGHT.divider(), 22);
    assert_eq!(FlashConfig::FLIGHT.fctl2(), 0xA555);
    assert_eq!(SMCLK_HZ / 22, 363_426);
    assert_eq!(FlashConfig::from_mclk(32_768, 1), None);
    assert_eq!(FlashConfig::from_mclk(30_000_000, 1), None);
}

#[test]
fn flash_erase_then_write_and_the_controller_locked_after() {
    let h = Handle::new();
    let mut f = flash(&h);
    f.erase_segment(0x2210).unwrap();
    f.write_word(0x2200, 0x1234).unwrap();
    assert_eq!(f.read_word(0x2200), 0x1234);
    {
        let mcu = h.mcu();
        assert_eq!(mcu.flash.erases.get(&0x2200), Some(&1));
        assert_eq!(mcu.flash.word_writes, 1);
        assert_eq!(mcu.flash.fctl3 & 0x0010, 0x0010, "LOCK set again");
        assert_eq!(mcu.flash.fctl1, 0);
    }
    no_violations(&h);
    // a 1 over a 0 without an erase: the model flags it, the driver's read-back catches it
    assert_eq!(
        f.write_word(0x2200, 0xFFFF),
        Err(FlashError::Verify { address: 0x2200 })
    );
    assert_eq!(h.mcu().violations().len(), 1);
}

#[test]
fn the_flash_model_enforces_the_password_and_the_lock() {
    let h = Handle::new();
    let mut regs = h.clone();
    // locked: a write is an access violation and changes nothing
    regs.write16(0x128, 0xA540);
    regs.write16(0x2200, 0);
    assert_eq!(h.mcu().flash.access_violations, 1);
    assert_eq!(h.mcu().flash.word(0x2200), 0xFFFF);
    // without the password: refused
    regs.write16(0x12C, 0x0000);
    assert_eq!(h.mcu().flash.key_violations, 1);
    assert_eq!(regs.read16(0x12C) & 0xFF00, 0x9600);
    // the driver reports a violation the controller flags
    let mut f = flash(&h);
    h.mcu().flash.refuse_next = true;
    assert_eq!(f.erase_segment(0x2200), Err(FlashError::AccessViolation));
    assert_eq!(h.mcu().flash.fctl3 & 0x0004, 0, "ACCVIFG cleared");
    assert_eq!(f.erase_segment(0x2200), Ok(()));
}

#[test]
fn crc16_ccitt_check_value() {
    assert_eq!(crc16_ccitt(b"123456789"), 0x29B1);
    assert_eq!(crc16_ccitt(b""), 0xFFFF);
}

fn elements(k: u32) -> [u32; ELEMENT_WORDS] {
    std::array::from_fn(|i| (i as u32).wrapping_mul(0x9E37_79B9) ^ k)
}

fn store(h: &Handle) -> ElementStore<Handle> {
    ElementStore::new(flash(h), FLIGHT_SEGMENTS).unwrap()
}

fn load(h: &Handle) -> Option<(u16, [u32; ELEMENT_WORDS])> {
    let mut words = [0u32; ELEMENT_WORDS];
    store(h).load(&mut words).map(|seq| (seq, words))
}

/// A record's words as the store writes them, read back from the model.
fn record(h: &Handle, base: u16) -> Vec<u16> {
    let mcu = h.mcu();
    (0..RECORD_WORDS as u16)
        .map(|i| mcu.flash.word(base + 2 * i))
        .collect()
}

#[test]
fn element_sets_alternate_between_the_two_segments() {
    let h = Handle::new();
    assert_eq!(load(&h), None);
    let mut s = store(&h);
    let (a, b, c) = (elements(1), elements(2), elements(3));
    assert_eq!(s.store(&a), Ok(0));
    assert_eq!(load(&h), Some((0, a)));
    assert_eq!(s.store(&b), Ok(1));
    assert_eq!(load(&h), Some((1, b)));
    assert_eq!(s.store(&c), Ok(2));
    assert_eq!(load(&h), Some((2, c)));
    {
        let mcu = h.mcu();
        assert_eq!(mcu.flash.erases.get(&0x2200), Some(&2));
        assert_eq!(mcu.flash.erases.get(&0x2400), Some(&1));
        assert_eq!(mcu.flash.word_writes, 3 * RECORD_WORDS as u32);
    }
    // the record format
    let r = record(&h, 0x2200);
    assert_eq!((r[0], r[1]), (RECORD_MAGIC, 2));
    assert_eq!((r[2], r[3]), (c[0] as u16, (c[0] >> 16) as u16));
    let bytes: Vec<u8> = r[..RECORD_WORDS - 1]
        .iter()
        .flat_map(|w| w.to_le_bytes())
        .collect();
    assert_eq!(r[RECORD_WORDS - 1], crc16_ccitt(&bytes));
    assert_eq!(record(&h, 0x2400)[1], 1);
    no_violations(&h);
}

#[test]
fn a_corrupt_or_erased_segment_is_ignored() {
    let h = Handle::new();
    let mut s = store(&h);
    s.store(&elements(1)).unwrap();
    s.store(&elements(2)).unwrap();
    // one bit of the newer record's elements flipped: the older set is used
    let w = h.mcu().flash.word(0x2400 + 40);
    h.mcu().flash.set_word(0x2400 + 40, w ^ 0x0100);
    assert_eq!(load(&h), Some((0, elements(1))));
    // a store then replaces the corrupt one (it is not the newest valid)
    s.store(&elements(3)).unwrap();
    assert_eq!(load(&h), Some((1, elements(3))));
    // the CRC word itself corrupted, and the other segment erased: nothing valid
    let crc_at = 0x2400 + 2 * (RECORD_WORDS as u16 - 1);
    let crc = h.mcu().flash.word(crc_at);
    h.mcu().flash.set_word(crc_at, !crc);
    for a in (0x2200..0x2400).step_by(2) {
        h.mcu().flash.set_word(a, 0xFFFF);
    }
    assert_eq!(load(&h), None);
    no_violations(&h);
}

#[test]
fn sequence_numbers_compare_across_the_wrap() {
    let h = Handle::new();
    let mut s = store(&h);
    s.store(&elements(1)).unwrap();
    // set the stored record's sequence to 0xFFFF (and its CRC to match)
    let mut r = record(&h, 0x2200);
    r[1] = 0xFFFF;
    let bytes: Vec<u8> = r[..RECORD_WORDS - 1]
        .iter()
        .flat_map(|w| w.to_le_bytes())
        .collect();
    r[RECORD_WORDS - 1] = crc16_ccitt(&bytes);
    for (i, w) in r.iter().enumerate() {
        h.mcu().flash.set_word(0x2200 + 2 * i as u16, *w);
    }
    assert_eq!(load(&h), Some((0xFFFF, elements(1))));
    assert_eq!(s.store(&elements(2)), Ok(0));
    assert_eq!(load(&h), Some((0, elements(2))));
    assert_eq!(s.store(&elements(3)), Ok(1));
    assert_eq!(load(&h), Some((1, elements(3))));
}

/// Power lost after each of a store's 120 flash operations (the erase, then 119 word writes):
/// at the reset the old set or the new one is found, never neither; the new one only once its
/// magic word is written.
#[test]
fn a_store_interrupted_by_a_reset_never_loses_both_copies() {
    for preloaded in [1usize, 2] {
        for cut in 0..=RECORD_WORDS as u32 + 1 {
            let h = Handle::new();
            let mut s = store(&h);
            for k in 0..preloaded {
                s.store(&elements(k as u32)).unwrap();
            }
            let old = load(&h).unwrap();
            let new = elements(99);
            h.mcu().flash.power_budget = Some(cut);
            let result = s.store(&new);
            h.mcu().flash.power_on();
            let found = load(&h);
            let seq = old.0.wrapping_add(1);
            if cut as usize > RECORD_WORDS {
                assert_eq!(result, Ok(seq));
                assert_eq!(found, Some((seq, new)), "cut {cut}");
            } else {
                // the store could not complete (its read-back fails, or a write did not verify)
                assert!(result.is_err(), "cut {cut}: {result:?}");
                assert_eq!(found, Some(old), "preloaded {preloaded}, cut {cut}");
            }
            // and the store works again after the reset
            let mut s = store(&h);
            let next = s.store(&elements(7)).unwrap();
            assert_eq!(load(&h), Some((next, elements(7))));
            no_violations(&h);
        }
    }
}

#[test]
fn the_store_refuses_bad_segments_and_keeps_a_real_element_set() {
    let h = Handle::new();
    for bad in [
        [0x2200, 0x2200],
        [0x2300, 0x2400],
        [0x2200, 0xFE00],
        [0x1000, 0x2200],
    ] {
        assert!(matches!(
            ElementStore::new(flash(&h), bad),
            Err(StoreError::BadSegments)
        ));
    }
    // the flight orbit's initialised elements survive the store and still initialise SGP4
    let tle = acs::tle::Tle::parse(
        "1 90101U 25001A   25079.50000000  .00000000  00000-0  00000-0 0  9997",
        "2 90101  97.4000  90.0000 0001000   0.0000   0.0000 15.21936487    10",
    )
    .unwrap();
    let words = Sgp4::new(&tle, Gravity::Wgs72).unwrap().to_words();
    store(&h).store(&words).unwrap();
    let (_, back) = load(&h).unwrap();
    assert_eq!(back, words);
    assert!(Sgp4::from_words(&back).is_ok());
    no_violations(&h);
}

// ---- the flight node images' adapters: the UART as the link's byte stream, the receive
// ring, the attitude node's tile bus ------------------------------------------------------------

use acs::hal::link::{ByteStream, FramedLink, NodeLink};
use acs::hal::msp430::tile_bus::{self, AttitudeBus};
use acs::hal::msp430::usci_uart::{RxRing, RX_RING_BYTES};

/// Sends `packet` over a FramedLink on the modelled USCI_A0 and returns the bytes on the line.
fn framed_line(packet: &[u8]) -> Vec<u8> {
    let h = Handle::new();
    let mut link: FramedLink<UsciUart<Handle>, 128> =
        FramedLink::new(UsciUart::new(h.clone(), UartConfig::FLIGHT));
    link.send(packet).unwrap();
    for _ in 0..10 {
        ByteStream::write(link.stream_mut(), &[]).unwrap();
        h.mcu().uart.tick();
    }
    no_violations(&h);
    let line = std::mem::take(&mut h.mcu().uart.tx_line);
    line
}

#[test]
fn the_uart_carries_framed_packets_both_ways() {
    // a packet with zeros in it: on the line 0x00, its COBS encoding (the `cobs` crate's, an
    // independent implementation), 0x00
    // the longest packet of the link, the REF's (125 B since issue #30's albedo): on the line
    // 128 B, exactly the receive ring's 128 (a longer REF would overrun it every period)
    let len = acs::link::messages::REFERENCE_PACKET_BYTES as u8;
    let packet: Vec<u8> = (0..len).map(|i| if i % 7 == 0 { 0 } else { i }).collect();
    let line = framed_line(&packet);
    let mut expected = vec![0u8];
    expected.extend(cobs::encode_vec(&packet));
    expected.push(0);
    assert_eq!(line, expected);
    assert!(
        line.len() <= usize::from(RX_RING_BYTES),
        "{} B on the line",
        line.len()
    );

    // the same line into the receiver, one byte per byte time, polled after each
    let h = Handle::new();
    let mut link: FramedLink<UsciUart<Handle>, 128> =
        FramedLink::new(UsciUart::new(h.clone(), UartConfig::FLIGHT));
    h.mcu()
        .uart
        .rx_line
        .extend(line.iter().map(|b| (*b, false)));
    let mut buf = [0u8; 128];
    let mut got = Vec::new();
    while h.mcu().uart.deliver() {
        if let Some(n) = link.receive(&mut buf).unwrap() {
            got.push(buf[..n].to_vec());
        }
    }
    assert_eq!(got, vec![packet]);
    no_violations(&h);
}

#[test]
fn a_byte_stream_write_fails_when_the_transmitter_stops() {
    let h = Handle::new();
    let mut uart = UsciUart::new(h.clone(), UartConfig::FLIGHT);
    h.mcu().uart.tx_stuck = true;
    // two bytes go (shift register, buffer), the third cannot: the write fails, bounded
    let before = h.mcu().accesses;
    assert_eq!(
        ByteStream::write(&mut uart, &[1, 2, 3, 4]),
        Err(UartError::Timeout)
    );
    assert!(h.mcu().accesses - before <= 2 * 200 + 10);
    assert_eq!(
        acs::hal::link::Error::kind(&UartError::Overrun),
        acs::hal::link::ErrorKind::Transport
    );
    no_violations(&h);
}

/// The receive ring and its handler as the firmware's USCIAB0RX handler runs it: the byte at
/// `count mod 128`, then `count + 1`.
struct Ring {
    bytes: [u8; RX_RING_BYTES as usize],
    count: u16,
}

impl Ring {
    fn new(count: u16) -> Self {
        Self {
            bytes: [0; RX_RING_BYTES as usize],
            count,
        }
    }

    fn handler(&mut self, byte: u8) {
        self.bytes[usize::from(self.count % RX_RING_BYTES)] = byte;
        self.count = self.count.wrapping_add(1);
    }

    fn read(&self, reader: &mut RxRing, buf: &mut [u8]) -> Result<usize, UartError> {
        reader.read(|| self.count, |i| self.bytes[i], buf)
    }
}

#[test]
fn the_receive_ring_gives_the_bytes_in_order_across_the_count_wrap() {
    // the count near its wrap: the reader follows it through
    let mut ring = Ring::new(65_500);
    let mut reader = RxRing::new();
    reader.resync(ring.count);
    let mut buf = [0u8; 16];
    assert_eq!(ring.read(&mut reader, &mut buf), Ok(0));
    let mut got = Vec::new();
    for k in 0..300u32 {
        ring.handler(k as u8);
        if k % 50 == 49 {
            // taken in pieces of at most 16 bytes
            loop {
                let n = ring.read(&mut reader, &mut buf).unwrap();
                if n == 0 {
                    break;
                }
                got.extend_from_slice(&buf[..n]);
            }
        }
    }
    assert_eq!(got, (0..300u32).map(|k| k as u8).collect::<Vec<_>>());
    assert!(ring.count < 65_500, "the count wrapped");
}

#[test]
fn a_lapped_receive_ring_is_an_overrun_and_the_reader_resumes() {
    let mut ring = Ring::new(0);
    let mut reader = RxRing::new();
    let mut buf = [0u8; 256];
    // exactly a ring's worth pending: all of it
    for k in 0..RX_RING_BYTES {
        ring.handler(k as u8);
    }
    assert_eq!(ring.read(&mut reader, &mut buf), Ok(128));
    // one byte more than the ring holds: dropped, reported
    for k in 0..=RX_RING_BYTES {
        ring.handler(k as u8);
    }
    assert_eq!(ring.read(&mut reader, &mut buf), Err(UartError::Overrun));
    assert_eq!(ring.read(&mut reader, &mut buf), Ok(0));
    ring.handler(42);
    assert_eq!(ring.read(&mut reader, &mut buf), Ok(1));
    assert_eq!(buf[0], 42);
    // the handler laps the reader while it copies: the copy is not trusted
    ring.handler(1);
    ring.handler(2);
    let mut counts = [ring.count, ring.count.wrapping_add(200)].into_iter();
    let bytes = ring.bytes;
    assert_eq!(
        reader.read(|| counts.next().unwrap_or(0), |i| bytes[i], &mut buf),
        Err(UartError::Overrun)
    );
}

#[test]
fn the_tile_address_map_is_distinct_and_legal() {
    let mut all = Vec::new();
    for base in [
        tile_bus::SUN_SENSOR_BASE,
        tile_bus::MAGNETOMETER_BASE,
        tile_bus::GYRO_BASE,
        tile_bus::WHEEL_BASE,
    ] {
        for tile in 0..acs::flight::TILES {
            all.push(tile_bus::address(base, tile).unwrap());
        }
        assert_eq!(tile_bus::address(base, 8), None);
    }
    assert_eq!(all.len(), 24);
    let mut sorted = all.clone();
    sorted.sort();
    sorted.dedup();
    assert_eq!(sorted.len(), 24, "an address used twice: {all:?}");
    // UM10204 reserves 0000 xxx and 1111 xxx
    assert!(all.iter().all(|a| *a >= 0x08 && 0x78 > *a), "{all:?}");
    assert_eq!(tile_bus::address(tile_bus::SUN_SENSOR_BASE, 5), Some(0x25));
    assert_eq!(tile_bus::address(tile_bus::WHEEL_BASE, 1), Some(0x39));
}

/// A part with the flight cube's devices at the map's addresses: tiles 1–5 each with a sun
/// sensor, magnetometer, gyro and wheel controller whose words tell their tile; tile 0 (the
/// telecom tile) with none.
fn flight_part() -> (Handle, AttitudeBus<Handle, NoopDelay>) {
    let h = Handle::new();
    {
        let mut mcu = h.mcu();
        for t in 1..6u8 {
            let k = i16::from(t);
            mcu.i2c.slaves.push(
                Slave::new(tile_bus::SUN_SENSOR_BASE + t)
                    .with_words(tile_bus::SUN_SENSOR_REGISTER, &[1, 100 * k, -100 * k]),
            );
            mcu.i2c.slaves.push(
                Slave::new(tile_bus::MAGNETOMETER_BASE + t)
                    .with_words(tile_bus::MAGNETOMETER_REGISTER, &[1000 + k, -1000 - k]),
            );
            mcu.i2c.slaves.push(
                Slave::new(tile_bus::GYRO_BASE + t).with_words(tile_bus::GYRO_REGISTER, &[-7 * k]),
            );
            mcu.i2c.slaves.push(Slave::new(tile_bus::WHEEL_BASE + t));
        }
    }
    let bus = tile_bus::attitude_bus(
        h.clone(),
        &I2cConfig::FLIGHT,
        PwmConfig::FLIGHT,
        NoopDelay::new(),
    );
    (h, bus)
}

#[test]
fn the_attitude_tile_bus_follows_its_address_map() {
    let (h, mut bus) = flight_part();
    for t in 1..6usize {
        let k = t as i16;
        assert_eq!(bus.read_sun(t), Ok(Some([100 * k, -100 * k])), "tile {t}");
        assert_eq!(
            bus.read_magnetometer(t),
            Ok([1000 + k, -1000 - k]),
            "tile {t}"
        );
        assert_eq!(bus.read_gyro(t), Ok(-7 * k), "tile {t}");
    }
    // the telecom tile's addresses answer nothing: its devices are absent
    assert_eq!(bus.read_sun(0), Err(ErrorKind::DeviceAbsent));
    assert_eq!(bus.read_gyro(0), Err(ErrorKind::DeviceAbsent));
    assert_eq!(bus.read_gyro(6), Err(ErrorKind::DeviceAbsent));

    // wheels: the set-point (of 10 000 = 1e-3 N·m·s) and the direction at their registers
    let wheel = |h: &Handle, t: u8| {
        let mcu = h.mcu();
        let s = mcu
            .i2c
            .slaves
            .iter()
            .find(|s| s.address == tile_bus::WHEEL_BASE + t)
            .unwrap();
        let r = usize::from(tile_bus::WHEEL_SETPOINT_REGISTER);
        (
            u16::from_be_bytes([s.registers[r], s.registers[r + 1]]),
            s.registers[usize::from(tile_bus::WHEEL_DIRECTION_REGISTER)],
        )
    };
    assert_eq!(bus.set_wheel_momentum(2, 2.5e-4), Ok(()));
    assert_eq!(wheel(&h, 2), (2_500, 1));
    assert_eq!(bus.set_wheel_momentum(3, -1.0e-3), Ok(()));
    assert_eq!(wheel(&h, 3), (10_000, 0));
    // beyond the limit: refused, and the wheel's set-point to zero
    assert_eq!(
        bus.set_wheel_momentum(3, 1.5e-3),
        Err(ErrorKind::OutOfRange)
    );
    assert_eq!(wheel(&h, 3).0, 0);
    // a controller that does not answer: the command is reported failed
    assert!(bus.set_wheel_momentum(0, 1.0e-4).is_err());

    // coils: Timer_B channels 3–5, direction pins P5.0–P5.2
    assert_eq!(bus.set_dipole(0, 0.1), Ok(()));
    assert_eq!(bus.set_dipole(1, -0.2), Ok(()));
    assert_eq!(bus.set_dipole(2, 0.05), Ok(()));
    {
        let mut mcu = h.mcu();
        assert_eq!(mcu.timer_b.duty(3), Some(0.5));
        assert_eq!(mcu.timer_b.duty(4), Some(1.0));
        assert_eq!(mcu.timer_b.duty(5), Some(0.25));
        assert_eq!(mcu.ports[usize::from(P5.output)] & 0b111, 0b101);
    }
    // the fault handler's safe state: every coil channel low, without the bus
    tile_bus::coils_off(&mut h.clone());
    {
        let mut mcu = h.mcu();
        for ch in 3..6 {
            assert_eq!(mcu.timer_b.duty(ch), Some(0.0), "TB{ch}");
        }
    }
    no_violations(&h);
}

#[test]
fn the_element_set_at_reset_is_the_newest_valid_record_else_the_fallback() {
    let sgp4 = |l1: &str, l2: &str| {
        let tle = acs::tle::Tle::parse(l1, l2).unwrap();
        Sgp4::new(&tle, Gravity::Wgs72).unwrap().to_words()
    };
    // the image's set (the flight orbit) and an uplinked one (Vallado's satellite 00005)
    let image = sgp4(
        "1 90101U 25001A   25079.50000000  .00000000  00000-0  00000-0 0  9997",
        "2 90101  97.4000  90.0000 0001000   0.0000   0.0000 15.21936487    10",
    );
    let uplinked = sgp4(
        "1 00005U 58002B   00179.78495062  .00000023  00000-0  28098-4 0  4753",
        "2 00005  34.2682 348.7242 1859667 331.7664  19.3264 10.82419157413667",
    );
    let h = Handle::new();
    let words = |o: Option<Sgp4>| o.map(|o| o.to_words());
    // nothing stored: the image's set
    let (orbit, seq) = store(&h).orbit_or(&image);
    assert_eq!((words(orbit), seq), (Some(image), None));
    // an uplinked set stored: it, at reset
    store(&h).store(&uplinked).unwrap();
    let (orbit, seq) = store(&h).orbit_or(&image);
    assert_eq!((words(orbit), seq), (Some(uplinked), Some(0)));
    // a newer record whose words do not initialise SGP4 (a valid CRC over bad words): the
    // image's set, not the older record (the store's newest is what the ground last sent)
    store(&h).store(&elements(7)).unwrap();
    assert!(Sgp4::from_words(&elements(7)).is_err());
    let (orbit, seq) = store(&h).orbit_or(&image);
    assert_eq!((words(orbit), seq), (Some(image), None));
    // that record corrupted: the older valid one, the uplinked set
    let w = h.mcu().flash.word(0x2400 + 40);
    h.mcu().flash.set_word(0x2400 + 40, w ^ 0x0100);
    let (orbit, seq) = store(&h).orbit_or(&image);
    assert_eq!((words(orbit), seq), (Some(uplinked), Some(0)));
    // neither set checks out: none
    let mut bad = image;
    bad[0] ^= 0xFFFF;
    assert!(Sgp4::from_words(&bad).is_err());
    store(&h).store(&elements(8)).unwrap();
    assert_eq!(words(store(&h).orbit_or(&bad).0), None);
    no_violations(&h);
}
