//! What the examples share: the orbit they fly and a stand-in for the satellite's tiles (the raw
//! words each tile's sensors deliver for a given attitude and rate, exact up to the words'
//! rounding; the host simulator, `acs sim`, adds noise, biases, albedo and device faults).
//!
//! Attitudes follow `acs::attitude`: the DCM `A` maps the reference frame (TEME of date, SGP4's)
//! to the body, `v_body = A · v_ref`; quaternions are scalar-first (`q0` = cos(Φ/2)).

// each example uses part of this module
#![allow(dead_code)]

use acs::attitude::Quaternion;
use acs::env::eclipse::{conical, Illumination};
use acs::env::igrf::{Degree, Igrf, FULL};
use acs::env::sun::precise;
use acs::linalg::Vec3;
use acs::orbit::sgp4::{Gravity, Sgp4};
use acs::tiles::{sun_angles_of_direction, Tile, GYRO_LSB_RADPS, MAGNETOMETER_LSB_NT, SUN_LSB_RAD};
use acs::time::{gmst_rad, Epoch, Utc};
use acs::tle::Tle;

/// A sun-synchronous orbit at about 500 km (the element set of the crate's uplink and
/// closed-loop tests; epoch 2025-03-20 12:00 UTC, inside the flight field model's 2025–2035).
pub const TLE: [&str; 2] = [
    "1 90101U 25001A   25079.50000000  .00000000  00000-0  00000-0 0  9997",
    "2 90101  97.4000  90.0000 0001000   0.0000   0.0000 15.21936487    10",
];

/// The parsed element set and its SGP4 propagator (WGS-72, the constants TLEs are fitted with).
pub fn orbit() -> (Tle, Sgp4) {
    let tle = Tle::parse(TLE[0], TLE[1]).expect("valid TLE");
    let sgp4 = Sgp4::new(&tle, Gravity::Wgs72).expect("SGP4 initialises");
    (tle, sgp4)
}

/// The environment at one instant, in the reference frame (TEME of date).
pub struct Sky {
    /// Position, km.
    pub r_teme_km: Vec3,
    /// Unit vector to the Sun (the precise model, 2.2″ of JPL DE421).
    pub sun_teme: Vec3,
    /// Geomagnetic field at the satellite (IGRF-14 to degree 13), nT.
    pub b_teme_nt: Vec3,
    /// Visible fraction of the solar disc (conical shadow).
    pub illumination: Illumination,
}

/// The environment at `now` on `orbit`.
pub fn sky(orbit: &Sgp4, now: &Epoch<Utc>) -> Sky {
    let state = orbit
        .propagate(now.span_since(&orbit.epoch()))
        .expect("SGP4 propagates");
    let sun = precise::sun(now).expect("Sun model in range");
    // UT1 ≈ UTC (no DUT1 given): 0.9 s at most, 6e-5 rad of Earth rotation
    let gmst = gmst_rad(&now.to_ut1(None).expect("UT1"));
    let igrf = Igrf::at_epoch(&FULL, now, Degree::FULL).expect("IGRF date in range");
    let b_teme_nt = igrf.teme(&state.r_teme_km, gmst).expect("field");
    let illumination = conical(&state.r_teme_km, &sun).expect("shadow model");
    Sky {
        r_teme_km: state.r_teme_km,
        sun_teme: sun.direction,
        b_teme_nt,
        illumination,
    }
}

/// The raw words of every tile, in the HAL's formats (`acs::hal`, "Raw formats").
#[derive(Clone, Debug, Default)]
pub struct RawTiles {
    /// Sun-sensor angles `(a, b)` in 1e-4 rad; `None`: the sensor sees no Sun.
    pub sun: Vec<Option<[i16; 2]>>,
    /// Magnetometer, tile x and y, 10 nT.
    pub mag: Vec<[i16; 2]>,
    /// Gyro, about the tile normal, 1e-4 rad/s.
    pub gyro: Vec<i16>,
}

/// Half-angle of a tile Sun sensor's field of view, rad (60°).
pub const SUN_FOV_RAD: f32 = 60.0 * core::f32::consts::PI / 180.0;

/// `x / lsb` rounded to the nearest `i16` word.
fn word(x: f32, lsb: f32) -> i16 {
    (x / lsb).round().clamp(-32_767.0, 32_766.0) as i16
}

/// The words `tiles` deliver when the satellite has `attitude` (TEME → body) and body rate
/// `omega_body_radps` under `sky`: a tile's Sun sensor sees the Sun within [`SUN_FOV_RAD`] of
/// its normal and outside the umbra.
pub fn raw_words(
    tiles: &[Tile],
    attitude: &Quaternion,
    omega_body_radps: &Vec3,
    sky: &Sky,
) -> RawTiles {
    let a = attitude.to_dcm();
    let sun_body = a.to_body(&sky.sun_teme);
    let b_body = a.to_body(&sky.b_teme_nt);
    let lit = sky.illumination.fraction > 0.0;
    let mut raw = RawTiles::default();
    for tile in tiles {
        let s_tile = tile.body_to_tile.to_body(&sun_body);
        let seen = lit && s_tile.z > SUN_FOV_RAD.cos();
        raw.sun.push(seen.then(|| {
            let angles = sun_angles_of_direction(&s_tile);
            [
                word(angles.a_rad, SUN_LSB_RAD),
                word(angles.b_rad, SUN_LSB_RAD),
            ]
        }));
        let b_tile = tile.body_to_tile.to_body(&b_body);
        raw.mag.push([
            word(b_tile.x, MAGNETOMETER_LSB_NT),
            word(b_tile.y, MAGNETOMETER_LSB_NT),
        ]);
        raw.gyro.push(word(
            tile.normal_body().dot(omega_body_radps),
            GYRO_LSB_RADPS,
        ));
    }
    raw
}

/// The angle between two attitudes, degrees.
pub fn angle_deg(a: &Quaternion, b: &Quaternion) -> f32 {
    a.angle_to(b).to_degrees()
}

/// `YYYY-MM-DD hh:mm:ss` of a UTC epoch.
pub fn utc(epoch: &Epoch<Utc>) -> String {
    let c = epoch.to_calendar();
    format!(
        "{}-{:02}-{:02} {:02}:{:02}:{:02}",
        c.year, c.month, c.day, c.hour, c.minute, c.second
    )
}
