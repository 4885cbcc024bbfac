//! Fault injection (issue 19 item 4): the flight loop (`acs::flight::CONFIG` through
//! `FlightLoop`) flies the `tracking` scenario's orbit under the realistic truth (fixed seed 5),
//! holding its target from rest, and one fault is injected per case
//! (`acs::host::sim::faults`) or applied from the ground (uplink, clock). Every case asserts:
//! the loop keeps stepping; no NaN and no out-of-limit command reaches an actuator (each wheel
//! command within `CONFIG.wheel_limit_nms`, each coil command within its limit, every report
//! field finite); the fault is reported; the loop recovers when the fault clears, as stated per
//! case. `docs/faults.md` tabulates the figures each case prints:
//! `cargo test --release --test faults -- --nocapture`.

use acs::acs_loop::{Mode, StepReport};
use acs::flight::{FlightLoop, CONFIG};
use acs::hal::{ErrorKind, TileBus};
use acs::host::sim::faults::{Fault, Sensor};
use acs::host::sim::scenarios::{self, Scenario};
use acs::host::sim::{Sample, Simulator};
use acs::tiles::TileState;
use acs::time::{days_from_civil, Epoch, Utc};
use acs::two_node::LinkDirection;
use acs::uplink::{self, kind, UplinkError, ARG_WORDS};

/// When the faults start, s (the loop has held its target for 299 s).
const FAULT_AT: f64 = 300.0;
/// The pointing error a recovered loop is back under, degrees: above the realistic truth's
/// undisturbed `tracking` (docs/simulator.md: 0.73–1.01° worst over seeds 1–8 from 1 200 s on
/// with the filter of issue #30; this run's, from 100 s on, is printed by `baseline`).
const BOUND_DEG: f64 = 2.0;
/// Seconds after a fault clears within which the pointing error must be back under
/// [`BOUND_DEG`] for good (to the end of the run).
const RECOVERY_S: f64 = 300.0;

/// A bus that records every actuator command the loop sends, forwarding it to the simulator.
struct Recorder<'a> {
    sim: &'a mut Simulator,
    wheels: Vec<(usize, f32)>,
    coils: Vec<(usize, f32)>,
}

impl TileBus for Recorder<'_> {
    fn read_sun(&mut self, tile: usize) -> Result<Option<[i16; 2]>, ErrorKind> {
        self.sim.read_sun(tile)
    }
    fn read_magnetometer(&mut self, tile: usize) -> Result<[i16; 2], ErrorKind> {
        self.sim.read_magnetometer(tile)
    }
    fn read_gyro(&mut self, tile: usize) -> Result<i16, ErrorKind> {
        self.sim.read_gyro(tile)
    }
    fn set_wheel_momentum(&mut self, tile: usize, h_nms: f32) -> Result<(), ErrorKind> {
        self.wheels.push((tile, h_nms));
        self.sim.set_wheel_momentum(tile, h_nms)
    }
    fn set_dipole(&mut self, coil: usize, m_am2: f32) -> Result<(), ErrorKind> {
        self.coils.push((coil, m_am2));
        self.sim.set_dipole(coil, m_am2)
    }
    fn read_wheel_momentum(&mut self, tile: usize) -> Result<Option<i16>, ErrorKind> {
        self.sim.read_wheel_momentum(tile)
    }
    fn read_coil_dipole(&mut self, coil: usize) -> Result<Option<i16>, ErrorKind> {
        self.sim.read_coil_dipole(coil)
    }
    fn delay_us(&mut self, us: u32) {
        self.sim.delay_us(us);
    }
}

/// A ground action at a time (s from the start).
#[derive(Clone, Debug)]
enum Ground {
    /// An uplinked command (code, argument words); its result is kept.
    Uplink(u16, Vec<u32>),
    /// The on-board clock jumps by this many seconds (it runs on from there).
    ClockJump(f64),
    /// The ground sets the on-board clock to UTC (uplink `CLOCK` with the true time).
    SetClock,
    /// Restore every tile the telemetry shows failed or whose wheel it shows failed, and every
    /// coil it shows failed (uplink `RESTORE`).
    RestoreFailed,
    /// Uplink `TRACK` of the scenario's target.
    Track,
    /// The link between the nodes fails this way until this time (s).
    Link(LinkFault, f64),
    /// A power-on reset of the reference node (RAM cleared: no clock, no STATUS; its element
    /// set at reset, the scenario's); the harness no longer sets its clock: it must come back
    /// from the attitude node's STATUS.
    ResetReference,
    /// A power-on reset of the attitude node; the reference node flies on.
    ResetAttitude,
}

/// How the link between the nodes fails (issue 29 item 3).
#[derive(Clone, Copy, Debug, PartialEq)]
enum LinkFault {
    /// Every packet lost, both ways.
    Down,
    /// Every packet damaged (one byte flipped: the receiver's CRC refuses it), both ways.
    Corrupt,
    /// Every packet delivered one period late (the one made for the step before).
    Late,
}

/// One run: the samples, the uplink results, the largest wheel and coil commands.
struct Run {
    samples: Vec<Sample>,
    uplinks: Vec<(f64, u16, Result<(), UplinkError>)>,
    max_wheel: f32,
    max_coil: f32,
    tile_states: Vec<(f64, Vec<TileState>)>,
}

fn scenario() -> Scenario {
    let mut s = scenarios::tracking(None).unwrap();
    // from rest on the target: the faults find a loop that holds its attitude
    s.initial.0 = s.target.unwrap();
    s
}

fn words(w: &[u32]) -> [u32; ARG_WORDS] {
    let mut a = [0u32; ARG_WORDS];
    a[..w.len()].copy_from_slice(w);
    a
}

fn track_words(q: &[f64; 4]) -> Vec<u32> {
    q.iter().map(|x| (*x as f32).to_bits()).collect()
}

/// The clock words of `e` (days since 2000-01-01, second of day, nanoseconds).
fn clock_words(e: &Epoch<Utc>) -> Vec<u32> {
    let c = e.to_calendar();
    let day = days_from_civil(c.year, c.month, c.day);
    let second = u32::from(c.hour) * 3600 + u32::from(c.minute) * 60 + u32::from(c.second);
    vec![day as u32, second, c.nano]
}

/// Flies the case: `faults` injected into the truth, `ground` actions applied at their times,
/// `duration_s` seconds. Asserts at every step: no NaN and no out-of-limit actuator command, a
/// finite report.
fn fly(faults: &[(Fault, f64, f64)], ground: &[(f64, Ground)], duration_s: f64) -> Run {
    fly_on(&scenario(), faults, ground, duration_s)
}

