//! The two nodes composed (`acs::two_node::TwoNodeLoop`: reference node, attitude node, their
//! messages as bytes) command what the one-image loop (`acs::acs_loop::AcsLoop`) commands, bit
//! for bit, at every step of the closed-loop scenarios under the realistic truth (issue #29): the
//! one-image loop flies the simulator through a recording bus, and the composition is stepped
//! on the same calls replayed, so it reads exactly what the loop read; every bus call (which
//! device, which command value) and every step's report must be the same. The composition's
//! attitude node also waits [`COIL_DECAY_US`] between switching the coils off and its first
//! read, each step (issue #29, item 4).

use std::collections::VecDeque;

use acs::acs_loop::{AcsLoop, StepReport};
use acs::attitude::Quaternion;
use acs::attitude_node::COIL_DECAY_US;
use acs::env::igrf::FULL_COEFFS;
use acs::flight::CONFIG;
use acs::hal::{ErrorKind, TileBus};
use acs::host::sim::realistic::TruthLevel;
use acs::host::sim::scenarios::{self, Satellite, Scenario};
use acs::two_node::TwoNodeLoop;

/// One bus call and what it returned (command values as their bits).
#[derive(Clone, Debug, PartialEq)]
enum Call {
    Sun(usize, Result<Option<[i16; 2]>, ErrorKind>),
    Mag(usize, Result<[i16; 2], ErrorKind>),
    Gyro(usize, Result<i16, ErrorKind>),
    Wheel(usize, u32, Result<(), ErrorKind>),
    Dipole(usize, u32, Result<(), ErrorKind>),
    WheelRead(usize, Result<Option<i16>, ErrorKind>),
    CoilRead(usize, Result<Option<i16>, ErrorKind>),
}

/// The simulator's bus, every call recorded.
struct Record<'a, B: TileBus> {
    bus: &'a mut B,
    calls: Vec<Call>,
}

impl<B: TileBus> TileBus for Record<'_, B> {
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
    fn set_wheel_momentum(&mut self, tile: usize, h_nms: f32) -> Result<(), ErrorKind> {
        let r = self.bus.set_wheel_momentum(tile, h_nms);
        self.calls.push(Call::Wheel(tile, h_nms.to_bits(), r));
        r
    }
    fn set_dipole(&mut self, coil: usize, m_am2: f32) -> Result<(), ErrorKind> {
        let r = self.bus.set_dipole(coil, m_am2);
        self.calls.push(Call::Dipole(coil, m_am2.to_bits(), r));
        r
    }
    fn read_wheel_momentum(&mut self, tile: usize) -> Result<Option<i16>, ErrorKind> {
        let r = self.bus.read_wheel_momentum(tile);
        self.calls.push(Call::WheelRead(tile, r));
        r
    }
    fn read_coil_dipole(&mut self, coil: usize) -> Result<Option<i16>, ErrorKind> {
        let r = self.bus.read_coil_dipole(coil);
        self.calls.push(Call::CoilRead(coil, r));
        r
    }
    fn delay_us(&mut self, us: u32) {
        self.bus.delay_us(us);
    }
}

/// The recorded calls replayed: each call must be the recorded one (the same device, the same
/// command bits) and gets its recorded answer.
struct Replay {
    calls: VecDeque<Call>,
    step: usize,
    /// The composition's calls in order: `b` a coil read-back, `c` a coil command, `w` a wait,
    /// `r` a read (a wheel's read-back included), `m` a wheel command.
    order: String,
}

impl Replay {
    fn next(&mut self, call: Call) -> Call {
        self.order.push(match call {
            Call::Sun(..) | Call::Mag(..) | Call::Gyro(..) | Call::WheelRead(..) => 'r',
            Call::CoilRead(..) => 'b',
            Call::Wheel(..) => 'm',
            Call::Dipole(..) => 'c',
        });
        let recorded = self.calls.pop_front();
        let same = match (&recorded, &call) {
            (Some(Call::Sun(a, _)), Call::Sun(b, _))
            | (Some(Call::Mag(a, _)), Call::Mag(b, _))
            | (Some(Call::Gyro(a, _)), Call::Gyro(b, _))
            | (Some(Call::WheelRead(a, _)), Call::WheelRead(b, _))
            | (Some(Call::CoilRead(a, _)), Call::CoilRead(b, _)) => a == b,
            (Some(r), c) => r == c,
            (None, _) => false,
        };
        assert!(
            same,
            "step {}: the composition called {call:?}, the loop {recorded:?}",
            self.step
        );
        recorded.unwrap_or(call)
    }
}

