//! Flies a ground plan ([`crate::host::planner`]) **open loop** in the simulator and compares
//! the flown final error with the planner's prediction (issue 10: "the plan can be flown and the
//! flown error matches the planned one").
//!
//! The planner's own model (circular orbit, seed-001 dipole or IGRF) differs from the
//! simulator's (SGP4 orbit, IGRF truth), so a plan made there would not be expected to land
//! when flown here. [`plan_for`] therefore plans in the simulator's field: it samples the truth
//! field `b_teme_nt` along the simulator's orbit ([`Field::Sampled`], linear interpolation), and
//! [`fly`] drives the simulator with the planned dipole commands (coil `i` along body axis `i`,
//! per-axis limit), held over each step and taken at its midpoint, no feedback.
//!
//! Attitudes follow [`crate::attitude`] (scalar-first, `v_body = A(q) v_ref`, reference TEME).

use super::{angle_between_deg, SimConfig, Simulator};
use crate::attitude::{Dcm, Euler321, Quaternion};
use crate::hal::TileBus;
use crate::host::planner::{command, plan, Field, Outcome, Problem};
use crate::linalg::Vec3d;

/// The planned and flown final errors of one manoeuvre.
#[derive(Clone, Debug)]
pub struct Flight {
    /// The planner's prediction.
    pub planned: Outcome,
    /// Flown final attitude error against `q_end`, degrees.
    pub flown_attitude_error_deg: f64,
    /// Flown final rate magnitude, deg/s (rest-to-rest: the rate error).
    pub flown_rate_error_degps: f64,
    /// Planned interior knots.
    pub params: Vec<f64>,
}

/// The truth field (TEME, nT) every `step_s` from the start over `duration_s` (inclusive).
pub fn sample_field(
    config: &SimConfig,
    duration_s: f64,
    step_s: f64,
) -> Result<Vec<[f64; 3]>, String> {
    if !(step_s > 0.0 && duration_s > 0.0 && duration_s / step_s <= 1e6) {
        return Err(format!("sampling {duration_s} s every {step_s} s"));
    }
    let n = (duration_s / step_s).ceil() as usize;
    let mut sim = Simulator::new(config.clone(), [1.0, 0.0, 0.0, 0.0], Vec3d::zeros())
        .map_err(|e| e.to_string())?;
    let mut out = Vec::with_capacity(n + 1);
    for k in 0..=n {
        let b = sim.env().b_teme_nt;
        out.push([b.x, b.y, b.z]);
        if k < n {
            sim.advance(step_s).map_err(|e| e.to_string())?;
        }
    }
    Ok(out)
}

/// `pb` with its field replaced by the simulator's truth field sampled every `step_s`, and its
/// coil limit by the smallest of the simulator's three coils.
pub fn plan_for(config: &SimConfig, pb: &Problem, step_s: f64) -> Result<Problem, String> {
    check_coils(config)?;
    let m_max = config
        .coils
        .iter()
        .map(|c| c.1)
        .fold(f64::INFINITY, f64::min);
    Ok(Problem {
        field: Field::Sampled {
            step_s,
            b_teme_nt: sample_field(config, pb.duration_s, step_s)?,
        },
        m_max_am2: m_max.min(pb.m_max_am2),
        ..pb.clone()
    })
}

fn check_coils(config: &SimConfig) -> Result<(), String> {
    let axes = [Vec3d::x(), Vec3d::y(), Vec3d::z()];
    let ok = config.coils.len() == 3
        && config
            .coils
            .iter()
            .zip(axes.iter())
            .all(|((a, lim), e)| (a - e).norm() < 1e-9 && *lim > 0.0);
    if ok {
        Ok(())
    } else {
        Err("plan flight needs three coils along body x, y, z".into())
    }
}

/// Plans `pb` in the simulator's field ([`plan_for`], field sampled every `field_step_s`), then
/// flies it open loop with the commands updated every `fly_step_s` (with wheels: see [`fly`]).
pub fn plan_and_fly(
    config: &SimConfig,
    pb: &Problem,
    field_step_s: f64,
    evals: usize,
    restarts: usize,
    fly_step_s: f64,
) -> Result<Flight, String> {
    let pb = plan_for(config, pb, field_step_s)?;
    let (params, planned) = plan(&pb, evals, restarts)?;
    let (att, rate) = fly(config, &pb, &params, fly_step_s)?;
    Ok(Flight {
        planned,
        flown_attitude_error_deg: att,
        flown_rate_error_degps: rate,
        params,
    })
}

/// For each body axis `x, y, z`, a working wheel tile whose normal is `±` that axis: (tile index,
/// sign of the normal).
fn wheel_tiles(config: &SimConfig) -> Result<[(usize, f64); 3], String> {
    let axis = |e: Vec3d| {
        config
            .tiles
            .iter()
            .enumerate()
            .filter(|(_, t)| t.equipment.reaction_wheel)
            .find_map(|(k, t)| {
                let d = t.normal_body().cast::<f64>().dot(&e);
                ((d.abs() - 1.0).abs() < 1e-6).then_some((k, d.signum()))
            })
            .ok_or_else(|| format!("no wheel tile along {e:?}"))
    };
    Ok([axis(Vec3d::x())?, axis(Vec3d::y())?, axis(Vec3d::z())?])
}

