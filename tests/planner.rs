//! Ground planner of seed 001 (host feature): the dipole field against note 001 §1.9 and the
//! test case of note 001 §4 (Tables 6.3–6.6).
//!
//! Full reproduction (release, a few minutes):
//! `cargo test --release --test planner -- --ignored --nocapture`
#![cfg(feature = "host")]

use acs::attitude::Quaternion;
use acs::control::wheels::Wheel;
use acs::host::planner::{
    dipole_field_t, nelder_mead, nelder_mead_box, plan, plan_minimum_time, plan_with, simulate,
    simulate_direct, simulate_time_scaled, Field, Optimiser, Problem, Wheels,
};
use acs::linalg::{Mat3, Vec3};
use acs::planning::allocation::DipoleSaturation;
use acs::planning::feasibility::{check, Limits};
use acs::planning::kinematics::from_scalar_last;

fn thesis_problem(duration_s: f64, wheels: bool) -> Problem {
    Problem {
        // note 001 §4, Tables 6.1–6.2
        inertia_kgm2: [0.7; 3],
        m_max_am2: 10.0,
        wheels: wheels.then_some(Wheels {
            inertia_kgm2: 8e-4,
            max_speed_radps: 5000.0 * std::f64::consts::PI / 30.0,
            max_torque_nm: 0.01,
        }),
        a_km: 6828.1,
        omega0_radps: Some(1.1190e-3), // Table 6.1, as note 001 §1.9's values
        inc_rad: 51f64.to_radians(),
        greenwich0_rad: 0.0, // assumption: α_G0 = 0 at t = 0 (ascending node), as note 001 §1.9
        // (6.1a), scalar last in the thesis
        q_start: from_scalar_last([0.24194098, 0.35736694, 0.13261083, 0.89228236]),
        q_end: Quaternion::IDENTITY,
        duration_s,
        knots: 4,
        dt_s: duration_s / 1500.0,
        // (6.4)/(6.6)/(6.7); c_τ is not given by the thesis (6.7): ours
        weights: [1e5, 1e8, if wheels { 1e3 } else { 0.0 }],
        field: Field::Dipole, // the thesis field
        variable_grid: false,
    }
}

#[test]
fn dipole_field_matches_note_001() {
    // note 001 §1.9 reference values (α_G0 = 0, t = 0 at the ascending node), tesla
    let cases = [
        (0.0, [-3.18621e-6, -4.54919e-6, 2.43431e-5]),
        (150.0, [-1.10871e-5, -5.88894e-6, 2.26668e-5]),
        (1500.0, [7.19626e-6, -3.41260e-5, -1.24295e-5]),
    ];
    let pb = thesis_problem(1500.0, false);
    for (t, expect) in cases {
        let b = dipole_field_t(0.0, t, &pb.position_km(t));
        for (g, e) in b.iter().zip(expect) {
            assert!((g - e).abs() < 1e-10, "t {t}: {b:?} vs {expect:?}");
        }
    }
}

#[test]
fn naive_guess_errors_like_note_001() {
    // note 001 §4 [D]: naive straight-line guess, 1500 s: 3.90°, 3.15e-2 deg/s
    let pb = thesis_problem(1500.0, false);
    let (o, _) = simulate(&pb, &pb.initial_guess(), 0).unwrap();
    println!("naive 1500 s: {o:?}");
    let pb = thesis_problem(150.0, false);
    let (o150, _) = simulate(&pb, &pb.initial_guess(), 0).unwrap();
    println!("naive 150 s: {o150:?}");
    assert!((o.attitude_error_deg - 3.90).abs() < 0.05, "{o:?}");
    assert!((o.rate_error_degps - 3.15e-2).abs() < 0.05e-2, "{o:?}");
    assert!((o150.attitude_error_deg - 4.09).abs() < 0.05, "{o150:?}");
}

