//! The ACS loop as one composition of its two nodes (issue #29): the *reference* node
//! ([`crate::reference_node`]: clock, SGP4, Sun, shadow, IGRF, guidance) and the *attitude*
//! node ([`crate::attitude_node`]: tile reads, determination, modes and fault management, laws,
//! allocation; the only one that commands actuators), joined by their messages
//! ([`crate::link::messages`]: STATUS and REF, their bytes bit for bit as on the link). One
//! [`AcsLoop::step`] per control period: the reference node makes the REF for the step at the
//! step's UTC, the attitude node runs the step with it and answers STATUS. The simulator, the
//! `acs` tool, the campaigns, the tests and the examples fly this composition; the flight
//! firmware runs each node on its own MSP430 (a team with one larger processor composes them in
//! one image exactly as here).
//!
//! Attitudes follow [`crate::attitude`]: `v_body = A · v_ref` with the reference frame TEME of
//! date; quaternions scalar-first.
//!
//! # One step
//! 1. Magnetorquers off (the magnetometers must not see them, note 002 §8.5).
//! 2. The REF (reference node): SGP4 position at the step's UTC epoch; the Sun by the thesis's
//!    model ([`crate::env::sun::schlyter`], Schlyter: 46.9″ at most against JPL DE421) and the
//!    cylindrical shadow test ([`crate::env::eclipse::cylindrical_illumination`]; the loop's
//!    pointing requirement is 0.1° = 360″, its Sun sensors' noise 1 mrad = 206″); the IGRF
//!    field in TEME through GMST (UT1 ≈ UTC); the guidance.
//! 3. Read every working tile: Sun angles (lit or not), magnetometer, gyro. A device that fails
//!    [`FAILURES_TO_MARK_FAILED`] times in a row has its tile marked failed, unless no device
//!    answered in the step before (the bus failing, not the tiles).
//! 4. Body field and rate by least squares over the tiles (operators cached per set of working
//!    tiles; a field whose magnitude is more than [`FIELD_MAGNITUDE_TOLERANCE`] from the model's
//!    is refused, [`Faults::field`]: a coil left on, a magnetometer gone wrong); Sun direction
//!    averaged over the lit tiles (only outside the umbra); attitude by
//!    Wahba's SVD (two-vector closed form) from the Sun and field pairs, filtered with the gyros
//!    ([`crate::determination::complementary`], which also bridges short gaps, e.g. eclipse
//!    entry, for at most `max_propagation_s`).
//! 5. Mode logic (below), the mode's law, wheel momentum and coil dipole commands.
//!
//! # Modes and transitions
//! | mode | law | actuators | leaves when |
//! |---|---|---|---|
//! | `Detumble` | B-dot (gyro form if the rate is known, else field derivative) | coils | `|ω| < exit_rate` → `SunSafe` |
//! | `SunSafe` | Sun pointing + rate damping; damping only in eclipse | wheels (coils if no wheel), coils dump momentum | a ground command → `Slew` or `Tracking` |
//! | `Slew` | the thesis's plan (principal-axis rotations at constant momentum), planned by the reference node and sent as each step's feed-forward momentum (it needs no attitude) | wheels | plan done → `Tracking` of the commanded attitude |
//! | `Tracking` | quaternion feedback | wheels, coils dump momentum | a new command |
//! From any mode: `|ω| > enter_rate` → `Detumble`; a ground command (sun-safe, track, a slew
//! that could be planned) → its mode. In `Slew` and `Tracking`, an invalid attitude makes the
//! step hold the wheels (no new momentum command) with the coils off, and after
//! [`INVALID_STEPS_TO_SAFE`] steps the loop falls back to `SunSafe`. The mode carries its data
//! (a slew the wheels' momentum before it and its target, tracking its target) and one function
//! makes every transition (`next_mode`, over these events; leaving `Detumble` forgets the
//! B-dot derivative's last sample).
//!
//! # Who owns which command
//! | command | node | why |
//! |---|---|---|
//! | sun-safe, mark a tile failed, restore a tile | attitude | a dead link never takes them away |
//! | track, slew | reference | the guidance and the slew planner are there |
//! | clock, element set | reference | the models are there |
//!
//! # Safe state
//! Whenever the attitude is not valid and the mode needs it, or any model fails, the coils are
//! off and the wheels hold their momentum (no torque). [`AcsLoop::safe`] puts all actuators in
//! the safe state (coils off, wheel momentum held).
//!
//! Memory: the nodes borrow their [`AcsConfig`] (the flight firmware keeps it in flash, a
//! `static`) and hold only their run-time state (`tests/closed_loop.rs::loop_state_size`
//! prints it on the host). No allocation.

