//! The benchmark cases, shared by the MSP430 benchmark firmware (`src/bin/bench.rs`) and the host
//! program that computes the expected results (`bench-host/`, same file by `#[path]`).
//!
//! Each case runs between [`Sink::begin`] and [`Sink::end`] (the simulator's break points),
//! reading its inputs through [`Sink::input`] and pinning its results with [`Sink::keep`] (both
//! opaque to the optimiser on the target, so no work moves out of the measured section), and
//! hands every result to [`Sink::out`]; the driver compares the target's results with the host's, bit for bit,
//! so a broken helper or kernel cannot be silently measured.
//!
//! Case `overhead` is the empty measurement (same input/output pattern as a 2-in/1-out case); the
//! driver subtracts its cycles and instructions from every other case.

use acs::fmath;

/// Where a case's inputs come from and its results go.
pub trait Sink {
    /// An input value, opaque to the optimiser (so it cannot be computed before [`Sink::begin`]).
    fn input(&mut self, x: f32) -> f32;
    /// A result, forced to exist here (so it cannot be computed after [`Sink::end`]).
    fn keep(&mut self, x: f32) -> f32;
    /// Starts the measured section of case `name`.
    fn begin(&mut self, name: &'static str);
    /// Ends the measured section.
    fn end(&mut self);
    /// A result, compared with the host's.
    fn out(&mut self, x: f32);
}

macro_rules! case1 {
    ($s:ident, $name:literal, $x:expr, $f:expr) => {{
        $s.begin($name);
        let x = $s.input($x);
        let r = $s.keep($f(x));
        $s.end();
        $s.out(r);
    }};
}

macro_rules! case2 {
    ($s:ident, $name:literal, $x:expr, $y:expr, $f:expr) => {{
        $s.begin($name);
        let x = $s.input($x);
        let y = $s.input($y);
        let r = $s.keep($f(x, y));
        $s.end();
        $s.out(r);
    }};
}

/// Runs every case in order.
#[inline(always)]
pub fn run<S: Sink>(s: &mut S) {
    case2!(s, "overhead", 1.25, -0.75, |x: f32, _y: f32| x);
    if cfg!(feature = "group-core") {
        run_core(s);
    }
    run_flight(s);
    #[cfg(feature = "group-step")]
    run_step(s);
    if cfg!(feature = "group-parts") {
        run_step_parts(s);
    }
}

/// The parts of one ACS step that no other group measures, each called as
/// `acs::acs_loop::AcsLoop::step` calls it, in the steady state (operators cached): a profile of
/// the step, which group `step` measures as one call.
#[inline(always)]
fn run_step_parts<S: Sink>(s: &mut S) {
    use acs::control::wheels::{Allocator, Wheel};
    use acs::determination::sun_sensor::sun_direction_body;
    use acs::env::eclipse::conical;
    use acs::linalg::Vec3;
    use acs::tiles::{SunAngles, CUBE_THESIS};
    use acs::time::{Epoch, Utc};

    let out3 = |s: &mut S, v: &Vec3| {
        s.out(v.x);
        s.out(v.y);
        s.out(v.z);
    };
    let tiles = &CUBE_THESIS;
    step_least_squares(s);

    let angles = |s: &mut S, a: f32, b: f32| {
        Some(SunAngles {
            a_rad: s.input(a),
            b_rad: s.input(b),
        })
    };
    let suns: [Option<SunAngles>; 6] = [
        None,
        angles(s, 0.12, -0.08),
        angles(s, -0.05, 0.25),
        angles(s, 0.3, 0.01),
        None,
        None,
    ];
    s.begin("step: Sun direction (3 lit tiles)");
    let d = sun_direction_body(tiles, &suns);
    let d = core::hint::black_box(d).unwrap_or_default();
    s.end();
    out3(s, &d);

    let utc: Option<Epoch<Utc>> = Epoch::from_parts(9_300, 43_210, 0).ok();
    let sun = utc.and_then(|t| acs::env::sun::precise::sun(&t).ok());
    let r = Vec3::new(s.input(-4_100.0), s.input(1_200.0), s.input(-5_600.0));
    s.begin("step: conical eclipse");
    let ill = sun.as_ref().and_then(|sun| conical(&r, sun).ok());
    let ill = core::hint::black_box(ill);
    s.end();
    s.out(ill.map_or(f32::NAN, |i| i.fraction));

    let mut wheels = [Wheel {
        axis_body: Vec3::z(),
        limit: 1.0e-3,
        working: false,
    }; 6];
    for (w, t) in wheels.iter_mut().zip(tiles.iter()) {
        *w = Wheel {
            axis_body: t.normal_body(),
            limit: 1.0e-3,
            working: t.has_working_wheel(),
        };
    }
    let h = Vec3::new(s.input(2.0e-4), s.input(-1.5e-4), s.input(3.0e-4));
    step_allocator_built(s, &wheels, &h);
    let alloc = Allocator::new(&wheels).ok();
    s.begin("step: wheel allocation (cached, 5 wheels)");
    let a = alloc.as_ref().and_then(|a| a.allocate(&wheels, &h).ok());
    let a = core::hint::black_box(a);
    s.end();
    for x in a.map_or([f32::NAN; 6], |a| a.wheel) {
        s.out(x);
    }

    run_step_laws(s);
}

/// The tile least squares of a step, the operator built (first step, or a change of the set of
/// tiles) and cached (own frame: its locals do not stay on the stack under the later cases).
#[inline(never)]
fn step_least_squares<S: Sink>(s: &mut S) {
    use acs::determination::least_squares::{angular_rate_body_cached, magnetic_field_body_cached};
    use acs::linalg::{Vec2, Vec3};
    use acs::tiles::CUBE_THESIS;

    let out3 = |s: &mut S, v: &Vec3| {
        s.out(v.x);
        s.out(v.y);
        s.out(v.z);
    };
    let tiles = &CUBE_THESIS;
    let mags: [Option<Vec2>; 6] = [
        None,
        Some(Vec2::new(s.input(21_000.0), s.input(-18_000.0))),
        Some(Vec2::new(s.input(-9_000.0), s.input(32_000.0))),
        Some(Vec2::new(s.input(15_000.0), s.input(24_000.0))),
        Some(Vec2::new(s.input(-26_000.0), s.input(7_000.0))),
        Some(Vec2::new(s.input(3_000.0), s.input(-31_000.0))),
    ];
    let mut cache = None;
    s.begin("step: magnetometer least squares (operator built, 5 tiles)");
    let b = magnetic_field_body_cached(&mut cache, tiles, &mags);
    let b = core::hint::black_box(b).unwrap_or_default();
    s.end();
    out3(s, &b);
    s.begin("step: magnetometer least squares (cached, 5 tiles)");
    let b = magnetic_field_body_cached(&mut cache, tiles, &mags);
    let b = core::hint::black_box(b).unwrap_or_default();
    s.end();
    out3(s, &b);

    let rates: [Option<f32>; 6] = [
        None,
        Some(s.input(0.002_5)),
        Some(s.input(-0.001_8)),
        Some(s.input(0.003_1)),
        Some(s.input(-0.001_2)),
        Some(s.input(0.000_9)),
    ];
    let mut cache = None;
    s.begin("step: gyro least squares (operator built, 5 tiles)");
    let w = angular_rate_body_cached(&mut cache, tiles, &rates);
    let w = core::hint::black_box(w).unwrap_or_default();
    s.end();
    out3(s, &w);
    s.begin("step: gyro least squares (cached, 5 tiles)");
    let w = angular_rate_body_cached(&mut cache, tiles, &rates);
    let w = core::hint::black_box(w).unwrap_or_default();
    s.end();
    out3(s, &w);
}

/// The allocator of `wheels` built from opaque axes (constant ones could be folded into the
/// closed-form pseudoinverse), then applied to `h` (own frame, as [`step_least_squares`]).
#[inline(never)]
fn step_allocator_built<S: Sink>(
    s: &mut S,
    wheels: &[acs::control::wheels::Wheel; 6],
    h: &acs::linalg::Vec3,
) {
    use acs::control::wheels::Allocator;
    use acs::linalg::Vec3;

    let mut opaque = *wheels;
    for w in opaque.iter_mut() {
        let a = w.axis_body;
        w.axis_body = Vec3::new(s.input(a.x), s.input(a.y), s.input(a.z));
    }
    s.begin("step: wheel allocator built (5 wheels)");
    let built = Allocator::new(&opaque).ok();
    let built = core::hint::black_box(built);
    s.end();
    let a = built.as_ref().and_then(|a| a.allocate(&opaque, h).ok());
    for x in a.map_or([f32::NAN; 6], |a| a.wheel) {
        s.out(x);
    }
}

/// The rest of a step's parts (the laws, the filter, the coils), as `AcsLoop::step` calls them
/// with the flight configuration's values (`crate::flight`-like gains, three 0.2 A·m² coils).
#[inline(never)]
fn run_step_laws<S: Sink>(s: &mut S) {
    use acs::attitude::Quaternion;
    use acs::control::magnetorquer::dumping_dipole;
    use acs::control::sun_safe::{sun_safe_torque, SunSafeGains};
    use acs::control::tracking::{tracking_torque, TrackingGains};
    use acs::control::wheels::{Allocator, Wheel};
    use acs::determination::mekf::{step, StepInputs, SunObservation};
    use acs::env::albedo::{irradiance, FieldOfView};
    use acs::flight::FILTER;
    use acs::linalg::{Mat3, Vec3};

    let out3 = |s: &mut S, v: &Vec3| {
        s.out(v.x);
        s.out(v.y);
        s.out(v.z);
    };
    let w = Vec3::new(s.input(0.002_5), s.input(-0.001_8), s.input(0.003_1));
    let b = Vec3::new(s.input(21_000.0), s.input(-18_000.0), s.input(9_000.0));

    let q = Quaternion {
        q0: s.input(0.8),
        q1: s.input(0.2),
        q2: s.input(-0.4),
        q3: s.input(0.4),
    };
    let m = Quaternion {
        q0: s.input(0.79),
        q1: s.input(0.21),
        q2: s.input(-0.41),
        q3: s.input(0.4),
    };
    // the flight filter one step: propagated, then the Sun (with the albedo's partials) and the
    // field
    let sun_body = Vec3::new(s.input(0.3), s.input(-0.5), s.input(0.81));
    let observation = SunObservation {
        body: sun_body,
        reference_teme: Vec3::new(s.input(0.31), s.input(-0.49), s.input(0.815)),
        d_reference_d_albedo: Vec3::new(s.input(0.02), s.input(0.01), s.input(-0.005)),
        variance_rad2: s.input(6.4e-6),
    };
    let b_teme = Vec3::new(s.input(20_800.0), s.input(-18_300.0), s.input(9_200.0));
    let inputs = StepInputs {
        omega_body_radps: Some(w),
        sun: Some(observation),
        field: Some((b, b_teme)),
        mag_tiles: 0b11_1110,
        gyro_tiles: 0b11_1110,
        dt_s: 1.0,
    };
    // started from the step's Sun and field (TRIAD, with its sensor sets), one step on
    let mut e = None;
    step(&FILTER, &mut e, &inputs);
    s.begin("step: attitude filter (propagate + Sun + field)");
    let outcome = step(&FILTER, &mut e, &inputs);
    core::hint::black_box((&e, outcome));
    s.end();
    let nan = Quaternion {
        q0: f32::NAN,
        q1: f32::NAN,
        q2: f32::NAN,
        q3: f32::NAN,
    };
    let qe = e.map_or(nan, |e| e.attitude);
    for x in [qe.q0, qe.q1, qe.q2, qe.q3] {
        s.out(x);
    }
    for x in e.map_or([f32::NAN; 10], |e| e.variances()) {
        s.out(x);
    }
    // its parts, one step on from there
    if let Some(f) = e.as_mut() {
        s.begin("step: attitude filter, propagation");
        let usable = f.propagate(&FILTER, &w, 1.0);
        core::hint::black_box((&*f, usable));
        s.end();
        s.begin("step: attitude filter, Sun update (2 scalars)");
        let sun = f.update_sun(&FILTER, &observation);
        core::hint::black_box((&*f, sun));
        s.end();
        s.begin("step: attitude filter, field update (3 scalars)");
        let field = f.update_field(&FILTER, &b, &b_teme);
        core::hint::black_box((&*f, field));
        s.end();
        s.out(f32::from(usable));
        s.out(f32::from(sun.accepted + field.accepted));
    }
    let qe = e.map_or(nan, |e| e.attitude);
    for x in [qe.q0, qe.q1, qe.q2, qe.q3] {
        s.out(x);
    }

    let r_teme = Vec3::new(s.input(-2_100.0), s.input(4_900.0), s.input(4_200.0));
    let sun_teme = Vec3::new(s.input(0.92), s.input(0.3), s.input(0.25));
    let fov = FieldOfView {
        boresight: Vec3::new(s.input(-0.3), s.input(0.6), s.input(0.74)),
        cos_half_angle: 0.342,
    };
    s.begin("step: albedo seen by one Sun sensor (32 points)");
    let d = irradiance(&r_teme, &sun_teme, 1.0, Some(&fov));
    let d = core::hint::black_box(d).unwrap_or(Vec3::new(f32::NAN, f32::NAN, f32::NAN));
    s.end();
    out3(s, &d);

    let gains = SunSafeGains {
        kp_nm: 2.0 * 0.05 * 0.05 * 0.014,
        kd_nms: 2.0 * 0.05 * 0.014,
    };
    let sun = Vec3::new(s.input(0.3), s.input(-0.5), s.input(0.81));
    s.begin("step: sun-safe law");
    let t = sun_safe_torque(&gains, Some(&sun), &Vec3::z(), &w);
    let t = core::hint::black_box(t).unwrap_or_default();
    s.end();
    out3(s, &t);

    let inertia = Mat3::from_diagonal(&Vec3::new(0.010, 0.012, 0.014));
    let tracking = TrackingGains::from_bandwidth(&inertia, 0.25, 0.9);
    let h_w = Vec3::new(s.input(2.0e-4), s.input(-1.5e-4), s.input(3.0e-4));
    s.begin("step: tracking law");
    let t = tracking_torque(&tracking, &inertia, &q, &w, &m, &Vec3::zeros(), &h_w);
    let t = core::hint::black_box(t).unwrap_or_default();
    s.end();
    out3(s, &t);

    // the loop allocates over `MAX_COILS` = 6 slots, three of them configured
    let mut coils = [Wheel {
        axis_body: Vec3::z(),
        limit: 1.0,
        working: false,
    }; 6];
    for (c, axis) in coils.iter_mut().zip([Vec3::x(), Vec3::y(), Vec3::z()]) {
        *c = Wheel {
            axis_body: axis,
            limit: 0.2,
            working: true,
        };
    }
    let alloc = Allocator::new(&coils).ok();
    s.begin("step: dumping + coil allocation (cached, 3 coils)");
    let dump = dumping_dipole(&h_w, &Vec3::zeros(), 1e-3, &b).unwrap_or_default();
    let a = alloc
        .as_ref()
        .and_then(|a| a.allocate(&coils, &(-dump)).ok());
    let a = core::hint::black_box(a);
    s.end();
    for x in a.map_or([f32::NAN; 6], |a| a.wheel) {
        s.out(x);
    }
}

/// The magnetometer words of the ACS step's cases and of the flight image's run in
/// `firmware/msp430-bench` (raw, one pair per tile; tile 0 has none): the body field
/// (1, −2, 0.5)/|·| with the magnitude of the on-board model on the flight element set at the
/// reset epoch (the loop refuses a field more than `FIELD_MAGNITUDE_TOLERANCE` from it), on each
/// tile's axes. `firmware/bench-host` computes them and checks these at every benchmark run.
pub const STEP_MAG: [[i16; 2]; 6] = [
    [0, 0],
    [-716, -1432],
    [1432, -2863],
    [-716, 2863],
    [-716, 1432],
    [-1432, -2863],
];

/// The ACS step as one call (`crate::flight`: the flight loop over the tile mailboxes), in every
/// mode: the first step (IGRF coefficients and the least-squares operators built) and the
/// steady state of Detumble, SunSafe, Slew and Tracking, each entered as in flight (the rate
/// readings, then uplinked commands through `crate::flight::take_uplink`, outside the measured
/// section). Results: each step's mode, fault bits, coil dipole and wheel momentum (body).
#[cfg(feature = "group-step")]
#[inline(always)]
fn run_step<S: Sink>(s: &mut S) {
    use crate::flight;
    let mut slot = None;
    flight::init_loop(&mut slot);
    let (Some(acs), Some(mut clock)) = (slot.as_mut(), flight::reset_clock()) else {
        s.out(f32::NAN);
        return;
    };
    let mut bus = crate::tiles::MailboxBus;
    // Sensors as in orbit: the Sun on five tiles (the sensor model averages them), the field
    // `STEP_MAG`, and first a tumble of ≈ 0.05 rad/s (Detumble), then rates of a few mrad/s
    // (below the exit threshold: SunSafe, whose law drives the wheels). So a step runs every part:
    // SGP4, Sun, eclipse, GMST, IGRF, least squares, Wahba's SVD, the filter, the mode's law and
    // the wheel and coil allocations.
    let sun = [
        [0, 0],
        [1200, -800],
        [-500, 2500],
        [3000, 100],
        [-2200, -1500],
        [700, 1900],
    ];
    let mag = STEP_MAG;
    crate::tiles::set_readings(sun, 0b11_1110, mag, [0, 500, -400, 450, -380, 300]);
    let mut attitude = None;
    // (name, uplink before the step: 0 none, 3 slew, 2 track)
    let steps: [(&str, u16); 8] = [
        ("ACS step (first)", 0),
        ("ACS step (Detumble)", 0),
        ("", 0),
        ("ACS step (SunSafe)", 0),
        ("", 3),
        ("ACS step (Slew)", 0),
        ("", 2),
        ("ACS step (Tracking)", 0),
    ];
    for (k, (name, uplink)) in steps.iter().enumerate() {
        if k == 2 {
            crate::tiles::set_readings(sun, 0b11_1110, mag, [0, 25, -18, 31, -12, 9]);
        }
        if *uplink != 0 {
            // a target 10° about body x from the attitude in force (or the identity)
            let q = attitude.map_or([1.0, 0.0, 0.0, 0.0], |q: acs::attitude::Quaternion| {
                let r = acs::attitude::Quaternion {
                    q0: 0.996_194_7,
                    q1: 0.087_155_74,
                    q2: 0.0,
                    q3: 0.0,
                };
                let t = q.mul(&r);
                [t.q0, t.q1, t.q2, t.q3]
            });
            flight::set_uplink(
                *uplink,
                &[
                    q[0].to_bits(),
                    q[1].to_bits(),
                    q[2].to_bits(),
                    q[3].to_bits(),
                    120f32.to_bits(),
                ],
            );
            flight::take_uplink(acs, &mut clock, attitude.as_ref());
        }
        let now = core::hint::black_box(clock);
        if !name.is_empty() {
            s.begin(name);
        }
        let report = acs.step(&mut bus, now, acs::flight::CONTROL_PERIOD_S);
        let report = core::hint::black_box(report);
        if !name.is_empty() {
            s.end();
        }
        attitude = report.attitude;
        clock = clock.add(flight::PERIOD);
        if name.is_empty() {
            continue;
        }
        s.out(report.mode as u8 as f32);
        s.out(f32::from(report.faults.bits()));
        let d = report.dipole_body_am2;
        let h = report.h_wheels_body;
        for x in [d.x, d.y, d.z, h.x, h.y, h.z] {
            s.out(x);
        }
    }
}

/// f32 primitives, the fmath kernels and the libm routines they replace.
#[inline(always)]
fn run_core<S: Sink>(s: &mut S) {
    // f32 primitives (the EABI helpers)
    case2!(s, "f32 mul", 1.234_567_8, -7.654_321, |x: f32, y: f32| x
        * y);
    case2!(s, "f32 add", 1.234_567_8, -7.654_321, |x: f32, y: f32| x
        + y);
    case2!(s, "f32 div", 1.234_567_8, -7.654_321, |x: f32, y: f32| x
        / y);
    // fmath kernels
    case2!(s, "fmath sqrt", 2.345_678, 0.0, |x: f32, _y: f32| {
        fmath::sqrt(x)
    });
    case2!(s, "fmath sin", 0.723_4, 0.0, |x: f32, _y: f32| fmath::sin(
        x
    ));
    case2!(s, "fmath cos", 0.723_4, 0.0, |x: f32, _y: f32| fmath::cos(
        x
    ));
    {
        s.begin("fmath sincos");
        let x = s.input(2.345_6);
        let (a, b) = fmath::sincos(x);
        let (a, b) = (s.keep(a), s.keep(b));
        s.end();
        s.out(a);
        s.out(b);
    }
    case2!(s, "fmath atan2", -0.383_1, -1.279_4, fmath::atan2);
    case1!(s, "fmath atan", 0.613_2, fmath::atan);
    case1!(s, "fmath asin", 0.613_2, fmath::asin);
    case1!(s, "fmath acos", 0.613_2, fmath::acos);
    case1!(s, "fmath sin (x = 1e4)", 10_000.123, fmath::sin);
    case1!(s, "fmath wrap_two_pi", 12_345.67, fmath::wrap_two_pi);
    case1!(s, "fmath exp", -1.234_5, fmath::exp);
    case2!(s, "fmath pow", 1.234_5, 3.5, fmath::pow);
    // libm's f32 routines (they compute in f64): the reference the kernels replace
    case1!(s, "libm sinf", 0.723_4, libm::sinf);
    case2!(s, "libm atan2f", -0.383_1, -1.279_4, libm::atan2f);
    case1!(s, "libm sqrtf", 2.345_678, libm::sqrtf);
}

/// The flight modules' cases (inputs: the AraMiS thesis cube, a LEO state, 2025).
#[inline(always)]
pub fn run_flight<S: Sink>(s: &mut S) {
    use acs::linalg::Vec3;
    use acs::time::{Epoch, Ut1, Utc};

    let nan3 = Vec3::new(f32::NAN, f32::NAN, f32::NAN);
    let out3 = |s: &mut S, v: &Vec3| {
        s.out(v.x);
        s.out(v.y);
        s.out(v.z);
    };

    // ---- time and frames
    if cfg!(feature = "group-orbit") {
        let ut1: Option<Epoch<Ut1>> = Epoch::from_parts(9_300, 43_210, 123_000_000).ok();
        s.begin("GMST (IAU-82)");
        let ut1 = core::hint::black_box(ut1);
        let g = ut1.as_ref().map_or(f32::NAN, acs::time::gmst_rad);
        let g = s.keep(g);
        s.end();
        s.out(g);
    }

    if cfg!(feature = "group-orbit") {
        let m = s.input(1.234_5);
        let e = s.input(0.185_966_7);
        s.begin("Kepler equation");
        let ea = s.keep(acs::orbit::kepler::solve_kepler(m, e));
        s.end();
        s.out(ea);
    }
    // ---- orbit (SGP4 alone in its image: see docs/firmware.md, it does not fit with anything else)
    if cfg!(feature = "group-sgp4") {
        let tle = crate::elements::test_tle();
        s.begin("SGP4 init");
        let sgp4 = tle
            .as_ref()
            .and_then(|t| acs::orbit::sgp4::Sgp4::new(t, acs::orbit::sgp4::Gravity::Wgs72).ok());
        core::hint::black_box(&sgp4);
        s.end();
        let whole = s.input(360.0);
        let frac = s.input(0.123_4);
        s.begin("SGP4 propagate");
        let st = sgp4
            .as_ref()
            .and_then(|p| p.propagate_split(whole, frac).ok());
        let st = core::hint::black_box(st);
        s.end();
        let r = st.map_or(nan3, |st| st.r_teme_km);
        out3(s, &r);
    }

    // The `sgp4` crate (f64, Vallado's code), the same elements, WGS-72, AFSPC mode: its image
    // does not fit the FG439 (nor the 16-bit address space): `--groups sgp4-peer` reports by how
    // much (docs/firmware.md, #9).
    #[cfg(feature = "group-sgp4-peer")]
    {
        use core::f64::consts::PI;
        let deg = PI / 180.0;
        let geo = sgp4::WGS72;
        let years = core::hint::black_box(0.491_409_8);
        s.begin("sgp4 crate init");
        let c = sgp4::Orbit::from_kozai_elements(
            &geo,
            34.268_2 * deg,
            348.724_2 * deg,
            0.185_966_7,
            331.766_4 * deg,
            19.326_4 * deg,
            10.824_191_574 * PI / 720.0,
        )
        .ok()
        .and_then(|o| {
            sgp4::Constants::new(
                geo,
                sgp4::afspc_epoch_to_sidereal_time,
                years,
                0.280_98e-4,
                o,
            )
            .ok()
        });
        core::hint::black_box(&c);
        s.end();
        let t = f64::from(s.input(360.0)) + f64::from(s.input(0.123_4));
        s.begin("sgp4 crate propagate");
        let p = c
            .as_ref()
            .and_then(|c| c.propagate(sgp4::MinutesSinceEpoch(t)).ok());
        let p = core::hint::black_box(p);
        s.end();
        let r = p.map_or(nan3, |p| {
            Vec3::new(
                p.position[0] as f32,
                p.position[1] as f32,
                p.position[2] as f32,
            )
        });
        out3(s, &r);
    }

    // ---- environment
    if cfg!(feature = "group-env") {
        // Opaque, so the Sun models cannot be constant-folded into the case (they were: the
        // precise Sun measured 41 728 folded, 56 519 not).
        let utc: Option<Epoch<Utc>> =
            core::hint::black_box(Epoch::from_parts(9_300, 43_210, 0).ok());
        s.begin("UTC -> TT");
        let tt = utc.as_ref().and_then(|e| e.to_tt_extrapolated().ok());
        let tt = core::hint::black_box(tt);
        s.end();
        s.out(tt.map_or(f32::NAN, |t| t.second_of_day() as f32));
        s.out(tt.map_or(f32::NAN, |t| t.nano() as f32));
        s.begin("sun (thesis)");
        let sun = utc
            .as_ref()
            .and_then(|e| acs::env::sun::schlyter::sun(e).ok());
        let sun = core::hint::black_box(sun);
        s.end();
        out3(s, &sun.map_or(nan3, |x| x.direction));
        s.begin("sun (precise)");
        let sun = utc
            .as_ref()
            .and_then(|e| acs::env::sun::precise::sun(e).ok());
        let sun = core::hint::black_box(sun);
        s.end();
        out3(s, &sun.map_or(nan3, |x| x.direction));
    }
    if cfg!(feature = "group-env") {
        use acs::env::igrf::coefficient_count;
        igrf_case::<{ coefficient_count(8) }, S>(s, "IGRF deg 8", "IGRF deg 8 at date", 8);
        igrf_case::<{ coefficient_count(10) }, S>(s, "IGRF deg 10", "IGRF deg 10 at date", 10);
        igrf_case::<{ coefficient_count(13) }, S>(s, "IGRF deg 13", "IGRF deg 13 at date", 13);
    }

    // ---- determination (own frames: their locals do not stay on the stack under the others)
    if cfg!(feature = "group-det") {
        det_least_squares(s);
        det_attitude(s);
        det_wahba3(s);
    }

    // ---- control
    if cfg!(feature = "group-ctl") {
        use acs::control::{bdot, slew, wheels};
        let q = acs::attitude::Quaternion::new_normalize(
            s.input(0.9),
            s.input(0.3),
            s.input(-0.2),
            s.input(0.25),
        );
        let m = q.map(|q| *q.to_dcm().matrix());
        s.begin("slew quaternion decomposition");
        let d = m.and_then(|m| slew::decompose(&m, slew::Branch::Shortest).ok());
        let d = core::hint::black_box(d);
        s.end();
        s.out(d.map_or(f32::NAN, |a| a.phi_a));
        s.out(d.map_or(f32::NAN, |a| a.theta_b));
        s.out(d.map_or(f32::NAN, |a| a.psi_c));
        let wheel = |x: f32, y: f32, z: f32| wheels::Wheel {
            axis_body: Vec3::new(x, y, z),
            limit: 0.005,
            working: true,
        };
        // opaque axes: constant ones would let the closed-form pseudoinverse be folded
        let ws = [
            wheel(s.input(1.0), s.input(0.0), s.input(0.0)),
            wheel(s.input(0.0), s.input(1.0), s.input(0.0)),
            wheel(s.input(0.0), s.input(0.0), s.input(1.0)),
            wheel(s.input(0.577), s.input(0.577), s.input(0.577)),
        ];
        let l = Vec3::new(s.input(0.001), s.input(-0.002), s.input(0.0005));
        s.begin("wheel allocation");
        let a = wheels::allocate(&ws, &l).ok();
        let a = core::hint::black_box(a);
        s.end();
        s.out(a.as_ref().map_or(f32::NAN, |a| a.wheel[0]));
        s.out(a.as_ref().map_or(f32::NAN, |a| a.wheel[3]));
        let cfg = bdot::BdotConfig {
            gain: 2.0e4,
            max_dipole_am2: Vec3::new(0.2, 0.2, 0.2),
        };
        let w = Vec3::new(s.input(0.01), s.input(-0.02), s.input(0.03));
        let b = Vec3::new(s.input(12_000.0), s.input(-30_000.0), s.input(18_000.0));
        s.begin("B-dot (gyro form)");
        let m = bdot::bdot_from_rates(&cfg, &w, &b).ok();
        let m = core::hint::black_box(m);
        s.end();
        out3(s, &m.unwrap_or(nan3));
    }
}

/// Body field and rate by least squares over the thesis cube's tiles.
#[inline(never)]
fn det_least_squares<S: Sink>(s: &mut S) {
    use acs::determination::least_squares;
    use acs::linalg::{Vec2, Vec3};
    let nan3 = Vec3::new(f32::NAN, f32::NAN, f32::NAN);
    // The thesis cube's six tiles as a constant table (in flash): `tiles::cube_thesis()`
    // builds a 24-slot `Tiles` (about 1 KB) on the stack.
    use acs::tiles::{Equipment, Tile, CUBE_THESIS_MATRICES as A};
    const TILES: [Tile; 6] = [
        Tile::new(A[0], Equipment::TELECOM),
        Tile::new(A[1], Equipment::POWER),
        Tile::new(A[2], Equipment::POWER),
        Tile::new(A[3], Equipment::POWER),
        Tile::new(A[4], Equipment::POWER),
        Tile::new(A[5], Equipment::POWER),
    ];
    let tiles = core::hint::black_box(&TILES);
    {
        let readings: [Option<Vec2>; 6] = [
            Some(Vec2::new(s.input(12_000.0), s.input(-8_000.0))),
            Some(Vec2::new(s.input(-3_000.0), s.input(20_000.0))),
            Some(Vec2::new(s.input(7_000.0), s.input(1_000.0))),
            Some(Vec2::new(s.input(-15_000.0), s.input(4_000.0))),
            Some(Vec2::new(s.input(2_500.0), s.input(-9_000.0))),
            Some(Vec2::new(s.input(5_000.0), s.input(6_000.0))),
        ];
        s.begin("magnetometer least squares");
        let b = least_squares::magnetic_field_body(tiles, &readings).ok();
        let b = core::hint::black_box(b);
        s.end();
        out3(s, &b.unwrap_or(nan3));
        let rates: [Option<f32>; 6] = [
            Some(s.input(0.01)),
            Some(s.input(-0.02)),
            Some(s.input(0.03)),
            Some(s.input(-0.011)),
            Some(s.input(0.019)),
            Some(s.input(-0.031)),
        ];
        s.begin("gyro least squares");
        let w = least_squares::angular_rate_body(tiles, &rates).ok();
        let w = core::hint::black_box(w);
        s.end();
        out3(s, &w.unwrap_or(nan3));
    }
}

/// The attitude solvers on two vector pairs.
#[inline(never)]
fn det_attitude<S: Sink>(s: &mut S) {
    use acs::determination::{self, Observation};
    use acs::linalg::Vec3;
    {
        let obs = [
            Observation {
                body: Vec3::new(s.input(0.2673), s.input(0.5345), s.input(0.8018)),
                reference: Vec3::new(s.input(0.7448), s.input(-0.6383), s.input(-0.1949)),
                weight: 0.5,
            },
            Observation {
                body: Vec3::new(s.input(-0.3124), s.input(0.9370), s.input(0.1562)),
                reference: Vec3::new(s.input(0.2), s.input(0.4), s.input(0.8944)),
                weight: 0.5,
            },
        ];
        for (name, solver) in [
            (
                "Wahba SVD",
                determination::wahba_svd::solve as fn(&[Observation]) -> _,
            ),
            ("QUEST", determination::quest::solve),
            ("TRIAD", determination::triad::solve),
        ] {
            s.begin(name);
            let sol = solver(&obs).ok();
            let sol = core::hint::black_box(sol);
            s.end();
            let q = sol.map(|x| x.quaternion);
            s.out(q.map_or(f32::NAN, |q| q.q0));
            s.out(q.map_or(f32::NAN, |q| q.q1));
        }
    }
}

/// Wahba's problem with three pairs: the general path (Jacobi SVD of `B`, then one
/// Gauss–Newton step).
#[inline(never)]
fn det_wahba3<S: Sink>(s: &mut S) {
    use acs::determination::{self, Observation};
    use acs::linalg::Vec3;
    {
        let obs3 = [
            Observation {
                body: Vec3::new(s.input(0.2673), s.input(0.5345), s.input(0.8018)),
                reference: Vec3::new(s.input(0.7448), s.input(-0.6383), s.input(-0.1949)),
                weight: 0.5,
            },
            Observation {
                body: Vec3::new(s.input(-0.3124), s.input(0.9370), s.input(0.1562)),
                reference: Vec3::new(s.input(0.2), s.input(0.4), s.input(0.8944)),
                weight: 0.5,
            },
            Observation {
                body: Vec3::new(s.input(0.6), s.input(-0.2), s.input(0.7746)),
                reference: Vec3::new(s.input(-0.5), s.input(0.3), s.input(0.8124)),
                weight: 0.25,
            },
        ];
        s.begin("Wahba SVD (3 vectors)");
        let sol = determination::wahba_svd::solve(&obs3).ok();
        let sol = core::hint::black_box(sol);
        s.end();
        let q = sol.map(|x| x.quaternion);
        s.out(q.map_or(f32::NAN, |q| q.q0));
        s.out(q.map_or(f32::NAN, |q| q.q1));
    }
}

/// Three components of a result.
fn out3<S: Sink>(s: &mut S, v: &acs::linalg::Vec3) {
    s.out(v.x);
    s.out(v.y);
    s.out(v.z);
}

/// IGRF at `degree` with a `C`-coefficient [`acs::env::igrf::Igrf`]: case `at_date` builds the
/// coefficients at the date (once per refresh in flight), case `name` is one field evaluation
/// (`Igrf::teme`, once per step). Not inlined, so that the three sizes do not share one stack
/// frame.
#[inline(never)]
fn igrf_case<const C: usize, S: Sink>(
    s: &mut S,
    name: &'static str,
    at_date: &'static str,
    degree: u8,
) {
    use acs::env::igrf::{Degree, Igrf, RECENT};
    use acs::linalg::Vec3;
    let nan3 = Vec3::new(f32::NAN, f32::NAN, f32::NAN);
    let year = s.input(2025.5);
    // Built (not measured) in place at another date, then refreshed in place: the flight
    // pattern (no copy of the coefficients on the 2 KB stack).
    let mut slot = None;
    let mut field = match Degree::new(degree) {
        Ok(d) => Igrf::<C>::emplace_year(&mut slot, &RECENT, 2021.0, d),
        Err(e) => Err(e),
    };
    s.begin(at_date);
    let refreshed = field
        .as_mut()
        .is_ok_and(|f| f.refresh_year(&RECENT, year).is_ok());
    core::hint::black_box(&field);
    s.end();
    let field = field.as_ref().ok().filter(|_| refreshed);
    s.out(field.map_or(f32::NAN, |f| f.degree_one_nt().0));
    let r = Vec3::new(s.input(4_000.0), s.input(-3_500.0), s.input(4_200.0));
    let gmst = s.input(1.234);
    s.begin(name);
    let b = field.and_then(|f| f.teme(&r, gmst).ok());
    let b = core::hint::black_box(b);
    s.end();
    out3(s, &b.unwrap_or(nan3));
}
