//! Body vectors from many one- and two-axis tile sensors by least squares (seed 000 §8.2–8.3;
//! note 000 §3.8 b–d).
//!
//! # Magnetic field (eqs. 8.9–8.16)
//! Tile m's magnetometer measures the field along its x̂ and ŷ (rows 1 and 2 of `A_m`, in
//! the body frame): `x̂_m·B = φ_xm`, `ŷ_m·B = φ_ym`. Stacking the working tiles gives the 2N×3
//! system `𝐁·B_uvw = Φ`, solved as `B_uvw = 𝐁⁺·Φ`. At least two tiles with non-parallel
//! normals are needed (rank 3).
//!
//! # Angular rate (eqs. 8.19–8.25)
//! Tile m's gyro measures `ẑ_m·ω = ω_zm`; `Z·ω_uvw = Ω`, `ω_uvw = Z⁺·Ω`. At least three tiles
//! with non-coplanar normals are needed.
//!
//! # Numerics (one-shot functions)
//! [`magnetic_field_body`] and [`angular_rate_body`] fold the rows one by one into a Givens QR
//! ([`crate::linalg::lsq`], constant memory whatever the number of tiles, error ∝ ε·κ), and
//! invert the 3×3 factor by SVD with the relative threshold [`RANK_REL_TOL`] on its singular
//! values (seed 000 eqs. 8.17–8.18; the thesis suggests "about 1e-6·σ_max", which is within 10
//! f32 ulps of the rounding floor of a rank-deficient 12-row matrix; 1e-5 keeps a margin). Rank
//! < 3 is [`DeterminationError::NotObservable`]: the working tiles do not span the space.
//! For the presets of [`crate::tiles`] with every tile working, the condition number of the
//! stacked matrix is 1.0 (cube with 4 tiles per face), 1.10 / 1.22 (hexagonal prism, magnetometers
//! / gyros), 1.15 / 1.41 (the thesis cube's tiles 1–5 and the octagonal prism), so the f32
//! result is within a few ulps of the exact least-squares solution (measured: relative error
//! ≤ 3e-7 on all presets, `cargo test --test determination least_squares -- --nocapture`).
//! They serve the host and the ground; the flight loop uses the cached operator.
//!
//! # Cached operator (the flight loop)
//! The rows depend only on the tile geometry and on which tiles give a reading, which changes
//! only when a device fails or comes back. [`TileSolver`] keeps `(𝐁ᵀ𝐁)⁻¹` for one such set; a
//! step is then `B = (𝐁ᵀ𝐁)⁻¹·𝐁ᵀΦ`, two rows of dot products per tile. On a change of the set
//! the Gram matrix `𝐁ᵀ𝐁 = Σ aₖaₖᵀ` of the contributing rows is accumulated in the same walk
//! as `𝐁ᵀΦ` and inverted in closed form ([`crate::linalg::pseudoinverse`]: adjugate over the
//! determinant of the pivoted Cholesky factorisation, no iteration, no square root), rank 3
//! required with the relative threshold [`GRAM_REL_TOL`] on the eigenvalues of `𝐁ᵀ𝐁` (the
//! squares of the singular values: an eigenvalue above `GRAM_REL_TOL·λ_max` always counts, one
//! below `GRAM_REL_TOL·λ_max/18` never does). The normal equations' error grows like `ε·κ²`
//! (κ = κ(𝐁) = √(λ_max/λ_min)): the sets accepted have κ² < 18/`GRAM_REL_TOL`, an error below
//! about 0.2 in the worst case, and those with `λ_min > GRAM_REL_TOL·λ_max` below 1.2e-2, as the
//! one-shot QR's `ε·κ` at [`RANK_REL_TOL`]. The tile geometries are far from it: κ² ≤ 9.
//!
//! Measured against the f64 least squares of the same f32 rows and readings, on every preset of
//! [`crate::tiles`] with every subset of tiles giving a reading (16 851 observable sets of
//! magnetometers, 14 733 of gyros; `cargo test --release --test determination tile_operator --
//! --nocapture`): `(𝐁ᵀ𝐁)⁻¹` within 2.2e-7 (field) and 2.3e-7 (rate) of f64 (max entry,
//! relative), the solution within 3.1e-7 and 3.1e-7 (relative). The 118 magnetometer and 2 236
//! gyro sets that do not span the space are all refused with their f64 rank; the rank comes
//! out the same for any threshold between 2.4e-7 (the rounding noise of those sets) and 0.11
//! (where the first observable set would be refused; the smallest `λ₃/λ₁` of an observable
//! set is 0.111). Against the one-shot QR solution: relative difference ≤ 2.8e-7 (field and
//! rate) on all presets with every tile working (`least_squares_on_presets`).
//!
//! Units: whatever the readings are in (nT for [`crate::tiles::RawMagnetometer::to_nt`];
//! the thesis used 10 nT), rad/s for the rates.

