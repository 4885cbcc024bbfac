//! The flight loop over the driver adapter (`acs::hal::bus::DeviceBus`) with mocked devices
//! (`embedded-hal-mock`): I²C sun sensors, magnetometers and gyros on one bus, PWM + direction
//! pin wheels and coils. Each step is flown twice: by a reference loop over a plain `TileBus`
//! serving the same readings, and by the loop under test over the drivers. The readings reach
//! the loop (the reports are equal, the Sun on the lit tile's normal), the loop's bus calls reach
//! the devices in order (the mocks' strict expectations are built from the reference's calls:
//! every I²C transaction, every duty cycle and direction), and device errors reach the loop as
//! their `ErrorKind` (a spy between the loop and the adapter records what the loop received).

use acs::acs_loop::{StepReport, FAILURES_TO_MARK_FAILED};
use acs::attitude_node::COIL_DECAY_US;
use acs::flight::{FlightLoop, CONFIG, TILES};
use acs::hal::bus::{DeviceBus, TileDevices};
use acs::hal::drivers::{
    I2cGyro, I2cMagnetometer, I2cSunSensor, PwmMagnetorquer, PwmReactionWheel,
};
use acs::hal::{ErrorKind, TileBus};
use acs::orbit::sgp4::Sgp4;
use acs::tiles::TileState;
use acs::time::{Epoch, TimeSpan, Utc};
use embedded_hal::delay::DelayNs;
use embedded_hal::i2c::{ErrorKind as I2cErrorKind, NoAcknowledgeSource};

mod common;
use embedded_hal_mock::eh1::digital::{Mock as PinMock, State, Transaction as PinTx};
use embedded_hal_mock::eh1::i2c::{Mock as I2cMock, Transaction as I2cTx};
use embedded_hal_mock::eh1::pwm::{Mock as PwmMock, Transaction as PwmTx};
use embedded_hal_mock::eh1::MockError;

const COILS: usize = 3;
/// The PWM channels' full scale: a duty count is then the driver's fraction of 10 000.
const MAX_DUTY: u16 = 10_000;
const SUN_REGISTER: u8 = 0x00;
const MAG_REGISTER: u8 = 0x03;
const GYRO_REGISTER: u8 = 0x10;

fn sun_address(tile: usize) -> u8 {
    0x20 + tile as u8
}
fn mag_address(tile: usize) -> u8 {
    0x30 + tile as u8
}
fn gyro_address(tile: usize) -> u8 {
    0x40 + tile as u8
}

/// A device of the satellite.
#[derive(Copy, Clone, Debug, PartialEq)]
enum Device {
    Sun(usize),
    Mag(usize),
    Gyro(usize),
    Wheel(usize),
    Coil(usize),
}

/// What a faulty device does.
#[derive(Copy, Clone, Debug, PartialEq)]
enum Fault {
    /// The I²C address is not acknowledged.
    Nack,
    /// An I²C bus error.
    BusError,
    /// The sensor answers a word at the end of its range.
    Saturated,
    /// The PWM channel refuses its duty cycle.
    PwmError,
}

impl Fault {
    /// The kind the bus must report for it (the drivers' documented mapping).
    fn kind(self) -> ErrorKind {
        match self {
            Fault::Nack => ErrorKind::DeviceAbsent,
            Fault::BusError => ErrorKind::Bus,
            Fault::Saturated => ErrorKind::OutOfRange,
            Fault::PwmError => ErrorKind::Other,
        }
    }
}

/// The readings every device gives (constant over the steps) and the faulty devices.
struct Sky {
    sun: [Option<[i16; 2]>; TILES],
    mag: [[i16; 2]; TILES],
    gyro: [i16; TILES],
    faults: Vec<(Device, Fault)>,
}

impl Sky {
    /// The Sun on tile 1's normal (angles 0, 0), the other tiles dark; a field and rates that
    /// differ per tile (the field of the on-board model's magnitude at the start: the loop
    /// refuses a field of any other).
    fn new(faults: Vec<(Device, Fault)>) -> Self {
        let mut sun = [None; TILES];
        sun[1] = Some([0, 0]);
        let pattern: Vec<[f32; 2]> = (0..TILES)
            .map(|i| [1.0 + 3.0 * i as f32, -2.0 + i as f32])
            .collect();
        let scale = common::field_scale(&pattern, &orbit(), &t0()).unwrap();
        let mut mag = [[0; 2]; TILES];
        let mut gyro = [0; TILES];
        for (i, [x, y]) in pattern.iter().enumerate() {
            mag[i] = [(x * scale).round() as i16, (y * scale).round() as i16];
            gyro[i] = 20 - 7 * i as i16;
        }
        Self {
            sun,
            mag,
            gyro,
            faults,
        }
    }