/// [`fly`] over another scenario (its orbit, truth and target).
fn fly_on(
    sc: &Scenario,
    faults: &[(Fault, f64, f64)],
    ground: &[(f64, Ground)],
    duration_s: f64,
) -> Run {
    let target = sc.target.unwrap();
    let mut sim = sc.simulator().unwrap();
    for (f, from, until) in faults {
        sim.inject(*f, *from, *until);
    }
    let mut acs = FlightLoop::new(&CONFIG, sc.orbit().unwrap()).unwrap();
    let mut pending: Vec<(f64, Ground)> = vec![(1.0, Ground::Track)];
    pending.extend(ground.iter().cloned());
    let dt = sc.dt_s;
    let steps = (duration_s / dt).round() as usize;
    let mut run = Run {
        samples: Vec::with_capacity(steps),
        uplinks: Vec::new(),
        max_wheel: 0.0,
        max_coil: 0.0,
        tile_states: Vec::new(),
    };
    let coil_limit = CONFIG.coils.iter().map(|c| c.limit).fold(0.0f32, f32::max);
    let mut offset_s = 0.0f64;
    let mut last_attitude = None;
    let mut link: Option<(LinkFault, f64)> = None;
    let mut reference_reset = false;
    // the packets of the step before, each way (for `LinkFault::Late`)
    let mut previous: [Option<Vec<u8>>; 2] = [None, None];
    for _ in 0..steps {
        let t = sim.truth().t_s;
        let mut clock = sim.epoch_at(t + offset_s);
        let mut k = 0;
        while k < pending.len() {
            if pending[k].0 > t + 1e-9 {
                k += 1;
                continue;
            }
            let (_, action) = pending.remove(k);
            let mut up = |code: u16, w: &[u32], clock: &mut Epoch<Utc>, acs: &mut FlightLoop| {
                let r = uplink::apply(code, &words(w), acs, clock, last_attitude.as_ref());
                run.uplinks.push((t, code, r));
            };
            match action {
                Ground::Uplink(code, w) => up(code, &w, &mut clock, &mut acs),
                Ground::ClockJump(s) => clock = sim.epoch_at(t + offset_s + s),
                Ground::SetClock => {
                    up(
                        kind::CLOCK,
                        &clock_words(&sim.epoch_at(t)),
                        &mut clock,
                        &mut acs,
                    );
                }
                Ground::RestoreFailed => {
                    for tile in 0..acs.tiles().len() {
                        if acs.tile_state(tile) == Some(TileState::Failed)
                            || acs.health().wheel_failed(tile)
                        {
                            up(kind::RESTORE, &[tile as u32], &mut clock, &mut acs);
                        }
                    }
                    for coil in 0..CONFIG.coils.len() {
                        if acs.health().coil_failed(coil) {
                            up(kind::RESTORE, &[coil as u32, 1], &mut clock, &mut acs);
                        }
                    }
                }
                Ground::Track => up(kind::TRACK, &track_words(&target), &mut clock, &mut acs),
                Ground::Link(fault, until) => link = Some((fault, until)),
                Ground::ResetReference => {
                    acs.reset_reference(sc.orbit().unwrap()).unwrap();
                    reference_reset = true;
                }
                Ground::ResetAttitude => acs.reset_attitude().unwrap(),
            }
            // the on-board clock as the action left it
            offset_s = clock.span_since(&sim.epoch_at(t)).as_seconds_f64();
        }
        let clock = sim.epoch_at(t + offset_s);
        let mut bus = Recorder {
            sim: &mut sim,
            wheels: Vec::new(),
            coils: Vec::new(),
        };
        // the reference node's clock: the ground's (with its jumps), until a reset takes it
        if !reference_reset {
            acs.reference_node_mut().set_clock(clock);
        }
        if link.is_some_and(|(_, until)| t + 1e-9 >= until) {
            link = None;
        }
        let mut report = StepReport::empty(acs.mode());
        acs.step_over_link(&mut bus, dt as f32, &mut report, |direction, bytes| {
            let way = usize::from(direction == LinkDirection::Status);
            let sent = bytes.to_vec();
            let delivered = match link.map(|(f, _)| f) {
                None => true,
                Some(LinkFault::Down) => false,
                Some(LinkFault::Corrupt) => {
                    bytes[12] ^= 0x40;
                    true
                }
                Some(LinkFault::Late) => match &previous[way] {
                    Some(p) if p.len() == bytes.len() => {
                        bytes.copy_from_slice(p);
                        true
                    }
                    _ => false,
                },
            };
            previous[way] = Some(sent);
            delivered
        });
        for (tile, h) in &bus.wheels {
            assert!(
                h.is_finite() && h.abs() <= CONFIG.wheel_limit_nms,
                "wheel {tile} commanded {h} at {t}"
            );
            run.max_wheel = run.max_wheel.max(h.abs());
        }
        for (coil, m) in &bus.coils {
            assert!(
                m.is_finite() && m.abs() <= coil_limit,
                "coil {coil} commanded {m} at {t}"
            );
            run.max_coil = run.max_coil.max(m.abs());
        }
        assert!(report.is_finite(), "report not finite at {t}: {report:?}");
        last_attitude = report.attitude;
        run.tile_states.push((
            t,
            (0..acs.tiles().len())
                .map(|i| acs.tile_state(i).unwrap())
                .collect(),
        ));
        run.samples
            .push(Sample::of_step(&sim, t, report, Some(target)));
        sim.advance(dt).unwrap();
    }
    assert_eq!(run.samples.len(), steps, "the loop kept stepping");
    run
}

fn err(s: &Sample) -> f64 {
    s.pointing_error_deg.unwrap()
}

/// The worst pointing error over `[a, b)`.
fn worst(run: &Run, a: f64, b: f64) -> f64 {
    run.samples
        .iter()
        .filter(|s| s.t_s >= a && s.t_s < b)
        .map(err)
        .fold(0.0, f64::max)
}

/// The first time in `[from, to)` from which the pointing error stays under `bound` until `to`.
fn back_under(run: &Run, from: f64, to: f64, bound: f64) -> Option<f64> {
    let mut at = None;
    for s in run.samples.iter().filter(|s| s.t_s >= from && s.t_s < to) {
        if err(s) < bound {
            at.get_or_insert(s.t_s);
        } else {
            at = None;
        }
    }
    at
}

/// The fault bits' names, bit 0 first (the ground's, `acs::telemetry`).
const NAMES: [&str; 12] = acs::telemetry::FAULT_BITS;

/// Steps of `[a, b)` with each fault bit set, as `name n` (only the bits seen).
fn bit_counts(run: &Run, a: f64, b: f64) -> String {
    let mut counts = [0usize; 12];
    let mut n = 0;
    for s in run.samples.iter().filter(|s| s.t_s >= a && s.t_s < b) {
        n += 1;
        let bits = s.report.faults.bits();
        for (k, c) in counts.iter_mut().enumerate() {
            *c += usize::from(bits & (1 << k) != 0);
        }
    }
    let seen: Vec<String> = counts
        .iter()
        .zip(NAMES)
        .filter(|(c, _)| **c > 0)
        .map(|(c, name)| format!("{name} {c}"))
        .collect();
    format!(
        "{} of {n} steps",
        if seen.is_empty() {
            "none".into()
        } else {
            seen.join(", ")
        }
    )
}

/// Modes over `[a, b)` as `Mode@t` at each change.
fn modes(run: &Run, a: f64, b: f64) -> String {
    let mut out = Vec::new();
    let mut last: Option<Mode> = None;
    for s in run.samples.iter().filter(|s| s.t_s >= a && s.t_s < b) {
        if last != Some(s.mode) {
            out.push(format!("{:?}@{:.0}", s.mode, s.t_s));
            last = Some(s.mode);
        }
    }
    out.join(" → ")
}

/// Tile-state changes over the run, as `tile k failed@t` / `restored@t`.
fn tile_changes(run: &Run) -> String {
    let mut out = Vec::new();
    for w in run.tile_states.windows(2) {
        for (k, (a, b)) in w[0].1.iter().zip(w[1].1.iter()).enumerate() {
            if a != b {
                let what = if *b == TileState::Failed {
                    "failed"
                } else {
                    "restored"
                };
                out.push(format!("tile {k} {what}@{:.0}", w[1].0));
            }
        }
    }
    if out.is_empty() {
        "none".into()
    } else {
        out.join(", ")
    }
}

