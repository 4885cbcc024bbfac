//! Reaction-wheel allocation: a body angular momentum (or torque) to individual wheels by the
//! minimum-norm pseudoinverse over the axes of the working wheels, with per-wheel saturation
//! that keeps the direction of the command (seed 000 §10.2.3, eq. 10.30; note 000 §3.10
//! "Wheel allocation" and §7.11–7.12).
//!
//! # Equations
//! With `W` the 3×n matrix whose columns are the unit spin axes `ẑ_m` of the working wheels
//! (body UVW) and `L` the body momentum a manoeuvre needs, the wheels take the opposite
//! momentum (conservation of angular momentum, eqs. 10.1–10.6):
//! ```text
//! W h = −L,   h = −Wᵀ (W Wᵀ)⁺ L        (minimum ‖h‖ among all exact solutions)
//! ```
//! `(W Wᵀ)⁺` is the pseudoinverse of the symmetric 3×3 matrix `W Wᵀ` in closed form
//! ([`crate::linalg::pseudoinverse`]: adjugate at rank 3, null vector at rank 2, `G/tr(G)²` at
//! rank 1) with eigenvalues below [`RANK_TOLERANCE`]·λ_max treated as zero (decided from the
//! invariants of `W Wᵀ`: an eigenvalue above 9·[`RANK_TOLERANCE`]·λ_max always counts, one below
//! [`RANK_TOLERANCE`]·λ_max never does). When the working wheels do not span the space, the
//! result is the least-squares allocation and [`WheelAllocation::unrealised`] says what part of
//! `L` no wheel can produce.
//!
//! # Accuracy
//! Measured against the f64 minimum-norm allocation of the same (f32) axes on every preset of
//! [`crate::tiles`] with every non-empty subset of working wheels (rank 3, 2 and 1), and the
//! flight configuration's three coils: 14 734 working sets of rank 3, 2 121 of rank 2 and 116
//! of rank 1 (`cargo test --release --test control allocator -- --nocapture`), the largest
//! errors are
//!
//! | rank | `(W Wᵀ)⁺` (max entry, relative) | `‖h − h₆₄‖/(‖L‖·‖W⁺‖)` | `‖unrealised − u₆₄‖/‖L‖` | null-space part of `h`, `/(‖L‖·‖W⁺‖)` |
//! |---|---|---|---|---|
//! | 3 | 2.29e-7 | 2.14e-7 | 3.71e-7 | 5.95e-8 |
//! | 2 | 2.38e-7 | 2.40e-7 | 4.84e-7 | 4.76e-8 |
//! | 1 | 1.12e-7 | 1.22e-7 | 1.30e-7 | 3.54e-8 |
//!
//! (the null-space part `h − W⁺W h` is zero for the minimum-norm solution: the last column is
//! how far the f32 commands are from minimum norm). The rank is the f64 one on every set; on
//! these geometries it comes out the same for any threshold between 2.4e-7 (the rounding noise
//! of the rank-deficient sets) and 0.12 (where the first working set would lose a rank).
//!
//! For the thesis's cube (one wheel per face) this gives each axis's component to the wheels on
//! that axis, split equally between the `+` and `−` faces: `h_m = −(L·ẑ_m)/n_axis`, the thesis's
//! rule. For the hexagonal prism it differs from eq. 10.30 (see `tests/control.rs`): the thesis
//! drives only the two faces adjacent to U with `(L_u/2)/cos 30°` each (0.577 for `L_u = 1`); the
//! minimum-norm solution spreads `L_u` over all four side wheels with a U component,
//! `L_u/(4 cos 30°)` each (0.289), with half the total ‖h‖² and the same net momentum.
//!
//! # Saturation
//! If any wheel would exceed its limit, the whole vector `h` is scaled by
//! `min_m(h_max,m / |h_m|)`: the body momentum keeps its direction and shrinks
//! ([`WheelAllocation::scale`] < 1).
//!
//! The same functions allocate a torque (N·m) when given torques and torque limits.

use core::fmt;

use crate::linalg::pseudoinverse::symmetric_pseudoinverse;
use crate::linalg::{dot, SymMat3, Vec3};

/// Relative eigenvalue threshold of the pseudoinverse of `W Wᵀ` (see the
/// [module docs](self) and [`crate::linalg::pseudoinverse`] for how it is applied).
pub const RANK_TOLERANCE: f32 = 1e-5;

