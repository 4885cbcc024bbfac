//! Magnetorquer sizing (Tables 3.2–3.7 of seed 002) and the disturbance budgets of seeds 002 and
//! 004, from tests/data/atmocube_tables.txt. Each value is compared to half a unit of its last
//! printed digit.

mod figures;

use acs::control::disturbance::{
    aero_force_n, circular_speed_m_s, dipole_polar_field_t, gravity_gradient_max_nm,
    residual_dipole_torque_nm, solar_pressure_force_n, two_body_torque_nm, MU_EARTH_M3_S2,
};
use acs::control::sizing::{
    alpha_a, coil_mass_kg, coil_resistance_ohm, current_at_power_a, dipole_at_power_am2,
    max_torque_nm, turns_for_dipole, wire_area_m2, RHO_CU_KG_M3, SIGMA_CU_OHM_M,
};

/// Rows of the data file with the given tag, as printed strings.
fn rows(tag: &str) -> Vec<Vec<String>> {
    include_str!("data/atmocube_tables.txt")
        .lines()
        .filter(|l| !l.starts_with('#') && l.split_whitespace().next() == Some(tag))
        .map(|l| l.split_whitespace().skip(1).map(str::to_string).collect())
        .collect()
}

/// Half a unit of the last printed digit of `s` ("1.49e-4" → 0.005e-4, "43.3" → 0.05).
fn half_unit(s: &str) -> f64 {
    let (mantissa, exp) = match s.split_once(['e', 'E']) {
        Some((m, e)) => (m, e.parse::<i32>().unwrap()),
        None => (s, 0),
    };
    let decimals = mantissa.split_once('.').map_or(0, |(_, d)| d.len()) as i32;
    0.5 * 10f64.powi(exp - decimals)
}

/// Asserts `computed` equals the printed `s` to its printed precision (plus f32 rounding).
fn check(computed: f32, s: &str, what: &str) {
    let printed: f64 = s.parse().unwrap();
    let tol = half_unit(s) + 1e-6 * printed.abs();
    let err = (computed as f64 - printed).abs();
    assert!(
        err <= tol,
        "{what}: computed {computed:e}, printed {s} (tol {tol:e})"
    );
}

const SIDE_M: f32 = 0.085; // square coil side, note 002 §6.2
const PERIMETER_M: f32 = 4.0 * SIDE_M;
const AREA_M2: f32 = SIDE_M * SIDE_M;
const B600_T: f32 = 2.0e-5;
const B400_T: f32 = 2.18e-5;
const B350_T: f32 = 2.23e-5;

fn dipole(d_mm: f32, turns: f32, power_w: f32) -> f32 {
    let aw = wire_area_m2(d_mm * 1e-3);
    dipole_at_power_am2(turns, power_w, aw, PERIMETER_M, SIGMA_CU_OHM_M, AREA_M2)
}

#[test]
fn table_3_2_and_3_3_turns_and_torque() {
    let alpha = alpha_a(0.25, wire_area_m2(0.35e-3), PERIMETER_M, SIGMA_CU_OHM_M);
    check(alpha, "2.1027", "alpha 0.35 mm 0.25 W");
    for r in rows("t32") {
        let m: f32 = r[0].parse().unwrap();
        check(turns_for_dipole(m, alpha, AREA_M2), &r[1], "Table 3.2 N");
    }
    for r in rows("t33") {
        let m: f32 = r[0].parse().unwrap();
        check(turns_for_dipole(m, alpha, AREA_M2), &r[1], "Table 3.3 N");
        check(max_torque_nm(m, B600_T), &r[2], "Table 3.3 T600");
        check(max_torque_nm(m, B400_T), &r[3], "Table 3.3 T400");
    }
    assert_eq!(rows("t32").len(), 12);
    assert_eq!(rows("t33").len(), 12);
}

/// The dipole columns of Tables 3.4–3.6 are internally inconsistent by one unit of their last
/// digit: with `M ∝ √P` no display rule and no coil area gives both 0.100 at 0.25 W (formula
/// 0.1008) and 0.150 at 0.55 W (formula 0.1495). The formula is therefore held to one unit of
/// the last printed digit, and the entries beyond half a unit are counted and printed. The
/// torque columns are the thesis's `T = M_printed · B`, held to half a unit.
fn check_dipole(computed: f32, s: &str, what: &str, beyond_half: &mut Vec<String>) {
    let printed: f64 = s.parse().unwrap();
    let err = (computed as f64 - printed).abs();
    assert!(
        err <= 2.0 * half_unit(s) + 1e-6,
        "{what}: computed {computed}, printed {s}"
    );
    if err > half_unit(s) {
        beyond_half.push(format!("{what}: formula {computed:.4}, printed {s}"));
    }
}