/// No step in `[a, b)` has a fault of `mask`.
fn no_step(run: &Run, a: f64, b: f64, mask: u16) -> bool {
    run.samples
        .iter()
        .filter(|s| s.t_s >= a && s.t_s < b)
        .all(|s| s.report.faults.bits() & mask == 0)
}

/// True if every step of `[a, b)` has a fault bit of `mask`.
fn every_step(run: &Run, a: f64, b: f64, mask: u16) -> bool {
    run.samples
        .iter()
        .filter(|s| s.t_s >= a && s.t_s < b)
        .all(|s| s.report.faults.bits() & mask != 0)
}

/// Prints the case's figures (one `FAULT` line, the rows of `docs/faults.md`) and returns the
/// recovery time after `clear_s` (s), if any.
fn summary(name: &str, run: &Run, clear_s: f64, end_s: f64) -> Option<f64> {
    let before = worst(run, 100.0, FAULT_AT);
    let during = worst(run, FAULT_AT, clear_s);
    let after = worst(run, clear_s, end_s);
    let back = back_under(run, clear_s, end_s, BOUND_DEG);
    let final_err = err(run.samples.last().unwrap());
    let rate = |a: f64, b: f64| {
        run.samples
            .iter()
            .filter(|s| s.t_s >= a && s.t_s < b)
            .map(|s| s.omega_true.norm().to_degrees())
            .fold(0.0, f64::max)
    };
    println!(
        "FAULT {name}: bits during [{FAULT_AT:.0}, {clear_s:.0}) s: {}; after: {}; modes {}; tiles: {}; \
         pointing worst before {before:.3}°, during {during:.3}°, after clear {after:.3}°, final {final_err:.3}°; \
         back under {BOUND_DEG}° for good (to {end_s:.0} s) {}; largest wheel command {:.3e} N·m·s, coil {:.3} A·m²; \
         true rate at most {:.3}°/s during, {:.3}°/s after",
        bit_counts(run, FAULT_AT, clear_s),
        bit_counts(run, clear_s, end_s),
        modes(run, 0.0, end_s),
        tile_changes(run),
        back.map_or("never".into(), |t| format!("at {t:.0} s ({:.0} s after the clear)", t - clear_s)),
        run.max_wheel,
        run.max_coil,
        rate(FAULT_AT, clear_s),
        rate(clear_s, end_s),
    );
    back.map(|t| t - clear_s)
}

fn recovered(name: &str, back: Option<f64>) {
    assert!(
        back.is_some_and(|s| s <= RECOVERY_S),
        "{name}: not back under {BOUND_DEG}° within {RECOVERY_S} s of the clear ({back:?})"
    );
}

const DEVICE_READ: u16 = 1;
const ACTUATOR: u16 = 1 << 1;
const ATTITUDE: u16 = 1 << 6;

/// The undisturbed run: the figures every case compares with.
#[test]
fn baseline() {
    let run = fly(&[], &[], 900.0);
    let back = summary("none (baseline)", &run, FAULT_AT, 900.0);
    assert!(worst(&run, 100.0, 900.0) < BOUND_DEG);
    assert!(back.is_some());
}

/// NaN where the float enters: every sensor of tile 2 (+W) reads NaN for 2 s (below the three
/// failures that mark a tile failed), then the magnetometer and gyro of tile 3 (−U) for 60 s
/// (marked failed, restored by the ground 60 s after the clear).
#[test]
fn nan_readings() {
    let (clear, end) = (FAULT_AT + 60.0, 1000.0);
    let mut f = Vec::new();
    for sensor in [Sensor::Sun, Sensor::Magnetometer, Sensor::Gyro] {
        f.push((
            Fault::NanReading { tile: 2, sensor },
            FAULT_AT,
            FAULT_AT + 2.0,
        ));
    }
    for sensor in [Sensor::Magnetometer, Sensor::Gyro] {
        f.push((Fault::NanReading { tile: 3, sensor }, FAULT_AT, clear));
    }
    let run = fly(&f, &[(clear + 60.0, Ground::RestoreFailed)], end);
    let back = summary("NaN readings", &run, clear, end);
    assert!(every_step(&run, FAULT_AT, FAULT_AT + 3.0, DEVICE_READ));
    assert!(run
        .tile_states
        .iter()
        .any(|(_, s)| s[3] == TileState::Failed));
    assert_eq!(run.tile_states.last().unwrap().1[2], TileState::Working);
    assert_eq!(run.tile_states.last().unwrap().1[3], TileState::Working);
    assert_eq!(run.samples.last().unwrap().mode, Mode::Tracking);
    recovered("NaN readings", back);
}

/// Raw words pinned at the `i16` extremes, delivered as valid readings, for 60 s: one sensor of
/// tile 1 (+V); the ground commands `TRACK` again 60 s after the clear.
fn out_of_range_run(sensor: Sensor) -> (Run, f64, f64) {
    let (clear, end) = (FAULT_AT + 60.0, 1200.0);
    let f = [(Fault::OutOfRange { tile: 1, sensor }, FAULT_AT, clear)];
    (fly(&f, &[(clear + 60.0, Ground::Track)], end), clear, end)
}

/// The invariants hold and the loop ends back on its target (after the ground's `TRACK`) for
/// each sensor: the gyro at `i16::MAX` (3.28 rad/s), the magnetometer at (`i16::MAX`,
/// `i16::MIN`) (±327 670 nT), the Sun sensor at (`i16::MAX`, `i16::MIN`) (±3.28 rad). How fast
/// (the magnetometer's is beyond [`RECOVERY_S`]) and what is reported: the test below (finding 1).
#[test]
fn out_of_range_reading() {
    for sensor in [Sensor::Gyro, Sensor::Magnetometer, Sensor::Sun] {
        let (run, clear, end) = out_of_range_run(sensor);
        let name = format!("out-of-range {sensor:?} words (tile 1)");
        let back = summary(&name, &run, clear, end);
        assert_eq!(run.samples.last().unwrap().mode, Mode::Tracking);
        assert!(back.is_some(), "{name}: never back under {BOUND_DEG}°");
    }
}

/// Finding 1 (fixed): the loop took `i16`-extreme words as valid readings and reported nothing
/// (the gyro's 3.28 rad/s sent it to `Detumble`; the magnetometer's field turned the satellite
/// 178° away, the Sun sensor's 54°, each back on target only 458-475 s after the clear). A word
/// pinned at either end of the range is now a failed read (`AcsLoop::read_tiles`): reported
/// (`device_read`) from the first step, the tile out of service after
/// `FAILURES_TO_MARK_FAILED` of them (the policy of every failed read), tracking kept.
#[test]
fn out_of_range_reading_is_reported() {
    use acs::acs_loop::FAILURES_TO_MARK_FAILED;
    use acs::tiles::TileState;
    for sensor in [Sensor::Gyro, Sensor::Magnetometer, Sensor::Sun] {
        let (run, clear, end) = out_of_range_run(sensor);
        let marked = FAULT_AT + f64::from(FAILURES_TO_MARK_FAILED);
        assert!(
            every_step(&run, FAULT_AT, marked, DEVICE_READ),
            "{sensor:?} not reported"
        );
        let failed_at = |t: f64| {
            run.tile_states
                .iter()
                .find(|(ts, _)| *ts >= t)
                .map(|(_, states)| states[1])
        };
        assert_eq!(failed_at(marked), Some(TileState::Failed), "{sensor:?}");
        assert!(run
            .samples
            .iter()
            .filter(|s| s.t_s >= FAULT_AT && s.t_s < clear)
            .all(|s| s.mode == Mode::Tracking));
        recovered(
            &format!("{sensor:?}"),
            back_under(&run, clear, end, BOUND_DEG).map(|t| t - clear),
        );
    }
}

