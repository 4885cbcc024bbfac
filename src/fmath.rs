//! f32 elementary functions used by the flight code: the single place where the crate's
//! transcendental functions come from.
//!
//! Every flight module calls these wrappers rather than `libm` directly, so that the f32-native
//! kernels written for the MSP430 (whose `libm` f32 routines compute in f64 and cost
//! 60 000–200 000 cycles a call, `../shared/notes/msp430-toolchain.md`) replace them in one place.
//! Until then they forward to `libm` (correctly rounded or within 1 ulp on the host).

/// Sine of `x` (radians).
#[inline]
pub fn sin(x: f32) -> f32 {
    libm::sinf(x)
}

/// Cosine of `x` (radians).
#[inline]
pub fn cos(x: f32) -> f32 {
    libm::cosf(x)
}

/// `(sin x, cos x)` of `x` (radians).
#[inline]
pub fn sincos(x: f32) -> (f32, f32) {
    libm::sincosf(x)
}

/// Tangent of `x` (radians).
#[inline]
pub fn tan(x: f32) -> f32 {
    libm::tanf(x)
}

/// Four-quadrant arctangent of `y / x`, radians in −π..=π.
#[inline]
pub fn atan2(y: f32, x: f32) -> f32 {
    libm::atan2f(y, x)
}

/// Arctangent, radians in −π/2..=π/2.
#[inline]
pub fn atan(x: f32) -> f32 {
    libm::atanf(x)
}

/// Arcsine, radians; NaN outside −1..=1 (clamp first where rounding may push past ±1).
#[inline]
pub fn asin(x: f32) -> f32 {
    libm::asinf(x)
}

/// Arccosine, radians; NaN outside −1..=1 (clamp first where rounding may push past ±1).
#[inline]
pub fn acos(x: f32) -> f32 {
    libm::acosf(x)
}

/// Square root; NaN for negative input.
#[inline]
pub fn sqrt(x: f32) -> f32 {
    libm::sqrtf(x)
}

/// Floor.
#[inline]
pub fn floor(x: f32) -> f32 {
    libm::floorf(x)
}

/// Absolute value.
#[inline]
pub fn abs(x: f32) -> f32 {
    libm::fabsf(x)
}

/// `x` reduced to `[0, 2π)` (NaN stays NaN).
#[inline]
pub fn wrap_two_pi(x: f32) -> f32 {
    let r = libm::fmodf(x, core::f32::consts::TAU);
    if r < 0.0 {
        r + core::f32::consts::TAU
    } else {
        r
    }
}

/// Power `x^y`.
#[inline]
pub fn pow(x: f32, y: f32) -> f32 {
    libm::powf(x, y)
}

/// Natural exponential.
#[inline]
pub fn exp(x: f32) -> f32 {
    libm::expf(x)
}
