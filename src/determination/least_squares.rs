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
//! measured relative difference from the one-shot functions ≤ 4.0e-7 (field) and 4.6e-7 (rate)
//! on all presets
//! (`cargo test --test determination cached -- --nocapture`).
//!
//! Units: whatever the readings are in (nT for [`crate::tiles::RawMagnetometer::to_nt`];
//! the thesis used 10 nT), rad/s for the rates.

use nalgebra::SVector;

use super::DeterminationError;
use crate::linalg::lsq::QrLeastSquares;
use crate::linalg::{SymMat3, Vec2, Vec3};
use crate::tiles::Tile;

/// Relative threshold on the singular values (see the module docs).
pub const RANK_REL_TOL: f32 = 1.0e-5;

fn check_lengths(tiles: usize, readings: usize) -> Result<(), DeterminationError> {
    if tiles == readings {
        Ok(())
    } else {
        Err(DeterminationError::LengthMismatch { tiles, readings })
    }
}

/// The body-frame magnetic field `B_uvw = 𝐁⁺·Φ` (eq. 8.16) from the tiles whose reading is
/// `Some((B_x, B_y))` (tile-frame components) and whose magnetometer is working. `readings`
/// has one entry per tile.
pub fn magnetic_field_body(
    tiles: &[Tile],
    readings: &[Option<Vec2>],
) -> Result<Vec3, DeterminationError> {
    check_lengths(tiles.len(), readings.len())?;
    let mut ls = QrLeastSquares::<1>::new();
    for (index, (tile, reading)) in tiles.iter().zip(readings.iter()).enumerate() {
        let Some(b_tile) = reading else { continue };
        if !tile.has_working_magnetometer() {
            continue;
        }
        if !(b_tile.x.is_finite() && b_tile.y.is_finite()) {
            return Err(DeterminationError::NonFinite { index });
        }
        ls.push(&tile.x_body(), &SVector::<f32, 1>::new(b_tile.x))?;
        ls.push(&tile.y_body(), &SVector::<f32, 1>::new(b_tile.y))?;
    }
    if ls.rows() == 0 {
        return Err(DeterminationError::NotObservable { rank: 0 });
    }
    let x = ls.solve_full_rank(RANK_REL_TOL)?;
    Ok(x.column(0).into_owned())
}