/// A stuck sensor: tile 2's (+W) magnetometer repeats its reading for 300 s.
#[test]
fn stuck_magnetometer() {
    let (clear, end) = (FAULT_AT + 300.0, 1200.0);
    let f = [(
        Fault::Stuck {
            tile: 2,
            sensor: Sensor::Magnetometer,
        },
        FAULT_AT,
        clear,
    )];
    let run = fly(&f, &[], end);
    let back = summary("stuck magnetometer", &run, clear, end);
    recovered("stuck magnetometer", back);
}

/// A stuck gyro: tile 3's (−U, the only gyro on U) gyro repeats its reading for 300 s.
fn stuck_gyro_run() -> (Run, f64, f64) {
    stuck_gyro_run_on(3)
}

/// A stuck gyro on tile `tile` for 300 s.
fn stuck_gyro_run_on(tile: usize) -> (Run, f64, f64) {
    let (clear, end) = (FAULT_AT + 300.0, 1200.0);
    let f = [(
        Fault::Stuck {
            tile,
            sensor: Sensor::Gyro,
        },
        FAULT_AT,
        clear,
    )];
    (fly(&f, &[], end), clear, end)
}

#[test]
fn stuck_gyro() {
    let (run, clear, end) = stuck_gyro_run();
    let back = summary("stuck gyro", &run, clear, end);
    assert_eq!(run.samples.last().unwrap().mode, Mode::Tracking);
    recovered("stuck gyro", back);
}

/// The first step from the fault with `device_read`, s.
fn first_device_read(run: &Run, clear: f64) -> Option<f64> {
    run.samples
        .iter()
        .filter(|s| s.t_s >= FAULT_AT && s.t_s < clear)
        .find(|s| s.report.faults.device_read)
        .map(|s| s.t_s)
}

/// Finding 2, fixed: the stuck gyro is reported (`acs::attitude_node::stuck`: 15 repeated
/// words with the filter's corrections about U past 0.1°), every step until the fault clears.
#[test]
fn stuck_gyro_is_reported() {
    let (run, clear, _) = stuck_gyro_run();
    println!(
        "STUCK first device_read {:?}",
        first_device_read(&run, clear)
    );
    assert!(every_step(
        &run,
        FAULT_AT + 15.0,
        clear,
        DEVICE_READ | (1 << 5)
    ));
}

/// A stuck gyro on an axis with two gyros (tile 2, +W; tile 1, +V): reported, recovered.
#[test]
fn stuck_gyro_two_on_the_axis() {
    for tile in [2, 1] {
        let (run, clear, end) = stuck_gyro_run_on(tile);
        let back = summary(&format!("stuck gyro tile {tile}"), &run, clear, end);
        let first = first_device_read(&run, clear);
        println!("STUCK tile {tile} first device_read {first:?}");
        assert!(every_step(&run, FAULT_AT + 60.0, clear, DEVICE_READ));
        recovered("stuck gyro two", back);
    }
}

/// Tile 2's (+W) Sun sensor repeats its reading for 300 s (not watched: no action needed).
#[test]
fn stuck_sun() {
    let (clear, end) = (FAULT_AT + 300.0, 1200.0);
    let f = [(
        Fault::Stuck {
            tile: 2,
            sensor: Sensor::Sun,
        },
        FAULT_AT,
        clear,
    )];
    let run = fly(&f, &[], end);
    let back = summary("stuck Sun", &run, clear, end);
    recovered("stuck Sun", back);
}

/// A dead tile: tile 2 (+W: Sun sensor, magnetometer, gyro, wheel) answers nothing for 60 s;
/// the loop marks it failed; the ground restores it 60 s after the fault clears.
#[test]
fn dead_tile() {
    let (clear, end) = (FAULT_AT + 60.0, 1000.0);
    let f = [(Fault::DeadTile { tile: 2 }, FAULT_AT, clear)];
    let run = fly(&f, &[(clear + 60.0, Ground::RestoreFailed)], end);
    let back = summary("dead tile", &run, clear, end);
    assert!(every_step(&run, FAULT_AT, FAULT_AT + 3.0, DEVICE_READ));
    // marked failed, its wheel still commanded (to rest): the refusals are reported
    assert!(every_step(&run, FAULT_AT + 3.0, clear, ACTUATOR));
    assert_eq!(run.tile_states.last().unwrap().1[2], TileState::Working);
    assert_eq!(run.samples.last().unwrap().mode, Mode::Tracking);
    recovered("dead tile", back);
}

/// Bursts of bus errors: every transaction fails for 2 s at 300, 320 and 340 s (below the
/// three failures that mark a tile failed).
#[test]
fn bus_error_bursts() {
    let end = 1000.0;
    let f: Vec<_> = [0.0, 20.0, 40.0]
        .iter()
        .map(|d| (Fault::BusErrors, FAULT_AT + d, FAULT_AT + d + 2.0))
        .collect();
    let run = fly(&f, &[], end);
    let clear = FAULT_AT + 42.0;
    let back = summary("bus error bursts (3 × 2 s)", &run, clear, end);
    for d in [0.0, 20.0, 40.0] {
        assert!(every_step(
            &run,
            FAULT_AT + d,
            FAULT_AT + d + 2.0,
            DEVICE_READ
        ));
        assert!(every_step(&run, FAULT_AT + d, FAULT_AT + d + 2.0, ACTUATOR));
    }
    assert!(run
        .tile_states
        .iter()
        .all(|(_, s)| s[1..].iter().all(|x| *x == TileState::Working)));
    assert_eq!(run.samples.last().unwrap().mode, Mode::Tracking);
    recovered("bus error bursts", back);
}

/// A longer burst: 5 s of bus errors marks every tile failed; the ground restores them 60 s
/// after the burst.
fn long_burst_run(seconds: f64, ground: &[(f64, Ground)]) -> (Run, f64, f64) {
    let (clear, end) = (FAULT_AT + seconds, 1200.0);
    let f = [(Fault::BusErrors, FAULT_AT, clear)];
    (fly(&f, ground, end), clear, end)
}

/// After a 5 s bus burst (every transaction failing) the loop keeps its tiles in service and
/// its attitude (finding 3, fixed: before, every tile was marked failed at the burst's third
/// step, for good without a ground `RESTORE`, and the loop ended 165° off its target).
#[test]
fn long_bus_burst_recovers_alone() {
    let (run, clear, end) = long_burst_run(5.0, &[]);
    let back = summary("bus error burst (5 s), no ground action", &run, clear, end);
    assert!(every_step(&run, FAULT_AT, clear, DEVICE_READ | ACTUATOR));
    assert!(run
        .tile_states
        .iter()
        .all(|(_, s)| s.iter().all(|x| *x == TileState::Working)));
    assert_eq!(run.samples.last().unwrap().mode, Mode::Tracking);
    recovered("long bus burst alone", back);
}

