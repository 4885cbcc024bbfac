//! The realistic truth (issue #18): a field that is not the flight model, the spacecraft's own
//! fields at the magnetometers, Earth albedo, and sensors and actuators as real hardware
//! behaves. `acs sim SCENARIO --truth realistic` (the default) flies it; `--truth ideal` flies
//! the simulator as it was before (the scenario's [`super::SensorNoise`], actuators that do what
//! they are told, the truth field IGRF itself).
//!
//! Every effect is a parameter of one table per device type below ([`Realism`]); a parameter set
//! to zero (or the switch to `false`) removes the effect, which is how the closed-loop tests
//! measure each effect's share of a figure. `docs/simulator.md` lists every effect with its
//! value and source. What the parameters do is in [`field`] (the truth field, the spacecraft's
//! fields, albedo) and [`devices`] (the per-device draws and the read and actuator models).
//!
//! # Sources
//! No datasheet is vendored in the repository: where a value is a named part's, the part is the
//! *class* the tile's device belongs to, with the figure its datasheet prints on its front page
//! (ADXRS453: ±300 °/s, 16 °/h bias stability, 16-bit word; HMC1001/1002: ±2 G range,
//! 27 µG resolution, set/reset; NewSpace NCSS-SA05: pinhole over a PSD, 114° field of view);
//! the seeds give the coil (seed 002 §6.4), the residual dipole and the solar-maximum drag
//! density (seed 004 §2.1), the pinhole sensor's random error (seed 004 §2.7) and the
//! magnetometer's ground-calibration spread (seed 002 §7.5). The rest are stated assumptions
//! (calibration residuals, mounting tolerances, friction, stray rotor fields): each says so.
//!
//! # Randomness
//! Every random quantity is a pure function of the scenario's seed, the device and the control
//! step ([`devices::gauss`]: a counter-based generator), never of the order or number of reads:
//! the processor-in-the-loop run, which reads through a recorder, and a loop that reads a tile
//! twice or skips a failed one see the same truth.

pub mod devices;
pub mod field;

/// Which truth the simulator flies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum TruthLevel {
    /// The simulator before issue #18: truth field = IGRF-14 degree 13, the scenario's Gaussian
    /// sensor noise and constant biases, wheels that slew to their command at the torque limit,
    /// coils that take their command at once. For the thesis scenarios, the thesis's own noise
    /// model (ideal sensors, or about 1 % noise).
    Ideal,
    /// [`Realism`]: the default of every scenario.
    #[default]
    Realistic,
}

impl TruthLevel {
    /// `ideal` or `realistic`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Ideal => "ideal",
            Self::Realistic => "realistic",
        }
    }
}

/// The solar activity the drag density is taken at (exponential atmosphere, 60 km scale
/// height, density at 500 km below).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SolarActivity {
    /// 4.38e-12 kg/m³ at 500 km: the maximum seed 004 §2.1 budgets for (the figure implied by
    /// its 1.18e-6 N·m, eq. 2.11). The ideal truth's density, and the realistic default.
    Maximum,
    /// 1.39e-12 kg/m³: the geometric mean of the maximum and the minimum.
    Moderate,
    /// 4.38e-13 kg/m³: one tenth of the maximum (seed 002 §3.3: "at solar minimum the
    /// disturbance is about 10× smaller").
    Minimum,
}

impl SolarActivity {
    /// Density at 500 km, kg/m³.
    pub fn density_500km(self) -> f64 {
        match self {
            Self::Maximum => 4.38e-12,
            Self::Moderate => 4.38e-12 / 10f64.sqrt(),
            Self::Minimum => 4.38e-13,
        }
    }
}

