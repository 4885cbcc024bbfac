//! The Sun direction in the body frame from the lit tiles' Sun sensors (note 000 §7 item 1, the
//! physically correct model; the `Tile` class's angle convention, seed 000 §6.2).
//!
//! For each working, lit tile m with sensor angles (a, b) (rad, [`crate::tiles`]):
//! ```text
//! ŝ_xyz = (sin b, cos b·sin a, cos b·cos a)        (tile frame)
//! ŝ_uvw = A_mᵀ · ŝ_xyz                              (body frame)
//! ```
//! Every sensor sees the same single direction, so the body vectors are averaged (sum, then
//! normalise) into **one** observation, to be paired with the Sun model's reference direction.
//! A Sun direction alone never gives a full attitude: pair it with the magnetic field.
//!
//! Accuracy: exact up to f32 rounding (≈1e-7 rad) for consistent sensors; with independent
//! sensor noise the average reduces it by about √n.

use super::DeterminationError;
use crate::linalg::{div, dot, lin3, norm, Vec3};
use crate::tiles::{sun_direction_tile, SunAngles, Tile};

/// The unit Sun direction in the body frame, averaged over the tiles whose reading is
/// `Some(angles)` (lit) and whose Sun sensor is working. `readings` has one entry per tile
/// (`None` = not lit or no reading).
pub fn sun_direction_body(
    tiles: &[Tile],
    readings: &[Option<SunAngles>],
) -> Result<Vec3, DeterminationError> {
    if tiles.len() != readings.len() {
        return Err(DeterminationError::LengthMismatch {
            tiles: tiles.len(),
            readings: readings.len(),
        });
    }
    let mut sum = Vec3::zeros();
    let mut lit = 0usize;
    for (index, (tile, reading)) in tiles.iter().zip(readings.iter()).enumerate() {
        let Some(angles) = reading else { continue };
        if !tile.has_working_sun_sensor() {
            continue;
        }
        if !(angles.a_rad.is_finite() && angles.b_rad.is_finite()) {
            return Err(DeterminationError::NonFinite { index });
        }
        // A_mᵀ·ŝ_xyz (`Tile::tile_to_body`), its columns being the tile axes in the body frame.
        let s = sun_direction_tile(angles);
        sum += lin3(
            &tile.x_body(),
            &tile.y_body(),
            &tile.normal_body(),
            s.x,
            s.y,
            s.z,
        );
        lit += 1;
    }
    let n = norm(&sum);
    if lit == 0 || !(n > 0.0) {
        return Err(DeterminationError::NoSunSensorLit);
    }
    Ok(div(&sum, n))
}

/// `(Σ 1/cos²θᵢ, n)` over the `n` lit, working sensors that [`sun_direction_body`] averages,
/// `θᵢ` each one's incidence (`cos θᵢ = n̂ᵢ · ŝ`, the tile's normal and the averaged direction
/// `sun_body`): the inputs of the filter's Sun variance
/// ([`super::mekf::sun_variance_rad2`]; a sensor's noise grows as `1/cos θ`). A sensor at or
/// beyond grazing incidence counts as 1/cos²θ = 100 (84°).
pub fn incidence_inv_cos2(
    tiles: &[Tile],
    readings: &[Option<SunAngles>],
    sun_body: &Vec3,
) -> (f32, u8) {
    let mut sum = 0.0f32;
    let mut lit = 0u8;
    for (tile, reading) in tiles.iter().zip(readings.iter()) {
        if reading.is_none() || !tile.has_working_sun_sensor() {
            continue;
        }
        let c = dot(&tile.normal_body(), sun_body);
        sum += if c * c > 0.01 { 1.0 / (c * c) } else { 100.0 };
        lit = lit.saturating_add(1);
    }
    (sum, lit)
}
