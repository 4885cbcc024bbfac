//! The arithmetic the frame conversions need, for f32 (flight, through [`crate::fmath`]) and f64
//! (host and one-time conversions, through `libm`), so each conversion is written once.

use core::ops::{Add, Div, Mul, Neg, Sub};

mod sealed {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
}

/// A floating-point type the frame conversions are generic over: f32 (flight) or f64 (host and
/// one-time conversions). Sealed: implemented for these two only.
pub trait Real:
    sealed::Sealed
    + Copy
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + nalgebra::RealField
{
    /// The constant `x` in this type (rounded for f32).
    fn of(x: f64) -> Self;
    /// Widened to f64 (for error values).
    fn to_f64(self) -> f64;
    /// Sine and cosine.
    fn sincos(self) -> (Self, Self);
    /// Square root.
    fn sqrt(self) -> Self;
    /// Four-quadrant arctangent of `self / x`.
    fn atan2(self, x: Self) -> Self;
    /// True unless NaN or infinite.
    fn finite(self) -> bool;
    /// Largest integer not above `self`.
    fn floor_(self) -> Self;
}

impl Real for f32 {
    #[inline]
    fn of(x: f64) -> Self {
        x as f32
    }
    #[inline]
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
    #[inline]
    fn sincos(self) -> (Self, Self) {
        crate::fmath::sincos(self)
    }
    #[inline]
    fn sqrt(self) -> Self {
        crate::fmath::sqrt(self)
    }
    #[inline]
    fn atan2(self, x: Self) -> Self {
        crate::fmath::atan2(self, x)
    }
    #[inline]
    fn finite(self) -> bool {
        self.is_finite()
    }
    #[inline]
    fn floor_(self) -> Self {
        crate::fmath::floor(self)
    }
}

impl Real for f64 {
    #[inline]
    fn of(x: f64) -> Self {
        x
    }
    #[inline]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline]
    fn sincos(self) -> (Self, Self) {
        libm::sincos(self)
    }
    #[inline]
    fn sqrt(self) -> Self {
        libm::sqrt(self)
    }
    #[inline]
    fn atan2(self, x: Self) -> Self {
        libm::atan2(self, x)
    }
    #[inline]
    fn finite(self) -> bool {
        self.is_finite()
    }
    #[inline]
    fn floor_(self) -> Self {
        libm::floor(self)
    }
}
