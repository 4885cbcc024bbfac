//! Propagates a TLE and gives the Sun and the geomagnetic field in the body frame for a given
//! attitude: the environment half of the ACS loop, on the host.
//!
//! `cargo run --example propagate [-- MINUTES]`: one row per `MINUTES` (default 10) over one
//! orbit. The orbit (`common::TLE`) is sun-synchronous with its ascending node at 18 h local
//! time, a dawn-dusk orbit: in March it never enters the Earth's shadow, and with the attitude
//! fixed in TEME the Sun barely moves in the body while the field turns about twice per orbit.
//!
//! Conventions (`acs::attitude`): the reference frame is TEME of date (SGP4's); the attitude
//! DCM `A` maps the reference frame to the body, `v_body = A · v_ref`; quaternions are
//! scalar-first, `q = (q0, q1, q2, q3)` with `q0 = cos(Φ/2)`, and `A(q)` is Shuster's passive
//! matrix.

mod common;

use acs::attitude::{Dcm, Euler321, Quaternion};
use acs::env::eclipse::Shadow;
use acs::time::TimeSpan;

fn main() {
    let step_min: i32 = std::env::args()
        .nth(1)
        .map(|s| s.parse().expect("MINUTES: a whole number"))
        .unwrap_or(10);
    let (tle, orbit) = common::orbit();

    // The attitude: a 3-2-1 rotation from TEME (yaw 30°, pitch −20°, roll 45°); the same as a
    // scalar-first quaternion.
    let a = Dcm::from_euler_321(&Euler321 {
        psi_rad: 30f32.to_radians(),
        theta_rad: (-20f32).to_radians(),
        phi_rad: 45f32.to_radians(),
    });
    let q: Quaternion = a.to_quaternion();
    println!(
        "TLE epoch {} UTC, attitude q = ({:.5}, {:.5}, {:.5}, {:.5}) (TEME → body, scalar first)",
        common::utc(&tle.epoch),
        q.q0,
        q.q1,
        q.q2,
        q.q3
    );
    println!(
        "{:>5} {:>9} {:>7}  {:>26}  {:>32}  {:>8}",
        "min", "h km", "shadow", "Sun in body (unit)", "field in body, nT", "|B| nT"
    );
    let period_min = (1440.0 / tle.mean_motion_rev_per_day).ceil() as i32;
    for minutes in (0..=period_min).step_by(step_min.max(1) as usize) {
        let now = tle.epoch.add(TimeSpan::new(60 * minutes, 0));
        let sky = common::sky(&orbit, &now);
        // v_body = A · v_ref
        let sun_body = a.to_body(&sky.sun_teme);
        let b_body = a.to_body(&sky.b_teme_nt);
        let shadow = match sky.illumination.shadow {
            Shadow::Sunlit => "sunlit",
            Shadow::Penumbra => "penumbra",
            Shadow::Umbra => "umbra",
            Shadow::Antumbra => "antumbra",
        };
        println!(
            "{minutes:>5} {:>9.1} {shadow:>7}  ({:>7.4}, {:>7.4}, {:>7.4})  ({:>9.0}, {:>9.0}, {:>9.0})  {:>8.0}",
            // height above the equatorial radius (WGS-72), not the geodetic altitude
            sky.r_teme_km.norm() - 6378.135,
            sun_body.x,
            sun_body.y,
            sun_body.z,
            b_body.x,
            b_body.y,
            b_body.z,
            b_body.norm()
        );
    }
}
