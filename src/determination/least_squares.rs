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
//! # Numerics
//! The rows are folded one by one into a Givens QR ([`crate::linalg::lsq`], constant memory
//! whatever the number of tiles, error ∝ ε·κ), and the 3×3 factor is inverted by SVD with the
//! relative threshold [`RANK_REL_TOL`] on its singular values (seed 000 eqs. 8.17–8.18; the
//! thesis suggests "about 1e-6·σ_max", which is within 10 f32 ulps of the rounding floor of
//! a rank-deficient 12-row matrix; 1e-5 keeps a margin). Rank < 3 is
//! [`DeterminationError::NotObservable`]: the working tiles do not span the space.
//! For the presets of [`crate::tiles`] with every tile working, the condition number of the
//! stacked matrix is 1.0 (cube with 4 tiles per face), 1.10 / 1.22 (hexagonal prism, magnetometers
//! / gyros), 1.15 / 1.41 (the thesis cube's tiles 1–5 and the octagonal prism), so the f32
//! result is within a few ulps of the exact least-squares solution (measured: relative error
//! ≤ 3e-7 on all presets, `cargo test --test determination least_squares -- --nocapture`).
//!
//! # Cached operator (the flight loop)
//! The rows depend only on the tile geometry and on which tiles give a reading, which changes
//! only when a device fails or comes back. [`TileSolver`] keeps `(𝐁ᵀ𝐁)⁻¹` (by the same QR and
//! SVD, so the same rank decision) for one such set; a step is then `B = (𝐁ᵀ𝐁)⁻¹·𝐁ᵀΦ`, two rows
//! of dot products per tile. Its rounding grows with κ² instead of κ (κ ≤ 1.41 for the presets):
//! measured relative difference from the one-shot functions ≤ 2.7e-7 (field) and 2.8e-7 (rate)
//! on all presets (`cargo test --test determination least_squares -- --nocapture`).
//!
//! Units: whatever the readings are in (nT for [`crate::tiles::RawMagnetometer::to_nt`];
//! the thesis used 10 nT), rad/s for the rates.

use nalgebra::SVector;

use super::DeterminationError;
use crate::linalg::lsq::QrLeastSquares;
use crate::linalg::svd::SvdError;
use crate::linalg::{lin2, scale, SymMat3, Vec2, Vec3};
use crate::tiles::Tile;

/// Relative threshold on the singular values (see the module docs).
pub const RANK_REL_TOL: f32 = 1.0e-5;

/// The readings of one kind of tile sensor, one entry per tile: the magnetometers' two
/// components (rows `x̂_m·B = φ_xm`, `ŷ_m·B = φ_ym`) or the gyros' one (`ẑ_m·ω = ω_zm`). One
/// (non-generic) copy of the solvers serves both.
#[derive(Copy, Clone)]
enum Readings<'a> {
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
fn solve_cached(
    cache: &mut Option<TileSolver>,
    tiles: &[Tile],
    readings: Readings,
) -> Result<Vec3, DeterminationError> {
    let mask = if readings.len() <= 32 {
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
    // On a change of the set, the rows are folded into the QR of the one-shot solution (values
    // ignored) in the same walk as Hᵀy; the walk's own errors come first, as when the
    // operator was built in a second walk.
    enum Operator {
        Cached(TileSolver),
        Rebuild(QrLeastSquares<1>, Result<(), SvdError>),
    }
    let mut operator = match cache {
        Some(s) if s.tiles == mask => Operator::Cached(*s),
        _ => Operator::Rebuild(QrLeastSquares::new(), Ok(())),
    };
    let mut rhs = Vec3::zeros(); // Hᵀy
    for_each_reading(tiles, readings, |tile, reading| {
        rhs += reading.transposed(tile);
        if let Operator::Rebuild(ls, status @ Ok(())) = &mut operator {
            *status = reading.push_rows(tile, ls, false);
        }
        Ok(())
    })?;
    let solver = match operator {
        Operator::Cached(s) => s,
        Operator::Rebuild(ls, status) => {
            *cache = None;
            status?;
            if ls.rows() == 0 {
                return Err(DeterminationError::NotObservable { rank: 0 });
            }
            let s = TileSolver {
                inverse_gram: SymMat3::from_upper(&ls.inverse_gram(RANK_REL_TOL)?),
                tiles: mask,
            };
            *cache = Some(s);
            s
        }
    };
    Ok(solver.inverse_gram.mul_vec(&rhs))
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