/// A burst longer than the loop waits without an attitude (60 s): the tiles stay in service,
/// the loop falls back to sun-safe, and the ground commands `TRACK` again 10 s after the clear.
/// Finding 8 (fixed): the tracking that follows settled into a limit cycle while the loop
/// integrated more torque than the wheels' 0.23 mN·m ([`acs::acs_loop::AcsConfig::wheel_torque_nm`]).
#[test]
fn minute_bus_burst() {
    let (run, clear, end) = long_burst_run(60.0, &[(FAULT_AT + 70.0, Ground::Track)]);
    let back = summary("bus error burst (60 s), ground track", &run, clear, end);
    assert!(every_step(&run, FAULT_AT, clear, DEVICE_READ | ACTUATOR));
    assert!(run
        .tile_states
        .iter()
        .all(|(_, s)| s.iter().all(|x| *x == TileState::Working)));
    assert_eq!(run.samples.last().unwrap().mode, Mode::Tracking);
    recovered("minute bus burst", back);
}

/// A wheel that stops: the wheel accepts every command and comes to rest, 120 s: tile 2's (+W,
/// one of two wheels on W) and tile 3's (−U, the only wheel on U).
fn wheel_stopped_run(tile: usize) -> (Run, f64, f64) {
    let (clear, end) = (FAULT_AT + 120.0, 1200.0);
    let f = [(Fault::WheelStopped { tile }, FAULT_AT, clear)];
    (fly(&f, &[], end), clear, end)
}

#[test]
fn wheel_stopped() {
    for tile in [2, 3] {
        let (run, clear, end) = wheel_stopped_run(tile);
        let back = summary(&format!("wheel stopped (tile {tile})"), &run, clear, end);
        assert_eq!(run.samples.last().unwrap().mode, Mode::Tracking);
        recovered("wheel stopped", back);
    }
}

/// Finding 4, fixed (issue #31): the stopped wheel's read-back (`TileBus::read_wheel_momentum`)
/// falls behind its command and does not come closer: failed (`acs::attitude_node::health`) and
/// reported every step until the ground restores it. The only wheel on U, it stays in the
/// allocation (taking it out would give up U for good).
#[test]
fn wheel_stopped_is_reported() {
    let (run, _, end) = wheel_stopped_run(3);
    assert!(every_step(&run, FAULT_AT + 5.0, end, ACTUATOR));
    assert!(!every_step(&run, FAULT_AT - 10.0, FAULT_AT, ACTUATOR));
}

/// A refusing wheel with a twin on its axis (tile 2, +W; tile 5 is −W) is failed after three
/// refusals and taken out of the allocation (issue #31): tile 5 holds W alone; the ground's
/// `RESTORE` 10 s after the fault clears returns it, and the reports stop.
#[test]
fn refusing_wheel_leaves_the_allocation_until_restored() {
    let (clear, end) = (FAULT_AT + 120.0, 1200.0);
    let f = [(Fault::WheelRefuses { tile: 2 }, FAULT_AT, clear)];
    let run = fly(&f, &[(clear + 10.0, Ground::RestoreFailed)], end);
    let back = summary("wheel refuses, restored", &run, clear, end);
    assert!(every_step(&run, FAULT_AT, clear + 10.0, ACTUATOR));
    let restored = run
        .uplinks
        .iter()
        .filter(|(t, code, r)| *t >= clear && *code == kind::RESTORE && r.is_ok())
        .count();
    assert_eq!(restored, 1);
    assert!(!run
        .samples
        .iter()
        .filter(|s| s.t_s >= clear + 11.0)
        .any(|s| s.report.faults.bits() & ACTUATOR != 0));
    recovered("wheel refuses, restored", back);
}

/// A wheel that refuses commands: tile 2's (+W) wheel fails every command for 120 s.
#[test]
fn wheel_refuses() {
    let (clear, end) = (FAULT_AT + 120.0, 1200.0);
    let f = [(Fault::WheelRefuses { tile: 2 }, FAULT_AT, clear)];
    let run = fly(&f, &[], end);
    let back = summary("wheel refuses commands", &run, clear, end);
    assert!(every_step(&run, FAULT_AT, clear, ACTUATOR));
    assert_eq!(run.samples.last().unwrap().mode, Mode::Tracking);
    recovered("wheel refuses", back);
}

/// An open-circuit magnetorquer: coil 2 (z) accepts and gives no dipole, 300 s.
fn coil_open_run() -> (Run, f64, f64) {
    let (clear, end) = (FAULT_AT + 300.0, 1200.0);
    let f = [(Fault::CoilOpen { coil: 2 }, FAULT_AT, clear)];
    (fly(&f, &[], end), clear, end)
}

#[test]
fn coil_open() {
    let (run, clear, end) = coil_open_run();
    let back = summary("open-circuit coil", &run, clear, end);
    assert_eq!(run.samples.last().unwrap().mode, Mode::Tracking);
    recovered("open coil", back);
}

/// Finding 5, fixed (issue #31): the coil's read-back (`TileBus::read_coil_dipole`) is not its
/// command: three strikes, from the fault's first step, fail it (`acs::attitude_node::health`),
/// and it is reported from then on, every step until the ground restores it. The sole coil on
/// its axis, it stays in the allocation.
#[test]
fn coil_open_is_reported() {
    let (run, clear, end) = coil_open_run();
    assert!(every_step(&run, FAULT_AT + 3.0, end, ACTUATOR));
    assert!(!every_step(&run, FAULT_AT - 10.0, FAULT_AT, ACTUATOR));
    let _ = clear;
}

/// A coil left on: coil 0 (x) stays at 0.2 A·m² for 60 s, through the coils-off before the
/// reads: its field reaches the magnetometers, its torque the body.
fn coil_left_on_run() -> (Run, f64, f64) {
    let (clear, end) = (FAULT_AT + 60.0, 1200.0);
    let f = [(
        Fault::CoilLeftOn {
            coil: 0,
            dipole_am2: 0.2,
        },
        FAULT_AT,
        clear,
    )];
    (fly(&f, &[], end), clear, end)
}

/// The invariants hold and the loop ends back on its target.
#[test]
fn coil_left_on() {
    let (run, clear, end) = coil_left_on_run();
    let back = summary("coil left on (0.2 A·m²)", &run, clear, end);
    assert_eq!(run.samples.last().unwrap().mode, Mode::Tracking);
    assert!(back.is_some(), "never back under {BOUND_DEG}°");
}

/// Finding 6, fixed: the coil's field (140 000 nT at its own tile's magnetometer, 4 000–20 000
/// nT at the others) corrupted the field the loop determined; nothing reported it, the attitude
/// measured from it was wrong by up to 180°, and the loop took 332 s to come back. Now the loop
/// refuses a field whose magnitude is more than `FIELD_MAGNITUDE_TOLERANCE` (10 %) from the
/// model's (`field` every step of the fault), propagates its attitude on the gyros meanwhile
/// and stays on its target.
#[test]
fn coil_left_on_is_reported_and_recovers() {
    let (run, clear, end) = coil_left_on_run();
    assert!(every_step(
        &run,
        FAULT_AT,
        clear,
        DEVICE_READ | (1 << 4) | ATTITUDE
    ));
    recovered(
        "coil left on",
        back_under(&run, clear, end, BOUND_DEG).map(|t| t - clear),
    );
}

/// All Sun sensors dark for 200 s in sunlight: the filter keeps the attitude with the field
/// and the gyros (no step without attitude, no fall-back); the ground commands `TRACK` again
/// 60 s after the Sun returns (as it did when the complementary filter, 120 s of propagation,
/// lost the attitude).
#[test]
fn sun_sensors_dark() {
    let (clear, end) = (FAULT_AT + 200.0, 1200.0);
    let f = [(Fault::SunSensorsDark, FAULT_AT, clear)];
    let run = fly(&f, &[(clear + 60.0, Ground::Track)], end);
    let back = summary("all Sun sensors dark (200 s)", &run, clear, end);
    let no_measurement = run
        .samples
        .iter()
        .filter(|s| s.t_s >= FAULT_AT && s.t_s < clear)
        .all(|s| s.report.measured_attitude.is_none() && s.report.sun_body.is_none());
    assert!(no_measurement);
    // the field and the gyros hold the attitude: never lost, never fallen back
    assert!(no_step(&run, FAULT_AT, clear, ATTITUDE));
    assert!(run
        .samples
        .iter()
        .filter(|s| s.t_s >= FAULT_AT)
        .all(|s| s.mode == Mode::Tracking));
    recovered("dark", back);
}

