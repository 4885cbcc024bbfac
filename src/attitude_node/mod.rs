//! The attitude node (issue #29): tile reads, determination, the mode machine and fault
//! management, the laws and the allocation; the only component that commands actuators. It owns
//! the control period: each step it takes the REF made for that step (the reference node's Sun,
//! shadow, field and guidance, [`crate::link::messages`]) if one is usable, runs the step and
//! returns STATUS.
//!
//! Attitudes follow [`crate::attitude`]: `v_body = A · v_ref` with the reference frame TEME of
//! date; quaternions scalar-first.
//!
//! # One step ([`AttitudeNode::step_into`])
//! 1. The coils' read-back checked against the previous step's commands ([`health`]), then
//!    magnetorquers off (the magnetometers must not see them, note 002 §8.5), then a wait of
//!    [`COIL_DECAY_US`] on the bus's timer ([`TileBus::delay_us`]) for their field to decay.
//! 2. The REF: used if it was made for this step and its clock is valid
//!    ([`crate::link::messages::Reference::usable_at`]); otherwise the step runs without
//!    reference (no Sun or field reference: the filter propagates with the gyros; detumble and
//!    sun-safe need none), reported as [`Faults::link`]. A guidance with a new id is the
//!    ground's track or slew command.
//! 3. Read every working tile ([`sensing`]).
//! 4. Body field, rate, Sun; the attitude filter, started by TRIAD ([`estimation`]).
//! 5. Mode events and the mode's law ([`laws`]), wheel and coil commands ([`actuation`]).
//!
//! | module | what |
//! |---|---|
//! | [`modes`] | the modes and their one transition function |
//! | [`faults`] | the step's faults and their telemetry word |
//! | [`health`] | the wheels' and coils' read-back checks: actuators failed, reported, and (a wheel with a twin) taken out of its allocation |
//! | [`sensing`] | tile reads, tiles taken out of service |
//! | [`stuck`] | the stuck-gyro watch: a gyro whose word repeats while the filter corrects about its axis |
//! | [`estimation`] | field, rate, Sun, the TRIAD start, the filter, the node's clock |
//! | [`laws`] | mode events, B-dot, sun-safe, slew momentum, tracking |
//! | [`actuation`] | wheel and coil allocation, saturation, dumping, the safe state |

use crate::acs_loop::{AcsConfig, AcsError, StepReport};
use crate::control::bdot::BdotState;
use crate::control::wheels::Allocator;
use crate::determination::least_squares::TileSolver;
use crate::determination::mekf::Mekf;
use crate::hal::TileBus;
use crate::link::messages::{GuidanceKind, Reference, Status};
use crate::telemetry::Housekeeping;
use crate::tiles::{Tile, TileState, MAX_TILES};
use crate::time::{Epoch, TimeSpan, Utc};

pub mod actuation;
pub mod estimation;
pub mod faults;
pub mod health;
pub mod laws;
pub mod modes;
pub mod sensing;
pub mod stuck;

pub use estimation::FIELD_MAGNITUDE_TOLERANCE;
pub use faults::Faults;
pub use modes::{Mode, INVALID_STEPS_TO_SAFE};
pub use sensing::FAILURES_TO_MARK_FAILED;

use health::ActuatorHealth;
use modes::{next_mode, Event, ModeState};
use stuck::StuckGyros;

/// The wait between switching the coils off and reading the tiles, µs: 5 ms, 12.8 time
/// constants of the flight coil (τ = L/R = 0.39 ms, seed 002 §6.4's coil; the simulator's
/// `CoilModel::CLASS`), so a coil's field at the magnetometers (up to 140 000 nT at its own
/// tile's, `docs/simulator.md`) has decayed by e^−12.8 to at most 0.4 nT, below the
/// magnetometers' 10 nT word. The one-image loop needed none: its 55 ms of models ran between
/// the two. Issue #29, item 4; `tests/two_node.rs` checks the order on the bus.
pub const COIL_DECAY_US: u32 = 5_000;