    fn fault(&self, device: Device) -> Option<Fault> {
        self.faults
            .iter()
            .find(|(d, _)| *d == device)
            .map(|(_, f)| *f)
    }
}

/// One bus call of the loop and what it returned.
#[derive(Copy, Clone, Debug, PartialEq)]
enum Call {
    Sun(usize, Result<Option<[i16; 2]>, ErrorKind>),
    Mag(usize, Result<[i16; 2], ErrorKind>),
    Gyro(usize, Result<i16, ErrorKind>),
    Wheel(usize, f32, Result<(), ErrorKind>),
    Coil(usize, f32, Result<(), ErrorKind>),
}

/// The reference bus: the sky's readings and the faults' kinds, served directly.
struct Reference<'a>(&'a Sky);

impl TileBus for Reference<'_> {
    fn read_sun(&mut self, tile: usize) -> Result<Option<[i16; 2]>, ErrorKind> {
        match self.0.fault(Device::Sun(tile)) {
            Some(f) => Err(f.kind()),
            None => Ok(self.0.sun[tile]),
        }
    }
    fn read_magnetometer(&mut self, tile: usize) -> Result<[i16; 2], ErrorKind> {
        match self.0.fault(Device::Mag(tile)) {
            Some(f) => Err(f.kind()),
            None => Ok(self.0.mag[tile]),
        }
    }
    fn read_gyro(&mut self, tile: usize) -> Result<i16, ErrorKind> {
        match self.0.fault(Device::Gyro(tile)) {
            Some(f) => Err(f.kind()),
            None => Ok(self.0.gyro[tile]),
        }
    }
    fn set_wheel_momentum(&mut self, tile: usize, _: f32) -> Result<(), ErrorKind> {
        self.0
            .fault(Device::Wheel(tile))
            .map_or(Ok(()), |f| Err(f.kind()))
    }
    fn set_dipole(&mut self, coil: usize, _: f32) -> Result<(), ErrorKind> {
        self.0
            .fault(Device::Coil(coil))
            .map_or(Ok(()), |f| Err(f.kind()))
    }
    fn delay_us(&mut self, _: u32) {}
}

/// A bus between the loop and another, recording every call and its result.
struct Spy<B> {
    bus: B,
    calls: Vec<Call>,
}

impl<B: TileBus> TileBus for Spy<B> {
    fn read_sun(&mut self, tile: usize) -> Result<Option<[i16; 2]>, ErrorKind> {
        let r = self.bus.read_sun(tile);
        self.calls.push(Call::Sun(tile, r));
        r
    }
    fn read_magnetometer(&mut self, tile: usize) -> Result<[i16; 2], ErrorKind> {
        let r = self.bus.read_magnetometer(tile);
        self.calls.push(Call::Mag(tile, r));
        r
    }
    fn read_gyro(&mut self, tile: usize) -> Result<i16, ErrorKind> {
        let r = self.bus.read_gyro(tile);
        self.calls.push(Call::Gyro(tile, r));
        r
    }
    fn set_wheel_momentum(&mut self, tile: usize, h: f32) -> Result<(), ErrorKind> {
        let r = self.bus.set_wheel_momentum(tile, h);
        self.calls.push(Call::Wheel(tile, h, r));
        r
    }
    fn set_dipole(&mut self, coil: usize, m: f32) -> Result<(), ErrorKind> {
        let r = self.bus.set_dipole(coil, m);
        self.calls.push(Call::Coil(coil, m, r));
        r
    }
    fn delay_us(&mut self, us: u32) {
        self.bus.delay_us(us);
    }
}

type Wheel = PwmReactionWheel<PwmMock, PinMock>;
type Coil = PwmMagnetorquer<PwmMock, PinMock>;
type Bus = DeviceBus<
    I2cSunSensor<I2cMock>,
    I2cMagnetometer<I2cMock>,
    I2cGyro<I2cMock>,
    Wheel,
    Coil,
    Timer,
    TILES,
    COILS,