#[test]
#[ignore = "optimisation, minutes: run in release"]
fn reproduce_tables_6_3_to_6_6() {
    // expected (issue 10, note 001 §4 [D]): 1500 s far below the thesis's 5.4e-3°; 150 s
    // magnetorquers only physics-limited near 0.8° / 0.081 deg/s; with wheels about 1e-5°.
    for (tf, wheels, evals, thesis, max_att_deg, min_att_deg) in [
        (
            1500.0,
            false,
            1500,
            "Table 6.3 inverse: 5.43564e-3 deg, 3.0886e-4 deg/s",
            1e-4,
            0.0,
        ),
        (
            150.0,
            false,
            1500,
            "Table 6.4 inverse: 0.78 deg, 8.1457e-2 deg/s",
            0.85,
            0.7,
        ),
        (
            150.0,
            true,
            1500,
            "Table 6.6: 1.8104e-5 deg, 2.2707e-4 deg/s",
            1e-4,
            0.0,
        ),
    ] {
        let pb = thesis_problem(tf, wheels);
        let t0 = std::time::Instant::now();
        let (p, o) = plan(&pb, evals, 2).unwrap();
        println!(
            "T_f {tf} s wheels {wheels}: attitude {:.4e} deg, rate {:.4e} deg/s, max |m| {:.3} A·m², \
             max wheel {:.1} rad/s, ∫τ_lost² {:.3e}; {:.1} s; params {p:?}\n   thesis {thesis}",
            o.attitude_error_deg,
            o.rate_error_degps,
            o.max_dipole_am2,
            o.max_wheel_speed_radps,
            o.lost_integral,
            t0.elapsed().as_secs_f64()
        );
        assert!(
            o.attitude_error_deg <= max_att_deg && o.attitude_error_deg >= min_att_deg,
            "{o:?}"
        );
        // the on-board feasibility check of the optimised profile
        let profile = pb.profile(&p).unwrap();
        let field = |t: f32| {
            let b = pb.field_nt(t as f64).unwrap();
            Vec3::new(b[0] as f32, b[1] as f32, b[2] as f32)
        };
        let inertia = Mat3::from_diagonal_element(0.7);
        let report = if wheels {
            let limits: Limits<3> = Limits {
                m_max_am2: Vec3::repeat(10.0),
                saturation: DipoleSaturation::PerAxisClip,
                wheels: [Vec3::x(), Vec3::y(), Vec3::z()].map(|a| Wheel {
                    axis_body: a,
                    limit: 0.01,
                    working: true,
                }),
                wheel_momentum_max: [8e-4 * 5000.0 * std::f32::consts::PI / 30.0; 3],
            };
            let r = check(&profile, &inertia, field, &limits, &[0.0; 3], 1500).unwrap();
            assert!(!r.wheel_torque_exceeded() && !r.wheel_speed_exceeded());
            format!("{r:?}")
        } else {
            let limits: Limits<0> = Limits {
                m_max_am2: Vec3::repeat(10.0),
                saturation: DipoleSaturation::PerAxisClip,
                wheels: [],
                wheel_momentum_max: [],
            };
            let r = check(&profile, &inertia, field, &limits, &[], 1500).unwrap();
            // 150 s magnetorquers only: the coils saturate (Table 6.4's physics limit)
            assert_eq!(r.dipole_saturated(), tf < 1000.0);
            format!("{r:?}")
        };
        println!("   on-board feasibility: {report}");
    }
}