/// The truth field: IGRF-14 at degree 13 plus an unmodelled part ([`field::UnmodelledField`]).
///
/// | parameter | value | source |
/// |---|---|---|
/// | unmodelled field RMS over the orbit's sphere | 100 nT (vector magnitude) | issue #18: the typical IGRF residual in LEO (external and crustal fields, secular-variation forecast error) |
/// | model | potential field of 48 random Earth-fixed dipoles at 0.6 R_E from the centre | a curl- and divergence-free field, smooth along the orbit: its autocorrelation falls to one half in 280 s, RMS 104 nT along a day of the `tracking` orbit (`tests/truth.rs`) |
#[derive(Clone, Debug, PartialEq)]
pub struct FieldTruth {
    /// RMS of the unmodelled field's magnitude over the sphere of the orbit's initial radius, nT.
    pub unmodelled_rms_nt: f64,
    /// Number of random dipole sources.
    pub sources: usize,
    /// Radius of the sources' sphere, in Earth radii.
    pub source_radius_re: f64,
}

impl FieldTruth {
    /// The default (table above).
    pub const DEFAULT: Self = Self {
        unmodelled_rms_nt: 100.0,
        sources: 48,
        source_radius_re: 0.6,
    };
}

/// The spacecraft's own fields at each magnetometer ([`field::Magnetics`]). Positions follow
/// the tile geometry: a tile's centre is its outward normal times the half side; a device's
/// place on its tile is given in the tile frame (z outward, so negative z is inside).
///
/// | parameter | value | source |
/// |---|---|---|
/// | half side of the cube | 67 mm | a uniform cube of the flight inertia and seed 004's 4 kg (scenarios' module docs) |
/// | magnetometer on its tile | (30, 20, −5) mm from the tile centre | assumption: off the centre, on the inner face of the tile |
/// | residual dipole left after the ground calibration | 1σ 1e-3 A·m² per body axis, at the body centre | assumption: 25 % of seed 004's 4e-3 A·m² (§2.1); the tiles' magnetometers are calibrated in the integrated satellite, which removes the static field of the dipole measured then, not its change in flight |
/// | coil | square, 85 mm side, 34 turns, centred in its tile's plane | seed 002 §6.4 (AtmoCube's final coil); the coil along a body axis sits in the power tile whose normal is that axis |
/// | wheel rotor's stray field | 2e-4 A·m² transverse dipole turning with the rotor, 20 mm inside the tile centre | assumption: leakage of a small BLDC's rotor magnet (no seed gives one); its static part is calibrated with the rest |
#[derive(Clone, Debug, PartialEq)]
pub struct SpacecraftMagnetics {
    /// Half side of the cube (tile centre to body centre), m.
    pub half_side_m: f64,
    /// Magnetometer position on its tile, tile frame, m.
    pub magnetometer_on_tile_m: [f64; 3],
    /// 1σ per body axis of the residual dipole not removed by the ground calibration, A·m².
    pub residual_dipole_error_am2: f64,
    /// Coil side, m.
    pub coil_side_m: f64,
    /// Coil turns.
    pub coil_turns: f64,
    /// Wheel rotor's transverse stray dipole, A·m².
    pub rotor_dipole_am2: f64,
    /// Wheel rotor position on its tile, tile frame, m.
    pub rotor_on_tile_m: [f64; 3],
}

impl SpacecraftMagnetics {
    /// The default (table above).
    pub const DEFAULT: Self = Self {
        half_side_m: 0.067,
        magnetometer_on_tile_m: [0.030, 0.020, -0.005],
        residual_dipole_error_am2: 1e-3,
        coil_side_m: 0.085,
        coil_turns: 34.0,
        rotor_dipole_am2: 2e-4,
        rotor_on_tile_m: [0.0, 0.0, -0.020],
    };
}