>;

/// The board's timer: adds up the waits it is asked, ns.
#[derive(Default)]
struct Timer(u64);

impl DelayNs for Timer {
    fn delay_ns(&mut self, ns: u32) {
        self.0 += u64::from(ns);
    }
}

/// The mocked devices (clones of the mocks inside the drivers: they share the expectations).
struct Mocks {
    i2c: I2cMock,
    wheel_pwm: Vec<PwmMock>,
    wheel_dir: Vec<PinMock>,
    coil_pwm: Vec<PwmMock>,
    coil_dir: Vec<PinMock>,
}

/// The adapter over the flight configuration's devices: tile 0 (telecom) has none, tiles 1–5
/// every device on one I²C bus, a PWM wheel each; three PWM coils.
fn board() -> (Bus, Mocks) {
    let i2c = I2cMock::new(&[]);
    let mut mocks = Mocks {
        i2c: i2c.clone(),
        wheel_pwm: Vec::new(),
        wheel_dir: Vec::new(),
        coil_pwm: Vec::new(),
        coil_dir: Vec::new(),
    };
    let tiles: [TileDevices<_, _, _, Wheel>; TILES] = std::array::from_fn(|i| {
        let pwm = PwmMock::new(&[]);
        let dir = PinMock::new(&[]);
        mocks.wheel_pwm.push(pwm.clone());
        mocks.wheel_dir.push(dir.clone());
        if !CONFIG.tiles[i].equipment.sun_sensor {
            return TileDevices::none();
        }
        TileDevices::new(
            I2cSunSensor::new(i2c.clone(), sun_address(i), SUN_REGISTER),
            I2cMagnetometer::new(i2c.clone(), mag_address(i), MAG_REGISTER),
            I2cGyro::new(i2c.clone(), gyro_address(i), GYRO_REGISTER),
            PwmReactionWheel::new(pwm, dir, CONFIG.wheel_limit_nms),
        )
    });
    let coils: [Option<Coil>; COILS] = std::array::from_fn(|c| {
        let pwm = PwmMock::new(&[]);
        let dir = PinMock::new(&[]);
        mocks.coil_pwm.push(pwm.clone());
        mocks.coil_dir.push(dir.clone());
        Some(PwmMagnetorquer::new(pwm, dir, CONFIG.coils[c].limit))
    });
    (DeviceBus::new(tiles, coils, Timer::default()), mocks)
}

fn bytes(words: &[i16]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_be_bytes()).collect()
}

/// The I²C transaction of a read from `address`: `words` answered, or the fault's error.
fn read(address: u8, register: u8, words: &[i16], fault: Option<Fault>) -> I2cTx {
    let tx = I2cTx::write_read(address, vec![register], bytes(words));
    match fault {
        Some(Fault::Nack) => {
            tx.with_error(I2cErrorKind::NoAcknowledge(NoAcknowledgeSource::Address))
        }
        Some(Fault::BusError) => tx.with_error(I2cErrorKind::Bus),
        _ => tx,
    }
}

/// The PWM and pin transactions of a bridge commanded to `value` of full scale `limit`: the
/// direction pin (high for `value ≥ 0`), then the duty `|value| / limit` of full scale rounded
/// to 1/10 000 (the drivers' contract); a refusal by the PWM channel when `fault` says so.
fn bridge(value: f32, limit: f32, fault: Option<Fault>) -> (Vec<PwmTx>, Vec<PinTx>) {
    assert!(
        value.is_finite() && value.abs() <= limit,
        "{value} beyond {limit}"
    );
    let duty = (value.abs() / limit * 10_000.0 + 0.5) as u16;
    let pin = vec![PinTx::set(if value >= 0.0 {
        State::High
    } else {
        State::Low
    })];
    let mut set = PwmTx::set_duty_cycle(duty);
    if fault == Some(Fault::PwmError) {
        set = set.with_error(MockError::Io(std::io::ErrorKind::Other));
    }
    (vec![PwmTx::max_duty_cycle(MAX_DUTY), set], pin)
}