/// The first umbra's entry and exit of `sc`, s, from the truth alone.
fn umbra_times(sc: &Scenario) -> (f64, f64) {
    let mut probe = sc.simulator().unwrap();
    let (mut entry, mut exit) = (None, None);
    while probe.truth().t_s < sc.duration_s && exit.is_none() {
        let t = probe.truth().t_s;
        let dark = probe.env().sun_fraction < 1e-9;
        if dark && entry.is_none() {
            entry = Some(t);
        }
        if !dark && entry.is_some() {
            exit = Some(t);
        }
        probe.advance(sc.dt_s).unwrap();
    }
    (entry.unwrap(), exit.unwrap())
}

/// All tiles dark in a real umbra: the `sun-safe` scenario's noon-midnight orbit (seed 3),
/// holding an inertial attitude from rest through its first eclipse; the ground commands
/// `TRACK` again 60 s after the umbra ends.
#[test]
fn umbra() {
    let mut sc = scenarios::sun_safe().unwrap();
    let target = scenario().target.unwrap();
    sc.target = Some(target);
    sc.initial = (target, nalgebra::Vector3::zeros());
    let (entry, exit) = umbra_times(&sc);
    let end = exit + 900.0;
    let run = fly_on(&sc, &[], &[(exit + 60.0, Ground::Track)], end);
    println!(
        "FAULT umbra: entry {entry:.0} s, exit {exit:.0} s ({:.0} s); bits in the umbra: {}; modes {}; \
         pointing worst before {:.3}°, in the umbra {:.3}°, after {:.3}°; back under {BOUND_DEG}° for good {}",
        exit - entry,
        bit_counts(&run, entry, exit),
        modes(&run, 0.0, end),
        worst(&run, 100.0, entry),
        worst(&run, entry, exit),
        worst(&run, exit, end),
        back_under(&run, exit, end, BOUND_DEG)
            .map_or("never".into(), |t| format!("at {t:.0} s ({:.0} s after the exit)", t - exit)),
    );
    // the control error: the filtered attitude against the target (what the law acts on)
    let control = |a: f64, b: f64| {
        run.samples
            .iter()
            .filter(|s| s.t_s >= a && s.t_s < b)
            .filter_map(|s| s.report.attitude)
            .map(|q| acs::host::sim::angle_between_deg(&target, &q))
            .fold(0.0, f64::max)
    };
    let estimate = |a: f64, b: f64| {
        run.samples
            .iter()
            .filter(|s| s.t_s >= a && s.t_s < b)
            .filter_map(|s| s.estimate_error_deg)
            .fold(0.0, f64::max)
    };
    let first_under = run
        .samples
        .iter()
        .find(|s| s.t_s >= exit && err(s) < BOUND_DEG)
        .map(|s| s.t_s - exit);
    println!(
        "FAULT umbra: first under {BOUND_DEG}° {first_under:?} s after the exit; from 120 s after the exit: pointing error at most {:.3}°, control error (filtered attitude against the target) at most {:.3}°, estimate error at most {:.3}° (before the umbra: pointing {:.3}°, control {:.3}°, estimate {:.3}°)",
        worst(&run, exit + 120.0, end),
        control(exit + 120.0, end),
        estimate(exit + 120.0, end),
        worst(&run, 100.0, entry),
        control(100.0, entry),
        estimate(100.0, entry),
    );
    // the field and the gyros hold the attitude through the umbra: never lost, never fallen back
    assert!(no_step(&run, entry, exit, ATTITUDE));
    assert!(run
        .samples
        .iter()
        .filter(|s| s.t_s >= entry)
        .all(|s| s.mode == Mode::Tracking));
    // this orbit's determination alone exceeds the 2° bound (before the umbra too): the
    // recovery is the pointing error under it within 120 s of the exit, and the control error
    // back to its size before the umbra
    assert!(first_under.is_some_and(|s| s <= 120.0), "{first_under:?}");
    assert!(control(exit + 120.0, end) <= control(100.0, entry).max(0.5));
}

/// A corrupt element set uploaded mid-flight: one word's bit flipped in transit (the checksum
/// refuses it), and a set with a NaN constant and a correct checksum (the finiteness check
/// refuses it). Both are refused with a typed error; the loop's next 300 steps are bit for bit
/// those of a twin that never received them.
#[test]
fn corrupt_elements_refused() {
    use acs::orbit::sgp4::{words_checksum, ELEMENT_WORDS};
    let sc = scenario();
    let good = sc.orbit().unwrap().to_words();
    let mut flipped = good;
    flipped[10] ^= 1 << 7;
    let mut nan = good;
    nan[5] = f32::NAN.to_bits();
    nan[ELEMENT_WORDS - 1] = words_checksum(&nan[..ELEMENT_WORDS - 1]);
    let target = sc.target.unwrap();
    let mut sim = sc.simulator().unwrap();
    let mut acs = FlightLoop::new(&CONFIG, sc.orbit().unwrap()).unwrap();
    let mut clock = sim.epoch_at(0.0);
    let mut last = None;
    let step = |sim: &mut Simulator, acs: &mut FlightLoop| {
        let t = sim.truth().t_s;
        let r = acs.step(sim, sim.epoch_at(t), 1.0);
        sim.advance(1.0).unwrap();
        r
    };
    for k in 0..FAULT_AT as usize {
        if k == 1 {
            let r = uplink::apply(
                kind::TRACK,
                &words(&track_words(&target)),
                &mut acs,
                &mut clock,
                None,
            );
            assert!(r.is_ok());
        }
        last = Some(step(&mut sim, &mut acs));
    }
    let (mut twin_sim, mut twin) = (sim.clone(), acs.clone());
    let mut results = Vec::new();
    for w in [&flipped, &nan] {
        let attitude = last.and_then(|r: StepReport| r.attitude);
        let r = uplink::apply(kind::ELEMENTS, w, &mut acs, &mut clock, attitude.as_ref());
        results.push(r);
    }
    println!(
        "FAULT corrupt element set: bit flip → {:?} (status {:#x}); NaN word with a valid checksum → {:?} (status {:#x})",
        results[0],
        uplink::status(&results[0]),
        results[1],
        uplink::status(&results[1]),
    );
    assert_eq!(
        results[0],
        Err(UplinkError::BadElementWord((ELEMENT_WORDS - 1) as u8))
    );
    assert!(matches!(results[1], Err(UplinkError::BadElementWord(_))));
    let mut worst_err = 0.0f64;
    for _ in 0..300 {
        let t = sim.truth().t_s;
        let a = step(&mut sim, &mut acs);
        let b = step(&mut twin_sim, &mut twin);
        assert_eq!(a, b, "the refused sets changed the loop at {t}");
        assert!(!a.faults.orbit);
        worst_err = worst_err.max(
            Sample::of_step(&sim, t, a, Some(target))
                .pointing_error_deg
                .unwrap(),
        );
    }
    println!("FAULT corrupt element set: the next 300 steps identical to a twin's (no orbit fault); worst pointing {worst_err:.3}°");
}