/// The attitude node's state: mode, estimator memories, commands in force, device health; for
/// at most `N` ≤ 32 tiles. It borrows its configuration (`'c`: on the MSP430 a `static` in
/// flash); the tiles' run-time health is kept here ([`AttitudeNode::tile_state`]), the
/// configuration's tile states are the initial ones.
#[derive(Clone, Debug)]
pub struct AttitudeNode<'c, const N: usize = MAX_TILES> {
    config: &'c AcsConfig<N>,
    /// Bit `i` set: tile `i` is out of service (failed at run time or configured failed).
    failed: u32,
    mode: ModeState,
    bdot: BdotState,
    invalid_steps: u16,
    /// A device answered in the previous step: failures mark a tile failed only then (a
    /// bus-wide burst is not the tiles' fault).
    bus_answered: bool,
    /// The node's copy of the clock: the UTC of the last step (the REF's, or one period on).
    clock: Option<Epoch<Utc>>,
    /// The control period as a time span.
    period: TimeSpan,
    /// The step number (the next step's).
    step: u32,
    /// Resets since first power (kept by the caller, reported in STATUS).
    boot_count: u16,
    /// The id of the last guidance accepted.
    guidance_id: u16,
    /// Consecutive steps without a usable REF (saturating).
    without_reference: u16,
    /// The mode fell back to `SunSafe` while the link was down: the guidance in force is taken
    /// again when usable REFs resume.
    resume_guidance: bool,
    /// The last usable REF's shadow was the umbra (no Sun reading is believed without a REF
    /// until one says otherwise).
    last_umbra: bool,
    /// `|B|²` of the last usable REF's field, nT² (the magnitude check without a REF).
    last_field_nt2: Option<f32>,
    /// The attitude filter's state ([`crate::determination::mekf`]).
    estimate: Option<Mekf>,
    /// Commanded momentum of each tile's wheel, kg·m²/s along the tile normal.
    wheel_h: [f32; N],
    failures: [u8; N],
    /// Each tile's last device error: the device (high nibble: 1 Sun sensor, 2 magnetometer,
    /// 3 gyro, 4 wheel) and its [`crate::hal::ErrorKind::code`]; 0 none since reset or restore.
    last_error: [u8; N],
    /// The housekeeping schedule the ground sets ([`crate::telemetry`]).
    housekeeping: Housekeeping,
    /// The wheels' and coils' read-back checks ([`health`]).
    health: ActuatorHealth<N>,
    /// Allocators of the wheels and the coils, rebuilt when their working set changes.
    wheel_allocator: Option<Allocator>,
    coil_allocator: Option<Allocator>,
    /// Least-squares operators of the magnetometers and the gyros, rebuilt when the set of
    /// tiles giving a reading changes.
    mag_solver: Option<TileSolver>,
    gyro_solver: Option<TileSolver>,
    /// The stuck-gyro watch ([`stuck`]).
    stuck: StuckGyros<N>,
}

impl<'c, const N: usize> AttitudeNode<'c, N> {
    /// A node in `Detumble` at step 0 for the given configuration.
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    pub fn new(config: &'c AcsConfig<N>) -> Result<Self, AcsError> {
        let finite = config.filter.is_valid()
            && config.detumble_enter_radps.is_finite()
            && config.detumble_exit_radps.is_finite()
            && config.wheel_limit_nms.is_finite()
            && config.dumping_gain_per_s.is_finite()
            && config.control_period_s > 0.0
            && config.control_period_s.is_finite();
        if !finite || config.detumble_exit_radps >= config.detumble_enter_radps || N > 32 {
            return Err(AcsError::InvalidConfig);
        }
        let failed = config
            .tiles
            .iter()
            .enumerate()
            .filter(|(_, t)| !t.is_working())
            .fold(0u32, |m, (i, _)| m | health::mask(i));
        Ok(Self {
            config,
            failed,
            mode: ModeState::Detumble,
            bdot: BdotState::default(),
            invalid_steps: 0,
            bus_answered: true,
            clock: None,
            period: TimeSpan::from_seconds_f32(config.control_period_s),
            step: 0,
            boot_count: 0,
            guidance_id: 0,
            without_reference: 0,
            resume_guidance: false,
            last_umbra: false,
            last_field_nt2: None,
            estimate: None,
            wheel_h: [0.0; N],
            failures: [0; N],
            last_error: [0; N],
            housekeeping: Housekeeping::new(),
            health: ActuatorHealth::new(),
            wheel_allocator: None,
            coil_allocator: None,
            mag_solver: None,
            gyro_solver: None,
            stuck: StuckGyros::new(),
        })
    }

    /// Sets the boot count STATUS reports (the firmware keeps it across resets).
    pub fn set_boot_count(&mut self, boot_count: u16) {
        self.boot_count = boot_count;
    }

    /// The current mode.
    pub fn mode(&self) -> Mode {
        self.mode.mode()
    }

    /// The node's copy of the clock: the UTC of its last step, `None` before the first REF
    /// with a valid clock.
    pub fn clock(&self) -> Option<Epoch<Utc>> {
        self.clock
    }

    /// The number of the next step (the REF it uses must carry it).
    pub fn step_number(&self) -> u32 {
        self.step
    }

    /// The configured tiles (their run-time state: [`AttitudeNode::tile_state`]).
    pub fn tiles(&self) -> &[Tile] {
        self.config.tiles.as_slice()
    }

    /// The run-time state of tile `tile`, `None` if there is no such tile.
    pub fn tile_state(&self, tile: usize) -> Option<TileState> {
        (self.config.tiles.len() > tile).then(|| {
            if self.is_working(tile) {
                TileState::Working
            } else {
                TileState::Failed
            }
        })
    }

