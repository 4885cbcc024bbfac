//! The ACS loop in one image: one [`AcsLoop::step`] per control period reads the tiles, propagates
//! the orbit, evaluates the Sun and field models, determines attitude and rate, runs the active
//! mode's law and commands the actuators (issue #8; the thesis's synchronous call sequence of
//! note 000 §1.5, closed).
//!
//! Since issue #29 the ACS flies as two nodes ([`crate::reference_node`],
//! [`crate::attitude_node`], composed on the host by [`crate::two_node::TwoNodeLoop`]), which
//! command bit for bit what this loop commands (`tests/two_node.rs`). This one-image form stays
//! for the benchmark's one-call step (its cycles bound each node's step without the hardware
//! multiplier) and the one-image size that CI reports; the two share their modes, faults and
//! constants (the attitude node's). It goes when the benchmark measures the nodes' steps apart.
//!
//! Attitudes follow [`crate::attitude`]: `v_body = A · v_ref` with the reference frame TEME of
//! date; quaternions scalar-first.
//!
//! # One step
//! 1. Magnetorquers off (the magnetometers must not see them, note 002 §8.5).
//! 2. SGP4 position at the step's UTC epoch; the Sun by the thesis's model
//!    ([`crate::env::sun::schlyter`], Schlyter: 46.9″ at most against JPL DE421) and the
//!    cylindrical shadow test ([`crate::env::eclipse::cylindrical_illumination`]): the flight
//!    image carries these rather than the precise Sun (2.2″) and the conical shadow, which
//!    together take 7.5 KB more of the MSP430's flash (issue #17; the loop's pointing
//!    requirement is 0.1° = 360″, its Sun sensors' noise 1 mrad = 206″);
//!    IGRF field in TEME through GMST (UT1 ≈ UTC), its coefficients interpolated to the step's
//!    date each step (not kept between steps: on the MSP430 that saves `4·F` bytes of RAM,
//!    780 B at the flight degree 13, for ≈ 63 500 cycles a step).
//! 3. Read every working tile: Sun angles (lit or not), magnetometer, gyro (after the models,
//!    so that on the MSP430 the raw readings live only under the determination, and the coils'
//!    field has the models' time to decay). A device that fails [`FAILURES_TO_MARK_FAILED`]
//!    times in a row has its tile marked failed, unless no device answered in the step before
//!    (the bus failing, not the tiles).
//! 4. Body field and rate by least squares over the tiles (operators cached per set of working
//!    tiles; a field whose magnitude is more than [`FIELD_MAGNITUDE_TOLERANCE`] from the model's
//!    is refused, [`Faults::field`]: a coil left on, a magnetometer gone wrong); Sun direction
//!    averaged over the lit tiles (only outside the umbra); the
//!    attitude filter, started by TRIAD (the Sun exact,
//!    [`crate::determination::triad::pair_quaternion`]) from the Sun and field pairs ([`crate::determination::mekf`]: propagated with the gyros, updated with
//!    the Sun and the field, its gyro and magnetometer biases estimated).
//! 5. Mode logic (below), the mode's law, wheel momentum and coil dipole commands.
//!
//! # Modes and transitions
//! | mode | law | actuators | leaves when |
//! |---|---|---|---|
//! | `Detumble` | B-dot (gyro form if the rate is known, else field derivative) | coils | `|ω| < exit_rate` → `SunSafe` |
//! | `SunSafe` | Sun pointing + rate damping; damping only in eclipse | wheels (coils if no wheel), coils dump momentum | a ground command → `Slew` or `Tracking` |
//! | `Slew` | the thesis's plan (principal-axis rotations) as a reference trajectory (rate ramps the wheels' torque allows, [`crate::control::slew_trajectory`]) tracked in closed loop: quaternion feedback about the reference beside its feed-forward momentum (the feed-forward alone without an attitude) | wheels | trajectory done → `Tracking` of the commanded attitude |
//! | `Tracking` | quaternion feedback | wheels, coils dump momentum | a new command |
//! From any mode: `|ω| > enter_rate` → `Detumble`; a ground command (sun-safe, track, a slew
//! that could be planned) → its mode. In `Slew` and `Tracking`, an invalid attitude makes the
//! step hold the wheels (no new momentum command) with the coils off, and after
//! [`INVALID_STEPS_TO_SAFE`] steps the loop falls back to `SunSafe`; in the umbra it waits for
//! the Sun instead, `Tracking` damping the rate (the filter cannot start without the Sun). The mode carries its data
//! (a slew its plan's progress and target, tracking its target) and one function makes every
//! transition (`next_mode`, over these events; leaving `Detumble` forgets the B-dot derivative's
//! last sample).
//!
//! # Safe state
//! Whenever the attitude is not valid and the mode needs it, or any model fails, the coils are
//! off and the wheels hold their momentum (no torque). [`AcsLoop::safe`] puts all actuators in
//! the safe state (coils off, wheel momentum held).
//!
//! Memory: the loop borrows its [`AcsConfig`] (the flight firmware keeps it in flash, a
//! `static`) and holds only its run-time state: the SGP4 elements and ≈ 400 B of mode,
//! estimator, commands, tile health and cached operators (`tests/closed_loop.rs::loop_state_size`
//! prints them on the host; the flight firmware's `loop_firmware` figures in
//! `target/msp430/bench.json` are its RAM on the part). No allocation.

use core::fmt;
use core::marker::PhantomData;

use crate::attitude::{Dcm, Quaternion};
use crate::attitude_node::health::{has_twin, ActuatorHealth};
use crate::attitude_node::laws::in_umbra;
use crate::attitude_node::stuck::StuckGyros;
use crate::control::bdot::{bdot_from_rates, BdotConfig, BdotState};
use crate::control::magnetorquer::{dipole_for_torque, dumping_dipole};
use crate::control::principal_axes::PrincipalAxes;
use crate::control::slew::{decompose, manoeuvre_matrix, plan, Branch, SlewLimits, SlewPlan};
use crate::control::slew_trajectory::{
    feedback_torque, SlewFollower, SlewReference, SlewTrajectory,
};
use crate::control::sun_safe::{sun_safe_torque, SunSafeGains};
use crate::control::tracking::{tracking_torque, TrackingGains};
use crate::control::wheels::{Allocator, Wheel, WheelAllocation, WheelError};
use crate::determination::least_squares::{
    angular_rate_body_cached, magnetic_field_body_cached, TileSolver,
};
use crate::determination::mekf::{self, Mekf, MekfConfig, StepInputs, SunObservation};
use crate::determination::sun_sensor::{incidence_inv_cos2, sun_direction_body};
use crate::env::albedo;
use crate::env::eclipse::{cylindrical_illumination, Illumination, Shadow};
use crate::env::igrf::{coefficient_count, Degree, Igrf, IgrfError, ModelId, FULL_COEFFS};
use crate::env::sun::{schlyter, Sun};
use crate::hal::TileBus;
use crate::linalg::{dot, Vec2, Vec3};
use crate::orbit::sgp4::Sgp4;
use crate::tiles::{RawGyro, RawMagnetometer, RawSunAngles, Tile, TileState, MAX_TILES};
use crate::time::{gmst_rad, Epoch, Utc};

pub use crate::attitude_node::{
    Faults, Mode, FAILURES_TO_MARK_FAILED, FIELD_MAGNITUDE_TOLERANCE, INVALID_STEPS_TO_SAFE,
};
const FIELD_SQUARED_LOW: f32 =
    (1.0 - FIELD_MAGNITUDE_TOLERANCE) * (1.0 - FIELD_MAGNITUDE_TOLERANCE);