/// A jump of the on-board clock: +60 s at 300 s, set right by the ground (uplink `CLOCK`) at
/// 420 s; −30 s at 1 200 s, set right at 1 320 s.
#[test]
fn clock_jumps() {
    let end = 2200.0;
    let ground = [
        (FAULT_AT, Ground::ClockJump(60.0)),
        (FAULT_AT + 120.0, Ground::SetClock),
        (1200.0, Ground::ClockJump(-30.0)),
        (1320.0, Ground::SetClock),
    ];
    let run = fly(&[], &ground, end);
    let clock_steps: Vec<f64> = run
        .samples
        .iter()
        .filter(|s| s.report.faults.clock)
        .map(|s| s.t_s)
        .collect();
    let clock_steps: Vec<f64> = clock_steps.iter().map(|t| t.round()).collect();
    println!("FAULT clock jumps: Faults::clock at {clock_steps:?} s");
    let back1 = summary(
        "clock +60 s at 300 s, set right at 420 s",
        &run,
        FAULT_AT + 120.0,
        1200.0,
    );
    let during2 = worst(&run, 1200.0, 1320.0);
    let back2 = back_under(&run, 1320.0, end, BOUND_DEG).map(|t| t - 1320.0);
    println!(
        "FAULT clock −30 s at 1 200 s, set right at 1 320 s: pointing worst during {during2:.3}°, after {:.3}°; back under {BOUND_DEG}° for good (to {end:.0} s) {back2:?} s after",
        worst(&run, 1320.0, end)
    );
    assert_eq!(
        clock_steps,
        vec![FAULT_AT, FAULT_AT + 120.0, 1200.0, 1320.0]
    );
    assert!(run.uplinks.iter().all(|(_, _, r)| r.is_ok()));
    assert_eq!(run.samples.last().unwrap().mode, Mode::Tracking);
    recovered("clock +60", back1);
    recovered("clock -30", back2);
}

/// A failed tile restored by command: the ground marks tile 2 (+W) failed at 300 s (uplink
/// `MARK_FAILED`) and restores it at 420 s (`RESTORE`).
#[test]
fn failed_tile_restored() {
    let (clear, end) = (FAULT_AT + 120.0, 1200.0);
    let ground = [
        (FAULT_AT, Ground::Uplink(kind::MARK_FAILED, vec![2])),
        (clear, Ground::Uplink(kind::RESTORE, vec![2])),
    ];
    let run = fly(&[], &ground, end);
    let back = summary("tile marked failed, restored by command", &run, clear, end);
    assert!(run.uplinks.iter().all(|(_, _, r)| r.is_ok()));
    let state_at = |t: f64| {
        run.tile_states
            .iter()
            .find(|(s, _)| *s >= t)
            .map(|(_, s)| s[2])
            .unwrap()
    };
    assert_eq!(state_at(FAULT_AT + 1.0), TileState::Failed);
    assert_eq!(state_at(clear + 1.0), TileState::Working);
    assert_eq!(run.samples.last().unwrap().mode, Mode::Tracking);
    recovered("failed tile restored", back);
}