use core::fmt;

use crate::attitude::{Dcm, Quaternion};
use crate::attitude_node::AttitudeNode;
use crate::control::bdot::BdotConfig;
use crate::control::principal_axes::PrincipalAxes;
use crate::control::slew::SlewLimits;
use crate::control::sun_safe::SunSafeGains;
use crate::control::tracking::TrackingGains;
use crate::control::wheels::Wheel;
use crate::env::igrf::{Degree, Model, FULL_COEFFS};
use crate::hal::TileBus;
use crate::linalg::Vec3;
use crate::link::messages::{Guidance, Reference, Status};
use crate::orbit::sgp4::Sgp4;
use crate::reference_node::ReferenceNode;
use crate::tiles::{Tile, TileState, MAX_TILES};
use crate::time::{Epoch, Utc};

pub use crate::attitude_node::{
    Faults, Mode, FAILURES_TO_MARK_FAILED, FIELD_MAGNITUDE_TOLERANCE, INVALID_STEPS_TO_SAFE,
};

/// Maximum number of magnetorquer coils.
pub const MAX_COILS: usize = 6;

/// Gains, limits and geometry of the loop, for at most `N` tiles (`N` ≤ 32; the host default
/// [`MAX_TILES`]; the flight firmware sizes it to its satellite, e.g. 6 for the thesis's cube, which
/// keeps the loop's RAM small).
#[derive(Clone, Debug)]
pub struct AcsConfig<const N: usize = MAX_TILES> {
    /// The satellite's tiles (their state is updated at run time in [`AcsLoop`]).
    pub tiles: heapless::Vec<Tile, N>,
    /// Principal axes and inertia (kg·m², body).
    pub axes: PrincipalAxes,
    /// Magnetorquer coils: axis in body, dipole limit (A·m²), working flag.
    pub coils: heapless::Vec<Wheel, MAX_COILS>,
    /// Momentum limit of each reaction wheel, kg·m²/s.
    pub wheel_limit_nms: f32,
    /// Torque the wheels deliver about each body axis, N·m: a torque law's body torque is
    /// scaled, keeping its direction, so that no axis asks more before it is integrated into
    /// the wheels' momentum (`ḣ = −τ`). Without it the loop commands a momentum the wheels
    /// cannot follow and, having no read-back, falls into a limit cycle (finding 8,
    /// `docs/faults.md`). If any component is not a positive finite number the torque is not
    /// limited at all (infinity: no limit; the flight value is checked at compile time).
    pub wheel_torque_nm: Vec3,
    /// B-dot gain and dipole limits.
    pub bdot: BdotConfig,
    /// Tracking gains.
    pub tracking: TrackingGains,
    /// Sun-safe gains.
    pub sun_safe: SunSafeGains,
    /// Body axis pointed at the Sun in `SunSafe` (unit).
    pub sun_axis_body: Vec3,
    /// Momentum-planner limits of the thesis's slew.
    pub slew_limits: SlewLimits,
    /// The control period, s: slew durations are rounded up to whole periods (the loop can only
    /// change a wheel command on a tick) with the momentum scaled to keep each angle exact.
    pub control_period_s: f32,
    /// Pause after each rotation of a slew, s: the wheels return to their momentum before the
    /// slew, so the body stops before it turns about the next axis (the thesis spaces its three
    /// rotations 5 s apart; without a stop, a torque-limited wheel would turn the body about an
    /// intermediate axis during the hand-over).
    pub slew_pause_s: f32,
    /// Momentum dumping gain, 1/s (0 disables dumping).
    pub dumping_gain_per_s: f32,
    /// Rate above which the loop detumbles, rad/s.
    pub detumble_enter_radps: f32,
    /// Rate below which detumbling ends, rad/s.
    pub detumble_exit_radps: f32,
    /// Geomagnetic model and degree used on board.
    pub igrf_model: &'static Model,
    /// Degree of the on-board field model.
    pub igrf_degree: Degree,
    /// Weights of the Sun and field observations in Wahba's loss (`σ⁻²`, rad⁻²).
    pub weights: (f32, f32),
    /// Gain of the attitude filter, 0 < k ≤ 1: the fraction of the measured-minus-predicted
    /// rotation taken each step (1 = raw measurements; about 0.1 averages ten steps of noise).
    pub filter_gain: f32,
    /// Longest time the attitude may be propagated with the gyros alone, s.
    pub max_propagation_s: f32,
}