    /// True if tile `tile` is in service at run time.
    fn is_working(&self, tile: usize) -> bool {
        self.failed & health::mask(tile) == 0
    }

    /// True if tile `tile` carries a wheel, is in service, and its wheel is in the allocation
    /// ([`health`]).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn has_working_wheel(&self, tile: usize, t: &Tile) -> bool {
        t.equipment.reaction_wheel && self.is_working(tile) && self.health.wheel_in(tile)
    }

    /// The wheels' and coils' health ([`health`]): which are failed, which out of their
    /// allocation.
    pub fn health(&self) -> &ActuatorHealth<N> {
        &self.health
    }

    /// Fails coil `coil` and takes it out of its allocation (`failed`, the ground's
    /// `MARK_FAILED` of a coil), or returns it to service (`RESTORE`); false (nothing changed) if
    /// there is no such coil.
    pub fn set_coil_failed(&mut self, coil: usize, failed: bool) -> bool {
        self.health
            .set_coil_failed(coil, failed, self.config.coils.len())
    }

    /// Marks a tile failed (ground command or fault detection); its devices are no longer used
    /// and its wheel is stopped at the next step.
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    pub fn mark_failed(&mut self, tile: usize) {
        if self.config.tiles.len() > tile {
            self.failed |= health::mask(tile);
        }
    }

    /// Returns a tile to service (ground command, e.g. after a power cycle of a tile marked
    /// failed): its devices, its wheel included ([`health`]), are used again from the next
    /// step, its bus-failure count restarts, and the cached allocators and least-squares
    /// operators are rebuilt for the new set.
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    pub fn restore(&mut self, tile: usize) {
        self.health.restore_wheel(tile);
        self.failed &= !health::mask(tile);
        if let Some(count) = self.failures.get_mut(tile) {
            *count = 0;
        }
        if let Some(e) = self.last_error.get_mut(tile) {
            *e = 0;
        }
    }

    /// The housekeeping schedule ([`crate::telemetry`]).
    pub fn housekeeping(&self) -> &Housekeeping {
        &self.housekeeping
    }

    /// The housekeeping schedule, for the ground's interval and the image's period count.
    pub fn housekeeping_mut(&mut self) -> &mut Housekeeping {
        &mut self.housekeeping
    }

    /// Consecutive steps without a usable REF (saturating).
    pub fn steps_without_reference(&self) -> u16 {
        self.without_reference
    }

    /// The attitude filter, if it runs.
    pub fn filter(&self) -> Option<&Mekf> {
        self.estimate.as_ref()
    }

    /// The attitude filter's covariance diagonal ([`Mekf::variances`]), NaN without a filter.
    pub fn filter_variances(&self) -> [f32; crate::determination::mekf::STATES] {
        self.estimate.as_ref().map_or(
            [f32::NAN; crate::determination::mekf::STATES],
            Mekf::variances,
        )
    }

    /// Each tile's wheel momentum commanded, kg·m²/s.
    pub fn wheels_commanded(&self) -> &[f32; N] {
        &self.wheel_h
    }

    /// Bit `c`: coil `c` is failed.
    pub fn coils_failed(&self) -> u8 {
        (self.health.masks().0 >> 24) as u8
    }

    /// Each tile's state as a telemetry code: bit 0 out of service, 1 its wheel failed, 2 its
    /// wheel out of its allocation, 3 its gyro held stuck, 4–7 its read failures in a row (to
    /// 15).
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    pub fn part_states(&self) -> [u8; N] {
        let (mut wheel_failed, mut wheel_out) = self.health.masks();
        let (mut failed, mut held) = (self.failed, self.stuck.held_mask());
        let mut out = self.failures;
        for o in out.iter_mut() {
            let bits =
                (failed & 1) | (wheel_failed & 1) << 1 | (wheel_out & 1) << 2 | (held & 1) << 3;
            *o = core::cmp::min(*o, 15) << 4 | bits as u8;
            failed >>= 1;
            wheel_failed >>= 1;
            wheel_out >>= 1;
            held >>= 1;
        }
        out
    }

    /// Each tile's last device error since reset or its restore: the device in the high
    /// nibble (1 Sun sensor, 2 magnetometer, 3 gyro, 4 wheel read-back) and the error in the
    /// low ([`crate::hal::ErrorKind::code`]; a word pinned at an end of its range is 3, out of
    /// range); 0 none.
    pub fn part_errors(&self) -> &[u8; N] {
        &self.last_error
    }

    /// The ground's sun-safe command (the attitude node's own: a dead link never takes it
    /// away). It starts the count of steps without attitude afresh.
    pub fn sun_safe(&mut self) {
        self.transition(Event::SunSafe);
        self.invalid_steps = 0;
        self.resume_guidance = false;
    }

    /// Applies [`next_mode`]; leaving `Detumble` forgets the B-dot derivative's last sample
    /// (a later detumble must not difference against it). Out of line: the modes' copies stay
    /// off the step's frame.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn transition(&mut self, event: Event) {
        let was_detumbling = matches!(self.mode, ModeState::Detumble);
        next_mode(&mut self.mode, event);
        if was_detumbling && !matches!(self.mode, ModeState::Detumble) {
            self.bdot.reset();
        }
    }

    /// A guidance with a new id is the ground's command through the reference node: track, or
    /// a slew from the wheels' momentum now. A command starts the count of steps without
    /// attitude afresh (after a fall-back it stayed at [`INVALID_STEPS_TO_SAFE`]: a `TRACK`
    /// would have gone straight back to `SunSafe`). After a fall-back to `SunSafe` while the
    /// link was down, the guidance in force is taken again when usable REFs resume (a slew
    /// still in progress as tracking of its target: its plan ran on by the clock meanwhile).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn accept(&mut self, reference: &Reference) {
        let g = &reference.guidance;
        let resume = self.resume_guidance && matches!(self.mode, ModeState::SunSafe);
        if g.id == self.guidance_id && !resume {
            return;
        }
        self.resume_guidance = false;
        self.guidance_id = g.id;
        match g.kind {
            GuidanceKind::None => return,
            GuidanceKind::Track => self.transition(Event::Track(g.target)),
            GuidanceKind::Slew if resume => self.transition(Event::Track(g.target)),
            GuidanceKind::Slew => self.transition(Event::Slew {
                h_base: self.wheels_body(),
                target: g.target,
            }),
        }
        self.invalid_steps = 0;
    }

    /// [`AttitudeNode::step_into`] returning its report.
    pub fn step<B: TileBus>(
        &mut self,
        bus: &mut B,
        reference: Option<&Reference>,
        dt_s: f32,
    ) -> (StepReport, Status) {
        let mut report = StepReport::empty(self.mode());
        let status = self.step_into(bus, reference, dt_s, &mut report);
        (report, status)
    }

    /// One control step, `dt_s` seconds after the previous one by the node's timer, with the
    /// REF that arrived for it (if any; one made for another step or without a valid clock is
    /// not used); writes its report into `report` (every field is set) and returns STATUS.
    ///
    /// The phases are separate functions kept out of line, so that their temporaries do not
    /// share one stack frame (on the MSP430 the step's peak stack is the deepest phase, not the
    /// sum of them).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub fn step_into<B: TileBus>(
        &mut self,
        bus: &mut B,
        reference: Option<&Reference>,
        dt_s: f32,
        report: &mut StepReport,
    ) -> Status {
        let mut faults = self.coils_off(bus, true);
        bus.delay_us(COIL_DECAY_US);
        let reference = reference.filter(|r| r.usable_at(self.step));
        match reference {
            Some(r) => {
                faults.take_reference(r.faults);
                self.without_reference = 0;
                self.accept(r);
            }
            None => {
                faults.link = true;
                self.without_reference = self.without_reference.saturating_add(1);
            }
        }
        report.reset(self.mode());
        report.sun_fraction = reference.and_then(|r| r.illumination.map(|i| i.fraction));
        let dt = self.sense(bus, reference, dt_s, &mut faults, report);
        self.change_mode(report);
        let guidance = reference.map(|r| &r.guidance);
        // the laws' dipole written into the report, their momentum used in place (each copy
        // is a `memcpy` on the MSP430)
        let h_target = self.laws(report, dt, guidance, &mut faults);
        self.actuate(
            bus,
            report.b_body_nt.as_ref(),
            (&mut report.dipole_body_am2, &mut report.h_wheels_body),
            h_target.as_ref(),
            &mut faults,
        );
        report.mode = self.mode();
        report.faults = faults;
        let status = Status {
            step: self.step,
            boot_count: self.boot_count,
            mode: self.mode().code() as u8,
            attitude: report.attitude,
            h_wheels_body_nms: report.h_wheels_body,
            guidance_id: self.guidance_id,
            faults: faults.bits(),
            utc: self.clock,
        };
        self.step = self.step.wrapping_add(1);
        status
    }

    /// Step phases 3 and 4: reads the tiles and determines from their readings (which live in
    /// this frame only); returns the seconds since the previous step.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn sense<B: TileBus>(
        &mut self,
        bus: &mut B,
        reference: Option<&Reference>,
        dt_s: f32,
        faults: &mut Faults,
        report: &mut StepReport,
    ) -> f32 {
        let readings = self.read_tiles(bus, faults);
        self.determine(&readings, reference, dt_s, faults, report)
    }
}