/// Sun sensor: a pinhole over a position-sensitive detector (the AraMiS tile's sensor, note 000
/// §1.2), class of the NewSpace pinhole sensors (NCSS-SA05: PSD, 114° field of view; NFSS-411:
/// 140°, < 0.1° RMS). The detector reports the irradiance-weighted centroid of everything that
/// comes through the pinhole: the Sun's spot and the Earth's albedo ([`devices`]).
///
/// The field of view is the wider of the class (140°): with the PSD's 114° the `tracking`
/// attitude puts the Sun in the cone about the telecom tile (+U, no sensor) that no sensor sees
/// (57° from the four neighbours' normals leaves a 33° cone; 70° leaves 20°), and the loop never
/// measures its attitude there (measured: it falls back to sun-safe after 340 s).
///
/// | effect | value | source |
/// |---|---|---|
/// | field of view | 70° half angle | NFSS-411 (140°); NCSS-SA05 (PSD) 114° |
/// | FOV edge | the spot (0.5° angular radius) is clipped by the detector's edge: dimmer, centroid pulled inward | geometry; spot radius assumed (pinhole ⌀ / height) |
/// | detection threshold | 0.35 × the normal-incidence solar signal | assumption: above the largest albedo signal of a 0.30 Earth at 500 km (0.257 on a nadir-facing sensor under a zenith Sun), so albedo alone is never taken for the Sun |
/// | noise | 1σ 0.02° per angle at normal incidence, × (normal-incidence signal / signal): 1/cos θ | seed 004 §2.7 (pinhole, ±0.026° at 3σ on a CMOS) rounded up for a PSD's analogue chain; the signal falls as cos θ |
/// | calibration residual | 0.1° RMS per angle, a smooth function of the angles drawn per sensor | NFSS-411 (< 0.1° RMS over the field of view); NCSS-SA05 quotes < 0.5° RMS |
/// | misalignment | 1σ 0.1° about each tile axis | assumption: tile on structure and sensor on tile |
/// | Earth albedo | uniform Lambertian Earth, albedo 0.30, 72-point quadrature of the visible cap | Earth's mean Bond albedo; model in [`field::albedo_cap`] |
/// | quantisation | 1e-4 rad | the HAL word (note 000 §1.3) |
#[derive(Clone, Debug, PartialEq)]
pub struct SunSensorModel {
    /// Half angle of the field of view, rad.
    pub fov_rad: f64,
    /// Angular radius of the Sun's spot, rad.
    pub spot_radius_rad: f64,
    /// Detection threshold, fraction of the normal-incidence solar signal.
    pub threshold: f64,
    /// 1σ noise per angle at normal incidence, rad.
    pub noise_rad: f64,
    /// RMS of the calibration residual per angle, rad.
    pub calibration_rad: f64,
    /// 1σ misalignment about each axis, rad.
    pub misalignment_rad: f64,
    /// Earth's albedo (0: no albedo).
    pub albedo: f64,
}

impl SunSensorModel {
    /// The class (table above).
    pub const CLASS: Self = Self {
        fov_rad: 70.0 * std::f64::consts::PI / 180.0,
        spot_radius_rad: 0.5 * std::f64::consts::PI / 180.0,
        threshold: 0.35,
        noise_rad: 0.02 * std::f64::consts::PI / 180.0,
        calibration_rad: 0.1 * std::f64::consts::PI / 180.0,
        misalignment_rad: 0.1 * std::f64::consts::PI / 180.0,
        albedo: 0.30,
    };
}

/// Magnetometer: a two-axis anisotropic-magnetoresistive bridge with set/reset, class Honeywell
/// HMC1001/1002 (±2 G, 27 µG resolution), read by the tile in 10 nT words. The field it sees is
/// the truth field plus the spacecraft's own ([`SpacecraftMagnetics`]).
///
/// | effect | value | source |
/// |---|---|---|
/// | scale factor | 1σ 1 % per axis | assumption: ground-calibrated sensitivity, its temperature coefficient (HMC100x: −0.06 %/°C at constant bridge current) over the tile's swing |
/// | non-orthogonality | 1σ 0.2° between the two bridges | assumption (both bridges on one die) |
/// | misalignment | 1σ 0.3° about each tile axis | assumption: part on tile, tile on structure |
/// | offset | 1σ 50 nT per axis | assumption: bridge offset left by set/reset and the calibration; seed 002 §7.5 measured 150–500 nT on a lab rig with 100 nT resolution (an upper bound) |
/// | noise | 1σ 3 nT | HMC1001/1002 resolution 27 µG |
/// | quantisation | 10 nT | the HAL word |
/// | range | ±200 000 nT (±2 G): beyond it the read fails (saturated) | HMC1001/1002 field range |
#[derive(Clone, Debug, PartialEq)]
pub struct MagnetometerModel {
    /// 1σ scale-factor error per axis (fraction).
    pub scale_factor: f64,
    /// 1σ non-orthogonality, rad.
    pub non_orthogonality_rad: f64,
    /// 1σ misalignment about each axis, rad.
    pub misalignment_rad: f64,
    /// 1σ offset per axis, nT.
    pub offset_nt: f64,
    /// 1σ noise per axis, nT.
    pub noise_nt: f64,
    /// Range, nT.
    pub range_nt: f64,
    /// The spacecraft's own fields at the magnetometer (residual dipole, coils, wheel rotors).
    pub contamination: bool,
}

