//! `acs demo`: the seed 000 chapter-12 scenario end to end on simulated tiles, our numbers
//! beside the thesis's (read from `data/thesis_ch12.txt`, copied from note 000 §4).

use std::collections::HashMap;

use super::CliError;
use crate::attitude::{Dcm, Euler321};
use crate::control::slew::{decompose, manoeuvre_matrix, Branch};
use crate::determination::least_squares::magnetic_field_body;
use crate::determination::sun_sensor::sun_direction_body;
use crate::determination::{quest, Observation};
use crate::env::igrf::{Degree, Igrf, FULL};
use crate::env::sun::{precise, schlyter};
use crate::hal::TileBus;
use crate::host::sim::realistic::TruthLevel;
use crate::host::sim::scenarios::{self, DTUSAT_TLE};
use crate::host::sim::{angle_between_deg, Simulator};
use crate::linalg::{Mat3, Vec3};
use crate::orbit::sgp4::{Gravity, Sgp4};
use crate::tiles::{RawMagnetometer, RawSunAngles};
use crate::time::gmst_rad;

/// Arguments of `acs demo` (none).
#[derive(clap::Args, Debug)]
pub struct Args {}

fn thesis_numbers() -> HashMap<String, Vec<f64>> {
    include_str!("../../../data/thesis_ch12.txt")
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .filter_map(|l| {
            let (k, v) = l.split_once('=')?;
            let nums = v
                .split_whitespace()
                .filter_map(|x| x.parse::<f64>().ok())
                .collect();
            Some((k.trim().to_string(), nums))
        })
        .collect()
}

fn v3(v: &Vec3) -> String {
    format!("({:.6}, {:.6}, {:.6})", v.x, v.y, v.z)
}

fn compute(e: impl std::fmt::Display) -> CliError {
    CliError::Compute(e.to_string())
}