/// One reaction wheel.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Wheel {
    /// Unit spin axis in body UVW (the tile's `ẑ`, row 3 of its orientation matrix).
    #[cfg_attr(feature = "defmt", defmt(Debug2Format))]
    pub axis_body: Vec3,
    /// Largest angular momentum magnitude, kg·m²/s (or torque, N·m, when allocating torque).
    pub limit: f32,
    /// False if the wheel has failed or is switched off: it gets zero.
    pub working: bool,
}

/// Errors of the allocation.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum WheelError {
    /// The command, an axis or a limit is NaN or infinite (or the axes' squares overflow).
    NotFinite,
    /// A working wheel has a zero axis (`|ẑ|² <` `f32::MIN_POSITIVE`, `|ẑ| < 1.1e-19`) or a
    /// non-positive limit (its index).
    InvalidWheel(u8),
    /// No working wheel.
    NoWorkingWheel,
    /// The [`Allocator`] was built for another working set of wheels: rebuild it.
    StaleAllocator,
}

impl fmt::Display for WheelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotFinite => write!(f, "wheel command or geometry is NaN or infinite"),
            Self::InvalidWheel(i) => write!(f, "wheel {i} has a zero axis or a non-positive limit"),
            Self::NoWorkingWheel => write!(f, "no working reaction wheel"),
            Self::StaleAllocator => write!(f, "the allocator was built for another working set"),
        }
    }
}

/// The result of an allocation over `N` wheels.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct WheelAllocation<const N: usize> {
    /// Command of each wheel along its own axis (momentum kg·m²/s or torque N·m), after
    /// saturation; zero for failed wheels.
    pub wheel: [f32; N],
    /// The factor (0..=1) the whole allocation was scaled by to respect the limits.
    pub scale: f32,
    /// The part of the requested body vector no combination of working wheels can produce
    /// (zero when they span the space), before saturation; same unit as the request.
    #[cfg_attr(feature = "defmt", defmt(Debug2Format))]
    pub unrealised: Vec3,
    /// Number of independent directions the working wheels span (0..=3).
    pub rank: u8,
}

/// Allocates the body vector `l_body` (the momentum or torque the body must receive) to the
/// wheels: each wheel gets the opposite (see the [module docs](self)).
///
/// Builds the [`Allocator`] of the wheel set and applies it: a loop that allocates every step
/// keeps the allocator instead (its pseudoinverse is most of the cost).
pub fn allocate<const N: usize>(
    wheels: &[Wheel; N],
    l_body: &Vec3,
) -> Result<WheelAllocation<N>, WheelError> {
    if l_body.iter().any(|x| !x.is_finite()) {
        return Err(WheelError::NotFinite);
    }
    Allocator::new(wheels)?.allocate(wheels, l_body)
}

/// The pseudoinverse `(W Wᵀ)⁺` of one wheel set, computed once ([`Allocator::new`]) and applied
/// to every command ([`Allocator::allocate`]): an allocation is then `N` dot products and the
/// saturation, instead of a 3×3 pseudoinverse each time (on the MSP430, measured by
/// `firmware/msp430-bench`: `docs/firmware.md`).
///
/// It is valid for the axes and the working set it was built from; [`Allocator::allocate`]
/// refuses ([`WheelError::StaleAllocator`]) a wheel set whose working set differs. The limits
/// are read at each allocation.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Allocator {
    pinv: SymMat3,
    rank: u8,
    working: u32,
}

/// Bit `i` set if wheel `i` works (wheels beyond 32 are not representable: refused by `new`).
fn working_mask<const N: usize>(wheels: &[Wheel; N]) -> u32 {
    wheels
        .iter()
        .enumerate()
        .filter(|(_, w)| w.working)
        .fold(0u32, |m, (i, _)| {
            m | 1u32.checked_shl(i as u32).unwrap_or(0)
        })
}