/// Flies the plan `p` of `pb` open loop from rest at `q_start`; returns the final attitude
/// error against `q_end` (degrees) and the final rate (deg/s).
///
/// With wheels ([`Problem::wheels`]) the planner's wheel torques `ḣ` (hybrid allocation at the
/// step midpoint, with the planned momentum, the planner's speed limit applied) are integrated
/// into a planned body momentum `h`, commanded each step as the momentum of one wheel tile per
/// body axis ([`TileBus::set_wheel_momentum`]; the simulator slews each wheel to it within the
/// step); the other wheels stay at zero. No attitude feedback.
pub fn fly(config: &SimConfig, pb: &Problem, p: &[f64], step_s: f64) -> Result<(f64, f64), String> {
    check_coils(config)?;
    if !(step_s > 0.0 && pb.duration_s / step_s <= 1e7) {
        return Err(format!("fly step {step_s} s"));
    }
    let wheels = match pb.wheels {
        Some(w) => Some((w, wheel_tiles(config)?)),
        None => None,
    };
    let profile = pb.profile(p)?;
    let q = pb.q_start;
    let q0 = [q.q0, q.q1, q.q2, q.q3].map(f64::from);
    let mut sim = Simulator::new(config.clone(), q0, Vec3d::zeros()).map_err(|e| e.to_string())?;
    let n = (pb.duration_s / step_s).round().max(1.0) as usize;
    let dt = pb.duration_s / n as f64;
    let mut h = [0.0f64; 3];
    for k in 0..n {
        let c = command(pb, &profile, (k as f64 + 0.5) * dt, &h)?;
        for (i, m) in c.dipole_am2.iter().enumerate() {
            sim.set_dipole(i, *m as f32)
                .map_err(|e| format!("coil {i}: {e:?}"))?;
        }
        if let Some((w, tiles)) = wheels {
            let h_max = w.inertia_kgm2 * w.max_speed_radps;
            for ((hi, hdot), (tile, sign)) in h.iter_mut().zip(c.wheel_torque_nm).zip(tiles) {
                let blocked = hi.abs() >= h_max && hdot * *hi > 0.0;
                if !blocked {
                    *hi = (*hi + hdot * dt).clamp(-h_max, h_max);
                }
                sim.set_wheel_momentum(tile, (sign * *hi) as f32)
                    .map_err(|e| format!("wheel tile {tile}: {e:?}"))?;
            }
        }
        sim.advance(dt).map_err(|e| e.to_string())?;
    }
    let t = sim.truth();
    Ok((
        angle_between_deg(&t.q, &pb.q_end),
        t.omega.norm().to_degrees(),
    ))
}

/// The manoeuvre of `acs sim plan-flight`: seed 001's test case ((30°, 35°, 40°) 3-2-1 →
/// identity, rest to rest, 1500 s, inertia 0.7 kg·m², 10 A·m² per body axis, magnetorquers
/// only; note 001 §4) in the thesis-slew scenario's orbit and date (DTUSAT, 2009-06-16,
/// [`super::scenarios::thesis_slew`]) without disturbances, and that simulator configuration.
pub fn thesis_case() -> Result<(SimConfig, Problem), String> {
    let mut config = super::scenarios::thesis_slew(false)
        .map_err(|e| e.to_string())?
        .with_truth(super::realistic::TruthLevel::Ideal)
        .sim;
    config.inertia = crate::linalg::Mat3d::from_diagonal_element(0.7);
    config.coils = [Vec3d::x(), Vec3d::y(), Vec3d::z()]
        .map(|a| (a, 10.0))
        .to_vec();
    config.disturbances = super::Disturbances::none();
    let q_start = Dcm::from_euler_321(&Euler321 {
        psi_rad: 30f32.to_radians(),
        theta_rad: 35f32.to_radians(),
        phi_rad: 40f32.to_radians(),
    })
    .to_quaternion()
    .canonical();
    let pb = Problem {
        inertia_kgm2: [0.7; 3],
        m_max_am2: 10.0,
        wheels: None,
        a_km: 6828.1,
        omega0_radps: None,
        inc_rad: 0.0,
        greenwich0_rad: 0.0,
        q_start,
        q_end: Quaternion::IDENTITY,
        duration_s: 1500.0,
        knots: 4,
        dt_s: 5.0,
        weights: [1e5, 1e8, 0.0],
        // replaced by the simulator's sampled field in [`plan_for`]
        field: Field::Dipole,
        variable_grid: false,
    };
    Ok((config, pb))
}

/// [`thesis_case`] with seed 001's three wheels (8e-4 kg·m², ±5000 rpm, 0.01 N·m; Table 6.2)
/// over `duration_s` (Table 6.6: 150 s), cost (6.7) with `c_τ = 1e3` (not given by the thesis),
/// 300 planner steps; the simulator's wheel limits set to the same momentum and torque.
pub fn thesis_case_wheels(duration_s: f64) -> Result<(SimConfig, Problem), String> {
    let (mut config, pb) = thesis_case()?;
    let wheels = crate::host::planner::Wheels {
        inertia_kgm2: 8e-4,
        max_speed_radps: 5000.0 * core::f64::consts::PI / 30.0,
        max_torque_nm: 0.01,
    };
    config.wheel_max_h_nms = wheels.inertia_kgm2 * wheels.max_speed_radps;
    config.wheel_max_torque_nm = wheels.max_torque_nm;
    let pb = Problem {
        wheels: Some(wheels),
        duration_s,
        dt_s: duration_s / 300.0,
        weights: [1e5, 1e8, 1e3],
        ..pb
    };
    Ok((config, pb))
}