/// Finding of the soak (fixed): a saturated allocation could exceed its limit by one ulp
/// (`h · (limit / |h|)` rounds up), which the reference drivers (`hal::drivers::drive_bridge`:
/// `magnitude > limit`) refuse, switching the coil or wheel off; the allocator now scales by
/// one ulp less. Searched over 200 000 random dipoles for the flight coils.
#[test]
fn saturated_allocation_within_limit() {
    use acs::control::wheels::Allocator;
    let coils: [acs::control::wheels::Wheel; 3] =
        [CONFIG.coils[0], CONFIG.coils[1], CONFIG.coils[2]];
    let allocator = Allocator::new(&coils).unwrap();
    let mut state = 0x1234_5678_9abc_def0u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        ((state >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
    };
    let mut over = Vec::new();
    for _ in 0..200_000 {
        let l = nalgebra::Vector3::new(next(), next(), next()) * 3.0;
        let a = allocator.allocate(&coils, &l).unwrap();
        for (m, c) in a.wheel.iter().zip(coils.iter()) {
            if m.abs() > c.limit {
                over.push(*m);
            }
        }
    }
    println!(
        "FAULT saturated allocation: {} of 600 000 coil commands above the 0.2 A·m² limit: {:?}",
        over.len(),
        &over[..over.len().min(5)]
    );
    assert!(over.is_empty());
}

/// An injection that never becomes active leaves the run bit for bit as it was (the faults
/// draw no random number and change nothing while inactive).
#[test]
fn inactive_injection_changes_nothing() {
    let plain = fly(&[], &[], 400.0);
    let never: Vec<_> = [
        Fault::BusErrors,
        Fault::DeadTile { tile: 2 },
        Fault::SunSensorsDark,
        Fault::CoilLeftOn {
            coil: 0,
            dipole_am2: 0.2,
        },
        Fault::WheelStopped { tile: 3 },
        Fault::NanReading {
            tile: 1,
            sensor: Sensor::Gyro,
        },
    ]
    .into_iter()
    .map(|f| (f, 1e9, f64::INFINITY))
    .collect();
    let with = fly(&never, &[], 400.0);
    for (a, b) in plain.samples.iter().zip(with.samples.iter()) {
        assert_eq!(a.report, b.report, "at {}", a.t_s);
        assert_eq!(a.omega_true, b.omega_true, "at {}", a.t_s);
    }
}

/// The bus answers of each fault, and `clear_fault` ends an injection "until cleared".
#[test]
fn injections_on_the_bus() {
    let mut sim = scenario().simulator().unwrap();
    let dead = sim.inject(Fault::DeadTile { tile: 2 }, 0.0, f64::INFINITY);
    assert_eq!(sim.read_gyro(2), Err(ErrorKind::DeviceAbsent));
    assert_eq!(sim.set_wheel_momentum(2, 0.0), Err(ErrorKind::DeviceAbsent));
    assert!(sim.read_gyro(1).is_ok());
    sim.clear_fault(dead);
    assert!(sim.read_gyro(2).is_ok());
    let t = sim.truth().t_s;
    let until = t + 1.0;
    sim.inject(Fault::BusErrors, t, until);
    assert_eq!(sim.read_magnetometer(1), Err(ErrorKind::Bus));
    assert_eq!(sim.set_dipole(0, 0.1), Err(ErrorKind::Bus));
    sim.inject(Fault::WheelRefuses { tile: 4 }, until, f64::INFINITY);
    sim.inject(
        Fault::OutOfRange {
            tile: 1,
            sensor: Sensor::Magnetometer,
        },
        until,
        f64::INFINITY,
    );
    sim.inject(
        Fault::NanReading {
            tile: 4,
            sensor: Sensor::Gyro,
        },
        until,
        f64::INFINITY,
    );
    sim.inject(Fault::SunSensorsDark, until, f64::INFINITY);
    sim.advance(1.0).unwrap();
    assert!(sim.read_magnetometer(2).is_ok());
    assert_eq!(sim.set_wheel_momentum(4, 1e-4), Err(ErrorKind::Other));
    assert_eq!(sim.read_magnetometer(1), Ok([i16::MAX, i16::MIN]));
    assert_eq!(sim.read_gyro(4), Err(ErrorKind::OutOfRange));
    assert!((0..6).all(|tile| matches!(sim.read_sun(tile), Ok(None) | Err(_))));
    assert!((0..6).any(|tile| sim.read_sun(tile) == Ok(None)));
}

const LINK: u16 = 1 << 11;

/// The link between the nodes fails (`fault`) for `seconds` from [`FAULT_AT`], the satellite
/// tracking its target (issue 29 item 3).
fn link_run(fault: LinkFault, seconds: f64, faults: &[(Fault, f64, f64)]) -> (Run, f64, f64) {
    let (clear, end) = (FAULT_AT + seconds, FAULT_AT + seconds + 600.0);
    let run = fly(faults, &[(FAULT_AT, Ground::Link(fault, clear))], end);
    (run, clear, end)
}

/// The steps from `a` to `b` without a usable REF (the `link` bit).
fn link_steps(run: &Run, a: f64, b: f64) -> usize {
    run.samples
        .iter()
        .filter(|s| s.t_s >= a && s.t_s < b && s.report.faults.bits() & LINK != 0)
        .count()
}

/// Link down 30 s: every step of it reported (`link`), the attitude bridged on the gyros, the
/// loop stays in `Tracking` and on its target.
#[test]
fn link_down_30_s() {
    let (run, clear, end) = link_run(LinkFault::Down, 30.0, &[]);
    let back = summary("link down 30 s", &run, clear, end);
    assert_eq!(link_steps(&run, FAULT_AT, clear), 30);
    assert_eq!(link_steps(&run, clear, end), 0);
    assert!(run
        .samples
        .iter()
        .filter(|s| s.t_s >= 60.0)
        .all(|s| s.mode == Mode::Tracking));
    recovered("link down 30 s", back);
}

/// Link down 10 minutes: without the REF's Sun and field the filter propagates on the gyros
/// alone, its attitude 1σ growing but within its limit (`max_attitude_sigma_rad`) for the ten
/// minutes: the loop keeps `Tracking` (it fell back to `SunSafe` with the complementary
/// filter's 120 s bridge) and takes the REFs again when they return, no ground command.
#[test]
fn link_down_10_min() {
    let (run, clear, end) = link_run(LinkFault::Down, 600.0, &[]);
    let back = summary("link down 10 min", &run, clear, end);
    assert_eq!(link_steps(&run, FAULT_AT, clear), 600);
    let during = |m: Mode| {
        run.samples
            .iter()
            .any(|s| s.t_s >= FAULT_AT && s.t_s < clear && s.mode == m)
    };
    assert!(!during(Mode::SunSafe), "no fall-back");
    assert!(no_step(&run, FAULT_AT, clear, ATTITUDE));
    assert_eq!(
        run.samples.last().unwrap().mode,
        Mode::Tracking,
        "and back by itself"
    );
    recovered("link down 10 min", back);
}

/// Damaged packets (the CRC refuses them) and packets one period late (made for another step)
/// for 30 s each: never used, each step reported, the loop stays on its target.
#[test]
fn link_corrupt_and_late() {
    for (fault, name) in [
        (LinkFault::Corrupt, "link corrupt 30 s"),
        (LinkFault::Late, "link late 30 s"),
    ] {
        let (run, clear, end) = link_run(fault, 30.0, &[]);
        let back = summary(name, &run, clear, end);
        assert_eq!(link_steps(&run, FAULT_AT, clear), 30, "{name}");
        assert!(run
            .samples
            .iter()
            .filter(|s| s.t_s >= 60.0)
            .all(|s| s.mode == Mode::Tracking));
        recovered(name, back);
    }
}

/// A coil left on while the link is down: without the REF's field the magnitude check runs
/// against the last REF's, its tolerance widening 0.1 %/s: the coil's field is still refused
/// (`field` every step of it) and the loop stays on its target.
#[test]
fn link_down_with_a_coil_left_on() {
    let coil = (
        Fault::CoilLeftOn {
            coil: 0,
            dipole_am2: 0.2,
        },
        FAULT_AT + 30.0,
        FAULT_AT + 90.0,
    );
    let (run, clear, end) = link_run(LinkFault::Down, 120.0, &[coil]);
    let back = summary("link down 120 s, coil left on 60 s", &run, clear, end);
    assert!(
        every_step(&run, coil.1 + 1.0, coil.2, 1 << 4),
        "the coil's field refused"
    );
    recovered("link down with a coil left on", back);
}

/// A power-on reset of the reference node while the attitude node flies on: the reset node has
/// no clock, its REFs are not used until a STATUS brings the attitude node's clock back (the
/// next period); the loop stays on its target.
#[test]
fn reference_node_reset() {
    let end = FAULT_AT + 600.0;
    let run = fly(&[], &[(FAULT_AT, Ground::ResetReference)], end);
    let back = summary("reference node reset", &run, FAULT_AT + 1.0, end);
    let missing = link_steps(&run, FAULT_AT, end);
    println!("FAULT reference node reset: {missing} steps without a usable REF");
    assert!(missing <= 2, "{missing}");
    recovered("reference node reset", back);
}

/// A power-on reset of the attitude node while the reference node flies on: the fresh node
/// detumbles, takes the guidance in force from the first REF made for its step, and is back on
/// its target.
#[test]
fn attitude_node_reset() {
    let end = FAULT_AT + 600.0;
    let run = fly(&[], &[(FAULT_AT, Ground::ResetAttitude)], end);
    let back = summary("attitude node reset", &run, FAULT_AT + 1.0, end);
    println!(
        "FAULT attitude node reset: {} steps without a usable REF",
        link_steps(&run, FAULT_AT, end)
    );
    assert_eq!(run.samples.last().unwrap().mode, Mode::Tracking);
    recovered("attitude node reset", back);
}

/// The link down through a real umbra (the `sun-safe` scenario's noon-midnight orbit, as
/// [`umbra`]), from 30 s before the entry to 30 s after the exit: without the reference node's
/// shadow, Sun or field the attitude node's filter propagates on the gyros alone until its
/// attitude 1σ passes its limit (about 1 250 s), then, its last REF made before the umbra, it
/// counts towards the fall-back to `SunSafe`, and, having fallen back for want of REFs, takes
/// its guidance again by itself when they return (no ground command).
#[test]
fn link_down_in_umbra() {
    let mut sc = scenarios::sun_safe().unwrap();
    let target = scenario().target.unwrap();
    sc.target = Some(target);
    sc.initial = (target, nalgebra::Vector3::zeros());
    let (entry, exit) = umbra_times(&sc);
    let (down, up, end) = (entry - 30.0, exit + 30.0, exit + 900.0);
    let run = fly_on(&sc, &[], &[(down, Ground::Link(LinkFault::Down, up))], end);
    let back = back_under(&run, up, end, BOUND_DEG);
    println!(
        "FAULT link down in umbra: link down {down:.0}–{up:.0} s, umbra {entry:.0}–{exit:.0} s; bits while down: {}; modes {}; \
         pointing worst before {:.3}°, while down {:.3}°, after {:.3}°; back under {BOUND_DEG}° for good {}",
        bit_counts(&run, down, up),
        modes(&run, 0.0, end),
        worst(&run, 100.0, down),
        worst(&run, down, up),
        worst(&run, up, end),
        back.map_or("never".into(), |t| format!("at {t:.0} s ({:.0} s after the link returned)", t - up)),
    );
    assert_eq!(link_steps(&run, down, up), (up - down) as usize);
    assert!(run
        .samples
        .iter()
        .filter(|s| s.t_s >= entry && s.t_s < exit)
        .all(|s| s.report.sun_body.is_none()));
    assert_eq!(
        run.samples.last().unwrap().mode,
        Mode::Tracking,
        "back by itself"
    );
}
