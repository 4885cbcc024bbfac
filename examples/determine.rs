//! Determines an attitude from raw tile readings: the determination half of the ACS loop
//! (`acs::acs_loop`, step phase 4), on the host, through the library's determination API.
//!
//! `cargo run --example determine`
//!
//! The raw words are those of the thesis's cube (`acs::tiles::cube_thesis`: tile 0 a telecom
//! tile without devices, tiles 1–5 power tiles) in the HAL's formats (`acs::hal`, "Raw
//! formats"): Sun angles in 1e-4 rad, magnetometer in 10 nT, gyro in 1e-4 rad/s. Here they
//! come from a stand-in (`common::raw_words`) for a known attitude, so the result can be
//! checked; on a board they come from the tiles' drivers.
//!
//! Conventions (`acs::attitude`): the DCM `A` maps the reference frame TEME of date to the
//! body, `v_body = A · v_ref`; quaternions are scalar-first.

mod common;

use acs::attitude::Quaternion;
use acs::determination::least_squares::{angular_rate_body, magnetic_field_body};
use acs::determination::sun_sensor::sun_direction_body;
use acs::determination::{wahba_svd, Observation};
use acs::flight::{FIELD_WEIGHT, SUN_WEIGHT};
use acs::linalg::Vec3;
use acs::tiles::{cube_thesis, RawGyro, RawMagnetometer, RawSunAngles};
use acs::time::TimeSpan;

fn main() {
    let tiles = cube_thesis();
    let (tle, orbit) = common::orbit();
    let now = tle.epoch.add(TimeSpan::new(600, 0));
    let sky = common::sky(&orbit, &now);

    // The stand-in's truth: an attitude and a slow rotation.
    let truth = Quaternion::new_normalize(0.8, 0.3, -0.4, 0.33).expect("non-zero");
    let omega_true = Vec3::new(0.002, -0.001, 0.0005);
    let raw = common::raw_words(&tiles, &truth, &omega_true, &sky);

    println!("raw words at {} UTC:", common::utc(&now));
    println!(
        "{:>4} {:>16} {:>16} {:>6}",
        "tile", "sun (a, b)", "mag (x, y)", "gyro"
    );
    for (i, tile) in tiles.iter().enumerate() {
        if !tile.equipment.magnetometer {
            println!("{i:>4} (no ACS device)");
            continue;
        }
        let sun = raw.sun[i].map_or("dark".to_string(), |[a, b]| format!("({a}, {b})"));
        let [x, y] = raw.mag[i];
        println!(
            "{i:>4} {sun:>16} {:>16} {:>6}",
            format!("({x}, {y})"),
            raw.gyro[i]
        );
    }

    // 1. Raw words to physical units in the tile frames (acs::tiles), one entry per tile
    //    (`None`: no reading; a tile without the device is skipped by the solvers).
    let sun: Vec<_> = raw
        .sun
        .iter()
        .map(|w| w.map(|[a, b]| RawSunAngles { a, b }.to_rad()))
        .collect();
    let mag: Vec<_> = raw
        .mag
        .iter()
        .map(|&[x, y]| Some(RawMagnetometer { x, y }.to_nt()))
        .collect();
    let gyro: Vec<_> = raw
        .gyro
        .iter()
        .map(|&w| Some(RawGyro(w).to_radps()))
        .collect();

    // 2. Body vectors from the tiles: the Sun averaged over the lit sensors, the field and the
    //    rate by least squares over the tiles' axes.
    let sun_body = sun_direction_body(&tiles, &sun).expect("a lit tile");
    let b_body_nt = magnetic_field_body(&tiles, &mag).expect("field determinable");
    let omega_body = angular_rate_body(&tiles, &gyro).expect("rate determinable");

    // 3. The same two directions in the reference frame, from the models (the loop's phase 2),
    //    and Wahba's problem by SVD, weighted as the flight configuration weights them.
    let observations = [
        Observation {
            body: sun_body,
            reference: sky.sun_teme,
            weight: SUN_WEIGHT,
        },
        Observation {
            body: b_body_nt,
            reference: sky.b_teme_nt,
            weight: FIELD_WEIGHT,
        },
    ];
    let solution = wahba_svd::solve(&observations).expect("Sun and field not parallel");
    let q = solution.quaternion;

    println!();
    println!(
        "Sun in body      ({:.5}, {:.5}, {:.5})",
        sun_body.x, sun_body.y, sun_body.z
    );
    println!(
        "field in body    ({:.0}, {:.0}, {:.0}) nT",
        b_body_nt.x, b_body_nt.y, b_body_nt.z
    );
    println!(
        "rate in body     ({:.5}, {:.5}, {:.5}) rad/s (stand-in: {:.5}, {:.5}, {:.5})",
        omega_body.x, omega_body.y, omega_body.z, omega_true.x, omega_true.y, omega_true.z
    );
    println!(
        "attitude         q = ({:.5}, {:.5}, {:.5}, {:.5}) (TEME → body, scalar first)",
        q.q0, q.q1, q.q2, q.q3
    );
    let t = truth.canonical();
    println!(
        "stand-in's truth q = ({:.5}, {:.5}, {:.5}, {:.5}): {:.4}° apart (the words' rounding)",
        t.q0,
        t.q1,
        t.q2,
        t.q3,
        common::angle_deg(&q, &truth)
    );
}