impl MagnetometerModel {
    /// The class (table above).
    pub const CLASS: Self = Self {
        scale_factor: 0.01,
        non_orthogonality_rad: 0.2 * std::f64::consts::PI / 180.0,
        misalignment_rad: 0.3 * std::f64::consts::PI / 180.0,
        offset_nt: 50.0,
        noise_nt: 3.0,
        range_nt: 200_000.0,
        contamination: true,
    };
}

/// Gyro: a single-axis MEMS vibrating gyro, class Analog Devices ADXRS453 (±300 °/s, 16 °/h
/// bias stability, 16-bit word). The tile averages its samples over the control period: the
/// reading is the mean rate of the period before the read (half a period of latency).
///
/// | effect | value | source |
/// |---|---|---|
/// | angle random walk | 0.015 °/√s: 1σ 0.015 °/s on a 1 s mean | ADXRS453 class (0.015 °/s/√Hz rate noise density) |
/// | bias instability | 16 °/h, first-order Gauss–Markov, correlation time 1 000 s | ADXRS453 (16 °/h null bias stability) |
/// | turn-on bias | 1σ 0.005 °/s | assumption: residual of a ground calibration at temperature |
/// | scale factor | 1σ 0.5 % | assumption: ground-calibrated |
/// | misalignment | 1σ 0.3° tilt of the sensitive axis about each tile axis | assumption: part on tile, tile on structure |
/// | quantisation | 1e-4 rad/s | the HAL word |
/// | range | ±300 °/s (beyond the HAL word's ±3.28 rad/s the read fails) | ADXRS453 |
#[derive(Clone, Debug, PartialEq)]
pub struct GyroModel {
    /// Angle random walk, rad/√s.
    pub arw_rad_per_sqrt_s: f64,
    /// Bias instability (Gauss–Markov 1σ), rad/s.
    pub bias_instability_radps: f64,
    /// Gauss–Markov correlation time, s.
    pub bias_correlation_s: f64,
    /// 1σ turn-on bias, rad/s.
    pub turn_on_bias_radps: f64,
    /// 1σ scale-factor error (fraction).
    pub scale_factor: f64,
    /// 1σ misalignment about each axis, rad.
    pub misalignment_rad: f64,
    /// Range, rad/s.
    pub range_radps: f64,
}

impl GyroModel {
    /// The class (table above).
    pub const CLASS: Self = Self {
        arw_rad_per_sqrt_s: 0.015 * std::f64::consts::PI / 180.0,
        bias_instability_radps: 16.0 / 3600.0 * std::f64::consts::PI / 180.0,
        bias_correlation_s: 1000.0,
        turn_on_bias_radps: 0.005 * std::f64::consts::PI / 180.0,
        scale_factor: 0.005,
        misalignment_rad: 0.3 * std::f64::consts::PI / 180.0,
        range_radps: 300.0 * std::f64::consts::PI / 180.0,
    };
}