const FIELD_SQUARED_HIGH: f32 =
    (1.0 + FIELD_MAGNITUDE_TOLERANCE) * (1.0 + FIELD_MAGNITUDE_TOLERANCE);
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
    /// cannot follow and, integrating the commanded momentum, falls into a limit cycle (finding 8,
    /// `docs/faults.md`). If any component is not a positive finite number the torque is not
    /// limited at all (infinity: no limit; the flight value is checked at compile time).
    pub wheel_torque_nm: Vec3,
    /// B-dot gain and dipole limits.
    pub bdot: BdotConfig,
    /// Tracking gains.
    pub tracking: TrackingGains,
    /// The slew feedback's bandwidth over the tracking law's, `k`: its gains are `K_p k²`,
    /// `K_d k` ([`Self::slew_gains`]). A slew's errors grow with its rate (a body whose inertia
    /// is 10 % off the loop's turns 10 % faster or slower than the feed-forward asks), which
    /// a hold's do not; `k` keeps `k ω_n T` small for the discrete loop.
    pub slew_gain_factor: f32,
    /// Sun-safe gains.
    pub sun_safe: SunSafeGains,
    /// Body axis pointed at the Sun in `SunSafe` (unit).
    pub sun_axis_body: Vec3,
    /// Momentum-planner limits of the thesis's slew.
    pub slew_limits: SlewLimits,
    /// The control period, s: a slew's ramps and rotations last whole periods (the loop can only
    /// change a wheel command on a tick; [`crate::control::slew_trajectory`]).
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
    /// Geomagnetic model used on board (its tables by name: [`ModelId`]).
    pub igrf_model: ModelId,
    /// Degree of the on-board field model.
    pub igrf_degree: Degree,
    /// The attitude filter's tuning ([`crate::determination::mekf`]).
    pub filter: MekfConfig,
}

impl<const N: usize> AcsConfig<N> {
    /// The slew feedback's gains: the tracking law's at `slew_gain_factor` times its bandwidth
    /// (`K_p k²`, `K_d k`).
    pub fn slew_gains(&self) -> TrackingGains {
        let k = self.slew_gain_factor;
        TrackingGains {
            kp_nm: crate::linalg::scale(&self.tracking.kp_nm, k * k),
            kd_nms: crate::linalg::scale(&self.tracking.kd_nms, k),
        }
    }

    /// The thesis's plan from `attitude` to `target` within `within_s` (both reference TEME →
    /// body) as the reference trajectory the wheels can follow ([`SlewTrajectory`]: this
    /// configuration's axes, slew limits, wheel torque, control period and pause).
    /// [`AcsError::CannotSlew`] if the decomposition or the planner refuses.
    #[cfg_attr(target_arch = "msp430", inline(always))]
    pub(crate) fn slew_trajectory(
        &self,
        attitude: &Dcm,
        target: &Dcm,
        within_s: f32,
    ) -> Result<SlewTrajectory, AcsError> {
        let m = manoeuvre_matrix(attitude, target, &self.axes);
        let angles = decompose(&m, Branch::Shortest).map_err(|_| AcsError::CannotSlew)?;
        let plan: SlewPlan = plan(&self.axes, &angles, &self.slew_limits, within_s)
            .map_err(|_| AcsError::CannotSlew)?;
        SlewTrajectory::new(
            &plan,
            &self.axes,
            &self.wheel_torque_nm,
            self.control_period_s,
            self.slew_pause_s,
        )
        .map_err(|_| AcsError::CannotSlew)
    }

    /// One step of a slew on the attitude side (both compositions: the attitude node and
    /// [`AcsLoop`]): `follower` moves on by `reference` (its last rate held without one), the
    /// feedback ([`feedback_torque`] at [`Self::slew_gains`]) on the step's estimate `det`
    /// (reference TEME → body, the gyros' rate) and the wheels' momentum `h_wheels` (body,
    /// kg·m²/s) is integrated into the momentum they hold. Returns the wheels' momentum with
    /// the reference's feed-forward (`None` without a reference: hold the momentum in force;
    /// without an attitude the feed-forward alone); a feedback that refuses its input sets
    /// `faults.law`.
    pub(crate) fn follow_slew(
        &self,
        follower: &mut SlewFollower,
        reference: Option<&SlewReference>,
        det: &StepReport,
        h_wheels: &Vec3,
        dt: f32,
        faults: &mut Faults,
    ) -> Option<Vec3> {
        let tracked = follower.advance(reference, det.attitude.as_ref(), dt);
        let r = reference?;
        if let (Some(target), Some(q), Some(w)) = (
            tracked,
            det.attitude.as_ref(),
            det.omega_body_radps.as_ref(),
        ) {
            match feedback_torque(
                &self.slew_gains(),
                &self.axes.inertia_body,
                &self.wheel_torque_nm,
                (q, w),
                &target,
                &r.rate_body_radps,
                h_wheels,
            ) {
                Ok(t) => follower.integrate(&t, dt),
                Err(_) => faults.law = true,
            }
        }
        Some(follower.h_wheels_nms(r))
    }
}

/// A ground command.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Command {
    /// Slew to `target` (reference → body, [`crate::attitude`]) within `within_s` seconds by the
    /// thesis's plan flown in closed loop ([`crate::control::slew_trajectory`]), then track it.
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
    /// The attitude measured from the Sun and the field by TRIAD (the Sun exact:
    /// [`crate::determination::triad::pair_quaternion`]; reference TEME → body) when the
    /// filter (re)started from it at this step; `None` at every other step (TRIAD is computed
    /// only to start the filter).
    pub measured_attitude: Option<Quaternion>,
    /// The filtered attitude the laws used (reference TEME → body), if valid.
    pub attitude: Option<Quaternion>,
    /// Body rate from the gyros, rad/s.
    pub omega_body_radps: Option<Vec3>,
    /// The filter's attitude 1σ about each body axis, rad (with [`Self::attitude`]).
    pub attitude_sigma_rad: Option<Vec3>,
    /// Scalar measurements the filter's innovation gate refused this step.
    pub refused_measurements: u8,
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
        self.attitude_sigma_rad = None;
        self.refused_measurements = 0;
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
        [
            self.omega_body_radps,
            self.b_body_nt,
            self.sun_body,
            self.attitude_sigma_rad,
        ]
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
            attitude_sigma_rad: None,
            refused_measurements: 0,
            b_body_nt: None,
            sun_body: None,
            sun_fraction: None,
            dipole_body_am2: Vec3::zeros(),
            h_wheels_body: Vec3::zeros(),
            faults: Faults::default(),
        }
    }
}

/// A slew in progress: its reference trajectory and start, and the follower with the momentum
/// the wheels hold beside the feed-forward (the two nodes' split: the reference node's
/// trajectory, the attitude node's follower).
#[derive(Copy, Clone, Debug, PartialEq)]
struct SlewProgress {
    trajectory: SlewTrajectory,
    started: Epoch<Utc>,
    follower: SlewFollower,
}

/// The mode with the data it runs on (issue #19 item 3): a slew carries its plan's progress and
/// its target, tracking its target, so no mode can run without its data. [`Mode`] is its tag
/// (telemetry); [`next_mode`] holds every transition.
#[derive(Copy, Clone, Debug, PartialEq)]
enum ModeState {
    Detumble,
    SunSafe,
    /// The slew flown in closed loop on its reference trajectory, then tracking of `target`
    /// (reference → body).
    Slew {
        progress: SlewProgress,
        target: Quaternion,
    },
    /// Tracking of `target` (reference → body).
    Tracking {
        target: Quaternion,
    },
}