use nalgebra::SVector;

use super::DeterminationError;
use crate::linalg::lsq::QrLeastSquares;
use crate::linalg::pseudoinverse::symmetric_pseudoinverse;
use crate::linalg::svd::SvdError;
use crate::linalg::{lin2, scale, SymMat3, Vec2, Vec3};
use crate::tiles::Tile;

/// Relative threshold on the singular values of the one-shot QR solution (see the module docs).
pub const RANK_REL_TOL: f32 = 1.0e-5;

/// Relative threshold on the eigenvalues of `HᵀH` of the cached operator [`TileSolver`] (see
/// the module docs).
pub const GRAM_REL_TOL: f32 = 1.0e-5;

/// The readings of one kind of tile sensor, one entry per tile: the magnetometers' two
/// components (rows `x̂_m·B = φ_xm`, `ŷ_m·B = φ_ym`) or the gyros' one (`ẑ_m·ω = ω_zm`). One
/// (non-generic) copy of the solvers serves both.
#[derive(Copy, Clone)]
pub(crate) enum Readings<'a> {
    Field(&'a [Option<Vec2>]),
    Rate(&'a [Option<f32>]),
}

/// One tile's reading: the magnetometer's `(φ_x, φ_y)` or the gyro's `ω_z`.
#[derive(Copy, Clone)]
enum Reading {
    Field(Vec2),
    Rate(f32),
}

impl Reading {
    /// Every component is finite.
    fn is_finite(&self) -> bool {
        match self {
            Self::Field(b) => b.x.is_finite() && b.y.is_finite(),
            Self::Rate(w) => w.is_finite(),
        }
    }

    /// `Hᵀy` of this reading's rows.
    fn transposed(&self, tile: &Tile) -> Vec3 {
        match self {
            Self::Field(b) => lin2(&tile.x_body(), b.x, &tile.y_body(), b.y),
            Self::Rate(w) => scale(&tile.normal_body(), *w),
        }
    }

    /// Adds this reading's rows `a` to the Gram matrix (`HᵀH += a aᵀ`).
    fn add_rows(&self, tile: &Tile, gram: &mut SymMat3) {
        match self {
            Self::Field(_) => {
                gram.add_outer(&tile.x_body());
                gram.add_outer(&tile.y_body());
            }
            Self::Rate(_) => gram.add_outer(&tile.normal_body()),
        }
    }

    /// Folds this reading's rows (body-frame row, measured value or 0) into `ls`.
    fn push_rows(
        &self,
        tile: &Tile,
        ls: &mut QrLeastSquares<1>,
        with_values: bool,
    ) -> Result<(), SvdError> {
        let value = |v: f32| SVector::<f32, 1>::new(if with_values { v } else { 0.0 });
        match self {
            Self::Field(b) => {
                ls.push(&tile.x_body(), &value(b.x))?;
                ls.push(&tile.y_body(), &value(b.y))
            }
            Self::Rate(w) => ls.push(&tile.normal_body(), &value(*w)),
        }
    }
}

impl Readings<'_> {
    fn len(&self) -> usize {
        match self {
            Self::Field(r) => r.len(),
            Self::Rate(r) => r.len(),
        }
    }

    /// Tile `index`'s reading, `None` if it has none or its sensor does not work.
    #[inline(always)]
    fn get(&self, index: usize, tile: &Tile) -> Option<Reading> {
        match self {
            Self::Field(r) => match r.get(index) {
                Some(Some(b)) if tile.has_working_magnetometer() => Some(Reading::Field(*b)),
                _ => None,
            },
            Self::Rate(r) => match r.get(index) {
                Some(Some(w)) if tile.has_working_gyro() => Some(Reading::Rate(*w)),
                _ => None,
            },
        }
    }
}

