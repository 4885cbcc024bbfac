//! The loop's mode machine, transition by transition (issue 19 item 3): a table of (mode before,
//! what happens, mode after), each row run on the flight loop (`FlightLoop` over `CONFIG`) with a
//! scripted tile bus. Every transition is made by one function, `attitude_node::modes::next_mode`,
//! from the events the step finds (rates, attitude lost, a plan done), the ground's sun-safe and
//! the reference node's guidance (track and slew commands, taken at the next step); its own
//! table of every (mode, event) pair is the unit test `attitude_node::modes::tests::next_mode_table`.

use acs::acs_loop::{AcsError, Command, Mode, StepReport, INVALID_STEPS_TO_SAFE};
use acs::attitude::{Dcm, Quaternion};
use acs::flight::{FlightLoop, CONFIG};
use acs::host::sim::realistic::TruthLevel;
use acs::host::sim::scenarios;
use acs::time::{Epoch, TimeSpan, Utc};

mod common;

/// Raw gyro words: every tile reads `gyro`, so the rate is `gyro`·1e-4 rad/s about U (the only
/// gyro on U, tile 3, −U, reads −ω_U; the opposite pairs on V and W cancel).
const STILL: i16 = 0; // 0 rad/s: below the detumble exit rate (0.0087 rad/s)
const SLOW: i16 = 200; // 0.02 rad/s: between the exit and entry rates (hysteresis)
const FAST: i16 = 10_000; // 1 rad/s: above the detumble entry rate (0.5 rad/s)

/// The magnetometers' words before scaling: a fixed direction in the body.
fn mag_pattern() -> Vec<[f32; 2]> {
    (0..6).map(|t| [100.0 + 300.0 * t as f32, -200.0]).collect()
}

/// A scripted tile bus: every gyro reads `gyro`, the magnetometers a fixed field direction
/// with the on-board model's magnitude (`scale` × [`mag_pattern`]: the loop refuses a field of
/// any other), tile 1's Sun sensor the Sun on its normal when `sun`; without `sun` no Sun and a
/// field three times too strong, which the loop refuses: no measurement at all.
struct Scripted {
    gyro: i16,
    sun: bool,
    scale: f32,
}

impl acs::hal::TileBus for Scripted {
    fn read_sun(&mut self, tile: usize) -> Result<Option<[i16; 2]>, acs::hal::ErrorKind> {
        Ok((self.sun && tile == 1).then_some([0, 0]))
    }
    fn read_magnetometer(&mut self, tile: usize) -> Result<[i16; 2], acs::hal::ErrorKind> {
        let [x, y] = mag_pattern()[tile];
        let scale = if self.sun {
            self.scale
        } else {
            3.0 * self.scale
        };
        Ok([(x * scale).round() as i16, (y * scale).round() as i16])
    }
    fn read_gyro(&mut self, _: usize) -> Result<i16, acs::hal::ErrorKind> {
        Ok(self.gyro)
    }
    fn set_wheel_momentum(&mut self, _: usize, _: f32) -> Result<(), acs::hal::ErrorKind> {
        Ok(())
    }
    fn set_dipole(&mut self, _: usize, _: f32) -> Result<(), acs::hal::ErrorKind> {
        Ok(())
    }
    fn delay_us(&mut self, _: u32) {}
}

/// What happens in a row.
#[derive(Clone, Copy, Debug)]
enum Event {
    /// Steps with this gyro word and Sun, `n` of them.
    Steps {
        gyro: i16,
        sun: bool,
        n: u32,
    },
    /// Steps (still, Sun seen) until the mode changes, at most `n`.
    UntilChange {
        n: u32,
    },
    /// Ground commands: sun-safe, track, slew (2° from the attitude now).
    SafeCmd,
    TrackCmd,
    SlewCmd,
    /// A slew commanded without an attitude to plan from (refused, nothing changes).
    SlewCmdWithoutAttitude,
}

/// A loop at the start of a row: a fresh loop brought to `mode` with the Sun seen and no rate.
struct Rig {
    acs: FlightLoop,
    orbit: acs::orbit::sgp4::Sgp4,
    t: i32,
    t0: Epoch<Utc>,
    report: StepReport,
    target: Quaternion,
}