impl ModeState {
    /// The mode's tag.
    fn mode(&self) -> Mode {
        match self {
            Self::Detumble => Mode::Detumble,
            Self::SunSafe => Mode::SunSafe,
            Self::Slew { .. } => Mode::Slew,
            Self::Tracking { .. } => Mode::Tracking,
        }
    }
}

/// What changes the mode: the step's findings and the ground's commands (a slew's plan by
/// reference: on the MSP430 an event the size of a plan would sit in the step's frame).
#[derive(Copy, Clone, Debug, PartialEq)]
enum Event<'p> {
    /// The body rate is above `detumble_enter_radps`.
    RateAbove,
    /// The body rate is below `detumble_exit_radps`.
    RateBelow,
    /// [`INVALID_STEPS_TO_SAFE`] steps in a row without a valid attitude.
    AttitudeLost,
    /// The slew's plan is done.
    SlewDone,
    /// Ground: sun-safe.
    SunSafe,
    /// Ground: track `target` (reference → body).
    Track(Quaternion),
    /// Ground: a slew to the target, planned from the attitude at the command.
    Slew(&'p SlewProgress, Quaternion),
}

/// The mode machine's one transition function (the table of the module docs): `state` becomes
/// the mode after `event`, in place (on the MSP430 a mode returned by value would be a plan-sized
/// copy). An event that does not apply to the mode leaves it.
fn next_mode(state: &mut ModeState, event: Event) {
    use ModeState as S;
    *state = match (&*state, event) {
        (_, Event::RateAbove) => S::Detumble,
        (S::Detumble, Event::RateBelow) => S::SunSafe,
        (S::Slew { .. } | S::Tracking { .. }, Event::AttitudeLost) => S::SunSafe,
        (S::Slew { target, .. }, Event::SlewDone) => S::Tracking { target: *target },
        (_, Event::SunSafe) => S::SunSafe,
        (_, Event::Track(target)) => S::Tracking { target },
        (_, Event::Slew(progress, target)) => S::Slew {
            progress: *progress,
            target,
        },
        (_, Event::RateBelow | Event::AttitudeLost | Event::SlewDone) => return,
    };
}

/// The loop's state: mode, estimator memories, commands in force, device health; for at most
/// `N` ≤ 32 tiles (see [`AcsConfig`]), with room for `F` IGRF coefficients (`F` ≥
/// [`coefficient_count`] of the configured degree: the default 195 for 13, the flight degree;
/// 80 for degree 8; they take `4·F` bytes of stack while the field is evaluated, none in the
/// loop's state).
///
/// The loop borrows its configuration (`'c`): on the MSP430 the flight configuration is a
/// `static` in flash and only the run-time state below takes RAM. The tiles' run-time health is
/// kept here ([`AcsLoop::tile_state`]); the configuration's tile states are the initial ones.
#[derive(Clone, Debug)]
pub struct AcsLoop<'c, const N: usize = MAX_TILES, const F: usize = FULL_COEFFS> {
    config: &'c AcsConfig<N>,
    /// Bit `i` set: tile `i` is out of service (failed at run time or configured failed).
    failed: u32,
    orbit: Option<Sgp4>,
    mode: ModeState,
    bdot: BdotState,
    invalid_steps: u16,
    /// A device answered in the previous step: failures mark a tile failed only then (a
    /// bus-wide burst is not the tiles' fault).
    bus_answered: bool,
    last_time: Option<Epoch<Utc>>,
    /// Filtered attitude and the seconds since it last saw a measurement.
    estimate: Option<Mekf>,
    /// Commanded momentum of each tile's wheel, kg·m²/s along the tile normal.
    wheel_h: [f32; N],
    failures: [u8; N],
    /// The wheels' and coils' read-back checks ([`crate::attitude_node::health`]).
    health: ActuatorHealth<N>,
    /// Allocators of the wheels and the coils, rebuilt when their working set changes.
    wheel_allocator: Option<Allocator>,
    coil_allocator: Option<Allocator>,
    /// Least-squares operators of the magnetometers and the gyros, rebuilt when the set of
    /// tiles giving a reading changes.
    mag_solver: Option<TileSolver>,
    gyro_solver: Option<TileSolver>,
    /// The stuck-gyro watch ([`crate::attitude_node::stuck`]).
    stuck: StuckGyros<N>,
    /// Room for the IGRF coefficients at a date, on the stack of the field evaluation only.
    field: PhantomData<[f32; F]>,
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

/// Allocates `l_body` with the cached allocator, rebuilding it first if the working set of
/// `actuators` changed (a failure) or there is none yet.
fn cached_allocation<const N: usize>(
    cache: &mut Option<Allocator>,
    actuators: &[Wheel; N],
    l_body: &Vec3,
) -> Result<WheelAllocation<N>, WheelError> {
    if !cache.is_some_and(|a| a.is_for(actuators)) {
        *cache = None;
        *cache = Some(Allocator::new(actuators)?);
    }
    match cache {
        Some(a) => a.allocate(actuators, l_body),
        None => Err(WheelError::StaleAllocator),
    }
}

/// Per-tile readings of one step, raw as the bus delivered them (the HAL's formats), with a bit
/// per tile for each device that gave one (`sun`: the sensor sees the Sun): 12 B a tile instead
/// of 32 B of converted options, and the conversions happen in the phase that uses them (on the
/// MSP430 the readings live under every phase of the step).
struct Readings<const N: usize> {
    sun: [[i16; 2]; N],
    mag: [[i16; 2]; N],
    gyro: [i16; N],
    sun_seen: u32,
    mag_read: u32,
    gyro_read: u32,
}

/// True if `|b|²` is within `(1 ± FIELD_MAGNITUDE_TOLERANCE)²` of `|m|²` (false for a NaN).
#[cfg_attr(target_arch = "msp430", inline(never))]
fn magnitude_agrees(b: &Vec3, m: &Vec3) -> bool {
    let (measured, model) = (dot(b, b), dot(m, m));
    measured >= FIELD_SQUARED_LOW * model && FIELD_SQUARED_HIGH * model >= measured
}

/// A law's command, or none (zero) with the refusal reported in `faults.law`.
fn reported(command: Option<Vec3>, faults: &mut Faults) -> Vec3 {
    faults.law |= command.is_none();
    command.unwrap_or_else(Vec3::zeros)
}

/// A raw word at either end of the `i16` range.
fn pinned(x: i16) -> bool {
    x == i16::MAX || x == i16::MIN
}

/// Bit `i` of `mask` (false beyond 31).
fn bit(mask: u32, i: usize) -> bool {
    mask & 1u32.checked_shl(i as u32).unwrap_or(0) != 0
}

impl<const N: usize> Readings<N> {
    /// The Sun angles of the tiles that see the Sun, rad.
    fn sun_rad(&self) -> [Option<crate::tiles::SunAngles>; N] {
        let mut out = [None; N];
        for (i, (o, [a, b])) in out.iter_mut().zip(self.sun.iter()).enumerate() {
            if bit(self.sun_seen, i) {
                *o = Some(RawSunAngles { a: *a, b: *b }.to_rad());
            }
        }
        out
    }

    /// The magnetometer readings, nT.
    fn mag_nt(&self) -> [Option<Vec2>; N] {
        let mut out = [None; N];
        for (i, (o, [x, y])) in out.iter_mut().zip(self.mag.iter()).enumerate() {
            if bit(self.mag_read, i) {
                *o = Some(RawMagnetometer { x: *x, y: *y }.to_nt());
            }
        }
        out
    }