#[test]
fn tables_3_4_to_3_7_dipole_and_torque_versus_power() {
    let mut beyond = Vec::new();
    // (P, wire, turns) -> printed dipole, for Table 3.7
    let mut printed_m: Vec<(String, f32, f32, f32)> = Vec::new();
    for r in rows("t345") {
        let p: f32 = r[0].parse().unwrap();
        for (k, turns) in [(1, 44.0), (4, 89.0)] {
            check_dipole(
                dipole(0.35, turns, p),
                &r[k],
                &format!("Table 3.4 N={turns} P={p}"),
                &mut beyond,
            );
            let m: f32 = r[k].parse().unwrap();
            check(max_torque_nm(m, B600_T), &r[k + 1], "Table 3.4 T600");
            check(max_torque_nm(m, B400_T), &r[k + 2], "Table 3.5 T400");
            printed_m.push((r[0].clone(), 0.35, turns, m));
        }
    }
    for r in rows("t36") {
        let p: f32 = r[0].parse().unwrap();
        for (k, turns) in [(1, 34.0), (3, 46.0)] {
            check_dipole(
                dipole(0.63, turns, p),
                &r[k],
                &format!("Table 3.6 N={turns} P={p}"),
                &mut beyond,
            );
            let m: f32 = r[k].parse().unwrap();
            check(max_torque_nm(m, B400_T), &r[k + 1], "Table 3.6 T");
            printed_m.push((r[0].clone(), 0.63, turns, m));
        }
    }
    for r in rows("t37") {
        let coils = [(0.35, 44.0), (0.35, 89.0), (0.63, 34.0), (0.63, 46.0)];
        for (k, (d, n)) in coils.iter().enumerate() {
            let m = printed_m
                .iter()
                .find(|(p, dd, nn, _)| *p == r[0] && dd == d && nn == n)
                .map(|e| e.3)
                .unwrap();
            check(
                max_torque_nm(m, B350_T),
                &r[k + 1],
                &format!("Table 3.7 P={} N={n}", r[0]),
            );
        }
    }
    figures::figure("control_sizing.dipole_beyond_half_unit", beyond.len());
    println!(
        "dipole entries of Tables 3.4–3.6 beyond half a printed unit ({} of 70):",
        beyond.len()
    );
    for b in &beyond {
        println!("  {b}");
    }
    assert_eq!(
        rows("t345").len() + rows("t36").len() + rows("t37").len(),
        16 + 19 + 11
    );
}

#[test]
fn turns_and_electrical_values_of_the_candidate_coils() {
    for r in rows("turns063") {
        let p: f32 = r[0].parse().unwrap();
        let alpha = alpha_a(p, wire_area_m2(0.63e-3), PERIMETER_M, SIGMA_CU_OHM_M);
        check(
            turns_for_dipole(0.1, alpha, AREA_M2),
            &r[1],
            "§6.3 turns for 0.1",
        );
        check(
            turns_for_dipole(0.143, alpha, AREA_M2),
            &r[2],
            "§6.3 turns for 0.143",
        );
    }
    for r in rows("coil") {
        let d: f32 = r[0].parse().unwrap();
        let n: f32 = r[1].parse().unwrap();
        let aw = wire_area_m2(d * 1e-3);
        let res = coil_resistance_ohm(n, PERIMETER_M, aw, SIGMA_CU_OHM_M);
        check(res, &r[2], "R");
        check(current_at_power_a(0.25, res), &r[3], "I at 0.25 W");
        check(current_at_power_a(1.0, res), &r[4], "I at 1 W");
        check(current_at_power_a(1.0, res) * res, &r[5], "V at 1 W");
        check(n * PERIMETER_M, &r[6], "wire length");
        check(
            coil_mass_kg(n, aw, PERIMETER_M, RHO_CU_KG_M3) * 1e3,
            &r[7],
            "mass g",
        );
    }
    // the chosen coil (34 turns, 0.63 mm) at 1 W: 0.3189 A·m² (note 002 §8.4)
    check(
        dipole(0.63, 34.0, 1.0),
        "0.3189",
        "chosen coil dipole at 1 W",
    );
}