/// A ground command.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Command {
    /// Slew to `target` (reference → body, [`crate::attitude`]) within `within_s` seconds by the
    /// thesis's open-loop plan, then track it.
    Slew {
        /// Commanded attitude `A_d`.
        target: Dcm,
        /// Commanded time `t_m`, s.
        within_s: f32,
    },
    /// Track `target` (reference → body) with the closed-loop law.
    Track {
        /// Commanded attitude.
        target: Quaternion,
    },
    /// Back to sun-safe.
    SunSafe,
}

/// What one step measured, decided and commanded.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct StepReport {
    /// The mode after this step's transitions.
    pub mode: Mode,
    /// The attitude measured this step by Wahba SVD (reference TEME → body), if any.
    pub measured_attitude: Option<Quaternion>,
    /// The filtered attitude the laws used (reference TEME → body), if valid.
    pub attitude: Option<Quaternion>,
    /// Body rate from the gyros, rad/s.
    pub omega_body_radps: Option<Vec3>,
    /// Body field from the magnetometers, nT.
    pub b_body_nt: Option<Vec3>,
    /// Sun direction in body axes (unit), if seen.
    pub sun_body: Option<Vec3>,
    /// Visible fraction of the solar disc from the orbit and Sun models: 0 in the (cylindrical)
    /// shadow, 1 outside it.
    pub sun_fraction: Option<f32>,
    /// Commanded body dipole, A·m².
    pub dipole_body_am2: Vec3,
    /// Commanded total wheel momentum (body), kg·m²/s.
    pub h_wheels_body: Vec3,
    /// Faults of this step.
    pub faults: Faults,
}

impl StepReport {
    /// Sets every field to [`StepReport::empty`]'s, in place.
    pub(crate) fn reset(&mut self, mode: Mode) {
        self.mode = mode;
        self.measured_attitude = None;
        self.attitude = None;
        self.omega_body_radps = None;
        self.b_body_nt = None;
        self.sun_body = None;
        self.sun_fraction = None;
        self.dipole_body_am2 = Vec3::zeros();
        self.h_wheels_body = Vec3::zeros();
        self.faults = Faults::default();
    }

    /// True if every value the report holds is finite (no NaN, no infinity): what the loop
    /// promises whatever its inputs (the fault table, the soak and the fuzzing check it).
    pub fn is_finite(&self) -> bool {
        let finite = |v: &Vec3| v.iter().all(|x| x.is_finite());
        let q_finite = |q: &Quaternion| [q.q0, q.q1, q.q2, q.q3].iter().all(|x| x.is_finite());
        [self.omega_body_radps, self.b_body_nt, self.sun_body]
            .iter()
            .flatten()
            .all(finite)
            && [self.attitude, self.measured_attitude]
                .iter()
                .flatten()
                .all(q_finite)
            && self.sun_fraction.is_none_or(f32::is_finite)
            && finite(&self.dipole_body_am2)
            && finite(&self.h_wheels_body)
    }

    /// A report of nothing measured or commanded yet, in `mode` (the value a caller of
    /// [`AcsLoop::step_into`] starts from).
    pub fn empty(mode: Mode) -> Self {
        Self {
            mode,
            measured_attitude: None,
            attitude: None,
            omega_body_radps: None,
            b_body_nt: None,
            sun_body: None,
            sun_fraction: None,
            dipole_body_am2: Vec3::zeros(),
            h_wheels_body: Vec3::zeros(),
            faults: Faults::default(),
        }
    }
}

/// Errors of [`AcsLoop::new`] and [`AcsLoop::command`].
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum AcsError {
    /// A configuration value is not finite or not positive where it must be, the tile capacity
    /// exceeds 32, or the IGRF degree needs more coefficients than the loop has room for.
    InvalidConfig,
    /// A slew cannot be planned now (no valid attitude, or the planner refused).
    CannotSlew,
}

impl fmt::Display for AcsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidConfig => write!(f, "invalid ACS configuration"),
            Self::CannotSlew => write!(f, "slew cannot be planned now"),
        }
    }
}

/// The two nodes composed in one program, joined by their messages as bytes (bit for bit what
/// the link carries): for at most `N` ≤ 32 tiles (see [`AcsConfig`]), with room for `F` IGRF
/// coefficients on the reference node (`F` ≥ the configured degree's
/// [`crate::env::igrf::coefficient_count`]: 80 for degree 8, the default 195 for 13).
#[derive(Clone, Debug)]
pub struct AcsLoop<'c, const N: usize = MAX_TILES, const F: usize = FULL_COEFFS> {
    reference: ReferenceNode<'c, N, F>,
    attitude: AttitudeNode<'c, N>,
    /// The attitude node's last STATUS, as the reference node received it.
    status: Option<Status>,
}