    /// The gyro readings, rad/s.
    fn gyro_radps(&self) -> [Option<f32>; N] {
        let mut out = [None; N];
        for (i, (o, w)) in out.iter_mut().zip(self.gyro.iter()).enumerate() {
            if bit(self.gyro_read, i) {
                *o = Some(RawGyro(*w).to_radps());
            }
        }
        out
    }
}

/// The models' outputs of one step (phase 2).
struct Models {
    r_teme_km: Option<Vec3>,
    sun: Option<Sun>,
    illumination: Option<Illumination>,
    b_teme_nt: Option<Vec3>,
}

impl<'c, const N: usize, const F: usize> AcsLoop<'c, N, F> {
    /// A loop in `Detumble` for the given configuration and orbit (an [`Sgp4`], or `None`: a
    /// loop without an element set, as after a corrupt one at start-up, still detumbles and
    /// keeps the Sun on its panel, the laws that need no reference, with [`Faults::orbit`] set
    /// each step until [`Self::set_orbit`] gives it one).
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    pub fn new(config: &'c AcsConfig<N>, orbit: impl Into<Option<Sgp4>>) -> Result<Self, AcsError> {
        let finite = config.filter.is_valid()
            && config.detumble_enter_radps.is_finite()
            && config.detumble_exit_radps.is_finite()
            && config.wheel_limit_nms.is_finite()
            && config.dumping_gain_per_s.is_finite()
            && config.slew_pause_s.is_finite()
            && config.control_period_s > 0.0
            && config.control_period_s.is_finite()
            && config.slew_pause_s >= 0.0;
        if !finite
            || config.detumble_exit_radps >= config.detumble_enter_radps
            || N > 32
            || coefficient_count(config.igrf_degree.get()) > F
        {
            return Err(AcsError::InvalidConfig);
        }
        let failed = config
            .tiles
            .iter()
            .enumerate()
            .filter(|(_, t)| !t.is_working())
            .fold(0u32, |m, (i, _)| {
                m | 1u32.checked_shl(i as u32).unwrap_or(0)
            });
        Ok(Self {
            config,
            failed,
            orbit: orbit.into(),
            mode: ModeState::Detumble,
            bdot: BdotState::default(),
            invalid_steps: 0,
            bus_answered: true,
            last_time: None,
            estimate: None,
            wheel_h: [0.0; N],
            failures: [0; N],
            health: ActuatorHealth::new(),
            wheel_allocator: None,
            coil_allocator: None,
            mag_solver: None,
            gyro_solver: None,
            stuck: StuckGyros::new(),
            field: PhantomData,
        })
    }

    /// Replaces the element set the loop propagates (an uplink: check the words with
    /// [`Sgp4::from_words`] first, so that a refused set leaves the one in use); the rest of the
    /// state is kept.
    pub fn set_orbit(&mut self, orbit: Sgp4) {
        self.orbit = Some(orbit);
    }

    /// The current mode.
    pub fn mode(&self) -> Mode {
        self.mode.mode()
    }