/// Reaction wheel: a brushless micro wheel with its own speed loop, class of the 1–2 mN·m·s
/// CubeSat wheels (e.g. CubeSpace CubeWheel Small: about 0.23 mN·m, 6 000 rpm; class figures,
/// not a vendored datasheet). The wheel's momentum at full speed is the flight configuration's
/// limit.
///
/// | effect | value | source |
/// |---|---|---|
/// | speed loop | first order (proportional), time constant 0.2 s (0.8 Hz) | assumption: class |
/// | torque limit | 2.3e-4 N·m | class (CubeWheel Small) |
/// | speed limit | 6 000 rpm = the flight momentum limit (rotor inertia = limit / 628 rad/s) | class |
/// | Coulomb friction | 5e-6 N·m | assumption: 2 % of the torque limit (bearings) |
/// | viscous friction | 1e-9 N·m per rad/s (6e-7 N·m at full speed) | assumption |
/// | set-point quantisation | 1 rpm | class interface (whole rpm) |
/// | momentum read-back | the tachometer's speed in whole rpm, at the read instant | class interface; [`super::Simulator::wheel_momentum_nms`] |
///
/// With a proportional loop the friction leaves a steady speed error (friction × time
/// constant, 1e-6 kg·m²/s) that only the read-back shows.
#[derive(Clone, Debug, PartialEq)]
pub struct WheelModel {
    /// Speed-loop time constant, s (0: the ideal wheel's slew at the torque limit).
    pub time_constant_s: f64,
    /// Motor torque limit, N·m.
    pub torque_limit_nm: f64,
    /// Speed limit, rad/s.
    pub speed_limit_radps: f64,
    /// Coulomb friction, N·m.
    pub coulomb_nm: f64,
    /// Viscous friction, N·m per rad/s.
    pub viscous_nm_per_radps: f64,
    /// Set-point quantum, rad/s.
    pub setpoint_lsb_radps: f64,
    /// Read-back quantum, rad/s.
    pub readback_lsb_radps: f64,
}

impl WheelModel {
    /// The class (table above).
    pub const CLASS: Self = Self {
        time_constant_s: 0.2,
        torque_limit_nm: 2.3e-4,
        speed_limit_radps: 6000.0 * 2.0 * std::f64::consts::PI / 60.0,
        coulomb_nm: 5e-6,
        viscous_nm_per_radps: 1e-9,
        setpoint_lsb_radps: 2.0 * std::f64::consts::PI / 60.0,
        readback_lsb_radps: 2.0 * std::f64::consts::PI / 60.0,
    };
}

/// Magnetorquer coil: seed 002 §6.4's air coil (85 mm square, 34 turns of 0.63 mm copper,
/// 0.593 Ω) driven by PWM from the tile.
///
/// | effect | value | source |
/// |---|---|---|
/// | rise and decay | first order, τ = L/R = 0.39 ms (L ≈ 0.23 mH: square loop of N turns, 2μ₀N²a/π·(ln(a/r_w) − 0.774), bundle radius 2.1 mm) | seed 002 §6.4 geometry (R = 0.593 Ω) |
/// | current limit | 0.85 A (0.209 A·m²) | assumption: the driver's limiter, above the flight's 0.2 A·m² (0.81 A) |
/// | quantisation | 8-bit PWM: 0.2 A·m² / 255 | assumption: an MSP430 Timer_A PWM |
/// | scale factor | 1σ 3 % | copper's +0.39 %/°C under a voltage-driven PWM over the tile's ±8 °C |
#[derive(Clone, Debug, PartialEq)]
pub struct CoilModel {
    /// Electrical time constant L/R, s (0: instantaneous).
    pub time_constant_s: f64,
    /// Current limit, A.
    pub current_limit_a: f64,
    /// Dipole per ampere, A·m²/A (turns × area).
    pub am2_per_a: f64,
    /// Dipole quantum, A·m² (0: none).
    pub lsb_am2: f64,
    /// 1σ scale-factor error (fraction).
    pub scale_factor: f64,
}