/// Sets the mocks' expectations for one step from the reference loop's calls (the previous
/// step's expectations must all have been met).
fn expect(mocks: &mut Mocks, sky: &Sky, calls: &[Call]) {
    let mut i2c = Vec::new();
    let mut wheel_pwm = vec![Vec::new(); TILES];
    let mut wheel_dir = vec![Vec::new(); TILES];
    let mut coil_pwm = vec![Vec::new(); COILS];
    let mut coil_dir = vec![Vec::new(); COILS];
    for call in calls {
        match *call {
            Call::Sun(i, _) => {
                let fault = sky.fault(Device::Sun(i));
                let words = match (fault, sky.sun[i]) {
                    (Some(Fault::Saturated), _) => [1, i16::MAX, 0],
                    (_, Some([a, b])) => [1, a, b],
                    (_, None) => [0, 0, 0],
                };
                i2c.push(read(sun_address(i), SUN_REGISTER, &words, fault));
            }
            Call::Mag(i, _) => {
                let fault = sky.fault(Device::Mag(i));
                let words = if fault == Some(Fault::Saturated) {
                    [i16::MIN, 0]
                } else {
                    sky.mag[i]
                };
                i2c.push(read(mag_address(i), MAG_REGISTER, &words, fault));
            }
            Call::Gyro(i, _) => {
                let fault = sky.fault(Device::Gyro(i));
                let words = if fault == Some(Fault::Saturated) {
                    [i16::MAX]
                } else {
                    [sky.gyro[i]]
                };
                i2c.push(read(gyro_address(i), GYRO_REGISTER, &words, fault));
            }
            Call::Wheel(i, h, _) => {
                let (pwm, pin) = bridge(h, CONFIG.wheel_limit_nms, sky.fault(Device::Wheel(i)));
                wheel_pwm[i].extend(pwm);
                wheel_dir[i].extend(pin);
            }
            Call::Coil(c, m, _) => {
                let (pwm, pin) = bridge(m, CONFIG.coils[c].limit, sky.fault(Device::Coil(c)));
                coil_pwm[c].extend(pwm);
                coil_dir[c].extend(pin);
            }
        }
    }
    mocks.i2c.update_expectations(&i2c);
    for (mock, tx) in mocks.wheel_pwm.iter_mut().zip(&wheel_pwm) {
        mock.update_expectations(tx);
    }
    for (mock, tx) in mocks.wheel_dir.iter_mut().zip(&wheel_dir) {
        mock.update_expectations(tx);
    }
    for (mock, tx) in mocks.coil_pwm.iter_mut().zip(&coil_pwm) {
        mock.update_expectations(tx);
    }
    for (mock, tx) in mocks.coil_dir.iter_mut().zip(&coil_dir) {
        mock.update_expectations(tx);
    }
}

/// Checks that every expectation was met.
fn done(mocks: &mut Mocks) {
    mocks.i2c.done();
    mocks.wheel_pwm.iter_mut().for_each(PwmMock::done);
    mocks.wheel_dir.iter_mut().for_each(PinMock::done);
    mocks.coil_pwm.iter_mut().for_each(PwmMock::done);
    mocks.coil_dir.iter_mut().for_each(PinMock::done);
}

/// The first step's epoch.
fn t0() -> Epoch<Utc> {
    Epoch::<Utc>::from_parts(9_210, 43_260, 0).unwrap()
}

fn orbit() -> Sgp4 {
    common::flight_orbit()
}

/// What one step of both loops did.
struct Flown {
    reference: StepReport,
    adapter: StepReport,
    calls: Vec<Call>,
}

/// Flies `steps` steps under `sky`: the reference loop, then the loop over the adapter with the
/// mocks expecting the reference's calls; checks at each step that both loops made the same bus
/// calls with the same results and reported the same. Returns the steps and the loop under test.
fn fly(sky: &Sky, steps: i32) -> (Vec<Flown>, FlightLoop) {
    let mut reference = FlightLoop::new(&CONFIG, orbit()).unwrap();
    let mut under_test = FlightLoop::new(&CONFIG, orbit()).unwrap();
    let (bus, mut mocks) = board();
    let mut spy = Spy {
        bus,
        calls: Vec::new(),
    };
    let t0 = t0();
    let mut flown = Vec::new();
    for k in 0..steps {
        let now = t0.add(TimeSpan::new(k, 0));
        let mut recorder = Spy {
            bus: Reference(sky),
            calls: Vec::new(),
        };
        let expected = reference.step(&mut recorder, now, 1.0);
        expect(&mut mocks, sky, &recorder.calls);
        spy.calls.clear();
        let report = under_test.step(&mut spy, now, 1.0);
        assert_eq!(spy.calls, recorder.calls, "step {k}: bus calls");
        assert_eq!(report, expected, "step {k}: report");
        flown.push(Flown {
            reference: expected,
            adapter: report,
            calls: spy.calls.clone(),
        });
    }
    done(&mut mocks);
    // the board's timer waited the attitude node's coil decay once a step
    let (_, _, timer) = spy.bus.release();
    let steps = u64::try_from(steps).unwrap_or(0);
    assert_eq!(timer.0, steps * u64::from(COIL_DECAY_US) * 1_000);
    (flown, under_test)
}