impl Rig {
    fn new(mode: Mode) -> Self {
        let scenario = scenarios::tracking(None)
            .unwrap()
            .with_truth(TruthLevel::Ideal);
        let tle = acs::tle::Tle::parse(&scenario.sim.tle.0, &scenario.sim.tle.1).unwrap();
        let orbit = acs::orbit::sgp4::Sgp4::new(&tle, scenario.gravity).unwrap();
        let t0 = tle.epoch.add(TimeSpan::new(60, 0));
        let mut rig = Self {
            acs: FlightLoop::new(&CONFIG, orbit.clone()).unwrap(),
            orbit,
            t: 0,
            t0,
            report: StepReport::empty(Mode::Detumble),
            target: Quaternion::IDENTITY,
        };
        assert_eq!(rig.acs.mode(), Mode::Detumble);
        // the attitude the still, lit bus gives: the target of the rows (small errors)
        rig.steps(STILL, true, 1);
        rig.target = rig
            .report
            .attitude
            .expect("an attitude from the Sun and the field");
        match mode {
            Mode::Detumble => rig.event(steps(FAST, true, 1)),
            Mode::SunSafe => {}
            Mode::Tracking => {
                rig.event(Event::TrackCmd);
                rig.deliver(&Event::TrackCmd);
            }
            Mode::Slew => {
                rig.event(Event::SlewCmd);
                rig.deliver(&Event::SlewCmd);
            }
        }
        assert_eq!(rig.acs.mode(), mode, "set-up");
        rig
    }

    /// A track or slew command is the reference node's: the attitude node takes it from the
    /// next step's REF, so one step (still, Sun seen) follows it; the other events act at once.
    fn deliver(&mut self, e: &Event) {
        if matches!(e, Event::TrackCmd | Event::SlewCmd) {
            self.steps(STILL, true, 1);
        }
    }

    fn steps(&mut self, gyro: i16, sun: bool, n: u32) {
        let pattern = mag_pattern();
        for _ in 0..n {
            let now = self.t0.add(TimeSpan::new(self.t, 0));
            let scale = common::field_scale(&pattern, &self.orbit, &now).unwrap();
            let mut bus = Scripted { gyro, sun, scale };
            self.acs.step_into(&mut bus, now, 1.0, &mut self.report);
            self.t += 1;
        }
    }

    fn event(&mut self, e: Event) {
        let now = self.t0.add(TimeSpan::new(self.t, 0));
        match e {
            Event::Steps { gyro, sun, n } => self.steps(gyro, sun, n),
            Event::UntilChange { n } => {
                let before = self.acs.mode();
                for _ in 0..n {
                    self.steps(STILL, true, 1);
                    if self.acs.mode() != before {
                        break;
                    }
                }
            }
            Event::SafeCmd => self.acs.command(Command::SunSafe, None, now).unwrap(),
            Event::TrackCmd => self
                .acs
                .command(
                    Command::Track {
                        target: self.target,
                    },
                    None,
                    now,
                )
                .unwrap(),
            Event::SlewCmd => {
                let attitude = self.report.attitude.expect("an attitude to plan from");
                // 2° about the body's first axis from the attitude now
                let target = Dcm::from_matrix_unchecked(
                    *Dcm::a1(2f32.to_radians()).matrix() * *attitude.to_dcm().matrix(),
                );
                self.acs
                    .command(
                        Command::Slew {
                            target,
                            within_s: 300.0,
                        },
                        Some(&attitude),
                        now,
                    )
                    .unwrap();
            }
            Event::SlewCmdWithoutAttitude => {
                let refused = self.acs.command(
                    Command::Slew {
                        target: Dcm::identity(),
                        within_s: 300.0,
                    },
                    None,
                    now,
                );
                assert_eq!(refused, Err(AcsError::CannotSlew));
            }
        }
    }
}

/// `Event::Steps`, shorter for the table.
fn steps(gyro: i16, sun: bool, n: u32) -> Event {
    Event::Steps { gyro, sun, n }
}

/// Steps without any measurement until the filter's estimate is no longer usable (its attitude
/// 1σ past `max_attitude_sigma_rad`), from a loop tracking with the Sun and the field.
fn unaided_steps() -> u32 {
    let mut rig = Rig::new(Mode::Tracking);
    let mut n = 0;
    while rig.report.attitude.is_some() {
        rig.steps(STILL, false, 1);
        n += 1;
        assert!(n < 100_000, "the estimate never expires");
    }
    // a minute at least (the complementary filter it replaced bridged 120 s)
    assert!(n > 60, "{n}");
    n
}