impl CoilModel {
    /// The coil of seed 002 §6.4 (table above).
    pub const CLASS: Self = Self {
        time_constant_s: 3.9e-4,
        current_limit_a: 0.85,
        am2_per_a: 34.0 * 0.085 * 0.085,
        lsb_am2: 0.2 / 255.0,
        scale_factor: 0.03,
    };
}

/// When, within a control step, the tiles are read and the actuators commanded, measured from
/// the step's start: the attitude node's (issue #29), which switches the coils off first, waits
/// [`crate::attitude_node::COIL_DECAY_US`] for their field to decay, reads the tiles, then
/// determines, runs its law and commands the actuators ([`crate::attitude_node`]); the models
/// ran on the reference node before the step (its REF arrived in the previous period).
///
/// | instant | value | source |
/// |---|---|---|
/// | tiles read | 5 ms | the node's wait (40 000 cycles of `acs_firmware::CycleDelay` at 8 MHz), which the coils-off commands before it and the REF's acceptance after it lengthen by a few hundred cycles: the earliest, so the coils' field is at its largest |
/// | actuators commanded | 106 ms | the attitude node's worst period in the two-node PIL, 848 335 cycles with the multiplier at 7 995 392 Hz (`firmware/pil`, `target/msp430/pil.json`; mspdebug counts the wait as 60 002 cycles, the part 40 000); 43 ms before the attitude filter of issue #30 |
///
/// The one-image loop flew 55 ms and 83 ms until issue #29 (its models before the reads, its
/// whole step). The I²C time of the reads and commands (about 10 ms and 4 ms at 100 kHz,
/// `firmware/src/periph.rs`) is not in either figure, as it was not before.
///
/// Before the commands the coils are off and the wheels hold the previous set-points. A
/// scenario whose period is shorter than these is refused by the simulator.
#[derive(Clone, Debug, PartialEq)]
pub struct StepTiming {
    /// Tiles read, s after the step's start.
    pub read_s: f64,
    /// Actuators commanded, s after the step's start.
    pub actuate_s: f64,
    /// The gyros give the body's mean rate over the control period (the tile averages its
    /// samples, [`GyroModel`]); false: the rate at the read, as the ideal truth's.
    pub gyro_period_mean: bool,
}

impl StepTiming {
    /// The flight attitude node's (table above).
    pub const FLIGHT: Self = Self {
        read_s: 0.005,
        actuate_s: 0.106,
        gyro_period_mean: true,
    };
}

/// Everything the realistic truth adds to the simulator (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct Realism {
    /// The truth field.
    pub field: FieldTruth,
    /// The spacecraft's own fields.
    pub magnetics: SpacecraftMagnetics,
    /// Sun sensors.
    pub sun_sensor: SunSensorModel,
    /// Magnetometers.
    pub magnetometer: MagnetometerModel,
    /// Gyros.
    pub gyro: GyroModel,
    /// Reaction wheels.
    pub wheel: WheelModel,
    /// Coils.
    pub coil: CoilModel,
    /// Read and command instants within a step.
    pub timing: StepTiming,
    /// Drag density.
    pub solar_activity: SolarActivity,
}

impl Realism {
    /// Every table's default: what `--truth realistic` flies.
    pub const DEFAULT: Self = Self {
        field: FieldTruth::DEFAULT,
        magnetics: SpacecraftMagnetics::DEFAULT,
        sun_sensor: SunSensorModel::CLASS,
        magnetometer: MagnetometerModel::CLASS,
        gyro: GyroModel::CLASS,
        wheel: WheelModel::CLASS,
        coil: CoilModel::CLASS,
        timing: StepTiming::FLIGHT,
        solar_activity: SolarActivity::Maximum,
    };
}