    /// The configured tiles (their run-time state: [`AcsLoop::tile_state`]).
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
        self.failed & 1u32.checked_shl(tile as u32).unwrap_or(0) == 0
    }

    /// True if tile `tile` carries a wheel, is in service, and its wheel is in the allocation
    /// ([`crate::attitude_node::health`]).
    fn has_working_wheel(&self, tile: usize, t: &Tile) -> bool {
        t.equipment.reaction_wheel && self.is_working(tile) && self.health.wheel_in(tile)
    }

    /// The wheels' and coils' health ([`crate::attitude_node::health`]).
    pub fn health(&self) -> &ActuatorHealth<N> {
        &self.health
    }

    /// Fails coil `coil` and takes it out of its allocation (`failed`), or returns it to
    /// service; false (nothing changed) if there is no such coil.
    pub fn set_coil_failed(&mut self, coil: usize, failed: bool) -> bool {
        self.health
            .set_coil_failed(coil, failed, self.config.coils.len())
    }

    /// Marks a tile failed (ground command or fault detection); its devices are no longer used
    /// and its wheel is stopped at the next step.
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    pub fn mark_failed(&mut self, tile: usize) {
        if self.config.tiles.len() > tile {
            self.failed |= 1u32.checked_shl(tile as u32).unwrap_or(0);
        }
    }

    /// Returns a tile to service (ground command, e.g. after a power cycle of a tile marked
    /// failed): its devices are used again from the next step, its bus-failure count restarts,
    /// and the cached allocators and least-squares operators are rebuilt for the new set.
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    pub fn restore(&mut self, tile: usize) {
        self.health.restore_wheel(tile);
        self.failed &= !1u32.checked_shl(tile as u32).unwrap_or(0);
        if let Some(count) = self.failures.get_mut(tile) {
            *count = 0;
        }
    }

    /// Accepts a ground command. A slew is planned from the last determined attitude
    /// (`attitude`, reference → body), so it needs one.
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    pub fn command(
        &mut self,
        command: Command,
        attitude: Option<&Quaternion>,
        now: Epoch<Utc>,
    ) -> Result<(), AcsError> {
        match command {
            Command::SunSafe => self.transition(Event::SunSafe),
            Command::Track { target } => self.transition(Event::Track(target)),
            Command::Slew { target, within_s } => {
                let attitude = attitude.ok_or(AcsError::CannotSlew)?;
                self.start_slew(attitude, &target, within_s, now)?;
            }
        }
        // a command starts the count of steps without attitude afresh (a fall-back left it at
        // INVALID_STEPS_TO_SAFE: a `TRACK` would have gone straight back to `SunSafe`)
        self.invalid_steps = 0;
        Ok(())
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

    /// The thesis's plan from `attitude` to `target` within `within_s` as a reference
    /// trajectory ([`SlewTrajectory`]), started `now` (the mode left as it was if the planner
    /// refuses; out of line: the planner's temporaries stay off the step's stack).
    #[inline(never)]
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    fn start_slew(
        &mut self,
        attitude: &Quaternion,
        target: &Dcm,
        within_s: f32,
        now: Epoch<Utc>,
    ) -> Result<(), AcsError> {
        let trajectory = self
            .config
            .slew_trajectory(&attitude.to_dcm(), target, within_s)?;
        let slew = SlewProgress {
            trajectory,
            started: now,
            follower: SlewFollower::new(self.wheels_body()),
        };
        self.transition(Event::Slew(&slew, target.to_quaternion()));
        Ok(())
    }

    /// Total commanded wheel momentum in body axes, kg·m²/s.
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    fn wheels_body(&self) -> Vec3 {
        self.config
            .tiles
            .iter()
            .zip(self.wheel_h.iter())
            .enumerate()
            .filter(|(i, (t, _))| self.has_working_wheel(*i, t))
            .fold(Vec3::zeros(), |acc, (_, (t, h))| acc + t.normal_body() * *h)
    }

    /// Puts every actuator in the safe state: coils off, wheels hold their momentum.
    pub fn safe<B: TileBus>(&mut self, bus: &mut B) -> Faults {
        self.coils_off(bus, false)
    }

    /// Switches the coils off; with `check`, each coil is first checked from its read-back
    /// ([`ActuatorHealth::coils_off`]).
    fn coils_off<B: TileBus>(&mut self, bus: &mut B, check: bool) -> Faults {
        self.health.coils_off(self.config.coils.len(), bus, check)
    }

    /// Step phase 3: reads every working tile (see the module docs), counting read failures. A
    /// tile is marked failed at [`FAILURES_TO_MARK_FAILED`] failures in a row only if some
    /// device answered in the previous step: when none does, the bus is failing, not the tiles
    /// (a bus-wide burst once took every tile out of service for good), and a sole tile left in
    /// service with sensors is never marked.
    #[inline(never)]
    fn read_tiles<B: TileBus>(&mut self, bus: &mut B, faults: &mut Faults) -> Readings<N> {
        let mut r = Readings {
            sun: [[0; 2]; N],
            mag: [[0; 2]; N],
            gyro: [0; N],
            sun_seen: 0,
            mag_read: 0,
            gyro_read: 0,
        };
        let config = self.config;
        // a device answered this step
        let mut any_read = false;
        for (i, (tile, (sun, (mag, gyro)))) in config
            .tiles
            .iter()
            .zip(
                r.sun
                    .iter_mut()
                    .zip(r.mag.iter_mut().zip(r.gyro.iter_mut())),
            )
            .enumerate()
        {
            if !self.is_working(i) {
                continue;
            }
            let here = 1u32.checked_shl(i as u32).unwrap_or(0);
            let mut failed = false;
            // a word pinned at either end of the i16 range is no reading (a saturated device
            // or a stuck line: no physical Sun angle, field or rate reaches it): a failed read
            if tile.equipment.sun_sensor {
                match bus.read_sun(i) {
                    Ok(Some([a, b])) if !pinned(a) && !pinned(b) => {
                        *sun = [a, b];
                        r.sun_seen |= here;
                        any_read = true;
                    }
                    Ok(None) => any_read = true,
                    _ => failed = true,
                }
            }
            if tile.equipment.magnetometer {
                match bus.read_magnetometer(i) {
                    Ok([x, y]) if !pinned(x) && !pinned(y) => {
                        *mag = [x, y];
                        r.mag_read |= here;
                        any_read = true;
                    }
                    _ => failed = true,
                }
            }
            if tile.equipment.gyro {
                match bus.read_gyro(i) {
                    Ok(w) if !pinned(w) => {
                        *gyro = w;
                        r.gyro_read |= here;
                        any_read = true;
                    }
                    _ => failed = true,
                }
            }
            if tile.equipment.reaction_wheel && self.health.wheel_in(i) {
                let commanded = self.wheel_h.get(i).copied().unwrap_or(0.0);
                let read = bus.read_wheel_momentum(i);
                let limit = config.wheel_limit_nms;
                if self.health.check_wheel(i, read, commanded, limit, faults)
                    && has_twin(&config.tiles, i, |j, t| self.has_working_wheel(j, t))
                {
                    self.health.take_wheel_out(i);
                }
            }
            if let Some(count) = self.failures.get_mut(i) {
                if failed {
                    faults.device_read = true;
                    *count = count.saturating_add(1);
                    if *count >= FAILURES_TO_MARK_FAILED && self.bus_answered {
                        // out of service from this step on: its readings of this step too
                        self.failed |= here;
                        r.sun_seen &= !here;
                        r.mag_read &= !here;
                        r.gyro_read &= !here;
                    }
                } else {
                    *count = 0;
                }
            }
        }
        self.bus_answered = any_read;
        r
    }

    /// One control step at UTC epoch `now`, `dt_s` seconds after the previous one.
    pub fn step<B: TileBus>(&mut self, bus: &mut B, now: Epoch<Utc>, dt_s: f32) -> StepReport {
        let mut report = StepReport::empty(self.mode());
        self.step_into(bus, now, dt_s, &mut report);
        report
    }

    /// [`AcsLoop::step`] writing its report into `report` (every field is set): on the MSP430 a
    /// report returned by value is built, then copied (118 B more stack under the step).
    ///
    /// The phases are separate functions kept out of line, so that their temporaries do not
    /// share one stack frame (on the MSP430 the step's peak stack is the deepest phase, not the
    /// sum of them).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub fn step_into<B: TileBus>(
        &mut self,
        bus: &mut B,
        now: Epoch<Utc>,
        dt_s: f32,
        report: &mut StepReport,
    ) {
        let mut faults = self.coils_off(bus, true);
        // The models first: the tiles are read after them, so the readings live only under
        // the determination (and the magnetometers see the coils' field decay meanwhile).
        let models = self.models(&now, &mut faults);
        // The determination writes its results straight into the report.
        report.reset(self.mode());
        report.sun_fraction = models.illumination.map(|i| i.fraction);
        let dt = self.sense(bus, &models, &now, dt_s, &mut faults, report);
        self.change_mode(report);
        let (dipole, h_target) = self.laws(report, dt, &now, &mut faults);
        let (dipole, h_wheels) = self.actuate(bus, report, dipole, h_target, &mut faults);
        report.mode = self.mode();
        report.dipole_body_am2 = dipole;
        report.h_wheels_body = h_wheels;
        report.faults = faults;
    }

    /// Step phases 3 and 4: reads the tiles and determines from their readings (which live in
    /// this frame only); returns the seconds since the previous step.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn sense<B: TileBus>(
        &mut self,
        bus: &mut B,
        models: &Models,
        now: &Epoch<Utc>,
        dt_s: f32,
        faults: &mut Faults,
        report: &mut StepReport,
    ) -> f32 {
        let readings = self.read_tiles(bus, faults);
        self.determine(&readings, models, now, dt_s, faults, report)
    }

    /// Step phase 2: orbit, Sun, eclipse and field models at `now`.
    #[inline(never)]
    fn models(&self, now: &Epoch<Utc>, faults: &mut Faults) -> Models {
        let orbit = self
            .orbit
            .as_ref()
            .and_then(|o| o.propagate(now.span_since(&o.epoch())).ok());
        faults.orbit = orbit.is_none();
        let sun = schlyter::sun(now).ok();
        let gmst = now.to_ut1(None).ok().map(|ut1| gmst_rad(&ut1));
        let illumination = match (&orbit, &sun) {
            (Some(o), Some(s)) => cylindrical_illumination(&o.r_teme_km, &s.direction).ok(),
            _ => None,
        };
        // the field model fails on its own (a date outside its tables) or at the point
        let field = self.field_teme(now, orbit.as_ref().map(|o| &o.r_teme_km), gmst, faults);
        let field_model_failed = matches!(
            field,
            Err(IgrfError::DateOutOfRange { .. }
                | IgrfError::DegreeAboveModel { .. }
                | IgrfError::CapacityTooSmall { .. })
        );
        faults.model = sun.is_none() || field_model_failed || gmst.is_none();
        let b_teme_nt = field.ok().flatten();
        Models {
            r_teme_km: orbit.as_ref().map(|o| o.r_teme_km),
            sun,
            illumination,
            b_teme_nt,
        }
    }

    /// Step phase 4: body field, rate and Sun direction from the tiles, attitude by TRIAD,
    /// filtered.
    #[inline(never)]
    fn determine(
        &mut self,
        readings: &Readings<N>,
        models: &Models,
        now: &Epoch<Utc>,
        dt_s: f32,
        faults: &mut Faults,
        report: &mut StepReport,
    ) -> f32 {
        let mut b_body_nt = self.field_body(readings);
        if let (Some(b), Some(m)) = (&b_body_nt, &models.b_teme_nt) {
            if !magnitude_agrees(b, m) {
                b_body_nt = None;
            }
        }
        let omega = self.rate_body(readings);
        faults.field = b_body_nt.is_none();
        faults.rate = omega.is_none();
        let in_umbra = models
            .illumination
            .is_some_and(|i| i.shadow == Shadow::Umbra);
        let sun_body = if in_umbra {
            None
        } else {
            self.sun_body(readings)
        };
        // the Sun as the sensors see it, with the albedo
        let fraction = models.illumination.map_or(1.0, |i| i.fraction);
        // the albedo the lit sensors see at the last attitude (the reference node's, from the
        // STATUS of the step before: [`crate::reference_node`])
        let albedo_teme = match (&models.r_teme_km, &models.sun, &self.estimate) {
            (Some(r), Some(s), Some(e)) => albedo::seen_by_lit_sensors(
                self.config.tiles.as_slice(),
                r,
                &s.direction,
                &e.attitude,
                self.config.filter.sun_sensor_cos_half_fov,
            ),
            _ => None,
        };
        let albedo = self.estimate.as_ref().map_or(0.0, |e| e.albedo);
        let sun_ref = models
            .sun
            .as_ref()
            .map(|s| mekf::sun_reference(&s.direction, fraction, albedo_teme.as_ref(), albedo));
        let elapsed = self.last_time.map(|t| now.seconds_since_f32(&t));
        self.last_time = Some(*now);
        // A step is one control period: a gap of any other size or sign (a clock correction, a
        // reset) must not be integrated into the wheels (a +60 s correction once kicked a
        // tracking satellite to 1.8 °/s). It restarts the filter and the B-dot derivative,
        // reported, and the laws integrate one nominal period.
        let period = self.config.control_period_s;
        let dt = match elapsed {
            None => dt_s,
            Some(e) if e > 0.0 && period + period >= e => e,
            Some(_) => {
                faults.clock = true;
                self.estimate = None;
                self.bdot.reset();
                period
            }
        };
        let sun = match (sun_body, sun_ref) {
            (Some(body), Some((reference_teme, d_reference_d_albedo))) => Some(SunObservation {
                body,
                reference_teme,
                d_reference_d_albedo,
                variance_rad2: self.sun_variance(readings, &body),
            }),
            _ => None,
        };
        let inputs = StepInputs {
            omega_body_radps: omega,
            sun,
            field: b_body_nt.zip(models.b_teme_nt),
            mag_tiles: self.mag_solver.as_ref().map_or(0, |s| s.tiles()),
            gyro_tiles: self.gyro_solver.as_ref().map_or(0, |s| s.tiles()),
            dt_s: dt,
        };
        // the gyros' own rate: a law's command must not depend on the filter's state (a REF
        // lost changes the estimate, not the commands of a mode without attitude); the bias
        // left in the rate (≤ 1e-4 rad/s) moves the tracking law's equilibrium by ζ·b/ω_n ≈
        // 0.01°; about a gyro held as stuck, the filter's bias is the rate
        // ([`crate::attitude_node::stuck`])
        report.omega_body_radps = omega;
        let (outcome, held) = self.stuck.filter_step(
            self.config.tiles.as_slice(),
            (&readings.gyro, readings.gyro_read),
            &self.config.filter,
            &mut self.estimate,
            &inputs,
            &mut report.omega_body_radps,
        );
        faults.device_read |= held;
        let estimate = self.estimate.as_ref();
        let attitude = estimate.map(|e| e.attitude);
        faults.attitude = attitude.is_none();
        report.b_body_nt = b_body_nt;
        report.attitude_sigma_rad = estimate.map(|e| e.attitude_sigma_rad());
        report.refused_measurements = outcome.refused;
        report.sun_body = sun_body;
        report.measured_attitude = attitude.filter(|_| outcome.started);
        report.attitude = attitude;
        dt
    }

    /// The body field from the magnetometers (least squares, cached operator), nT. Out of line,
    /// as [`Self::rate_body`] and [`Self::sun_body`]: each converts its readings in its own frame.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn field_body(&mut self, readings: &Readings<N>) -> Option<Vec3> {
        let tiles = self.config.tiles.as_slice();
        let mag = readings.mag_nt();
        let mag = mag.get(..tiles.len())?;
        magnetic_field_body_cached(&mut self.mag_solver, tiles, mag).ok()
    }

    /// The body rate from the gyros (least squares, cached operator), rad/s.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn rate_body(&mut self, readings: &Readings<N>) -> Option<Vec3> {
        let tiles = self.config.tiles.as_slice();
        let gyro = readings.gyro_radps();
        let gyro = gyro.get(..tiles.len())?;
        angular_rate_body_cached(&mut self.gyro_solver, tiles, gyro).ok()
    }

    /// The Sun direction in body axes from the lit tiles' sensors (unit).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn sun_body(&self, readings: &Readings<N>) -> Option<Vec3> {
        let tiles = self.config.tiles.as_slice();
        let sun = readings.sun_rad();
        sun_direction_body(tiles, sun.get(..tiles.len())?).ok()
    }

    /// The Sun observation's variance per axis, rad², from the lit sensors' incidence
    /// ([`crate::determination::mekf::sun_variance_rad2`]).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn sun_variance(&self, readings: &Readings<N>, sun_body: &Vec3) -> f32 {
        let tiles = self.config.tiles.as_slice();
        let sun = readings.sun_rad();
        let (sum, n) = incidence_inv_cos2(tiles, sun.get(..tiles.len()).unwrap_or(&[]), sun_body);
        mekf::sun_variance_rad2(&self.config.filter, sum, n)
    }

    /// Step phase 5a: the events of the rate and of the validity of the attitude.
    fn change_mode(&mut self, det: &StepReport) {
        let rate = det.omega_body_radps.map(|w| crate::linalg::norm(&w));
        if let Some(r) = rate {
            if r > self.config.detumble_enter_radps {
                self.transition(Event::RateAbove);
            } else if self.config.detumble_exit_radps > r {
                self.transition(Event::RateBelow);
            }
        }
        if matches!(self.mode(), Mode::Slew | Mode::Tracking) {
            if det.attitude.is_some() {
                self.invalid_steps = 0;
            } else if !in_umbra(det) {
                self.invalid_steps = self.invalid_steps.saturating_add(1);
                if self.invalid_steps >= INVALID_STEPS_TO_SAFE {
                    self.transition(Event::AttitudeLost);
                }
            }
        }
    }

    /// Step phase 5b: the mode's law. Returns the coil dipole (body, A·m²) and the wheel
    /// momentum to hold (body, kg·m²/s; `None`: hold the momentum in force). A law that
    /// refuses its input sets `faults.law` and commands nothing (coils off, wheels held).
    #[inline(never)]
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    fn laws(
        &mut self,
        det: &StepReport,
        dt: f32,
        now: &Epoch<Utc>,
        faults: &mut Faults,
    ) -> (Vec3, Option<Vec3>) {
        // by reference: on the MSP430 each copy of an option is a `memcpy` call
        let (omega, b_body_nt) = (det.omega_body_radps.as_ref(), det.b_body_nt.as_ref());
        let mut dipole = Vec3::zeros();
        let mut torque: Option<Vec3> = None;
        let mut h_target: Option<Vec3> = None;
        match &self.mode {
            ModeState::Detumble => {
                dipole = match (omega, b_body_nt) {
                    (Some(w), Some(b)) => {
                        // the derivative form must not difference against a sample taken
                        // before a gyro outage: forget it while the gyro form runs
                        self.bdot.reset();
                        reported(bdot_from_rates(&self.config.bdot, w, b).ok(), faults)
                    }
                    // `Ok(None)`: the first sample of the derivative form, nothing to command
                    (None, Some(b)) => match self.bdot.update(&self.config.bdot, b, dt) {
                        Ok(m) => m.unwrap_or_else(Vec3::zeros),
                        Err(_) => reported(None, faults),
                    },
                    _ => Vec3::zeros(),
                };
            }
            ModeState::SunSafe => {
                if let Some(w) = omega {
                    torque = sun_safe_torque(
                        &self.config.sun_safe,
                        det.sun_body.as_ref(),
                        &self.config.sun_axis_body,
                        w,
                    )
                    .ok();
                    faults.law |= torque.is_none();
                }
            }
            ModeState::Slew { .. } | ModeState::Tracking { .. } => {}
        }
        // a slew: its reference followed in closed loop, the feedback's torque integrated into
        // the wheels beside the feed-forward (without an attitude the feed-forward alone); its
        // trajectory done: track its target
        let period = self.config.control_period_s;
        let reference = match &mut self.mode {
            ModeState::Slew { progress, .. } => Some(
                progress
                    .trajectory
                    .at(now.seconds_since_f32(&progress.started), period),
            ),
            _ => None,
        };
        match reference {
            Some(Some(reference)) => {
                let h_w = self.wheels_body();
                let config = self.config;
                if let ModeState::Slew { progress, .. } = &mut self.mode {
                    h_target = config.follow_slew(
                        &mut progress.follower,
                        Some(&reference),
                        det,
                        &h_w,
                        dt,
                        faults,
                    );
                }
            }
            Some(None) => self.transition(Event::SlewDone),
            None => {}
        }
        // the wheels' momentum in force, summed once for the tracking law and the integration
        let mut h_now: Option<Vec3> = None;
        if let ModeState::Tracking { target } = &self.mode {
            // no attitude in the umbra (the filter starts with the Sun): damp the rate, wait
            if let (None, Some(w), true) = (det.attitude.as_ref(), omega, in_umbra(det)) {
                torque =
                    sun_safe_torque(&self.config.sun_safe, None, &self.config.sun_axis_body, w)
                        .ok();
                faults.law |= torque.is_none();
            }
            if let (Some(q), Some(w)) = (det.attitude.as_ref(), omega) {
                let h_w = self.wheels_body();
                h_now = Some(h_w);
                torque = tracking_torque(
                    &self.config.tracking,
                    &self.config.axes.inertia_body,
                    q,
                    w,
                    target,
                    &Vec3::zeros(),
                    &h_w,
                )
                .ok();
                faults.law |= torque.is_none();
            }
        }
        // wheels: a torque law integrates into momentum (ḣ = −τ); a slew sets momentum
        if let Some(tau) = torque {
            if self.have_wheels() {
                // no more than the wheels deliver: a momentum they cannot follow is never
                // commanded (the laws integrate the commanded momentum: the read-back only
                // checks the wheels, `attitude_node::health`). The coils' per-axis scaling keeping
                // the direction; it refuses a limit that is not positive and finite: none
                let tau = crate::control::magnetorquer::saturate_dipole(
                    &tau,
                    &self.config.wheel_torque_nm,
                )
                .map_or(tau, |(t, _)| t);
                let h_w = h_now.unwrap_or_else(|| self.wheels_body());
                h_target = Some(crate::linalg::sub_scaled(&h_w, &tau, dt));
            } else if let Some(b) = b_body_nt {
                dipole = reported(dipole_for_torque(&tau, b).ok(), faults);
            }
        }
        (dipole, h_target)
    }

    /// Step phase 5c: wheel momentum (the target, or the momentum in force re-sent: it stops
    /// failed tiles' wheels), momentum dumping through the coils outside detumble, coil dipole.
    /// Returns the dipole commanded and the wheels' total momentum now commanded (body).
    #[inline(never)]
    fn actuate<B: TileBus>(
        &mut self,
        bus: &mut B,
        det: &StepReport,
        dipole: Vec3,
        h_target: Option<Vec3>,
        faults: &mut Faults,
    ) -> (Vec3, Vec3) {
        let h = h_target.unwrap_or_else(|| self.wheels_body());
        faults.saturated |= self.command_wheels(bus, &h, faults);
        // a failed actuator is reported every step until the ground restores it
        faults.actuator |= self.health.any_failed();
        // what the wheels now hold: dumped through the coils and reported
        let h_wheels = self.wheels_body();
        let mut dipole = dipole;
        if !matches!(self.mode, ModeState::Detumble)
            && self.config.dumping_gain_per_s > 0.0
            && self.have_wheels()
        {
            if let Some(b) = det.b_body_nt {
                let dump = dumping_dipole(
                    &h_wheels,
                    &Vec3::zeros(),
                    self.config.dumping_gain_per_s,
                    &b,
                )
                .ok();
                dipole += reported(dump, faults);
            }
        }
        (self.command_coils(bus, &dipole, faults), h_wheels)
    }

    /// True if any tile has a working wheel.
    fn have_wheels(&self) -> bool {
        self.config
            .tiles
            .iter()
            .enumerate()
            .any(|(i, t)| self.has_working_wheel(i, t))
    }

    /// The field in TEME at `r_teme_km` (`None` without a position or GMST) from the
    /// coefficients of the on-board model at `now`, built on this function's stack (out of
    /// line: the `4·F` bytes exist only while the field is evaluated).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    fn field_teme(
        &self,
        now: &Epoch<Utc>,
        r_teme_km: Option<&Vec3>,
        gmst: Option<f32>,
        faults: &mut Faults,
    ) -> Result<Option<Vec3>, IgrfError> {
        let mut slot: Option<Igrf<F>> = None;
        let field = Igrf::emplace_epoch(
            &mut slot,
            self.config.igrf_model.model(),
            now,
            self.config.igrf_degree,
        )?;
        faults.extrapolated = field.is_extrapolated();
        match (r_teme_km, gmst) {
            (Some(r), Some(g)) => field.teme(r, g).map(Some),
            _ => Ok(None),
        }
    }

    /// Allocates a total body momentum to the wheels (the wheels hold `h`, the body the
    /// opposite) and commands them, each wheel limited on its own. Returns true if one was
    /// limited. A limit that is not positive commands nothing (reported in `faults.law`).
    fn command_wheels<B: TileBus>(&mut self, bus: &mut B, h: &Vec3, faults: &mut Faults) -> bool {
        // allocated without a limit, then each wheel limited on its own: a wheel at its limit
        // stays there and the others keep the momentum they were asked to hold (scaling the
        // whole allocation would take momentum from wheels the law never asked to change)
        let limit = self.config.wheel_limit_nms;
        if !(limit > 0.0) {
            // no wheel can hold anything: none is commanded (they hold), reported
            faults.law = true;
            return false;
        }
        let mut wheels = [Wheel {
            axis_body: Vec3::z(),
            limit: 1.0,
            working: false,
        }; N];
        for (i, (w, t)) in wheels.iter_mut().zip(self.config.tiles.iter()).enumerate() {
            *w = Wheel {
                axis_body: t.normal_body(),
                limit: f32::MAX,
                working: self.has_working_wheel(i, t),
            };
        }
        // the allocator gives the wheels −W⁺L: ask for the body momentum −h so they hold +h;
        // with no working wheel every wheel is commanded to stop; on any other refusal (a NaN
        // target...) no wheel is commanded: they hold the momentum in force, reported
        let alloc = match cached_allocation(&mut self.wheel_allocator, &wheels, &(-h)) {
            Ok(a) => Some(a),
            Err(WheelError::NoWorkingWheel) => None,
            Err(_) => {
                faults.law = true;
                return false;
            }
        };
        let mut saturated = false;
        for (i, (cmd, (tile, wheel))) in self
            .wheel_h
            .iter_mut()
            .zip(self.config.tiles.iter().zip(wheels.iter()))
            .enumerate()
        {
            if !tile.equipment.reaction_wheel {
                continue;
            }
            let value = match &alloc {
                Some(a) if wheel.working => {
                    let h = a.wheel.get(i).copied().unwrap_or(0.0);
                    if crate::fmath::abs(h) > limit {
                        saturated = true;
                        libm::copysignf(limit, h)
                    } else {
                        h
                    }
                }
                _ => 0.0,
            };
            *cmd = value;
            let accepted = bus.set_wheel_momentum(i, value).is_ok();
            self.health.wheel_commanded(i, accepted);
            faults.actuator |= !accepted;
        }
        saturated
    }

    /// Allocates a body dipole to the coils (least squares over their axes, saturated keeping
    /// direction) and commands them; returns the dipole commanded.
    fn command_coils<B: TileBus>(&mut self, bus: &mut B, m: &Vec3, faults: &mut Faults) -> Vec3 {
        let mut coils = [Wheel {
            axis_body: Vec3::z(),
            limit: 1.0,
            working: false,
        }; MAX_COILS];
        for (i, (c, cfg)) in coils.iter_mut().zip(self.config.coils.iter()).enumerate() {
            *c = Wheel {
                working: cfg.working && self.health.coil_in(i),
                ..*cfg
            };
        }
        let alloc = match cached_allocation(&mut self.coil_allocator, &coils, &(-m)) {
            Ok(a) => a,
            Err(e) => {
                // the coils stay off (`safe`); a refused dipole is reported
                faults.law |= !matches!(e, WheelError::NoWorkingWheel);
                return Vec3::zeros();
            }
        };
        faults.saturated |= !(alloc.scale >= 1.0);
        let mut produced = Vec3::zeros();
        for (i, (value, coil)) in alloc.wheel.iter().zip(coils.iter()).enumerate() {
            if coil.working {
                let accepted = bus.set_dipole(i, *value).is_ok();
                self.health.coil_commanded(i, *value, accepted);
                faults.actuator |= !accepted;
                produced += coil.axis_body * *value;
            }
        }
        produced
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every (mode, event) pair through `next_mode` against the table of the module docs; the
    /// scripted-bus walk of every transition through the public API is `tests/modes.rs`.
    #[test]
    fn next_mode_table() {
        let q = |x: f32| Quaternion {
            q0: 1.0,
            q1: x,
            q2: 0.0,
            q3: 0.0,
        };
        let config = &crate::flight::CONFIG;
        let angles = crate::control::slew::AxisAngles {
            phi_a: 0.1,
            theta_b: 0.0,
            psi_c: 0.0,
        };
        let p = plan(&config.axes, &angles, &config.slew_limits, 100.0).unwrap();
        let torque = config.wheel_torque_nm;
        let progress = SlewProgress {
            trajectory: SlewTrajectory::new(&p, &config.axes, &torque, 1.0, 5.0).unwrap(),
            started: Epoch::<Utc>::from_parts(0, 0, 0).unwrap(),
            follower: SlewFollower::new(Vec3::zeros()),
        };
        let detumble = ModeState::Detumble;
        let sun_safe = ModeState::SunSafe;
        let slew = ModeState::Slew {
            progress,
            target: q(0.1),
        };
        let tracking = ModeState::Tracking { target: q(0.2) };
        let new_slew = ModeState::Slew {
            progress,
            target: q(0.3),
        };
        let events = [
            Event::RateAbove,
            Event::RateBelow,
            Event::AttitudeLost,
            Event::SlewDone,
            Event::SunSafe,
            Event::Track(q(0.4)),
            Event::Slew(&progress, q(0.3)),
        ];
        let track_new = ModeState::Tracking { target: q(0.4) };
        // rows: the state before; the state after each event, in `events`' order
        #[rustfmt::skip]
        let table = [
            (detumble, [detumble, sun_safe, detumble, detumble, sun_safe, track_new, new_slew]),
            (sun_safe, [detumble, sun_safe, sun_safe, sun_safe, sun_safe, track_new, new_slew]),
            (slew, [detumble, slew, sun_safe, ModeState::Tracking { target: q(0.1) }, sun_safe, track_new, new_slew]),
            (tracking, [detumble, tracking, sun_safe, tracking, sun_safe, track_new, new_slew]),
        ];
        for (before, afters) in table.iter() {
            for (event, after) in events.iter().zip(afters.iter()) {
                let mut state = *before;
                next_mode(&mut state, *event);
                assert_eq!(state, *after, "{before:?} + {event:?}");
            }
        }
    }

    /// Issue 19 item 5, wheel saturation: a momentum one wheel cannot hold is limited on that
    /// wheel alone, and the wheels the request did not change keep their momentum (before, the
    /// whole allocation was scaled down, so they gave theirs up to the body).
    #[test]
    fn saturation_limits_the_wheel_not_the_store() {
        use crate::hal::ErrorKind;
        struct Wheels([Option<f32>; 6]);
        impl TileBus for Wheels {
            fn read_sun(&mut self, _: usize) -> Result<Option<[i16; 2]>, ErrorKind> {
                Err(ErrorKind::Other)
            }
            fn read_magnetometer(&mut self, _: usize) -> Result<[i16; 2], ErrorKind> {
                Err(ErrorKind::Other)
            }
            fn read_gyro(&mut self, _: usize) -> Result<i16, ErrorKind> {
                Err(ErrorKind::Other)
            }
            fn set_wheel_momentum(&mut self, tile: usize, h_nms: f32) -> Result<(), ErrorKind> {
                let slot = self.0.get_mut(tile).ok_or(ErrorKind::Other)?;
                *slot = Some(h_nms);
                Ok(())
            }
            fn set_dipole(&mut self, _: usize, _: f32) -> Result<(), ErrorKind> {
                Ok(())
            }
            fn delay_us(&mut self, _: u32) {}
        }
        let config = &crate::flight::CONFIG;
        let limit = config.wheel_limit_nms;
        let mut acs = crate::flight::OneImageLoop::new(config, None).unwrap();
        let mut bus = Wheels([None; 6]);
        let mut faults = Faults::default();
        // the two z wheels hold 0.8 of their limit each
        let h0 = Vec3::new(0.0, 0.0, 1.6 * limit);
        assert!(!acs.command_wheels(&mut bus, &h0, &mut faults));
        let before = bus.0;
        // three limits more about x, which has one wheel
        let h1 = h0 + Vec3::new(3.0 * limit, 0.0, 0.0);
        assert!(acs.command_wheels(&mut bus, &h1, &mut faults));
        assert!(!faults.law);
        for (i, tile) in config.tiles.iter().enumerate() {
            let n = tile.normal_body();
            if !tile.equipment.reaction_wheel {
                assert_eq!(bus.0[i], None);
            } else if n.z.abs() > 0.99 {
                assert_eq!(bus.0[i], before[i], "tile {i}: z wheel changed");
                assert!(bus.0[i].is_some_and(|h| (h.abs() - 0.8 * limit).abs() < 1e-9));
            } else if n.x.abs() > 0.99 {
                assert_eq!(bus.0[i].map(f32::abs), Some(limit), "tile {i}: x wheel");
            }
        }
        assert_eq!(acs.wheels_body().z, h0.z);
        // a negative limit (a NaN one is refused by `AcsLoop::new`): nothing commanded, reported
        let bad = AcsConfig {
            wheel_limit_nms: -1.0,
            ..config.clone()
        };
        let mut acs =
            AcsLoop::<{ crate::flight::TILES }, { crate::flight::FIELD_COEFFS }>::new(&bad, None)
                .unwrap();
        let mut bus = Wheels([None; 6]);
        let mut faults = Faults::default();
        assert!(!acs.command_wheels(&mut bus, &h0, &mut faults));
        assert!(faults.law);
        assert_eq!(bus.0, [None; 6]);
    }
}
