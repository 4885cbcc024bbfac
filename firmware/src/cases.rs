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