#[test]
fn the_loop_steps_over_mocked_drivers() {
    let sky = Sky::new(Vec::new());
    let (flown, acs) = fly(&sky, 6);
    for (k, f) in flown.iter().enumerate() {
        let r = &f.adapter;
        assert_eq!(r.faults.bits(), f.reference.faults.bits());
        assert!(
            !r.faults.device_read && !r.faults.actuator,
            "step {k}: {:?}",
            r.faults
        );
        // the readings reached the loop: the Sun on tile 1's normal, a field, a rate
        let sun = r.sun_body.expect("Sun seen");
        assert!((sun - CONFIG.tiles[1].normal_body()).norm() < 1e-6, "{sun}");
        assert!(
            r.b_body_nt.is_some() && r.omega_body_radps.is_some(),
            "{r:?}"
        );
        // every powered tile's three sensors were read, and every coil commanded
        for i in 1..TILES {
            assert!(f.calls.contains(&Call::Sun(i, Ok(sky.sun[i]))));
            assert!(f.calls.contains(&Call::Mag(i, Ok(sky.mag[i]))));
            assert!(f.calls.contains(&Call::Gyro(i, Ok(sky.gyro[i]))));
        }
        for c in 0..COILS {
            assert!(f
                .calls
                .iter()
                .any(|x| matches!(x, Call::Coil(cc, _, Ok(())) if *cc == c)));
        }
    }
    // commands beyond zero reached the devices (each one a duty cycle the mocks checked)
    let commanded = |f: &Flown| {
        f.calls.iter().any(|c| match c {
            Call::Wheel(_, h, _) => *h != 0.0,
            Call::Coil(_, m, _) => *m != 0.0,
            _ => false,
        })
    };
    assert!(flown.iter().any(commanded), "no non-zero command");
    assert!((0..TILES).all(|i| acs.tile_state(i) == Some(TileState::Working)));
}

#[test]
fn device_errors_reach_the_loop_as_their_kind() {
    let sky = Sky::new(vec![
        (Device::Mag(2), Fault::Nack),
        (Device::Gyro(3), Fault::BusError),
        (Device::Sun(4), Fault::Saturated),
        (Device::Coil(1), Fault::PwmError),
    ]);
    let steps = i32::from(FAILURES_TO_MARK_FAILED) + 2;
    let (flown, acs) = fly(&sky, steps);
    let first = &flown[0];
    // what the loop received from the adapter
    assert!(first
        .calls
        .contains(&Call::Mag(2, Err(ErrorKind::DeviceAbsent))));
    assert!(first.calls.contains(&Call::Gyro(3, Err(ErrorKind::Bus))));
    assert!(first
        .calls
        .contains(&Call::Sun(4, Err(ErrorKind::OutOfRange))));
    assert!(first
        .calls
        .iter()
        .any(|c| matches!(c, Call::Coil(1, _, Err(ErrorKind::Other)))));
    assert!(first.adapter.faults.device_read && first.adapter.faults.actuator);
    // a tile that keeps failing is out of service, and no longer read
    for i in [2, 3, 4] {
        assert_eq!(acs.tile_state(i), Some(TileState::Failed), "tile {i}");
    }
    for i in [1, 5] {
        assert_eq!(acs.tile_state(i), Some(TileState::Working), "tile {i}");
    }
    let last = flown.last().unwrap();
    assert!(!last.calls.iter().any(|c| matches!(
        c,
        Call::Sun(2..=4, _) | Call::Mag(2..=4, _) | Call::Gyro(2..=4, _)
    )));
    assert!(last.adapter.faults.actuator && !last.adapter.faults.device_read);
}