#[test]
fn every_transition_of_the_mode_machine() {
    use Event::*;
    use Mode::*;
    // without a measurement the filter bridges on the gyros until its attitude 1σ passes its
    // limit; then the loop waits INVALID_STEPS_TO_SAFE steps without attitude before it gives up
    let bridge = unaided_steps() - 1;
    let lost = bridge + INVALID_STEPS_TO_SAFE as u32 + 2;
    #[rustfmt::skip]
    let table: &[(Mode, Event, Mode, &str)] = &[
        // rates (change_mode)
        (Detumble, steps(STILL, true, 1), SunSafe, "rate below the exit rate"),
        (Detumble, steps(SLOW, true, 5), Detumble, "hysteresis: between the rates"),
        (Detumble, steps(FAST, true, 5), Detumble, "still tumbling"),
        (SunSafe, steps(FAST, true, 1), Detumble, "rate above the entry rate"),
        (SunSafe, steps(SLOW, true, 5), SunSafe, "hysteresis: between the rates"),
        (SunSafe, steps(STILL, false, 2 * lost), SunSafe, "no attitude: stays"),
        (Tracking, steps(FAST, true, 1), Detumble, "rate above the entry rate"),
        (Slew, steps(FAST, true, 1), Detumble, "rate above the entry rate"),
        // attitude lost (change_mode)
        (Tracking, steps(STILL, false, bridge), Tracking, "bridged on the gyros"),
        (Tracking, steps(STILL, false, lost), SunSafe, "attitude lost"),
        (Slew, steps(STILL, false, lost), SunSafe, "attitude lost"),
        (Tracking, steps(STILL, true, 2 * lost), Tracking, "attitude kept"),
        // the slew's plan (laws)
        (Slew, UntilChange { n: 2_000 }, Tracking, "plan done: tracks its target"),
        // the ground (command)
        (Detumble, SafeCmd, SunSafe, "command"),
        (Detumble, TrackCmd, Tracking, "command"),
        (SunSafe, TrackCmd, Tracking, "command"),
        (SunSafe, SlewCmd, Slew, "command"),
        (SunSafe, SlewCmdWithoutAttitude, SunSafe, "refused: no attitude"),
        (Tracking, SafeCmd, SunSafe, "command"),
        (Tracking, SlewCmd, Slew, "command"),
        (Tracking, SlewCmdWithoutAttitude, Tracking, "refused: no attitude"),
        (Slew, SafeCmd, SunSafe, "command"),
        (Slew, TrackCmd, Tracking, "command"),
        (Slew, SlewCmd, Slew, "a new plan"),
    ];
    let mut seen = std::collections::HashSet::new();
    for (k, (before, event, after, what)) in table.iter().enumerate() {
        let mut rig = Rig::new(*before);
        rig.event(*event);
        rig.deliver(event);
        assert_eq!(
            rig.acs.mode(),
            *after,
            "row {k}: {before:?} + {event:?} ({what})"
        );
        seen.insert((*before as u8, *after as u8));
    }
    // every mode is left and entered
    for m in [Detumble, SunSafe, Slew, Tracking] {
        assert!(
            seen.iter().any(|(b, a)| *b == m as u8 && *a != m as u8),
            "{m:?} left"
        );
        assert!(
            seen.iter().any(|(b, a)| *a == m as u8 && *b != m as u8),
            "{m:?} entered"
        );
    }
}

/// A ground command starts the count of steps without attitude afresh: after a fall-back to
/// `SunSafe` (the count at `INVALID_STEPS_TO_SAFE`), a `TRACK` commanded while the attitude is
/// still missing keeps `Tracking` for `INVALID_STEPS_TO_SAFE` steps again (before, the count
/// carried over and the first step without attitude sent the loop straight back).
#[test]
fn a_command_restarts_the_count_of_steps_without_attitude() {
    let lost = unaided_steps() + INVALID_STEPS_TO_SAFE as u32 + 1;
    let mut rig = Rig::new(Mode::Tracking);
    rig.event(steps(STILL, false, lost));
    assert_eq!(rig.acs.mode(), Mode::SunSafe, "fell back");
    rig.event(Event::TrackCmd);
    rig.event(steps(STILL, false, INVALID_STEPS_TO_SAFE as u32 - 1));
    assert_eq!(rig.acs.mode(), Mode::Tracking, "a fresh count");
    rig.event(steps(STILL, false, 1));
    assert_eq!(rig.acs.mode(), Mode::SunSafe, "and the fall-back again");
}