#[test]
fn cli_plan_writes_profile_errors_and_plot() {
    let dir = std::env::temp_dir().join(format!("acs-plan-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let desc = dir.join("m.json");
    std::fs::write(
        &desc,
        r#"{"duration_s": 1500, "evals": 40, "restarts": 0, "steps": 300}"#,
    )
    .unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_acs"))
        .args([
            "plan",
            desc.to_str().unwrap(),
            "--out",
            dir.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    println!("{stdout}");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("final_attitude_error_deg:"));
    let csv = std::fs::read_to_string(dir.join("profile.csv")).unwrap();
    assert_eq!(csv.lines().count(), 302);
    assert!(std::fs::read_to_string(dir.join("plan.svg"))
        .unwrap()
        .contains("<svg"));
    assert!(stdout.contains("knot_times_s: 0.000 500.000 1000.000 1500.000"));
    // variable grid (Table 6.5): the knot times are optimised and reported, increasing
    std::fs::write(
        &desc,
        r#"{"duration_s": 150, "evals": 40, "restarts": 0, "steps": 150, "field": "dipole",
            "variable_grid": true}"#,
    )
    .unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_acs"))
        .args([
            "plan",
            desc.to_str().unwrap(),
            "--out",
            dir.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    println!("{stdout}");
    assert!(out.status.success());
    let times: Vec<f64> = stdout
        .lines()
        .find_map(|l| l.strip_prefix("knot_times_s: "))
        .unwrap()
        .split(' ')
        .map(|t| t.parse().unwrap())
        .collect();
    assert_eq!(times.len(), 4);
    assert!(times[0] == 0.0 && times[3] == 150.0, "{times:?}");
    assert!(times.windows(2).all(|w| w[1] > w[0]), "{times:?}");
    let interior: Vec<&str> = stdout
        .lines()
        .find_map(|l| l.strip_prefix("interior_knots_qv: "))
        .unwrap()
        .split(") (")
        .collect();
    assert_eq!(interior.len(), 2);
    // bad input: exit code 2
    std::fs::write(&desc, r#"{"duration_s": -1}"#).unwrap();
    let bad = std::process::Command::new(env!("CARGO_BIN_EXE_acs"))
        .args([
            "plan",
            desc.to_str().unwrap(),
            "--out",
            dir.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
#[ignore = "optimisation: run in release"]
fn pattern_search_alone() {
    // note 001 §3.7 Algorithm 2 alone (no Nelder-Mead restart), 150 s magnetorquers only
    let pb = thesis_problem(150.0, false);
    let (_, o) = plan_with(&pb, Optimiser::PatternSearch, 3000, 0).unwrap();
    println!("pattern search 150 s MT only: {o:?}");
    assert!(o.attitude_error_deg < 0.85, "{o:?}");
    let pb = thesis_problem(1500.0, false);
    let (_, o) = plan_with(&pb, Optimiser::PatternSearch, 3000, 0).unwrap();
    // finding: on the 1500 s valley the compass search alone stalls (0.17° after 3000
    // evaluations); printed, not asserted. One Nelder–Mead run after it reaches 1.3e-3° (a
    // different basin from Nelder–Mead alone, max |m| 0.23 A·m²): better than Table 6.3.
    println!("pattern search 1500 s MT only, alone: {o:?}");
    let (_, o) = plan_with(&pb, Optimiser::PatternSearch, 3000, 1).unwrap();
    println!("pattern search + 1 Nelder-Mead run, 1500 s MT only: {o:?}");
    assert!(o.attitude_error_deg < 5.43564e-3, "{o:?}"); // Table 6.3, inverse dynamics
}

#[test]
#[ignore = "optimisation: run in release"]
fn direct_dynamics() {
    // note 001 §3.3: dipole splined per axis (6 knots, 18 ordinates), Nelder–Mead from m = 0;
    // costs (6.3) [1e5, 1e9, 1] at 1500 s and (6.5) [1e5, 1e8] at 150 s
    for (tf, weights, thesis) in [
        (
            1500.0,
            [1e5, 1e9, 1.0],
            "Table 6.3 direct: 7.7272e-3 deg, 8.3589e-3 deg/s",
        ),
        (
            150.0,
            [1e5, 1e8, 0.0],
            "Table 6.4 direct: 0.75 deg, 8.17e-2 deg/s",
        ),
    ] {
        let mut pb = thesis_problem(tf, false);
        pb.weights = weights;
        let cost = |p: &[f64]| {
            simulate_direct(&pb, p, 0)
                .map(|(o, _)| o.cost)
                .unwrap_or(f64::MAX)
        };
        let mut x = vec![0.0; 18];
        for _ in 0..3 {
            x = nelder_mead(cost, &x, -10.0, 10.0, 4000, 1e-18, 1e-12).x;
        }
        let (o, _) = simulate_direct(&pb, &x, 0).unwrap();
        println!("direct T_f {tf}: {o:?}\n   thesis {thesis}");
        if tf < 1000.0 {
            // physics-limited like Table 6.4 direct (0.75°)
            assert!(
                o.attitude_error_deg > 0.7 && o.attitude_error_deg < 0.85,
                "{o:?}"
            );
            assert!(o.max_dipole_am2 >= 10.0 - 1e-9);
        } else {
            // the effort term trades accuracy for ∫mᵀm: same order as Table 6.3 direct (7.7e-3°)
            assert!(o.attitude_error_deg < 10.0 * 7.7272e-3, "{o:?}");
        }
    }
}

#[test]
fn integration_step_converged() {
    // the predicted errors do not depend on the RK4 step: the optimised knots printed by
    // `reproduce_tables_6_3_to_6_6` simulated with 1500 and 12 000 steps
    let cases: [(f64, bool, [f64; 6]); 3] = [
        (
            1500.0,
            false,
            [
                0.3198530196936018,
                0.2071735539038121,
                0.17573047080840515,
                0.251767052804392,
                0.009334078231511025,
                -0.02044788944323192,
            ],
        ),
        (
            150.0,
            false,
            [
                0.22399985332694589,
                0.28975099935171134,
                0.16362190533335558,
                0.013777492634101463,
                0.16765050754217592,
                0.04173230921219749,
            ],
        ),
        (
            150.0,
            true,
            [
                0.1727465774545842,
                0.23161475622958216,
                0.09971831225290007,
                0.09053984759969216,
                0.06670186899181718,
                0.05120599647987714,
            ],
        ),
    ];
    for (tf, wheels, p) in cases {
        let mut pb = thesis_problem(tf, wheels);
        let (coarse, _) = simulate(&pb, &p, 0).unwrap();
        pb.dt_s = tf / 12_000.0;
        let (fine, _) = simulate(&pb, &p, 0).unwrap();
        let d_att = (coarse.attitude_error_deg - fine.attitude_error_deg).abs();
        let d_rate = (coarse.rate_error_degps - fine.rate_error_degps).abs();
        println!(
            "T_f {tf} wheels {wheels}: 1500 steps {:.4e} deg {:.4e} deg/s; 12000 steps {:.4e} deg {:.4e} deg/s",
            coarse.attitude_error_deg, coarse.rate_error_degps, fine.attitude_error_deg, fine.rate_error_degps
        );
        assert!(d_att < 0.1 * coarse.attitude_error_deg.max(1e-5), "{d_att}");
        assert!(d_rate < 0.1 * coarse.rate_error_degps.max(1e-6), "{d_rate}");
    }
}

fn igrf_problem(duration_s: f64, steps: f64) -> Problem {
    // the thesis manoeuvre (magnetorquers only) in IGRF-14 on 2025-01-01 00:00 UTC
    let start = acs::time::Epoch::from_calendar(acs::time::Calendar {
        year: 2025,
        month: 1,
        day: 1,
        hour: 0,
        minute: 0,
        second: 0,
        nano: 0,
    })
    .unwrap();
    Problem {
        field: Field::Igrf { start },
        dt_s: duration_s / steps,
        ..thesis_problem(duration_s, false)
    }
}

#[test]
fn igrf_field_physical_and_plan_converges() {
    // IGRF magnitude along the 450 km orbit over a whole orbit (5615 s): between the
    // equatorial ~20 000 nT and polar ~50 000 nT of LEO
    let pb = igrf_problem(1500.0, 300.0);
    let (mut lo, mut hi) = (f64::MAX, 0.0f64);
    for k in 0..=600 {
        let b = pb.field_nt(k as f64 * 10.0).unwrap();
        let m = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
        lo = lo.min(m);
        hi = hi.max(m);
    }
    println!("IGRF |B| along the orbit: {lo:.0}..{hi:.0} nT");
    assert!(lo > 20_000.0 && hi < 60_000.0, "{lo} {hi}");
    // the dipole and IGRF differ (not the same model by accident)
    let dip = Problem {
        field: Field::Dipole,
        ..pb.clone()
    };
    assert_ne!(dip.field_nt(0.0).unwrap(), pb.field_nt(0.0).unwrap());
    // planning in IGRF converges: from the naive guess's degrees to a small final error
    let (naive, _) = simulate(&pb, &pb.initial_guess(), 0).unwrap();
    let t0 = std::time::Instant::now();
    let (_, o) = plan(&pb, 400, 1).unwrap();
    println!(
        "IGRF 1500 s, 300 steps: naive {:.3} deg, planned {:.3e} deg {:.3e} deg/s ({} s)",
        naive.attitude_error_deg,
        o.attitude_error_deg,
        o.rate_error_degps,
        t0.elapsed().as_secs_f64()
    );
    assert!(o.attitude_error_deg < 0.05, "{o:?}");
    assert!(
        o.attitude_error_deg < naive.attitude_error_deg / 20.0,
        "{o:?}"
    );
}

#[test]
fn plan_flown_open_loop_in_simulator_matches_prediction() {
    // the thesis manoeuvre (1500 s, magnetorquers only, 10 A·m² per axis, inertia 0.7 kg·m²)
    // planned in the simulator's own truth field (DTUSAT SGP4 orbit, IGRF, 2009-06-16; sampled
    // every 5 s), then flown open loop in the f64 simulator without disturbances, commands
    // updated every 0.02 s (as `acs sim plan-flight`)
    let (config, pb) = acs::host::sim::plan_flight::thesis_case().unwrap();
    // the naive guess in the same field, for scale
    let sampled = acs::host::sim::plan_flight::plan_for(&config, &pb, 5.0).unwrap();
    let (naive, _) = simulate(&sampled, &sampled.initial_guess(), 0).unwrap();
    let t0 = std::time::Instant::now();
    let f = acs::host::sim::plan_flight::plan_and_fly(&config, &pb, 5.0, 400, 1, 0.02).unwrap();
    println!(
        "plan flight 1500 s: naive {:.3} deg; planned {:.4e} deg {:.4e} deg/s, flown {:.4e} deg {:.4e} deg/s ({:.1} s)",
        naive.attitude_error_deg,
        f.planned.attitude_error_deg,
        f.planned.rate_error_degps,
        f.flown_attitude_error_deg,
        f.flown_rate_error_degps,
        t0.elapsed().as_secs_f64()
    );
    assert!(
        f.planned.attitude_error_deg < naive.attitude_error_deg / 20.0,
        "{f:?}"
    );
    // Tolerance: the simulator holds the field (and we hold the dipole) over each `advance`
    // step, the planner's RK4 sees them continuous; that lag scales with the step (measured on
    // this plan: 0.1 s steps flew 5.4e-3 deg away from the prediction, 0.02 s steps 1.4e-3 deg,
    // about 3 % of the error, the rest of it from the 5 s field samples and the planner's 5 s
    // RK4 step). 4e-3 deg and 2 % of the rate: about 3x the 0.02 s figure.
    assert!(
        (f.flown_attitude_error_deg - f.planned.attitude_error_deg).abs() < 4e-3,
        "{f:?}"
    );
    assert!(
        (f.flown_rate_error_degps - f.planned.rate_error_degps).abs()
            < 0.02 * f.planned.rate_error_degps,
        "{f:?}"
    );
}

#[test]
#[ignore = "optimisation: run in release"]
fn variable_time_grid_table_6_5() {
    // Table 6.5: 150 s, magnetorquers only, inverse dynamics, the interior knot abscissae
    // optimised too, from the fixed-grid optimum (Table 6.4 knots of
    // `integration_step_converged`) on the uniform grid (gap parameters 0.5)
    let fixed_p = [
        0.22399985332694589,
        0.28975099935171134,
        0.16362190533335558,
        0.013777492634101463,
        0.16765050754217592,
        0.04173230921219749,
    ];
    let fixed_pb = thesis_problem(150.0, false);
    let (fixed, _) = simulate(&fixed_pb, &fixed_p, 0).unwrap();
    let pb = Problem {
        variable_grid: true,
        ..fixed_pb
    };
    let mut x: Vec<f64> = fixed_p.iter().copied().chain([0.5, 0.5]).collect();
    // the uniform grid reproduces the fixed-grid outcome (up to the f32 knot times)
    let (start, _) = simulate(&pb, &x, 0).unwrap();
    assert!(
        (start.cost - fixed.cost).abs() <= 1e-6 * fixed.cost,
        "{start:?} {fixed:?}"
    );
    let cost = |p: &[f64]| simulate(&pb, p, 0).map(|(o, _)| o.cost).unwrap_or(f64::MAX);
    let t0 = std::time::Instant::now();
    for _ in 0..2 {
        x = nelder_mead(cost, &x, -1.0, 1.0, 1500, 1e-18, 1e-12).x;
    }
    let (o, _) = simulate(&pb, &x, 0).unwrap();
    let times = pb.knot_times(&x[6..]);
    println!(
        "Table 6.5 variable grid 150 s MT only: attitude {:.4e} deg, rate {:.4e} deg/s, cost {:.4e} \
         (fixed grid {:.4e} deg, {:.4e} deg/s, cost {:.4e}); knots {times:?} s; {:.1} s; params {x:?}\n   \
         thesis Table 6.5 inverse: 0.52 deg, 8.12e-2 deg/s (direct 1.1468 deg)",
        o.attitude_error_deg,
        o.rate_error_degps,
        o.cost,
        fixed.attitude_error_deg,
        fixed.rate_error_degps,
        fixed.cost,
        t0.elapsed().as_secs_f64()
    );
    // guaranteed: Nelder–Mead keeps its best point, which starts at the fixed-grid optimum
    assert!(o.cost.is_finite() && o.cost <= start.cost, "{o:?}");
    assert!(o.attitude_error_deg.is_finite() && o.rate_error_degps.is_finite());
    assert!(times.windows(2).all(|w| w[1] > w[0]), "{times:?}");
    assert!(times[0] == 0.0 && times[3] == 150.0, "{times:?}");
}

/// The thesis's cost (6.5)/(6.6), `c_q |δq|² + c_ω |δω|²` with [1e5, 1e8], δω in rad/s, of a
/// final error given as an angle (deg) and a rate (deg/s): `|δq| = sin(θ/2)`.
fn thesis_cost_150(attitude_deg: f64, rate_degps: f64) -> f64 {
    let dq = (attitude_deg.to_radians() / 2.0).sin();
    let dw = rate_degps.to_radians();
    1e5 * dq * dq + 1e8 * dw * dw
}

/// The Table 6.4 optimum (fixed grid, inverse, α_G0 = 0) of `integration_step_converged`.
const TABLE_6_4_KNOTS: [f64; 6] = [
    0.22399985332694589,
    0.28975099935171134,
    0.16362190533335558,
    0.013777492634101463,
    0.16765050754217592,
    0.04173230921219749,
];

#[test]
#[ignore = "optimisation: run in release"]
fn table_6_5_attitude_rate_trade_off() {
    // Why our Table 6.5 attitude (0.85°) is not the thesis's 0.52°: the cost (6.6) is ≈ 98 %
    // rate term (c_ω|δω|² ≈ 200 against c_q|δq|² ≈ 2–5), so the optimum's attitude error is
    // weakly determined. Thesis points in its own cost: Table 6.4 inverse 0.78° / 8.1457e-2 °/s
    // → 206.7; Table 6.5 inverse 0.52° / 8.12e-2 → 202.9; Table 6.5 direct 1.1468° / 7.9847e-2
    // → 204.2 (its variable grid too traded attitude for rate, 0.75° → 1.15°).
    let thesis_65 = thesis_cost_150(0.52, 8.12e-2);
    let thesis_64 = thesis_cost_150(0.78, 8.1457e-2);
    let thesis_65_direct = thesis_cost_150(1.1468, 7.9847e-2);
    println!(
        "thesis cost (6.6): Table 6.4 inverse {thesis_64:.2}, Table 6.5 inverse {thesis_65:.2}, \
         Table 6.5 direct {thesis_65_direct:.2}"
    );
    let pb = Problem {
        variable_grid: true,
        ..thesis_problem(150.0, false)
    };
    let mut x: Vec<f64> = TABLE_6_4_KNOTS.iter().copied().chain([0.5, 0.5]).collect();
    // the Pareto front of (attitude, rate) on the variable grid: raise c_q step by step
    // (continuation from the previous optimum), each time report the thesis's cost of the point
    let mut front = Vec::new();
    for k in [1.0, 3.0, 10.0, 30.0, 100.0] {
        let pk = Problem {
            weights: [1e5 * k, 1e8, 0.0],
            ..pb.clone()
        };
        let cost = |p: &[f64]| simulate(&pk, p, 0).map(|(o, _)| o.cost).unwrap_or(f64::MAX);
        for _ in 0..2 {
            x = nelder_mead(cost, &x, -1.0, 1.0, 1500, 1e-18, 1e-12).x;
        }
        let (o, _) = simulate(&pb, &x, 0).unwrap();
        let j = thesis_cost_150(o.attitude_error_deg, o.rate_error_degps);
        println!(
            "c_q = {:.0e}: attitude {:.4} deg, rate {:.5e} deg/s, thesis cost (6.6) {j:.3} \
             (own cost {:.3}); knots {:?} s",
            1e5 * k,
            o.attitude_error_deg,
            o.rate_error_degps,
            o.cost,
            pb.knot_times(&x[6..])
        );
        front.push((k, o.attitude_error_deg, o.rate_error_degps, j, x.clone()));
    }
    // c_q = 1e5 is the thesis's own problem: its optimum is no worse than the Table 6.4 start
    let (fixed, _) = simulate(&thesis_problem(150.0, false), &TABLE_6_4_KNOTS, 0).unwrap();
    assert!(front[0].3 <= fixed.cost * (1.0 + 1e-9), "{front:?}");
    // Nelder–Mead at c_q = 1e5 stopped in a local minimum: points of the front cost less in
    // the thesis's own cost, and dominate the thesis's Table 6.5 point (smaller attitude AND rate)
    let best = front
        .iter()
        .min_by(|a, b| a.3.total_cmp(&b.3))
        .unwrap()
        .clone();
    assert!(best.3 < front[0].3 && best.3 < thesis_65, "{best:?}");
    assert!(
        front.iter().any(|f| f.1 < 0.52 && f.2 < 8.12e-2),
        "no point dominates the thesis's"
    );
    // the best of them polished with the thesis's weights (2 × 1500): our Table 6.5 figure
    let cost = |p: &[f64]| simulate(&pb, p, 0).map(|(o, _)| o.cost).unwrap_or(f64::MAX);
    let mut x = best.4.clone();
    for _ in 0..2 {
        x = nelder_mead(cost, &x, -1.0, 1.0, 1500, 1e-18, 1e-12).x;
    }
    let (o, _) = simulate(&pb, &x, 0).unwrap();
    println!(
        "Table 6.5 inverse, continuation then c_q = 1e5: attitude {:.4} deg, rate {:.5e} deg/s, \
         cost {:.3} (thesis 0.52 deg, 8.12e-2 deg/s, cost {thesis_65:.3}); knots {:?} s; params \
         {x:?}",
        o.attitude_error_deg,
        o.rate_error_degps,
        o.cost,
        pb.knot_times(&x[6..])
    );
    assert!(o.cost <= best.3 * (1.0 + 1e-9), "{o:?}");
}

#[test]
#[ignore = "optimisation: run in release"]
fn table_6_4_6_5_greenwich_angle_sweep() {
    // The thesis does not give α_G0 (note 001 §1.9): the 150 s magnetorquer-only optimum on the
    // fixed and on the variable grid for several α_G0 (Nelder–Mead 3 × 1500 from the naive
    // guess, then 2 × 1500 on the variable grid from that optimum).
    let mut rows = Vec::new();
    for g_deg in [0.0, 60.0, 120.0, 180.0, 240.0, 300.0] {
        let pb = Problem {
            greenwich0_rad: f64::to_radians(g_deg),
            ..thesis_problem(150.0, false)
        };
        let (p, fixed) = plan(&pb, 1500, 2).unwrap();
        let pv = Problem {
            variable_grid: true,
            ..pb.clone()
        };
        let mut x: Vec<f64> = p.iter().copied().chain([0.5, 0.5]).collect();
        let cost = |p: &[f64]| simulate(&pv, p, 0).map(|(o, _)| o.cost).unwrap_or(f64::MAX);
        for _ in 0..2 {
            x = nelder_mead(cost, &x, -1.0, 1.0, 1500, 1e-18, 1e-12).x;
        }
        let (var, _) = simulate(&pv, &x, 0).unwrap();
        println!(
            "α_G0 {g_deg:5.1}°: fixed {:.4} deg {:.5e} deg/s cost {:.2}; variable {:.4} deg \
             {:.5e} deg/s cost {:.2}; knots {:?}",
            fixed.attitude_error_deg,
            fixed.rate_error_degps,
            fixed.cost,
            var.attitude_error_deg,
            var.rate_error_degps,
            var.cost,
            pv.knot_times(&x[6..])
        );
        assert!(var.cost <= fixed.cost * (1.0 + 1e-9));
        rows.push((g_deg, fixed.attitude_error_deg, var.attitude_error_deg));
    }
    println!("α_G0, fixed, variable (deg): {rows:?}");
}

#[test]
#[ignore = "optimisation: run in release"]
fn direct_dynamics_variable_grid_table_6_5() {
    // Table 6.5 direct column (1.1468°, 7.9847e-2 °/s): direct dynamics, 150 s, cost (6.5),
    // 6 knots per axis, the 4 interior abscissae optimised too (gap parameters, 0.5 = uniform),
    // from the fixed-grid direct optimum (Table 6.4 direct: thesis 0.75°, 8.17e-2 °/s).
    let mut pb = thesis_problem(150.0, false);
    pb.weights = [1e5, 1e8, 0.0];
    let cost = |p: &[f64]| {
        simulate_direct(&pb, p, 0)
            .map(|(o, _)| o.cost)
            .unwrap_or(f64::MAX)
    };
    let t0 = std::time::Instant::now();
    let mut x = vec![0.0; 18];
    for _ in 0..3 {
        x = nelder_mead(cost, &x, -10.0, 10.0, 4000, 1e-18, 1e-12).x;
    }
    let (fixed, _) = simulate_direct(&pb, &x, 0).unwrap();
    let pv = Problem {
        variable_grid: true,
        ..pb.clone()
    };
    let mut y: Vec<f64> = x.iter().copied().chain([0.5; 4]).collect();
    // the uniform grid reproduces the fixed-grid outcome
    let (start, _) = simulate_direct(&pv, &y, 0).unwrap();
    assert!(
        (start.cost - fixed.cost).abs() <= 1e-6 * fixed.cost,
        "{start:?} {fixed:?}"
    );
    let lo: Vec<f64> = [-10.0; 18].into_iter().chain([-1.0; 4]).collect();
    let hi: Vec<f64> = [10.0; 18].into_iter().chain([1.0; 4]).collect();
    let cost_v = |p: &[f64]| {
        simulate_direct(&pv, p, 0)
            .map(|(o, _)| o.cost)
            .unwrap_or(f64::MAX)
    };
    for _ in 0..3 {
        y = nelder_mead_box(cost_v, &y, &lo, &hi, 4000, 1e-18, 1e-12).x;
    }
    let (var, _) = simulate_direct(&pv, &y, 0).unwrap();
    println!(
        "direct 150 s: fixed grid {:.4} deg {:.5e} deg/s cost {:.3}; variable grid {:.4} deg \
         {:.5e} deg/s cost {:.3}; knots {:?} s; {:.0} s\n   thesis Table 6.4 direct 0.75 deg \
         8.17e-2 deg/s (cost {:.2}), Table 6.5 direct 1.1468 deg 7.9847e-2 deg/s (cost {:.2})",
        fixed.attitude_error_deg,
        fixed.rate_error_degps,
        fixed.cost,
        var.attitude_error_deg,
        var.rate_error_degps,
        var.cost,
        pv.knot_times(&y[18..]),
        t0.elapsed().as_secs_f64(),
        thesis_cost_150(0.75, 8.17e-2),
        thesis_cost_150(1.1468, 7.9847e-2)
    );
    assert!(var.cost <= fixed.cost * (1.0 + 1e-9), "{var:?} {fixed:?}");
    assert!(var.max_dipole_am2 >= 10.0 - 1e-9, "{var:?}");
}

#[test]
#[ignore = "optimisation: run in release"]
fn continuation_150s_fixed_and_variable_grid() {
    // the 150 s magnetorquer-only optima with the thesis weights are local: Nelder–Mead with
    // c_q raised ten times (2 × 1500), then back at the thesis's c_q = 1e5 (2 × 1500), from the
    // Table 6.4 optimum, on the fixed and on the variable grid
    for variable_grid in [false, true] {
        let pb = Problem {
            variable_grid,
            ..thesis_problem(150.0, false)
        };
        let mut x: Vec<f64> = TABLE_6_4_KNOTS.to_vec();
        if variable_grid {
            x.extend([0.5, 0.5]);
        }
        let (start, _) = simulate(&pb, &x, 0).unwrap();
        for cq in [1e6, 1e5] {
            let pk = Problem {
                weights: [cq, 1e8, 0.0],
                ..pb.clone()
            };
            let cost = |p: &[f64]| simulate(&pk, p, 0).map(|(o, _)| o.cost).unwrap_or(f64::MAX);
            for _ in 0..2 {
                x = nelder_mead(cost, &x, -1.0, 1.0, 1500, 1e-18, 1e-12).x;
            }
            let (o, _) = simulate(&pb, &x, 0).unwrap();
            println!(
                "variable grid {variable_grid}, after c_q = {cq:.0e}: attitude {:.4} deg, rate \
                 {:.5e} deg/s, thesis cost {:.3} (start {:.3}); knots {:?}; params {x:?}",
                o.attitude_error_deg,
                o.rate_error_degps,
                o.cost,
                start.cost,
                pb.knot_times(if variable_grid { &x[6..] } else { &[] })
            );
        }
    }
}

#[test]
fn plan_with_wheels_flown_open_loop_in_simulator() {
    // Table 6.6's manoeuvre (150 s, magnetorquers + three wheels, cost (6.7) with c_τ = 1e3)
    // planned in the simulator's truth field (sampled every 1 s), then flown open loop with
    // the dipole and the wheel momenta commanded every 0.02 s (as `acs sim plan-flight`)
    use acs::host::sim::plan_flight::{fly, plan_and_fly, plan_for, thesis_case_wheels};
    let (config, pb) = thesis_case_wheels(150.0).unwrap();
    let t0 = std::time::Instant::now();
    let f = plan_and_fly(&config, &pb, 1.0, 400, 1, 0.02).unwrap();
    println!(
        "plan flight 150 s with wheels: planned {:.4e} deg {:.4e} deg/s (max wheel {:.1} rad/s), \
         flown {:.4e} deg {:.4e} deg/s ({:.1} s)",
        f.planned.attitude_error_deg,
        f.planned.rate_error_degps,
        f.planned.max_wheel_speed_radps,
        f.flown_attitude_error_deg,
        f.flown_rate_error_degps,
        t0.elapsed().as_secs_f64()
    );
    // The gap is the zero-order hold of the commands and of the simulator's field over each
    // step (first order in the step; measured on this plan: 0.1 s 1.1e-2 deg, 0.05 s 1.9e-3,
    // 0.02 s 7.4e-4, 0.01 s 3.7e-4, 0.005 s 1.8e-4 deg, planned 7.4e-6 deg): checked at 0.02 s
    // (2e-3 deg, about 3x the measured 7.4e-4) and by halving the step twice.
    let sampled = plan_for(&config, &pb, 1.0).unwrap();
    let mut gaps = Vec::new();
    for step in [0.1, 0.05, 0.02, 0.01, 0.005] {
        let (a, r) = fly(&config, &sampled, &f.params, step).unwrap();
        println!("   flown with {step} s steps: {a:.4e} deg {r:.4e} deg/s");
        gaps.push((a - f.planned.attitude_error_deg).abs());
    }
    assert!(f.planned.attitude_error_deg < 1e-4, "{f:?}");
    assert!(
        (f.flown_attitude_error_deg - f.planned.attitude_error_deg).abs() < 2e-3,
        "{f:?}"
    );
    assert!(f.flown_rate_error_degps < 1e-4, "{f:?}");
    assert!(gaps[4] < gaps[2] / 3.0, "{gaps:?}");
}

#[test]
fn time_scaling_is_a_stretched_manoeuvre() {
    // note 001 §1.11 (eqs. 4.8–4.10): integrating in pseudo-time with every derivative times
    // x9 = 0.6 over T_f = 150 s is the 90 s manoeuvre in real time; J_T = c_T x9 T_f
    let pb = thesis_problem(150.0, true);
    let p = pb.initial_guess();
    let scaled = simulate_time_scaled(&pb, &p, 0.6, 0.0).unwrap();
    let real = Problem {
        duration_s: 90.0,
        dt_s: 0.6 * pb.dt_s,
        ..pb.clone()
    };
    let (direct, _) = simulate(&real, &p, 0).unwrap();
    println!("scaled: {scaled:?}\nreal 90 s: {direct:?}");
    for (a, b) in [
        (scaled.attitude_error_deg, direct.attitude_error_deg),
        (scaled.rate_error_degps, direct.rate_error_degps),
        (scaled.cost, direct.cost),
        (scaled.lost_integral, direct.lost_integral),
        (scaled.max_wheel_speed_radps, direct.max_wheel_speed_radps),
    ] {
        assert!((a - b).abs() <= 1e-9 * b.abs().max(1e-12), "{a} {b}");
    }
    let with_t = simulate_time_scaled(&pb, &p, 0.6, 2.0).unwrap();
    assert!((with_t.cost - scaled.cost - 2.0 * 0.6 * 150.0).abs() < 1e-9);
    // scale 1 is the unscaled simulation; bad scales are errors
    let one = simulate_time_scaled(&pb, &p, 1.0, 0.0).unwrap();
    assert_eq!(one, simulate(&pb, &p, 0).unwrap().0);
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(simulate_time_scaled(&pb, &p, bad, 0.0).is_err());
    }
}

#[test]
#[ignore = "optimisation: run in release"]
fn minimum_time_with_wheels() {
    // note 001 §1.11: the Table 6.6 manoeuvre (magnetorquers + wheels) with the duration free,
    // x9 ∈ [0.05, 1] of 150 s, cost (6.7) + c_T x9 T_f with c_T = 0.1 /s (our choice: the
    // thesis reports no minimum-time result)
    let pb = thesis_problem(150.0, true);
    let t0 = std::time::Instant::now();
    let (p, scale, o) = plan_minimum_time(&pb, 0.1, 0.05, 1.0, 1500, 2).unwrap();
    let t_real = scale * pb.duration_s;
    // physics bound: |ω̇| ≤ (|ḣ| + |m × B|) / I with |ḣ| ≤ 0.01√3 N·m and |m × B| ≤ 10√3 A·m² ×
    // 4.5401e-5 T (note 001 §1.9: the largest |B| on this orbit), and the rotation angle ≤ ∫|ω|:
    // a rest-to-rest rotation by θ takes at least 2√(θ/α_max)
    let alpha_max = (0.01 * 3f64.sqrt() + 10.0 * 3f64.sqrt() * 4.5401e-5) / 0.7;
    let theta = 53.6777f64.to_radians() - o.attitude_error_deg.to_radians();
    let bound = 2.0 * (theta / alpha_max).sqrt();
    println!(
        "minimum time with wheels: {t_real:.2} s (bound {bound:.2} s), attitude {:.4e} deg, rate \
         {:.4e} deg/s, max wheel {:.1} rad/s, cost {:.4}; {:.1} s; params {p:?}",
        o.attitude_error_deg,
        o.rate_error_degps,
        o.max_wheel_speed_radps,
        o.cost,
        t0.elapsed().as_secs_f64()
    );
    assert!(t_real >= bound && t_real < 150.0, "{t_real} {bound}");
}

#[test]
#[ignore = "optimisation: run in release"]
fn table_6_4_6_5_five_knots() {
    // the thesis gives the knot count (n = 4) only for 1500 s (note 001 §3.5): the 150 s
    // magnetorquer-only case with n = 5, fixed grid (Nelder–Mead 3 × 1500 from the naive
    // guess) then variable grid (2 × 1500 from that optimum)
    let pb = Problem {
        knots: 5,
        ..thesis_problem(150.0, false)
    };
    let (p, fixed) = plan(&pb, 1500, 2).unwrap();
    let pv = Problem {
        variable_grid: true,
        ..pb.clone()
    };
    let mut x: Vec<f64> = p.iter().copied().chain([0.5; 3]).collect();
    let cost = |p: &[f64]| simulate(&pv, p, 0).map(|(o, _)| o.cost).unwrap_or(f64::MAX);
    for _ in 0..2 {
        x = nelder_mead(cost, &x, -1.0, 1.0, 1500, 1e-18, 1e-12).x;
    }
    let (var, _) = simulate(&pv, &x, 0).unwrap();
    println!(
        "5 knots, 150 s MT only: fixed {:.4} deg {:.5e} deg/s cost {:.2}; variable {:.4} deg \
         {:.5e} deg/s cost {:.2}; knots {:?} s",
        fixed.attitude_error_deg,
        fixed.rate_error_degps,
        fixed.cost,
        var.attitude_error_deg,
        var.rate_error_degps,
        var.cost,
        pv.knot_times(&x[9..])
    );
    assert!(var.cost <= fixed.cost * (1.0 + 1e-9));
}