/// Runs `acs demo`.
pub fn run(_args: &Args) -> Result<(), CliError> {
    let th = thesis_numbers();
    let get = |k: &str| th.get(k).cloned().unwrap_or_default();
    println!("acs demo — AraMiS ACS thesis, chapter 12, end to end on simulated tiles");
    println!("(thesis values: Bonjean, AraMiS ACS thesis, 2010, ch. 12; copied in data/thesis_ch12.txt)\n");

    // 1. orbit
    let tle = crate::tle::Tle::parse(DTUSAT_TLE.0, DTUSAT_TLE.1).map_err(compute)?;
    let sc = scenarios::thesis_slew(false)
        .map_err(compute)?
        .with_truth(TruthLevel::Ideal);
    let now = sc.sim.start;
    let orbit = Sgp4::new(&tle, Gravity::Wgs84).map_err(|e| compute(format!("{e:?}")))?;
    let bug = orbit
        .propagate_split(1080.0, 0.0)
        .map_err(|e| compute(format!("{e:?}")))?;
    let span = now.span_since(&tle.epoch);
    let state = orbit
        .propagate(span)
        .map_err(|e| compute(format!("{e:?}")))?;
    let r_th = get("r_km");
    println!(
        "1. Orbit (SGP4, WGS-84, DTUSAT TLE epoch {})",
        super::iso_utc_ms(&tle.epoch)
    );
    if let [x, y, z] = r_th[..] {
        let d = (bug.r_teme_km - Vec3::new(x as f32, y as f32, z as f32)).norm();
        println!("   thesis r at 'tsince 1080 min' (its f32 Julian-date bug): ({x:.3}, {y:.3}, {z:.3}) km");
        println!(
            "   ours at 1080 min:                                     {} km  (|Δ| = {:.1} m)",
            v3(&bug.r_teme_km),
            d * 1e3
        );
    }
    let (w, f) = span.split_minutes();
    println!(
        "   the true time since epoch is {:.3} min (thesis note: {:?}): r = {} km",
        w + f,
        get("tsince_true_min"),
        v3(&state.r_teme_km)
    );

    // 2. Sun
    let sun_t = schlyter::sun(&now).map_err(|e| compute(format!("{e:?}")))?;
    let (ra, dec) = sun_t.right_ascension_declination();
    let sun_p = precise::sun(&now).map_err(|e| compute(format!("{e:?}")))?;
    println!("\n2. Sun at {}", super::iso_utc_ms(&now));
    println!(
        "   thesis model (Schlyter): RA {:.6}°, Dec {:.6}°   thesis printed: {:?}",
        ra.to_degrees(),
        dec.to_degrees(),
        get("sun_ra_dec_deg")
    );
    let (a, b) = (sun_p.direction.normalize(), sun_t.direction.normalize());
    let sep = a.cross(&b).norm().atan2(a.dot(&b)).to_degrees() * 3600.0;
    println!(
        "   precise model (TEME, apparent): {}  ({:.0}″ from the thesis model)",
        v3(&sun_p.direction),
        sep
    );

    // 3. field
    let ut1 = now.to_ut1(None).map_err(compute)?;
    let igrf = Igrf::at_epoch(&FULL, &now, Degree::FULL).map_err(|e| compute(format!("{e:?}")))?;
    let b_true = igrf
        .teme(&state.r_teme_km, gmst_rad(&ut1))
        .map_err(|e| compute(format!("{e:?}")))?;
    let b_1080 = igrf
        .teme(&bug.r_teme_km, gmst_rad(&ut1))
        .map_err(|e| compute(format!("{e:?}")))?;
    println!("\n3. Geomagnetic field (IGRF-14, degree 13, TEME)");
    println!("   thesis printed B_ijk: {:?} (unphysical: radians fed as degrees, GMST = 0, note 000 §0.5)", get("b_ijk"));
    println!(
        "   ours at the thesis's position (1080 min): {} nT   (note's correct value: {:?})",
        v3(&b_1080),
        get("b_ijk_correct")
    );
    println!(
        "   ours at the true position:                {} nT",
        v3(&b_true)
    );

    // 4. determination from simulated tiles (ideal sensors)
    let mut sim = Simulator::new(sc.sim.clone(), sc.initial.0, sc.initial.1).map_err(compute)?;
    let tiles = sc.flight.config().tiles.clone();
    let mut sun_readings = Vec::new();
    let mut mag_readings = Vec::new();
    for i in 0..tiles.len() {
        let has = tiles.get(i).map(|t| t.equipment);
        let sun = if has.is_some_and(|e| e.sun_sensor) {
            sim.read_sun(i).ok().flatten()
        } else {
            None
        };
        let mag = if has.is_some_and(|e| e.magnetometer) {
            sim.read_magnetometer(i).ok()
        } else {
            None
        };
        sun_readings.push(sun.map(|[a, b]| RawSunAngles { a, b }.to_rad()));
        mag_readings.push(mag.map(|[x, y]| RawMagnetometer { x, y }.to_nt()));
    }
    let s_body = sun_direction_body(&tiles, &sun_readings).map_err(compute)?;
    let b_body = magnetic_field_body(&tiles, &mag_readings).map_err(compute)?;
    let b_ref = sim.env().b_teme_nt.cast::<f32>();
    let s_ref = sim.env().sun_teme.cast::<f32>();
    let sol = quest::solve(&[
        Observation {
            body: s_body,
            reference: s_ref,
            weight: 1.0,
        },
        Observation {
            body: b_body,
            reference: b_ref,
            weight: 1.0,
        },
    ])
    .map_err(compute)?;
    let lit = sun_readings.iter().filter(|r| r.is_some()).count();
    println!("\n4. Attitude determination (ideal tiles: int16 quantisation only; {lit} lit tiles, 5 magnetometers)");
    println!("   true A: 3-2-1 (Φ, θ, Ψ) = (0°, −30°, −45°); QUEST from Sun + field: error {:.4}° (thesis Test 1: A_eo ≈ I to 1e-7, its unphysical Sun model)", angle_between_deg(&sc.initial.0, &sol.quaternion));
    let e = sol.dcm.to_euler_321();
    println!(
        "   determined 3-2-1: ({:.4}°, {:.4}°, {:.4}°)",
        e.phi_rad.to_degrees(),
        e.theta_rad.to_degrees(),
        e.psi_rad.to_degrees()
    );

    // 5. slew plan
    let axes = sc.flight.config().axes;
    let a_d = Dcm::from_matrix_unchecked(Mat3::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0));
    let a_true = Dcm::from_euler_321(&Euler321 {
        phi_rad: 0.0,
        theta_rad: (-30f32).to_radians(),
        psi_rad: (-45f32).to_radians(),
    });
    let m = manoeuvre_matrix(&a_true, &a_d, &axes);
    let th_br = decompose(&m, Branch::Thesis).map_err(compute)?;
    let short = decompose(&m, Branch::Shortest).map_err(compute)?;
    println!("\n5. Slew planning (A → A_d = 90° about I, principal axes by Jacobi)");
    println!(
        "   thesis branch [Φ_A, θ_B, Ψ_C] = [{:.7}, {:.7}, {:.7}] rad, total {:.1}°   thesis: {:?}",
        th_br.phi_a,
        th_br.theta_b,
        th_br.psi_c,
        th_br.total_rad().to_degrees(),
        get("test1_angle")
    );
    println!(
        "   shortest branch               = [{:.7}, {:.7}, {:.7}] rad, total {:.1}°",
        short.phi_a,
        short.theta_b,
        short.psi_c,
        short.total_rad().to_degrees()
    );

    // 6. simulated slew, closed by tracking
    println!(
        "\n6. Simulated slew (RK4 rigid body + wheels, f64 truth; the plan flown in closed loop, then tracking)"
    );
    for (noisy, key) in [
        (false, "simulink_error_ideal_deg"),
        (true, "simulink_error_noisy_deg"),
    ] {
        let sc = scenarios::thesis_slew(noisy)
            .map_err(compute)?
            .with_truth(TruthLevel::Ideal);
        let samples = sc.run().map_err(compute)?;
        let end = samples
            .windows(2)
            .find(|w| {
                w[0].mode == crate::acs_loop::Mode::Slew
                    && w[1].mode == crate::acs_loop::Mode::Tracking
            })
            .and_then(|w| w[1].pointing_error_deg);
        let last = samples.last().and_then(|s| s.pointing_error_deg);
        println!(
            "   {}: error at the end of the plan {:.4}°, after {:.0} s of tracking {:.4}°   thesis (Simulink): {:?}°",
            if noisy { "1 % sensor noise" } else { "ideal sensors   " },
            end.unwrap_or(f64::NAN),
            sc.duration_s,
            last.unwrap_or(f64::NAN),
            get(key)
        );
    }
    println!("\nMore scenarios: `acs sim detumble|thesis-slew|thesis-slew-noisy|sun-safe|tracking|failed-tile|slew|tracking-eclipse --out DIR`.");
    Ok(())
}