/// Calls `f` for each working tile with a reading, in order; a non-finite reading stops the
/// walk with [`DeterminationError::NonFinite`] and its index.
fn for_each_reading(
    tiles: &[Tile],
    readings: Readings,
    mut f: impl FnMut(&Tile, &Reading) -> Result<(), DeterminationError>,
) -> Result<(), DeterminationError> {
    if tiles.len() != readings.len() {
        return Err(DeterminationError::LengthMismatch {
            tiles: tiles.len(),
            readings: readings.len(),
        });
    }
    for (index, tile) in tiles.iter().enumerate() {
        let Some(reading) = readings.get(index, tile) else {
            continue;
        };
        if !reading.is_finite() {
            return Err(DeterminationError::NonFinite { index });
        }
        f(tile, &reading)?;
    }
    Ok(())
}

/// The rows of the working tiles with a reading folded into a Givens QR, with the readings as
/// the right-hand side (`with_values`) or zeros.
fn factor(
    tiles: &[Tile],
    readings: Readings,
    with_values: bool,
) -> Result<QrLeastSquares<1>, DeterminationError> {
    let mut ls = QrLeastSquares::<1>::new();
    for_each_reading(tiles, readings, |tile, reading| {
        Ok(reading.push_rows(tile, &mut ls, with_values)?)
    })?;
    if ls.rows() == 0 {
        return Err(DeterminationError::NotObservable { rank: 0 });
    }
    Ok(ls)
}

/// The one-shot least-squares solution by Givens QR with the readings as the right-hand side.
#[cfg_attr(target_arch = "msp430", inline(never))]
fn solve(tiles: &[Tile], readings: Readings) -> Result<Vec3, DeterminationError> {
    let x = factor(tiles, readings, true)?.solve_full_rank(RANK_REL_TOL)?;
    Ok(x.column(0).into_owned())
}

/// The body-frame magnetic field `B_uvw = 𝐁⁺·Φ` (eq. 8.16) from the tiles whose reading is
/// `Some((B_x, B_y))` (tile-frame components) and whose magnetometer is working. `readings`
/// has one entry per tile.
pub fn magnetic_field_body(
    tiles: &[Tile],
    readings: &[Option<Vec2>],
) -> Result<Vec3, DeterminationError> {
    solve(tiles, Readings::Field(readings))
}

/// The body-frame angular rate `ω_uvw = Z⁺·Ω` (eq. 8.25) from the tiles whose reading is
/// `Some(ω_z)` (rad/s about the tile normal) and whose gyro is working. `readings` has one
/// entry per tile.
pub fn angular_rate_body(
    tiles: &[Tile],
    readings: &[Option<f32>],
) -> Result<Vec3, DeterminationError> {
    solve(tiles, Readings::Rate(readings))
}

/// `(HᵀH)⁻¹` of the rows of one set of tiles (bit `i` of `tiles` set: tile `i` contributes),
/// built on first use by [`magnetic_field_body_cached`] or [`angular_rate_body_cached`] and
/// reused while the set does not change (see the [module docs](self)).
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TileSolver {
    inverse_gram: SymMat3,
    tiles: u32,
}

impl TileSolver {
    /// `(HᵀH)⁻¹` of the rows of the tiles this operator was built for.
    pub fn inverse_gram(&self) -> &SymMat3 {
        &self.inverse_gram
    }

    /// The set of tiles it was built for (bit `i` set: tile `i` contributes).
    pub fn tiles(&self) -> u32 {
        self.tiles
    }
}