/// The body-frame angular rate `ω_uvw = Z⁺·Ω` (eq. 8.25) from the tiles whose reading is
/// `Some(ω_z)` (rad/s about the tile normal) and whose gyro is working. `readings` has one
/// entry per tile.
pub fn angular_rate_body(
    tiles: &[Tile],
    readings: &[Option<f32>],
) -> Result<Vec3, DeterminationError> {
    check_lengths(tiles.len(), readings.len())?;
    let mut ls = QrLeastSquares::<1>::new();
    for (index, (tile, reading)) in tiles.iter().zip(readings.iter()).enumerate() {
        let Some(omega_z) = reading else { continue };
        if !tile.has_working_gyro() {
            continue;
        }
        if !omega_z.is_finite() {
            return Err(DeterminationError::NonFinite { index });
        }
        ls.push(&tile.normal_body(), &SVector::<f32, 1>::new(*omega_z))?;
    }
    if ls.rows() == 0 {
        return Err(DeterminationError::NotObservable { rank: 0 });
    }
    let x = ls.solve_full_rank(RANK_REL_TOL)?;
    Ok(x.column(0).into_owned())
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
fn contributing<T>(
    tiles: &[Tile],
    readings: &[Option<T>],
    works: impl Fn(&Tile) -> bool,
) -> Option<u32> {
    let mut mask = 0u32;
    for (i, (tile, reading)) in tiles.iter().zip(readings.iter()).enumerate() {
        if reading.is_some() && works(tile) {
            mask |= 1u32.checked_shl(u32::try_from(i).ok()?)?;
        }
    }
    Some(mask)
}

impl TileSolver {
    /// The solver of the magnetometers of the tiles in `mask` (bit i: tile i).
    fn magnetometers(tiles: &[Tile], mask: u32) -> Result<Self, DeterminationError> {
        let mut ls = QrLeastSquares::<1>::new();
        for (i, tile) in tiles.iter().enumerate().take(32) {
            if mask & (1 << i) != 0 {
                ls.push(&tile.x_body(), &SVector::<f32, 1>::zeros())?;
                ls.push(&tile.y_body(), &SVector::<f32, 1>::zeros())?;
            }
        }
        Self::finish(&ls, mask)
    }

    /// The solver of the gyros of the tiles in `mask` (bit i: tile i).
    fn gyros(tiles: &[Tile], mask: u32) -> Result<Self, DeterminationError> {
        let mut ls = QrLeastSquares::<1>::new();
        for (i, tile) in tiles.iter().enumerate().take(32) {
            if mask & (1 << i) != 0 {
                ls.push(&tile.normal_body(), &SVector::<f32, 1>::zeros())?;
            }
        }
        Self::finish(&ls, mask)
    }

    fn finish(ls: &QrLeastSquares<1>, tiles: u32) -> Result<Self, DeterminationError> {
        if ls.rows() == 0 {
            return Err(DeterminationError::NotObservable { rank: 0 });
        }
        Ok(Self {
            inverse_gram: SymMat3::from_upper(&ls.inverse_gram(RANK_REL_TOL)?),
            tiles,
        })
    }
}

/// [`magnetic_field_body`] with the operator kept in `cache` (rebuilt when the set of
/// contributing tiles changes; left `None` when that set is not observable).
pub fn magnetic_field_body_cached(
    cache: &mut Option<TileSolver>,
    tiles: &[Tile],
    readings: &[Option<Vec2>],
) -> Result<Vec3, DeterminationError> {
    check_lengths(tiles.len(), readings.len())?;
    let Some(mask) = contributing(tiles, readings, Tile::has_working_magnetometer) else {
        return magnetic_field_body(tiles, readings);
    };
    let mut rhs = Vec3::zeros(); // 𝐁ᵀΦ
    for (index, (tile, reading)) in tiles.iter().zip(readings.iter()).enumerate() {
        let Some(b_tile) = reading else { continue };
        if !tile.has_working_magnetometer() {
            continue;
        }
        if !(b_tile.x.is_finite() && b_tile.y.is_finite()) {
            return Err(DeterminationError::NonFinite { index });
        }
        rhs += tile.x_body() * b_tile.x + tile.y_body() * b_tile.y;
    }
    let solver = cached(cache, mask, || TileSolver::magnetometers(tiles, mask))?;
    Ok(solver.inverse_gram.mul_vec(&rhs))
}

/// [`angular_rate_body`] with the operator kept in `cache` (rebuilt when the set of
/// contributing tiles changes; left `None` when that set is not observable).
pub fn angular_rate_body_cached(
    cache: &mut Option<TileSolver>,
    tiles: &[Tile],
    readings: &[Option<f32>],
) -> Result<Vec3, DeterminationError> {
    check_lengths(tiles.len(), readings.len())?;
    let Some(mask) = contributing(tiles, readings, Tile::has_working_gyro) else {
        return angular_rate_body(tiles, readings);
    };
    let mut rhs = Vec3::zeros(); // ZᵀΩ
    for (index, (tile, reading)) in tiles.iter().zip(readings.iter()).enumerate() {
        let Some(omega_z) = reading else { continue };
        if !tile.has_working_gyro() {
            continue;
        }
        if !omega_z.is_finite() {
            return Err(DeterminationError::NonFinite { index });
        }
        rhs += tile.normal_body() * *omega_z;
    }
    let solver = cached(cache, mask, || TileSolver::gyros(tiles, mask))?;
    Ok(solver.inverse_gram.mul_vec(&rhs))
}

/// The cached solver if it is for `mask`, else a new one from `build` (stored on success).
fn cached(
    cache: &mut Option<TileSolver>,
    mask: u32,
    build: impl FnOnce() -> Result<TileSolver, DeterminationError>,
) -> Result<TileSolver, DeterminationError> {
    match cache {
        Some(s) if s.tiles == mask => Ok(*s),
        _ => {
            *cache = None;
            let s = build()?;
            *cache = Some(s);
            Ok(s)
        }
    }
}