/// The seed 002 budget with the given arms: (aerodynamic torque at each Table 3.1 row, T_sp).
fn atmocube_budget(b_cube_m: f32, b_boom_m: f32) -> (Vec<f32>, f32) {
    let (a_cube, a_boom, cd, q) = (1e-2, 4.2e-4, 2.5, 0.6);
    // seed 002's own constants: μ = G·m⊕ = 6.67e-11 · 5.98e24 (note 002 §3.1, §9.1) and
    // R⊕ = 6371 km; with 3.986e14 or 6378 km the rows are 0.1–0.4 % lower, beyond the rounding
    let mu = 6.67e-11 * 5.98e24;
    let r_earth_m = 6371e3;
    let ta = rows("t31")
        .iter()
        .map(|r| {
            let h_km: f32 = r[0].parse().unwrap();
            let rho: f32 = r[1].parse().unwrap();
            let v = circular_speed_m_s(mu, r_earth_m + h_km * 1e3);
            two_body_torque_nm(
                aero_force_n(rho, cd, a_cube, v),
                b_cube_m,
                aero_force_n(rho, cd, a_boom, v),
                b_boom_m,
            )
        })
        .collect();
    let tsp = two_body_torque_nm(
        solar_pressure_force_n(a_cube, q, 0.0, 2.0),
        b_cube_m,
        solar_pressure_force_n(a_boom, q, 0.0, 2.0),
        b_boom_m,
    );
    (ta, tsp)
}

#[test]
fn atmocube_disturbance_budget_and_the_lever_arm_slip() {
    // as printed: reproduced only with the slipped arms 0.62 m / 1.438 m (note 002 §3.3)
    let (ta, tsp) = atmocube_budget(0.62, 1.438);
    // T_a ∝ ρ and ρ is printed to three digits: its rounding propagates to T_a
    for (t, r) in ta.iter().zip(rows("t31")) {
        let rho: f64 = r[1].parse().unwrap();
        let printed: f64 = r[2].parse().unwrap();
        let tol = half_unit(&r[2]) + printed.abs() * half_unit(&r[1]) / rho;
        let err = (*t as f64 - printed).abs();
        figures::figure(
            &format!("control_sizing.table_3_1.{}km_rel", r[0]),
            err / printed,
        );
        println!(
            "Table 3.1 {} km: T_a {t:.4e} printed {} (rel err {:.2}%)",
            r[0],
            r[2],
            100.0 * err / printed
        );
        assert!(
            err <= tol,
            "Table 3.1 at {} km: {t:e} vs {} (tol {tol:e})",
            r[0],
            r[2]
        );
    }
    check(tsp, &rows("tsp")[0][0], "T_sp");
    // the consistent arms (6.2 cm offset): cube and boom nearly cancel, ~1000x smaller
    let (ta_ok, tsp_ok) = atmocube_budget(0.062, 1.488);
    let at600 = ta_ok.last().copied().unwrap();
    figures::figure("control_sizing.consistent_600km_nm", at600);
    figures::figure("control_sizing.thesis_600km_nm", ta.last().unwrap());
    println!(
        "AtmoCube at 600 km: T_a = {:.3e} N·m (thesis arms) vs {at600:.3e} (consistent)",
        ta.last().unwrap()
    );
    assert!(at600.abs() < 2e-10, "{at600}");
    assert!(tsp_ok.abs() < 1e-10, "{tsp_ok}");
    assert!(ta.last().unwrap() / at600.abs() > 900.0);
}

#[test]
fn cubesat_3u_budget_of_seed_004() {
    let r_earth_m = 6371e3;
    for r in rows("t004") {
        let h_km: f32 = r[0].parse().unwrap();
        let radius = r_earth_m + h_km * 1e3;
        let gg = gravity_gradient_max_nm(
            MU_EARTH_M3_S2,
            radius,
            0.042,
            0.0067,
            std::f32::consts::FRAC_PI_4,
        );
        check(gg, &r[1], "004 M_G");
        let b = dipole_polar_field_t(8.1e15, radius);
        check(b * 1e9, &r[2], "004 B_pole nT");
        check(residual_dipole_torque_nm(4e-3, b), &r[3], "004 M_M");
        check(
            circular_speed_m_s(MU_EARTH_M3_S2, radius),
            &r[4],
            "004 V_circ",
        );
    }
    let a = &rows("aero3u")[0];
    let v: Vec<f32> = a.iter().map(|s| s.parse().unwrap()).collect();
    check(
        aero_force_n(v[4], v[0], v[1], v[2]) * v[3],
        &a[5],
        "004 3U aerodynamic torque",
    );
}