impl TileBus for Replay {
    fn read_sun(&mut self, tile: usize) -> Result<Option<[i16; 2]>, ErrorKind> {
        match self.next(Call::Sun(tile, Ok(None))) {
            Call::Sun(_, r) => r,
            _ => Err(ErrorKind::Other),
        }
    }
    fn read_magnetometer(&mut self, tile: usize) -> Result<[i16; 2], ErrorKind> {
        match self.next(Call::Mag(tile, Ok([0, 0]))) {
            Call::Mag(_, r) => r,
            _ => Err(ErrorKind::Other),
        }
    }
    fn read_gyro(&mut self, tile: usize) -> Result<i16, ErrorKind> {
        match self.next(Call::Gyro(tile, Ok(0))) {
            Call::Gyro(_, r) => r,
            _ => Err(ErrorKind::Other),
        }
    }
    fn set_wheel_momentum(&mut self, tile: usize, h_nms: f32) -> Result<(), ErrorKind> {
        let call = Call::Wheel(tile, h_nms.to_bits(), Ok(()));
        match self.next(call) {
            Call::Wheel(_, _, r) => r,
            _ => Err(ErrorKind::Other),
        }
    }
    fn set_dipole(&mut self, coil: usize, m_am2: f32) -> Result<(), ErrorKind> {
        match self.next(Call::Dipole(coil, m_am2.to_bits(), Ok(()))) {
            Call::Dipole(_, _, r) => r,
            _ => Err(ErrorKind::Other),
        }
    }
    fn read_wheel_momentum(&mut self, tile: usize) -> Result<Option<i16>, ErrorKind> {
        match self.next(Call::WheelRead(tile, Ok(None))) {
            Call::WheelRead(_, r) => r,
            _ => Err(ErrorKind::Other),
        }
    }
    fn read_coil_dipole(&mut self, coil: usize) -> Result<Option<i16>, ErrorKind> {
        match self.next(Call::CoilRead(coil, Ok(None))) {
            Call::CoilRead(_, r) => r,
            _ => Err(ErrorKind::Other),
        }
    }
    fn delay_us(&mut self, us: u32) {
        // the one wait of a step, the attitude node's (item 4 of issue #29)
        assert_eq!(us, COIL_DECAY_US, "step {}", self.step);
        self.order.push('w');
    }
}

/// Flies `scenario` (at most `max_steps`) with both; returns the steps compared.
fn compare<const N: usize, const F: usize>(
    scenario: &Scenario,
    one: &mut AcsLoop<'_, N, F>,
    two: &mut TwoNodeLoop<'_, N, F>,
    max_steps: usize,
) -> usize {
    let mut sim = scenario.simulator().unwrap();
    let dt_s = scenario.dt_s;
    let steps = ((scenario.duration_s / dt_s).round() as usize).min(max_steps);
    let mut pending = scenario.commands.clone();
    let mut last: Option<Quaternion> = None;
    for step in 0..steps {
        let t = sim.truth().t_s;
        let now = sim.epoch_at(t);
        while let Some(k) = pending.iter().position(|(at, _)| *at <= t) {
            let (_, c) = pending.remove(k);
            let a = one.command(c, last.as_ref(), now);
            let b = two.command(c, last.as_ref(), now);
            assert_eq!(a, b, "{}: command at step {step}", scenario.name);
        }
        let mut record = Record {
            bus: &mut sim,
            calls: Vec::new(),
        };
        let mut r1 = StepReport::empty(one.mode());
        one.step_into(&mut record, now, dt_s as f32, &mut r1);
        let mut replay = Replay {
            calls: record.calls.into(),
            step,
            order: String::new(),
        };
        let mut r2 = StepReport::empty(two.mode());
        two.step_into(&mut replay, now, dt_s as f32, &mut r2);
        assert!(replay.calls.is_empty(), "{}: step {step}", scenario.name);
        // the composition reads its coils back (`b`), switches every coil off (the thesis
        // satellite has none), waits once, then reads (the one-image loop makes the same calls
        // without the wait: its models ran between the two)
        let after_coils = replay.order.trim_start_matches(['b', 'c']);
        assert!(
            after_coils.starts_with("wr"),
            "{}: step {step}: {}",
            scenario.name,
            replay.order
        );
        assert_eq!(replay.order.matches('w').count(), 1);
        // bit for bit: the debug form prints every f32 exactly (and -0.0 as such)
        assert_eq!(
            format!("{r1:?}"),
            format!("{r2:?}"),
            "{}: step {step}",
            scenario.name
        );
        last = r1.attitude;
        sim.advance(dt_s).unwrap();
    }
    steps
}