impl Default for Realism {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// One group of effects of the realistic truth, to measure its share of a closed-loop figure
/// ([`Realism::without`], [`Realism::only`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Effect {
    /// The unmodelled part of the field.
    UnmodelledField,
    /// The spacecraft's own fields at the magnetometers.
    SpacecraftField,
    /// Earth albedo on the Sun sensors.
    Albedo,
    /// The Sun sensors' noise, calibration residual and misalignment (not their field of view,
    /// spot and threshold).
    SunSensorErrors,
    /// The magnetometers' scale factor, non-orthogonality, misalignment, offset and noise.
    MagnetometerErrors,
    /// The gyros' noise, biases, scale factor and misalignment.
    GyroErrors,
    /// The wheels' speed loop, torque limit, friction and quanta (without it the wheel is the
    /// ideal truth's: it slews at the simulator's `wheel_max_torque_nm`).
    Wheel,
    /// The coils' time constant, quantum, scale factor and current limit.
    Coil,
    /// The read latency, the actuation instant and the gyros' averaging over the period
    /// (without it the gyros read the rate at the step's start, as the ideal truth's).
    Timing,
}

impl Effect {
    /// Every group.
    pub const ALL: [Self; 9] = [
        Self::UnmodelledField,
        Self::SpacecraftField,
        Self::Albedo,
        Self::SunSensorErrors,
        Self::MagnetometerErrors,
        Self::GyroErrors,
        Self::Wheel,
        Self::Coil,
        Self::Timing,
    ];

    /// A short name.
    pub fn name(self) -> &'static str {
        match self {
            Self::UnmodelledField => "unmodelled field",
            Self::SpacecraftField => "spacecraft field",
            Self::Albedo => "albedo",
            Self::SunSensorErrors => "Sun sensor errors",
            Self::MagnetometerErrors => "magnetometer errors",
            Self::GyroErrors => "gyro errors",
            Self::Wheel => "wheel dynamics",
            Self::Coil => "coil dynamics",
            Self::Timing => "step timing",
        }
    }
}

impl Realism {
    /// These tables with `effect` removed (its parameters zero; the wheels without limits and
    /// with an instantaneous speed loop; the coils instantaneous and unlimited).
    pub fn without(&self, effect: Effect) -> Self {
        let mut r = self.clone();
        match effect {
            Effect::UnmodelledField => r.field.unmodelled_rms_nt = 0.0,
            Effect::SpacecraftField => r.magnetometer.contamination = false,
            Effect::Albedo => r.sun_sensor.albedo = 0.0,
            Effect::SunSensorErrors => {
                r.sun_sensor.noise_rad = 0.0;
                r.sun_sensor.calibration_rad = 0.0;
                r.sun_sensor.misalignment_rad = 0.0;
            }
            Effect::MagnetometerErrors => {
                let m = &mut r.magnetometer;
                m.scale_factor = 0.0;
                m.non_orthogonality_rad = 0.0;
                m.misalignment_rad = 0.0;
                m.offset_nt = 0.0;
                m.noise_nt = 0.0;
            }
            Effect::GyroErrors => {
                let g = &mut r.gyro;
                g.arw_rad_per_sqrt_s = 0.0;
                g.bias_instability_radps = 0.0;
                g.turn_on_bias_radps = 0.0;
                g.scale_factor = 0.0;
                g.misalignment_rad = 0.0;
            }
            Effect::Wheel => {
                let w = &mut r.wheel;
                w.time_constant_s = 0.0;
                w.torque_limit_nm = f64::INFINITY;
                w.coulomb_nm = 0.0;
                w.viscous_nm_per_radps = 0.0;
                w.setpoint_lsb_radps = 0.0;
                w.readback_lsb_radps = 0.0;
            }
            Effect::Coil => {
                let c = &mut r.coil;
                c.time_constant_s = 0.0;
                c.lsb_am2 = 0.0;
                c.scale_factor = 0.0;
                c.current_limit_a = f64::INFINITY;
            }
            Effect::Timing => {
                r.timing.read_s = 0.0;
                r.timing.actuate_s = 0.0;
                r.timing.gyro_period_mean = false;
            }
        }
        r
    }

    /// These tables with every effect but `effect` removed.
    pub fn only(&self, effect: Effect) -> Self {
        Effect::ALL
            .iter()
            .filter(|e| **e != effect)
            .fold(self.clone(), |r, e| r.without(*e))
    }
}