impl<'c, const N: usize, const F: usize> AcsLoop<'c, N, F> {
    /// A loop in `Detumble` for the given configuration and orbit (an [`Sgp4`], or `None`: a
    /// loop without an element set, as after a corrupt one at start-up, still detumbles and
    /// keeps the Sun on its panel, the laws that need no reference, with [`Faults::orbit`] set
    /// each step until [`Self::set_orbit`] gives it one).
    pub fn new(config: &'c AcsConfig<N>, orbit: impl Into<Option<Sgp4>>) -> Result<Self, AcsError> {
        Ok(Self {
            reference: ReferenceNode::new(config, orbit)?,
            attitude: AttitudeNode::new(config)?,
            status: None,
        })
    }

    /// Replaces the element set the reference node propagates (an uplink: check the words with
    /// [`Sgp4::from_words`] first, so that a refused set leaves the one in use).
    pub fn set_orbit(&mut self, orbit: Sgp4) {
        self.reference.set_orbit(orbit);
    }

    /// The current mode.
    pub fn mode(&self) -> Mode {
        self.attitude.mode()
    }

    /// The reference node's guidance in force (a track or slew command takes effect at the
    /// next step, when the attitude node receives it in the REF).
    pub fn guidance(&self) -> &Guidance {
        self.reference.guidance()
    }

    /// The configured tiles (their run-time state: [`AcsLoop::tile_state`]).
    pub fn tiles(&self) -> &[Tile] {
        self.attitude.tiles()
    }

    /// The run-time state of tile `tile`, `None` if there is no such tile.
    pub fn tile_state(&self, tile: usize) -> Option<TileState> {
        self.attitude.tile_state(tile)
    }

    /// Marks a tile failed (ground command or fault detection); its devices are no longer used
    /// and its wheel is stopped at the next step.
    pub fn mark_failed(&mut self, tile: usize) {
        self.attitude.mark_failed(tile);
    }

    /// Returns a tile to service (ground command, e.g. after a power cycle of a tile marked
    /// failed).
    pub fn restore(&mut self, tile: usize) {
        self.attitude.restore(tile);
    }

    /// Accepts a ground command, at the node that owns it (module docs); it takes effect at the
    /// next step. A slew is planned from the last determined attitude (`attitude`, reference →
    /// body), so it needs one.
    pub fn command(
        &mut self,
        command: Command,
        attitude: Option<&Quaternion>,
        now: Epoch<Utc>,
    ) -> Result<(), AcsError> {
        match command {
            Command::SunSafe => self.attitude.sun_safe(),
            Command::Track { target } => self.reference.track(target),
            Command::Slew { target, within_s } => {
                let attitude = attitude.ok_or(AcsError::CannotSlew)?;
                self.reference.slew(attitude, &target, within_s, now)?;
            }
        }
        Ok(())
    }

    /// Puts every actuator in the safe state: coils off, wheels hold their momentum.
    pub fn safe<B: TileBus>(&mut self, bus: &mut B) -> Faults {
        self.attitude.safe(bus)
    }

    /// One control step at UTC epoch `now`, `dt_s` seconds after the previous one.
    pub fn step<B: TileBus>(&mut self, bus: &mut B, now: Epoch<Utc>, dt_s: f32) -> StepReport {
        let mut report = StepReport::empty(self.mode());
        self.step_into(bus, now, dt_s, &mut report);
        report
    }

    /// [`AcsLoop::step`] writing its report into `report` (every field is set): the reference
    /// node makes the REF for the step at `now`, which crosses to the attitude node as its
    /// bytes; the attitude node's STATUS crosses back the same way.
    pub fn step_into<B: TileBus>(
        &mut self,
        bus: &mut B,
        now: Epoch<Utc>,
        dt_s: f32,
        report: &mut StepReport,
    ) {
        self.reference.set_clock(now);
        let step = self.attitude.step_number();
        let reference = self.reference.reference(step, self.status.as_ref());
        let reference = Reference::from_bytes(&reference.to_bytes()).ok();
        let status = self
            .attitude
            .step_into(bus, reference.as_ref(), dt_s, report);
        self.status = Status::from_bytes(&status.to_bytes()).ok();
    }
}