#[test]
fn the_composition_commands_what_the_one_image_loop_commands() {
    let all = [
        scenarios::detumble(),
        scenarios::sun_safe(),
        scenarios::tracking(None),
        scenarios::slew(),
        scenarios::thesis_slew(false),
    ];
    for scenario in all {
        let scenario = scenario.unwrap().with_truth(TruthLevel::Realistic);
        let orbit = scenario.orbit().unwrap();
        let steps = match &scenario.flight {
            Satellite::Flight => {
                let mut one = acs::flight::OneImageLoop::new(&CONFIG, orbit.clone()).unwrap();
                let mut two =
                    TwoNodeLoop::<{ acs::flight::TILES }, { acs::flight::FIELD_COEFFS }>::new(
                        &CONFIG, orbit,
                    )
                    .unwrap();
                compare(&scenario, &mut one, &mut two, 1_500)
            }
            Satellite::Thesis(config) => {
                let mut one =
                    AcsLoop::<{ acs::flight::TILES }, FULL_COEFFS>::new(config, orbit.clone())
                        .unwrap();
                let mut two =
                    TwoNodeLoop::<{ acs::flight::TILES }, FULL_COEFFS>::new(config, orbit).unwrap();
                compare(&scenario, &mut one, &mut two, 3_000)
            }
        };
        println!("{}: {steps} steps bit for bit", scenario.name);
    }
}

/// Over a link that drops every packet the attitude node flies without a REF (the link fault);
/// after a reset the reference node has no clock (its REF says so) until the next STATUS brings
/// the attitude node's back, the step after: from then on the REFs are those of a composition
/// never reset, with the clock it was given (`TwoNodeLoop::step_over_link`, `reset_reference`,
/// as the PIL flies the two node images).
#[test]
fn the_reference_node_gets_its_clock_back_from_a_status_after_a_reset() {
    use acs::link::messages::Reference;
    type Flight<'c> = TwoNodeLoop<'c, { acs::flight::TILES }, { acs::flight::FIELD_COEFFS }>;
    let scenario = scenarios::tracking(None)
        .unwrap()
        .with_truth(TruthLevel::Realistic);
    let orbit = scenario.orbit().unwrap();
    let mut sim = scenario.simulator().unwrap();
    let mut linked = Flight::new(&CONFIG, orbit.clone()).unwrap();
    let mut reset = linked.clone();
    let start = sim.epoch_at(sim.truth().t_s);
    linked.reference_node_mut().set_clock(start);
    reset.reference_node_mut().set_clock(start);
    let dt_s = scenario.dt_s as f32;
    let reference = |l: &Flight<'_>| Reference::from_packet(l.packets().0).unwrap().0;
    for step in 0..12u32 {
        let now = sim.epoch_at(sim.truth().t_s);
        let mut record = Record {
            bus: &mut sim,
            calls: Vec::new(),
        };
        let mut r1 = StepReport::empty(linked.mode());
        linked.step_over_link(&mut record, dt_s, &mut r1, |_, _| true);
        assert_eq!(reference(&linked).utc, now, "step {step}");
        assert!(!r1.faults.link, "step {step}");
        if step == 8 {
            reset.reset_reference(orbit.clone()).unwrap();
        }
        let mut replay = Replay {
            calls: record.calls.into(),
            step: step as usize,
            order: String::new(),
        };
        let mut r2 = StepReport::empty(reset.mode());
        // steps 5 to 7: every packet lost
        let lost = (5..8).contains(&step);
        reset.step_over_link(&mut replay, dt_s, &mut r2, |_, _| !lost);
        let r = reference(&reset);
        match step {
            5..=7 => assert!(r2.faults.link && r.clock_valid, "step {step}"),
            // the reset: no clock, and its REF counts its steps from 0
            8 => assert!(r2.faults.link && !r.clock_valid && r.step == 0),
            _ => {
                assert!(!r2.faults.link && r.clock_valid, "step {step}");
                assert_eq!((r.step, r.utc), (step, now), "step {step}");
            }
        }
        if step >= 10 {
            // the same REF as the composition never reset, but for its sequence count
            assert_eq!(reference(&linked).to_bytes(), r.to_bytes(), "step {step}");
        }
        sim.advance(scenario.dt_s).unwrap();
    }
}