impl Allocator {
    /// The allocator of `wheels` (at most 32): checks every working wheel (finite unit-able
    /// axis, positive finite limit) and computes `(W Wᵀ)⁺`.
    pub fn new<const N: usize>(wheels: &[Wheel; N]) -> Result<Self, WheelError> {
        let mut gram = SymMat3::zeros();
        let mut any = false;
        for (i, w) in wheels.iter().enumerate() {
            if !w.working {
                continue;
            }
            if i >= 32 {
                return Err(WheelError::InvalidWheel(i as u8));
            }
            if !crate::linalg::finite3(&w.axis_body) || !w.limit.is_finite() {
                return Err(WheelError::NotFinite);
            }
            // finite axis: its square is finite or +∞ (then the pseudoinverse refuses it)
            if !(dot(&w.axis_body, &w.axis_body) >= f32::MIN_POSITIVE) || !(w.limit > 0.0) {
                return Err(WheelError::InvalidWheel(i as u8));
            }
            gram.add_outer(&w.axis_body);
            any = true;
        }
        if !any {
            return Err(WheelError::NoWorkingWheel);
        }
        // (W Wᵀ)⁺ in closed form with a relative threshold (out of range: the squares overflow)
        let p =
            symmetric_pseudoinverse(&gram, RANK_TOLERANCE).map_err(|_| WheelError::NotFinite)?;
        Ok(Self {
            pinv: p.pinv,
            rank: p.rank,
            working: working_mask(wheels),
        })
    }

    /// `(W Wᵀ)⁺` of the working wheels.
    pub fn pseudoinverse(&self) -> &SymMat3 {
        &self.pinv
    }

    /// Number of independent directions the working wheels span (0..=3).
    pub fn rank(&self) -> u8 {
        self.rank
    }

    /// True if `wheels` has the working set this allocator was built for.
    pub fn is_for<const N: usize>(&self, wheels: &[Wheel; N]) -> bool {
        working_mask(wheels) == self.working
    }

    /// Allocates `l_body` to `wheels` (the set this allocator was built from, limits as given
    /// now): each wheel gets the opposite (see the [module docs](self)).
    pub fn allocate<const N: usize>(
        &self,
        wheels: &[Wheel; N],
        l_body: &Vec3,
    ) -> Result<WheelAllocation<N>, WheelError> {
        // a torque not finite is refused first, by allocate_current
        if crate::linalg::finite3(l_body) && !self.is_for(wheels) {
            return Err(WheelError::StaleAllocator);
        }
        self.allocate_current(wheels, l_body)
    }

    /// [`Allocator::allocate`] for `wheels` known to have this allocator's working set (the
    /// attitude node's cache checked it: no second check).
    pub(crate) fn allocate_current<const N: usize>(
        &self,
        wheels: &[Wheel; N],
        l_body: &Vec3,
    ) -> Result<WheelAllocation<N>, WheelError> {
        if !crate::linalg::finite3(l_body) {
            return Err(WheelError::NotFinite);
        }
        // y = (W Wᵀ)⁺ L; each wheel h_m = −ẑ_m · y
        let y = self.pinv.mul_vec(l_body);
        let mut wheel = [0.0f32; N];
        let mut realised = Vec3::zeros(); // W Wᵀ y
        for (h, w) in wheel.iter_mut().zip(wheels.iter()) {
            if w.working {
                let along = crate::linalg::dot(&w.axis_body, &y);
                *h = -along;
                realised += crate::linalg::scale(&w.axis_body, along);
            }
        }
        // saturation keeping the direction (a NaN limit is refused: `!(mag <= limit)`)
        let mut scale = 1.0f32;
        for (h, w) in wheel.iter().zip(wheels.iter()) {
            if !w.working {
                continue;
            }
            if !(w.limit.is_finite() && w.limit > 0.0) {
                return Err(WheelError::NotFinite);
            }
            let mag = if *h >= 0.0 { *h } else { -*h };
            if mag > w.limit {
                scale = crate::fmath::min(scale, w.limit / mag);
            }
        }
        if !(scale >= 1.0) {
            // One ulp below the rounded limit/|h|: h·scale then never rounds above a limit,
            // which a driver would refuse (|h|·pred(fl(L/|h|)) ≤ L(1 + 2⁻²⁴)(1 − 2⁻²⁴) < L, and
            // rounding to nearest keeps a value below the float L at or below it).
            scale = f32::from_bits(scale.to_bits().saturating_sub(1));
            for h in wheel.iter_mut() {
                *h *= scale;
            }
        }
        Ok(WheelAllocation {
            wheel,
            scale,
            unrealised: crate::linalg::sub(l_body, &realised),
            rank: self.rank,
        })
    }
}

/// The body vector the wheels produce on the body, `−Σ h_m ẑ_m` (the inverse of [`allocate`]).
pub fn body_vector<const N: usize>(wheels: &[Wheel; N], wheel_values: &[f32; N]) -> Vec3 {
    wheels
        .iter()
        .zip(wheel_values.iter())
        .filter(|(w, _)| w.working)
        .fold(Vec3::zeros(), |acc, (w, h)| acc - w.axis_body * *h)
}