/// Bit `i` set for each tile `i` (< 32) that contributes, or `None` if a contributing tile has
/// an index ≥ 32 (no cache: the one-shot function is used).
fn contributing(tiles: &[Tile], readings: Readings) -> Option<u32> {
    let mut mask = 0u32;
    for (i, tile) in tiles.iter().enumerate().take(readings.len()) {
        if readings.get(i, tile).is_some() {
            mask |= 1u32.checked_shl(u32::try_from(i).ok()?)?;
        }
    }
    Some(mask)
}

/// [`contributing`] for at most 32 readings (every index fits the mask).
fn contributing_32(tiles: &[Tile], readings: Readings) -> u32 {
    let mut mask = 0u32;
    for (i, tile) in tiles.iter().enumerate().take(readings.len()) {
        if readings.get(i, tile).is_some() {
            mask |= 1u32.wrapping_shl(i as u32);
        }
    }
    mask
}

/// The solution with the operator kept in `cache`, rebuilt when the set of contributing tiles
/// changes (left `None` when that set is not observable). Inlined into the public functions:
/// where the caller's readings are a short array (the flight loop), the compiler sees that
/// there are at most 32 and drops the one-shot fallback; the rest is one shared copy.
#[inline(always)]
pub(crate) fn solve_cached(
    cache: &mut Option<TileSolver>,
    tiles: &[Tile],
    readings: Readings,
) -> Result<Vec3, DeterminationError> {
    let mask = if 32 >= readings.len() {
        Some(contributing_32(tiles, readings))
    } else {
        contributing(tiles, readings)
    };
    match mask {
        Some(mask) => solve_masked(cache, tiles, readings, mask),
        None => solve(tiles, readings),
    }
}

/// [`solve_cached`] for the set of tiles `mask`.
#[cfg_attr(target_arch = "msp430", inline(never))]
fn solve_masked(
    cache: &mut Option<TileSolver>,
    tiles: &[Tile],
    readings: Readings,
    mask: u32,
) -> Result<Vec3, DeterminationError> {
    // On a change of the set, the Gram matrix HᵀH of the contributing rows is accumulated in
    // the same walk as Hᵀy; the walk's own errors come first. The cached operator is used in
    // place (on the MSP430 each copy of it is a `memcpy`).
    let cached = matches!(cache, Some(s) if s.tiles == mask);
    let mut gram = SymMat3::zeros();
    let mut rhs = Vec3::zeros(); // Hᵀy
    for_each_reading(tiles, readings, |tile, reading| {
        rhs += reading.transposed(tile);
        if !cached {
            reading.add_rows(tile, &mut gram);
        }
        Ok(())
    })?;
    if !cached {
        *cache = None;
        // (HᵀH)⁻¹ in closed form, rank 3 required (out of range: a tile's rows overflow)
        let p = symmetric_pseudoinverse(&gram, GRAM_REL_TOL)
            .map_err(|_| DeterminationError::Linalg(SvdError::NonFinite))?;
        if 3 > p.rank {
            return Err(DeterminationError::NotObservable { rank: p.rank });
        }
        *cache = Some(TileSolver {
            inverse_gram: p.pinv,
            tiles: mask,
        });
    }
    match cache {
        Some(s) => Ok(s.inverse_gram.mul_vec(&rhs)),
        // not reached: the operator was there or has just been built
        None => Err(DeterminationError::NotObservable { rank: 0 }),
    }
}

/// [`magnetic_field_body`] with the operator kept in `cache` (rebuilt when the set of
/// contributing tiles changes; left `None` when that set is not observable).
pub fn magnetic_field_body_cached(
    cache: &mut Option<TileSolver>,
    tiles: &[Tile],
    readings: &[Option<Vec2>],
) -> Result<Vec3, DeterminationError> {
    solve_cached(cache, tiles, Readings::Field(readings))
}

/// [`angular_rate_body`] with the operator kept in `cache` (rebuilt when the set of
/// contributing tiles changes; left `None` when that set is not observable).
pub fn angular_rate_body_cached(
    cache: &mut Option<TileSolver>,
    tiles: &[Tile],
    readings: &[Option<f32>],
) -> Result<Vec3, DeterminationError> {
    solve_cached(cache, tiles, Readings::Rate(readings))
}
