//! Closed-loop results (`docs/closed-loop.md`), with fixed random seeds: the flight loop flying
//! simulated tiles. `detumble`, `sun-safe`, `tracking`, `tracking-eclipse`, `failed-tile` and
//! `slew` fly the flight configuration (`acs::flight::CONFIG` through `FlightLoop`, what the firmware flies); the
//! thesis slews fly the thesis's satellite (`acs::host::sim::scenarios`). Run with
//! `cargo test --release --test closed_loop -- --nocapture` to see the figures: each
//! requirement of `docs/closed-loop.md`'s table prints one `REQUIREMENT MET` or
//! `REQUIREMENT NOT MET` line per truth.
//!
//! Every scenario flies twice (issue #18): against the ideal truth (the simulator before the
//! realistic truth; for the thesis scenarios the thesis's own noise model), where the
//! requirements are asserted, and against the realistic truth (`acs::host::sim::realistic`, what
//! `acs sim` flies by default), where only the absence of NaN and a bounded motion are asserted
//! and the figure is printed with its verdict: the flight code's answers to the realistic truth
//! (issue #18 item 4) come later. `realistic_figures_by_cause` prints, for the worst figures,
//! each effect's share: the figure without it, and with it alone.

use acs::acs_loop::Mode;
use acs::env::igrf::{Degree, Model};
use acs::flight::{FlightLoop, CONFIG};
use acs::host::sim::realistic::{Effect, Realism, TruthLevel};
use acs::host::sim::scenarios::{self, Scenario};
use acs::host::sim::{angle_between_deg, Sample};

mod common;
mod figures;
use figures::figure;

/// The key of a figure of `docs/closed-loop.md` / `docs/simulator.md`: `closed_loop.NAME.TRUTH.what`.
fn key(name: &str, truth: TruthLevel, what: &str) -> String {
    format!("closed_loop.{name}.{}.{what}", truth.name())
}

const TRUTHS: [TruthLevel; 2] = [TruthLevel::Ideal, TruthLevel::Realistic];

fn orbit_s() -> f64 {
    94.6 * 60.0
}

fn report(name: &str, truth: TruthLevel, samples: &[Sample]) {
    let last = samples.last().unwrap();
    let max_est = samples
        .iter()
        .filter_map(|s| s.estimate_error_deg)
        .fold(0.0f64, f64::max);
    println!(
        "{name} ({} truth): {} steps, final mode {:?}, final rate {:.4} °/s, final pointing {:?}°, max estimate error {max_est:.3}°",
        truth.name(),
        samples.len(),
        last.mode,
        last.omega_true.norm().to_degrees(),
        last.pointing_error_deg
    );
}

/// Prints one line per requirement (`docs/closed-loop.md`) and truth: whether it is met and the figure.
fn requirement(name: &str, truth: TruthLevel, requirement: &str, met: bool, figure: &str) {
    let verdict = if met { "MET" } else { "NOT MET" };
    figures::verdict(&key(name, truth, "verdict"), met);
    println!(
        "{name} ({} truth): REQUIREMENT {verdict} ({requirement}): {figure}",
        truth.name()
    );
}

fn no_nan(samples: &[Sample]) {
    for s in samples {
        assert!(
            s.omega_true.iter().all(|x| x.is_finite()),
            "truth NaN at {}",
            s.t_s
        );
        assert!(
            s.dipole_am2.iter().all(|x| x.is_finite()),
            "dipole NaN at {}",
            s.t_s
        );
        assert!(
            s.report.h_wheels_body.iter().all(|x| x.is_finite()),
            "wheel NaN at {}",
            s.t_s
        );
        assert!(
            s.pointing_error_deg.is_none_or(|e| e.is_finite())
                && s.estimate_error_deg.is_none_or(|e| e.is_finite()),
            "error NaN at {}",
            s.t_s
        );
    }
}

/// What the realistic truth asserts: no NaN, and a bounded motion: the body rate within the
/// gyros' word (±3.27 rad/s), the wheels' total momentum within six wheels at the largest limit
/// of the scenarios (the thesis's 2e-3 kg·m²/s), the coils within their limits.
fn bounded(samples: &[Sample]) {
    no_nan(samples);
    let wheels = 6.0 * f64::from(CONFIG.wheel_limit_nms).max(2e-3) * 1.001;
    let coils = f64::from(CONFIG.coils[0].limit) * 3f64.sqrt() * 1.001;
    for s in samples {
        assert!(s.omega_true.norm() < 3.27, "rate at {}", s.t_s);
        assert!(s.h_wheels_body.norm() <= wheels, "wheels at {}", s.t_s);
        assert!(
            f64::from(s.dipole_am2.norm()) <= coils,
            "coils at {}",
            s.t_s
        );
    }
}

fn fly(scenario: Result<Scenario, acs::host::sim::SimError>, truth: TruthLevel) -> Vec<Sample> {
    scenario.unwrap().with_truth(truth).run().unwrap()
}

#[test]
fn detumble_within_three_orbits() {
    for truth in TRUTHS {
        let samples = fly(scenarios::detumble(), truth);
        report("detumble", truth, &samples);
        bounded(&samples);
        let first_below = samples
            .iter()
            .find(|s| s.omega_true.norm().to_degrees() < 0.5)
            .map(|s| s.t_s);
        let last = samples.last().unwrap();
        let end_degps = last.omega_true.norm().to_degrees();
        figure(&key("detumble", truth, "end_degps"), end_degps);
        if let Some(t) = first_below {
            figure(&key("detumble", truth, "below_s"), t);
            figure(&key("detumble", truth, "below_orbits"), t / orbit_s());
        }
        let met = end_degps < 0.5 && first_below.is_some_and(|t| t <= 3.0 * orbit_s());
        let figure = match first_below {
            Some(t) => format!(
                "below 0.5°/s after {t:.0} s ({:.2} orbits); {end_degps:.4}°/s at 3 orbits",
                t / orbit_s()
            ),
            None => format!("never below 0.5°/s; {end_degps:.4}°/s at 3 orbits"),
        };
        requirement("detumble", truth, "< 0.5°/s within 3 orbits", met, &figure);
        if truth == TruthLevel::Ideal {
            assert!(end_degps < 0.5);
            assert!(first_below.unwrap() <= 3.0 * orbit_s());
        }
    }
}

/// The error at the end of the plan (where the loop switches from Slew to Tracking)
/// and at the end of the run; `None` if the plan never completed.
fn slew_end_error(samples: &[Sample]) -> Option<(f64, f64)> {
    let end = samples
        .windows(2)
        .find(|w| w[0].mode == Mode::Slew && w[1].mode == Mode::Tracking)
        .map(|w| w[1].pointing_error_deg.unwrap())?;
    Some((end, samples.last().unwrap().pointing_error_deg.unwrap()))
}

/// The thesis slews (seed 000 ch. 12) against the thesis's figures: `noisy` the 1 % noise test.
fn thesis_slew(noisy: bool, limit_deg: f64, thesis_deg: f64) {
    let name = if noisy {
        "thesis-slew-noisy"
    } else {
        "thesis-slew"
    };
    for truth in TRUTHS {
        let samples = fly(scenarios::thesis_slew(noisy), truth);
        report(name, truth, &samples);
        bounded(&samples);
        let end = slew_end_error(&samples);
        let (met, figure) = match end {
            Some((plan_end, closed)) => {
                figure(&key(name, truth, "plan_end_deg"), plan_end);
                figure(&key(name, truth, "run_end_deg"), closed);
                println!("{name} ({} truth): error at the end of the plan {plan_end:.4}° (thesis {thesis_deg}°), after tracking {closed:.4}°", truth.name());
                (
                    plan_end <= limit_deg,
                    format!("{plan_end:.3}°; {closed:.3}° after tracking"),
                )
            }
            None => (false, "the plan never completed".to_string()),
        };
        requirement(
            name,
            truth,
            &format!("≤ {limit_deg}° at the end of the plan"),
            met,
            &figure,
        );
        if truth == TruthLevel::Ideal {
            let (plan_end, _) = end.expect("the slew completed");
            assert!(plan_end <= limit_deg, "{plan_end}");
        }
    }
}

#[test]
fn thesis_slew_ideal_sensors() {
    thesis_slew(false, 0.15, 0.148);
}

/// In the realistic truth the thesis's noise model gives way to the realistic sensors: the two
/// thesis slews are then the same run.
#[test]
fn thesis_slew_one_percent_noise() {
    thesis_slew(true, 0.45, 0.42);
}

/// When the pointing error first falls below `limit_deg` (`None`: never), and the worst error
/// from 600 s later (from 600 s if it never falls below) to the end (the requirement's "within
/// one orbit and after"; ∞ if no step is left after it).
fn settling(samples: &[Sample], limit_deg: f64) -> (Option<f64>, f64) {
    let settled_at = samples
        .iter()
        .find(|s| s.pointing_error_deg.unwrap() < limit_deg)
        .map(|s| s.t_s);
    let tail = samples
        .iter()
        .filter(|s| s.t_s > settled_at.unwrap_or(0.0) + 600.0)
        .filter_map(|s| s.pointing_error_deg)
        .reduce(f64::max)
        .unwrap_or(f64::INFINITY);
    (settled_at, tail)
}

/// `tracking` in the realistic truth over seeds 1–8 (the truth's and the sensors' draws): how far
/// one seed's tail figure moves (`docs/simulator.md`), the spread of the worst and the RMS
/// pointing error from 1 200 s on.
#[test]
fn tracking_realistic_over_seeds() {
    let tails: Vec<(f64, f64)> = (1..=8)
        .map(|seed| {
            let mut sc = scenarios::tracking(None)
                .unwrap()
                .with_truth(TruthLevel::Realistic);
            sc.sim.seed = seed;
            let samples = sc.run().unwrap();
            no_nan(&samples);
            steady(&samples, 1200.0)
        })
        .collect();
    let span = |v: Vec<f64>| {
        let min = v.iter().copied().fold(f64::INFINITY, f64::min);
        (min, v.iter().copied().fold(0.0, f64::max))
    };
    let (worst, rms) = (
        span(tails.iter().map(|t| t.0).collect()),
        span(tails.iter().map(|t| t.1).collect()),
    );
    let k = |what: &str| format!("closed_loop.tracking.realistic.seeds_1_8.{what}");
    figure(&k("from_1200_worst_min_deg"), worst.0);
    figure(&k("from_1200_worst_max_deg"), worst.1);
    figure(&k("from_1200_rms_min_deg"), rms.0);
    figure(&k("from_1200_rms_max_deg"), rms.1);
    assert!(worst.1.is_finite() && rms.1 > 0.0);
}

/// `tracking` in the ideal truth over seeds 1–24 (the sensors' draws), with the flight
/// configuration: how many seeds meet the requirement (< 0.1° within one orbit and from 600 s
/// after settling on) and the spread of the worst error after settling (issue #29: the scenario's
/// own seed meets it with the degree-13 field model; the others say how robustly).
#[test]
fn tracking_ideal_over_seeds() {
    const REQUIREMENT_DEG: f64 = 0.1;
    let mut tails: Vec<f64> = Vec::new();
    let mut met = 0;
    for seed in 1..=24 {
        let mut sc = scenarios::tracking(None)
            .unwrap()
            .with_truth(TruthLevel::Ideal);
        sc.sim.seed = seed;
        let samples = sc.run().unwrap();
        no_nan(&samples);
        let (settled_at, tail) = settling(&samples, REQUIREMENT_DEG);
        assert!(settled_at.is_some_and(|t| t < orbit_s()), "seed {seed}");
        met += usize::from(tail < REQUIREMENT_DEG);
        tails.push(tail);
    }
    tails.sort_by(f64::total_cmp);
    let median = (tails[11] + tails[12]) / 2.0;
    let k = |what: &str| format!("closed_loop.tracking.ideal.seeds_1_24.{what}");
    figure(&k("met"), met);
    figure(&k("tail_min_deg"), tails[0]);
    figure(&k("tail_median_deg"), median);
    figure(&k("tail_max_deg"), tails[23]);
    println!(
        "tracking (ideal truth), seeds 1–24: requirement met in {met} of 24; worst error from 600 s after settling {:.3}° to {:.3}°, median {median:.3}°",
        tails[0], tails[23]
    );
    assert!(tails[23].is_finite());
}

/// The worst and RMS pointing error from `from_s` on.
fn steady(samples: &[Sample], from_s: f64) -> (f64, f64) {
    let v: Vec<f64> = samples
        .iter()
        .filter(|s| s.t_s >= from_s)
        .filter_map(|s| s.pointing_error_deg)
        .collect();
    let worst = v.iter().copied().fold(0.0, f64::max);
    let rms = (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt();
    (worst, rms)
}

/// A field model's difference to the truth along a scenario's orbit: the largest
/// `|B_truth − B_model|` (nT) and, while the Sun is seen, the largest angle between the two
/// fields' projections on the plane normal to the Sun (degrees): with the Sun and the field as
/// the two observations, that is the error of the attitude about the Sun line the field model
/// alone makes, whatever the sensors, weights or filter. In the ideal truth (IGRF-14 at degree
/// 13) it is the model's truncation.
fn field_model_error(scenario: &Scenario, model: &Model, degree: Degree) -> (f64, f64) {
    use acs::env::igrf::{Igrf, FULL_COEFFS};
    let mut sim = scenario.simulator().unwrap();
    let steps = (scenario.duration_s / scenario.dt_s).round() as usize;
    let (mut max_nt, mut max_deg) = (0.0f64, 0.0f64);
    for _ in 0..steps {
        let env = sim.env().clone();
        let epoch = sim.epoch_at(sim.truth().t_s);
        let gmst = acs::time::gmst_rad_f64(&epoch.to_ut1(None).unwrap()) as f32;
        let flight = Igrf::<FULL_COEFFS>::from_epoch(model, &epoch, degree)
            .unwrap()
            .teme(&env.r_teme_km.cast::<f32>(), gmst)
            .unwrap()
            .cast::<f64>();
        let truth = env.b_teme_nt;
        max_nt = max_nt.max((truth - flight).norm());
        if env.sun_fraction > 0.5 {
            let s = env.sun_teme.normalize();
            let p = (flight - s * s.dot(&flight)).normalize();
            let q = (truth - s * s.dot(&truth)).normalize();
            max_deg = max_deg.max(p.cross(&q).norm().atan2(p.dot(&q)).to_degrees());
        }
        sim.advance(scenario.dt_s).unwrap();
    }
    (max_nt, max_deg)
}

/// The tracking requirement, < 0.1° within one orbit and after, asserted in the ideal truth
/// with the flight configuration: IGRF at degree 13 on board since issue #29 (item 6), the
/// truth's own field model. The test also flies the same run with the field model at degree 8,
/// the flight model before #29, which did not meet it: its truncation alone turns the attitude
/// about the Sun line by up to 0.11° on this orbit (degrees 9–13 are up to 105 nT at 500 km);
/// both truncations are measured here from the models, not copied. In the realistic truth it
/// prints the figures (and `realistic_figures_by_cause` their causes).
#[test]
fn tracking_with_wheels_and_noisy_tiles() {
    use acs::acs_loop::AcsConfig;
    use acs::env::igrf::coefficient_count;
    use acs::flight::TILES;
    use acs::two_node::TwoNodeLoop;
    const REQUIREMENT_DEG: f64 = 0.1;
    for truth in TRUTHS {
        let scenario = scenarios::tracking(None).unwrap().with_truth(truth);
        let samples = scenario.run().unwrap();
        report("tracking", truth, &samples);
        bounded(&samples);
        let (settled_at, tail) = settling(&samples, REQUIREMENT_DEG);
        let target = scenario.target.unwrap();
        let after: Vec<&Sample> = samples
            .iter()
            .filter(|s| s.t_s > settled_at.unwrap_or(0.0) + 600.0)
            .collect();
        let control = after
            .iter()
            .filter_map(|s| s.report.attitude)
            .map(|q| angle_between_deg(&target, &q))
            .fold(0.0, f64::max);
        let determination = after
            .iter()
            .filter_map(|s| s.estimate_error_deg)
            .fold(0.0, f64::max);
        let (worst, rms) = steady(&samples, 1200.0);
        let since = settled_at.map_or("never".to_string(), |t| format!("after {t:.0} s"));
        figure(
            &key("tracking", truth, "settled_s"),
            settled_at.map_or("never".to_string(), |t| t.to_string()),
        );
        figure(&key("tracking", truth, "tail_deg"), tail);
        figure(&key("tracking", truth, "from_1200_worst_deg"), worst);
        figure(&key("tracking", truth, "from_1200_rms_deg"), rms);
        figure(&key("tracking", truth, "tail_control_deg"), control);
        figure(
            &key("tracking", truth, "tail_determination_deg"),
            determination,
        );
        println!(
            "tracking ({} truth): below {REQUIREMENT_DEG}° {since}; worst from 600 s later on {tail:.4}° (filtered attitude against the target {control:.4}°, against the truth {determination:.4}°); from 1 200 s on worst {worst:.4}°, RMS {rms:.4}°",
            truth.name()
        );
        let met = settled_at.is_some_and(|t| t < orbit_s()) && tail < REQUIREMENT_DEG;
        if truth == TruthLevel::Ideal {
            let (model_nt, model_deg) =
                field_model_error(&scenario, CONFIG.igrf_model.model(), CONFIG.igrf_degree);
            // the flight configuration at degree 8, as it flew before issue #29
            let eight = Degree::new(8).unwrap();
            let (truncation_nt, truncation_deg) =
                field_model_error(&scenario, CONFIG.igrf_model.model(), eight);
            let degree_8 = AcsConfig {
                igrf_degree: eight,
                ..CONFIG.clone()
            };
            let mut acs = TwoNodeLoop::<TILES, { coefficient_count(8) }>::new(
                &degree_8,
                scenario.orbit().unwrap(),
            )
            .unwrap();
            let (settled_8, tail_8) = settling(&scenario.fly(&mut acs).unwrap(), REQUIREMENT_DEG);
            figure(&key("tracking", truth, "field_model_nt"), model_nt);
            figure(&key("tracking", truth, "field_model_deg"), model_deg);
            figure(
                &key("tracking", truth, "truncation_degree_8_nt"),
                truncation_nt,
            );
            figure(
                &key("tracking", truth, "truncation_degree_8_deg"),
                truncation_deg,
            );
            figure(&key("tracking", truth, "tail_degree_8_deg"), tail_8);
            println!(
                "tracking (ideal truth): the flight field model (degree {}) against the truth on this orbit: up to {model_nt:.4} nT, {model_deg:.6}° about the Sun line; degree 8 (the flight model before #29): up to {truncation_nt:.1} nT, {truncation_deg:.4}° about the Sun line, and the same run with it on board: {tail_8:.4}° at worst from 600 s after settling",
                CONFIG.igrf_degree.get()
            );
            requirement(
                "tracking",
                truth,
                "< 0.1° within one orbit and after",
                met,
                &format!("below 0.1° {since}; {tail:.3}° at worst from 600 s later on (with the degree-8 field model of before #29: {tail_8:.3}°)"),
            );
            // the flight model is the truth's but for f32 rounding: the truth's tables (`FULL`)
            // count the date from 1900, so 125 + the year's fraction rounds (3.8e-6 yr, ≤ 0.001
            // nT at ≤ 165 nT/yr) and the coefficients at the date may differ by an ulp, after
            // which the two f32 syntheses round differently, each within 0.02 nT of the f64
            // synthesis (`tests/igrf.rs`, `f32_error_against_f64_synthesis`): ≤ 0.041 nT
            assert!(model_nt < 0.041, "{model_nt}");
            let settled_at = settled_at.expect("the error falls below the limit");
            assert!(settled_at < orbit_s());
            assert!(tail < REQUIREMENT_DEG, "{tail}");
            // degree 8: the requirement plus its truncation error, plus what the filter's
            // magnetometer-bias state makes of a slowly varying model error (it takes part of
            // it for a bias, which turns the estimate when the error changes: measured 0.220°
            // with the state, 0.203° with it frozen, against 0.212° for the first two): a fifth
            // of the truncation error at most
            assert!(settled_8.is_some_and(|t| t < orbit_s()));
            assert!(tail_8 < REQUIREMENT_DEG + 1.2 * truncation_deg, "{tail_8}");
        } else {
            requirement(
                "tracking",
                truth,
                "< 0.1° within one orbit and after",
                met,
                &format!("below 0.1° {since}; {tail:.3}° at worst from 600 s later on; from 1 200 s on {worst:.3}° worst, {rms:.3}° RMS (causes: realistic_figures_by_cause)"),
            );
        }
    }
}

/// The flight configuration's slew: the plan, flown in closed loop on its reference trajectory,
/// completes within the commanded time and tracking then converges (asserted in the ideal
/// truth); in both truths it ends within 1° of its target (issue #30's goal for the `slew`
/// campaign, asserted on this run).
#[test]
fn flight_slew_completes_and_converges() {
    for truth in TRUTHS {
        let samples = fly(scenarios::slew(), truth);
        report("slew", truth, &samples);
        bounded(&samples);
        let begun = samples
            .iter()
            .find(|s| s.mode == Mode::Slew)
            .expect("the slew was accepted")
            .t_s;
        let ended = samples
            .windows(2)
            .find(|w| w[0].mode == Mode::Slew && w[1].mode == Mode::Tracking)
            .map(|w| w[1].t_s);
        match (ended, slew_end_error(&samples)) {
            (Some(ended), Some((plan_end, closed))) => {
                figure(&key("slew", truth, "plan_begin_s"), begun);
                figure(&key("slew", truth, "plan_end_s"), ended);
                figure(&key("slew", truth, "plan_end_deg"), plan_end);
                figure(&key("slew", truth, "run_end_deg"), closed);
                println!(
                    "slew ({} truth): plan from {begun:.0} s to {ended:.0} s, error at its end {plan_end:.3}°, {closed:.3}° at the end of the run",
                    truth.name()
                );
                assert!(plan_end <= 1.0, "{plan_end}");
                if truth == TruthLevel::Ideal {
                    assert!(ended - begun <= 300.0);
                    assert!(closed < 0.5, "{closed}");
                }
            }
            _ => {
                println!("slew ({} truth): the plan never completed", truth.name());
                assert!(truth != TruthLevel::Ideal, "the slew completed");
            }
        }
    }
}

#[test]
fn failed_tile_still_converges() {
    for truth in TRUTHS {
        let samples = fly(scenarios::tracking(Some(2)), truth);
        report("failed-tile", truth, &samples);
        bounded(&samples);
        let end = samples.last().unwrap().pointing_error_deg.unwrap();
        let (worst, rms) = steady(&samples, 1200.0);
        figure(&key("failed-tile", truth, "end_deg"), end);
        figure(&key("failed-tile", truth, "from_1200_worst_deg"), worst);
        figure(&key("failed-tile", truth, "from_1200_rms_deg"), rms);
        requirement(
            "failed-tile",
            truth,
            "still converges",
            end < 0.5,
            &format!(
                "{end:.3}° at the end of the orbit; from 1 200 s on {worst:.3}° worst, {rms:.3}° RMS"
            ),
        );
        if truth == TruthLevel::Ideal {
            assert!(end < 0.5, "{end}");
        }
    }
}

#[test]
fn sun_safe_through_a_whole_eclipse() {
    for truth in TRUTHS {
        let samples = fly(scenarios::sun_safe(), truth);
        report("sun-safe", truth, &samples);
        bounded(&samples);
        let dark: Vec<&Sample> = samples.iter().filter(|s| s.sun_fraction == 0.0).collect();
        println!(
            "sun-safe ({} truth): {} s in umbra",
            truth.name(),
            dark.len()
        );
        assert!(
            dark.len() > 1000,
            "the scenario must contain a whole eclipse"
        );
        // in the umbra no attitude is measured: the loop runs gyro/magnetometer laws, never NaN
        let measured_in_umbra = dark
            .iter()
            .filter(|s| s.report.measured_attitude.is_some())
            .count();
        let end_degps = samples.last().unwrap().omega_true.norm().to_degrees();
        figure(&key("sun-safe", truth, "umbra_s"), dark.len());
        figure(&key("sun-safe", truth, "end_degps"), end_degps);
        requirement(
            "sun-safe",
            truth,
            "no NaN, actuators safe or gyro/magnetometer laws",
            measured_in_umbra == 0,
            &format!(
                "no NaN through {} s of umbra ({measured_in_umbra} attitudes measured there); {end_degps:.4}°/s at the end",
                dark.len()
            ),
        );
        if truth == TruthLevel::Ideal {
            assert_eq!(measured_in_umbra, 0);
        }
    }
}

/// The worst and the 99th percentile (nearest rank) of the pointing errors of `samples` (NaN
/// when there are none).
fn worst_and_p99(samples: &[&Sample]) -> (f64, f64) {
    let mut v: Vec<f64> = samples
        .iter()
        .filter_map(|s| s.pointing_error_deg)
        .collect();
    if v.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    v.sort_by(f64::total_cmp);
    let rank = ((0.99 * v.len() as f64).ceil() as usize).clamp(1, v.len());
    (v[v.len() - 1], v[rank - 1])
}

/// `tracking-eclipse` (issue #30): `tracking` on a noon-midnight orbit (β ≈ 0, the longest
/// umbra at 500 km), three orbits. The geometry is measured from the truth's own orbit and Sun:
/// β along the run and each umbra (the conical model, `acs::env::eclipse::conical`, the
/// samples' `sun_fraction` 0). After the first orbit, the worst and p99 pointing error in the
/// umbra and in sunlight (every step outside the umbra, the penumbra's few seconds included)
/// separately, the steps in SunSafe and the falls back to it, the fraction of sunlit steps, and
/// the filter's consistency: the share of steps whose estimate error is within three times its
/// own total 1σ (`StepReport::attitude_sigma_rad`), in sunlight and in the umbra. The issue's
/// goals (ideal truth: ≤ 0.5° worst and ≤ 0.4° p99 in the umbra and in sunlight; realistic: ≤ 3°
/// worst in the umbra and within 3σ at ≥ 99 % of the sunlit steps; neither falls back to
/// SunSafe) are printed as met or not met and not asserted. Asserted: no NaN and a bounded
/// motion, and the geometry (β within 0.05°, every umbra within 1 % of the cylindrical
/// shadow's length).
#[test]
fn tracking_eclipse() {
    const NAME: &str = "tracking-eclipse";
    let orbit = orbit_s();
    // the geometry, from the truth (the same orbit in both truths)
    let scenario = scenarios::tracking_eclipse().unwrap();
    let mut sim = scenario.simulator().unwrap();
    let (mut beta_min, mut beta_max) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut period_s = 0.0;
    let mut t = 0.0;
    while t <= scenario.duration_s {
        let env = sim.env();
        let n = env.r_teme_km.cross(&env.v_teme_kmps);
        if t == 0.0 {
            // the Keplerian period of the initial osculating state
            let mu = 398_600.441_8;
            let a = 1.0 / (2.0 / env.r_teme_km.norm() - env.v_teme_kmps.norm_squared() / mu);
            period_s = 2.0 * std::f64::consts::PI * (a * a * a / mu).sqrt();
        }
        let beta = n.normalize().dot(&env.sun_teme).asin().to_degrees();
        beta_min = beta_min.min(beta);
        beta_max = beta_max.max(beta);
        sim.advance(60.0).unwrap();
        t += 60.0;
    }
    figure(&format!("closed_loop.{NAME}.beta_min_deg"), beta_min);
    figure(&format!("closed_loop.{NAME}.beta_max_deg"), beta_max);
    assert!(
        beta_min.abs() < 0.05 && beta_max.abs() < 0.05,
        "β {beta_min}..{beta_max}"
    );
    // the cylindrical shadow at β = 0: the fraction acos(√(h² + 2R⊕h) / r) / π of the orbit
    let r_km = 6378.137 + 500.0;
    let h_km: f64 = 500.0;
    let cylinder_s = ((h_km * h_km + 2.0 * 6378.137 * h_km).sqrt() / r_km).acos()
        / std::f64::consts::PI
        * period_s;
    figure(&format!("closed_loop.{NAME}.cylinder_umbra_s"), cylinder_s);

    for truth in TRUTHS {
        let scenario = scenarios::tracking_eclipse().unwrap().with_truth(truth);
        let samples = scenario.run().unwrap();
        report(NAME, truth, &samples);
        bounded(&samples);
        assert!(samples.last().unwrap().t_s >= 3.0 * period_s);
        // each umbra: (entry, seconds)
        let mut passes: Vec<(f64, f64)> = Vec::new();
        for w in samples.windows(2) {
            match (w[0].sun_fraction == 0.0, w[1].sun_fraction == 0.0) {
                (false, true) => passes.push((w[1].t_s, scenario.dt_s)),
                (true, true) => {
                    if let Some(p) = passes.last_mut() {
                        p.1 += scenario.dt_s;
                    }
                }
                _ => {}
            }
        }
        let whole: Vec<f64> = passes
            .iter()
            .filter(|(entry, s)| *entry + s < samples.last().unwrap().t_s)
            .map(|p| p.1)
            .collect();
        assert!(whole.len() >= 3, "{passes:?}");
        for s in &whole {
            assert!((s / cylinder_s - 1.0).abs() < 0.01, "{s} s of umbra");
        }
        let list = |v: &[f64]| {
            v.iter()
                .map(|x| format!("{x:.0}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        figure(&key(NAME, truth, "umbra_passes_s"), list(&whole));
        figure(
            &key(NAME, truth, "umbra_entries_s"),
            list(&passes.iter().map(|p| p.0).collect::<Vec<_>>()),
        );

        // the steps after the first orbit (half a step of margin: the clocks' f64 sums)
        let after: Vec<&Sample> = samples
            .iter()
            .filter(|s| s.t_s > orbit + 0.5 * scenario.dt_s)
            .collect();
        // the first umbra while the loop still tracks: how far the attitude drifted before any
        // fall-back
        let first_umbra: Vec<&Sample> = samples
            .iter()
            .filter(|s| {
                passes
                    .first()
                    .is_some_and(|(entry, len)| s.t_s >= *entry && s.t_s < entry + len)
                    && s.mode == Mode::Tracking
            })
            .collect();
        let (first_umbra_worst, _) = worst_and_p99(&first_umbra);
        figure(
            &key(NAME, truth, "first_umbra_tracking_s"),
            first_umbra.len() as f64 * scenario.dt_s,
        );
        figure(
            &key(NAME, truth, "first_umbra_tracking_worst_deg"),
            first_umbra_worst,
        );
        let (umbra, sunlit): (Vec<&Sample>, Vec<&Sample>) =
            after.iter().partition(|s| s.sun_fraction == 0.0);
        let (umbra_worst, umbra_p99) = worst_and_p99(&umbra);
        let (sunlit_worst, sunlit_p99) = worst_and_p99(&sunlit);
        let sun_safe_steps = after.iter().filter(|s| s.mode == Mode::SunSafe).count();
        let fallbacks = samples
            .windows(2)
            .filter(|w| {
                matches!(w[0].mode, Mode::Slew | Mode::Tracking) && w[1].mode == Mode::SunSafe
            })
            .map(|w| w[1].t_s)
            .collect::<Vec<_>>();
        let sunlit_fraction = sunlit.len() as f64 / after.len() as f64;
        figure(
            &key(NAME, truth, "after_orbit_umbra_worst_deg"),
            umbra_worst,
        );
        figure(&key(NAME, truth, "after_orbit_umbra_p99_deg"), umbra_p99);
        figure(
            &key(NAME, truth, "after_orbit_sunlit_worst_deg"),
            sunlit_worst,
        );
        figure(&key(NAME, truth, "after_orbit_sunlit_p99_deg"), sunlit_p99);
        figure(
            &key(NAME, truth, "after_orbit_sun_safe_steps"),
            sun_safe_steps,
        );
        figure(&key(NAME, truth, "after_orbit_steps"), after.len());
        figure(
            &key(NAME, truth, "after_orbit_sunlit_fraction"),
            sunlit_fraction,
        );
        figure(&key(NAME, truth, "fallbacks"), fallbacks.len());
        figure(&key(NAME, truth, "fallbacks_at_s"), list(&fallbacks));
        // the filter's consistency: the estimate's error angle within three times its total
        // 1σ, √(σx² + σy² + σz²) (the samples carry the error's angle, not its axes)
        let consistent = |v: &[&Sample]| {
            let within = v
                .iter()
                .filter(
                    |s| match (s.estimate_error_deg, s.report.attitude_sigma_rad) {
                        (Some(e), Some(sigma)) => e <= 3.0 * f64::from(sigma.norm()).to_degrees(),
                        _ => false,
                    },
                )
                .count();
            within as f64 / v.len().max(1) as f64
        };
        let (sunlit_3sigma, umbra_3sigma) = (consistent(&sunlit), consistent(&umbra));
        figure(
            &key(NAME, truth, "after_orbit_sunlit_within_3_sigma"),
            sunlit_3sigma,
        );
        figure(
            &key(NAME, truth, "after_orbit_umbra_within_3_sigma"),
            umbra_3sigma,
        );
        println!(
            "{NAME} ({} truth): after the first orbit, umbra worst {umbra_worst:.3}° p99 {umbra_p99:.3}° ({} steps), sunlight worst {sunlit_worst:.3}° p99 {sunlit_p99:.3}° ({} steps, {:.1} % of them); {sun_safe_steps} steps in SunSafe; fall-backs at {:?} s",
            truth.name(),
            umbra.len(),
            sunlit.len(),
            100.0 * sunlit_fraction,
            fallbacks
        );
        // issue #30's goals, reported, not asserted
        let no_fallback = fallbacks.is_empty();
        let (goal, met) = match truth {
            TruthLevel::Ideal => (
                "goal of #30, not asserted: after the first orbit ≤ 0.5° worst and ≤ 0.4° p99 in the umbra and in sunlight; no fall-back to SunSafe",
                umbra_worst <= 0.5
                    && umbra_p99 <= 0.4
                    && sunlit_worst <= 0.5
                    && sunlit_p99 <= 0.4
                    && no_fallback,
            ),
            TruthLevel::Realistic => (
                "goal of #30, not asserted: after the first orbit ≤ 3° worst in the umbra, the error within 3σ of the filter's own at ≥ 99 % of the sunlit steps; no fall-back to SunSafe",
                umbra_worst <= 3.0 && sunlit_3sigma >= 0.99 && no_fallback,
            ),
        };
        figures::verdict(&key(NAME, truth, "no_fallback_verdict"), no_fallback);
        requirement(
            NAME,
            truth,
            goal,
            met,
            &format!(
                "after the first orbit: umbra {umbra_worst:.3}° worst, {umbra_p99:.3}° p99; sunlight {sunlit_worst:.3}° worst, {sunlit_p99:.3}° p99; within the filter's 3σ at {:.1} % of the sunlit steps ({:.1} % in the umbra); {} fall-backs to SunSafe, {sun_safe_steps} steps in it",
                100.0 * sunlit_3sigma,
                100.0 * umbra_3sigma,
                fallbacks.len()
            ),
        );
    }
}

/// A named change of the tables.
type Part = (&'static str, fn(&mut Realism));

/// A scenario's figure flown against `realism`.
fn figure_with(
    scenario: fn() -> Result<Scenario, acs::host::sim::SimError>,
    realism: Realism,
    metric: fn(&[Sample]) -> (f64, f64),
) -> (f64, f64) {
    let mut sc = scenario().unwrap().with_truth(TruthLevel::Realistic);
    sc.sim.realism = Some(realism);
    let samples = sc.run().unwrap();
    no_nan(&samples);
    metric(&samples)
}

/// Prints a scenario's realistic figure without each effect and with it alone (the others
/// removed), and the spacecraft field split into its sources; returns the figure with no
/// effect at all.
fn causes(
    name: &str,
    figure_key: &str,
    what: &str,
    scenario: fn() -> Result<Scenario, acs::host::sim::SimError>,
    metric: fn(&[Sample]) -> (f64, f64),
) -> (f64, f64) {
    let full = Realism::DEFAULT;
    let nothing = Effect::ALL.iter().fold(full.clone(), |r, e| r.without(*e));
    let ideal = {
        let samples = scenario()
            .unwrap()
            .with_truth(TruthLevel::Ideal)
            .run()
            .unwrap();
        metric(&samples)
    };
    let all = figure_with(scenario, full.clone(), metric);
    let none = figure_with(scenario, nothing.clone(), metric);
    let fig = |what: &str, f: (f64, f64)| {
        figure(&format!("causes.{figure_key}.{what}.worst_deg"), f.0);
        figure(&format!("causes.{figure_key}.{what}.rms_deg"), f.1);
    };
    fig("ideal", ideal);
    fig("realistic", all);
    fig("nothing", none);
    println!("causes, {name} ({what}):");
    println!("  ideal truth {:.3}° / {:.3}°", ideal.0, ideal.1);
    println!("  realistic truth {:.3}° / {:.3}°", all.0, all.1);
    println!(
        "  realistic, every effect removed {:.3}° / {:.3}°",
        none.0, none.1
    );
    println!("  | effect | without it | it alone |");
    for e in Effect::ALL {
        let without = figure_with(scenario, full.without(e), metric);
        let alone = figure_with(scenario, full.only(e), metric);
        let slug = e.name().replace(' ', "_");
        fig(&format!("without.{slug}"), without);
        fig(&format!("alone.{slug}"), alone);
        println!(
            "  | {} | {:.3}° / {:.3}° | {:.3}° / {:.3}° |",
            e.name(),
            without.0,
            without.1,
            alone.0,
            alone.1
        );
    }
    let parts: [Part; 3] = [
        ("residual dipole", |r| {
            r.magnetics.rotor_dipole_am2 = 0.0;
            r.coil.time_constant_s = 0.0;
        }),
        ("wheel rotors", |r| {
            r.magnetics.residual_dipole_error_am2 = 0.0;
            r.coil.time_constant_s = 0.0;
        }),
        ("coils", |r| {
            r.magnetics.residual_dipole_error_am2 = 0.0;
            r.magnetics.rotor_dipole_am2 = 0.0;
        }),
    ];
    let wheel_parts: [Part; 2] = [
        ("wheels: torque limit alone", |r| {
            r.wheel.time_constant_s = 0.0;
            r.wheel.torque_limit_nm = Realism::DEFAULT.wheel.torque_limit_nm;
        }),
        ("wheels: speed loop, friction, quanta alone", |r| {
            let w = Realism::DEFAULT.wheel;
            r.wheel = acs::host::sim::realistic::WheelModel {
                torque_limit_nm: f64::INFINITY,
                ..w
            };
        }),
    ];
    for (part, set) in wheel_parts {
        let mut alone = full.only(Effect::Wheel).without(Effect::Wheel);
        set(&mut alone);
        let f = figure_with(scenario, alone, metric);
        fig(&format!("alone.{}", part.replace([' ', ':', ','], "_")), f);
        println!("  | {part} | | {:.3}° / {:.3}° |", f.0, f.1);
    }
    for (part, keep) in parts {
        let mut alone = full.only(Effect::SpacecraftField);
        // the coils' decay needs their time constant and the read latency kept
        alone.coil.time_constant_s = full.coil.time_constant_s;
        alone.timing = full.timing.clone();
        keep(&mut alone);
        let f = figure_with(scenario, alone, metric);
        fig(
            &format!("alone.spacecraft_field.{}", part.replace(' ', "_")),
            f,
        );
        println!(
            "  | spacecraft field: {part} alone | | {:.3}° / {:.3}° |",
            f.0, f.1
        );
    }
    none
}

/// Issue #30 item 2: the albedo answer against the truth's albedo at 0.20, 0.30 and 0.45 while
/// the flight model starts from 0.30 ± 50 % (`flight::FILTER`) and estimates it: the worst and
/// RMS pointing error in sunlight, `tracking` from 1 200 s on and `tracking-eclipse` after the
/// first orbit. Printed with the criterion (each within 20 % of the 0.30 figure), not
/// asserted; asserted: no NaN.
#[test]
fn albedo_robustness() {
    fn sunlit(s: &[Sample], from_s: f64) -> (f64, f64) {
        let v: Vec<f64> = s
            .iter()
            .filter(|s| s.t_s >= from_s && s.sun_fraction > 0.0)
            .filter_map(|s| s.pointing_error_deg)
            .collect();
        let worst = v.iter().copied().fold(0.0, f64::max);
        let rms = (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt();
        (worst, rms)
    }
    type ScenarioFn = fn() -> Result<Scenario, acs::host::sim::SimError>;
    let scenarios: [(&str, ScenarioFn, f64); 2] = [
        ("tracking", || scenarios::tracking(None), 1200.0),
        ("tracking-eclipse", scenarios::tracking_eclipse, orbit_s()),
    ];
    for (name, scenario, from_s) in scenarios {
        let mut worst = Vec::new();
        for albedo in [0.20, 0.30, 0.45] {
            let mut realism = Realism::DEFAULT;
            realism.sun_sensor.albedo = albedo;
            let mut sc = scenario().unwrap().with_truth(TruthLevel::Realistic);
            sc.sim.realism = Some(realism);
            let samples = sc.run().unwrap();
            no_nan(&samples);
            let (w, rms) = sunlit(&samples, from_s);
            figure(
                &format!("closed_loop.albedo.{name}.{albedo:.2}.sunlit_worst_deg"),
                w,
            );
            figure(
                &format!("closed_loop.albedo.{name}.{albedo:.2}.sunlit_rms_deg"),
                rms,
            );
            worst.push(w);
        }
        let holds = worst.iter().all(|w| *w <= 1.2 * worst[1]);
        figures::verdict(&format!("closed_loop.albedo.{name}.holds"), holds);
        println!(
            "albedo {name}: sunlit worst {:.3}° / {:.3}° / {:.3}° at a truth albedo of 0.20 / 0.30 / 0.45 (holds within 20 %: {holds})",
            worst[0], worst[1], worst[2]
        );
    }
}

/// The worst figures of the realistic truth, effect by effect (printed; asserted only that with
/// every effect removed the figures come back to the ideal truth's size).
#[test]
fn realistic_figures_by_cause() {
    fn tracking() -> Result<Scenario, acs::host::sim::SimError> {
        scenarios::tracking(None)
    }
    fn thesis() -> Result<Scenario, acs::host::sim::SimError> {
        scenarios::thesis_slew(false)
    }
    fn tracking_tail(s: &[Sample]) -> (f64, f64) {
        steady(s, 1200.0)
    }
    fn transient(s: &[Sample]) -> (f64, f64) {
        let v: Vec<f64> = s
            .iter()
            .filter(|x| x.t_s >= 200.0 && x.t_s < 1200.0)
            .filter_map(|x| x.pointing_error_deg)
            .collect();
        let worst = v.iter().copied().fold(0.0, f64::max);
        (
            worst,
            (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt(),
        )
    }
    fn plan_end(s: &[Sample]) -> (f64, f64) {
        slew_end_error(s).unwrap_or((f64::INFINITY, f64::INFINITY))
    }
    let none = causes(
        "tracking",
        "tracking_tail",
        "worst / RMS pointing error from 1 200 s on",
        tracking,
        tracking_tail,
    );
    assert!(none.0 < 0.2, "{none:?}");
    causes(
        "tracking",
        "tracking_transient",
        "worst / RMS pointing error from 200 s to 1 200 s",
        tracking,
        transient,
    );
    let none = causes(
        "thesis-slew",
        "thesis_slew",
        "error at the end of the plan / at the end of the run",
        thesis,
        plan_end,
    );
    assert!(none.0 < 0.15, "{none:?}");
}

#[test]
fn loop_state_size() {
    use acs::acs_loop::AcsConfig;
    use acs::attitude_node::AttitudeNode;
    use acs::flight::{FlightLoop, OneImageLoop, FIELD_COEFFS};
    use acs::reference_node::ReferenceNode;
    use std::mem::size_of;
    let orbit = size_of::<acs::orbit::sgp4::Sgp4>();
    // each node borrows the configuration (in flash on the MSP430): only a reference is inside;
    // the IGRF coefficients are not kept between steps (the field evaluation's stack)
    let reference = size_of::<&AcsConfig>();
    // sized as the flight images are: six tiles, the flight degree's coefficients
    let attitude = size_of::<AttitudeNode<6>>();
    let reference_node = size_of::<ReferenceNode<6, FIELD_COEFFS>>();
    println!(
        "AttitudeNode<6> {attitude} B = state {} B + a reference to the configuration (host, 64-bit)",
        attitude - reference
    );
    println!(
        "ReferenceNode<6, {FIELD_COEFFS}> {reference_node} B = SGP4 elements {orbit} B + state {} B + a reference to the configuration (host, 64-bit)",
        reference_node - orbit - reference
    );
    // the attitude filter's state (issue #30: a 10-state covariance, 55 × 4 B) took it past 512;
    // the actuators' read-back checks (issue #31) to 656 B, the stuck-gyro watch
    // (`attitude_node::stuck`, 30 B, and the filter's correction of the step, 12 B) to 696 B
    assert!(attitude - reference <= 704);
    // a slew's reference trajectory (issue #30 item 4: three rotations' profiles and the
    // attitude they start at, 152 B on the host) took it past 160: measured 232 B
    assert!(reference_node - orbit - reference <= 240);
    // the composition: both nodes, the last STATUS and the last two packets; the one image
    println!(
        "FlightLoop (the two nodes composed) {} B, OneImageLoop {} B (host, 64-bit)",
        size_of::<FlightLoop>(),
        size_of::<OneImageLoop>()
    );
    // the per-tile state shrinks with the capacity, and the configuration is not part of a node
    assert!(attitude < size_of::<AttitudeNode>());
}

/// The `tracking` scenario, its TLE and the flight SGP4 of it.
fn tracking_setup() -> (scenarios::Scenario, acs::tle::Tle, acs::orbit::sgp4::Sgp4) {
    let scenario = scenarios::tracking(None)
        .unwrap()
        .with_truth(TruthLevel::Ideal);
    let tle = acs::tle::Tle::parse(&scenario.sim.tle.0, &scenario.sim.tle.1).unwrap();
    let orbit = acs::orbit::sgp4::Sgp4::new(&tle, scenario.gravity).unwrap();
    (scenario, tle, orbit)
}

/// A tile bus with constant readings (no Sun, a field and rates that differ per tile) that
/// records the wheel commands.
struct WheelRecorder(Vec<(usize, f32)>);

impl acs::hal::TileBus for WheelRecorder {
    fn read_sun(&mut self, _: usize) -> Result<Option<[i16; 2]>, acs::hal::ErrorKind> {
        Ok(None)
    }
    fn read_magnetometer(&mut self, tile: usize) -> Result<[i16; 2], acs::hal::ErrorKind> {
        Ok([100 + tile as i16 * 300, -200])
    }
    fn read_gyro(&mut self, tile: usize) -> Result<i16, acs::hal::ErrorKind> {
        Ok(20 - tile as i16 * 7)
    }
    fn set_wheel_momentum(&mut self, tile: usize, h_nms: f32) -> Result<(), acs::hal::ErrorKind> {
        self.0.push((tile, h_nms));
        Ok(())
    }
    fn set_dipole(&mut self, _: usize, _: f32) -> Result<(), acs::hal::ErrorKind> {
        Ok(())
    }
    fn delay_us(&mut self, _: u32) {}
}

/// With every wheel failed the allocation has nothing to work with: every wheel-equipped tile
/// is still commanded to zero momentum (stopped), not left at its last command.
#[test]
fn no_working_wheel_stops_every_wheel() {
    let (_, tle, orbit) = tracking_setup();
    let mut acs = FlightLoop::new(&CONFIG, orbit).unwrap();
    let wheel_tiles: Vec<usize> = (0..acs.tiles().len())
        .filter(|&i| acs.tiles()[i].equipment.reaction_wheel)
        .collect();
    assert!(!wheel_tiles.is_empty());
    for &i in &wheel_tiles {
        acs.mark_failed(i);
    }
    let mut bus = WheelRecorder(Vec::new());
    let now = tle.epoch.add(acs::time::TimeSpan::new(60, 0));
    acs.step(&mut bus, now, 1.0);
    for &i in &wheel_tiles {
        assert!(
            bus.0.contains(&(i, 0.0)),
            "wheel of tile {i} not stopped: {:?}",
            bus.0
        );
    }
}

/// A loop without room for the configured IGRF degree's coefficients is refused: a loop with
/// room for degree 8 (the flight loop's before issue #29) refuses the flight configuration
/// (degree 13), and takes it at degree 8; a loop of the flight loop's size takes both.
#[test]
fn igrf_capacity_is_checked() {
    use acs::acs_loop::{AcsConfig, AcsError};
    use acs::env::igrf::coefficient_count;
    use acs::flight::{FIELD_COEFFS, TILES};
    use acs::two_node::TwoNodeLoop as AcsLoop;
    let (_, _, orbit) = tracking_setup();
    let degree_8 = AcsConfig {
        igrf_degree: Degree::new(8).unwrap(),
        ..CONFIG.clone()
    };
    const F8: usize = coefficient_count(8);
    assert_eq!(CONFIG.igrf_degree, Degree::FULL);
    assert_eq!(
        AcsLoop::<TILES, F8>::new(&CONFIG, orbit.clone()).err(),
        Some(AcsError::InvalidConfig)
    );
    assert!(AcsLoop::<TILES, F8>::new(&degree_8, orbit.clone()).is_ok());
    assert!(AcsLoop::<TILES, FIELD_COEFFS>::new(&degree_8, orbit.clone()).is_ok());
    assert!(FlightLoop::new(&CONFIG, orbit).is_ok());
}

/// A tile marked failed and restored by the ground is used again: its wheel is commanded by the
/// allocation (rebuilt for the new working set), not held at zero.
#[test]
fn restored_tile_returns_to_service() {
    use acs::tiles::TileState;

    let (_, tle, orbit) = tracking_setup();
    let mut acs = FlightLoop::new(&CONFIG, orbit).unwrap();
    let tile = (0..acs.tiles().len())
        .find(|&i| acs.tiles()[i].equipment.reaction_wheel)
        .unwrap();
    acs.mark_failed(tile);
    let mut t = tle.epoch.add(acs::time::TimeSpan::new(60, 0));
    let mut bus = WheelRecorder(Vec::new());
    for _ in 0..3 {
        acs.step(&mut bus, t, 1.0);
        t = t.add(acs::time::TimeSpan::new(1, 0));
    }
    assert!(bus
        .0
        .iter()
        .filter(|(i, _)| *i == tile)
        .all(|(_, h)| *h == 0.0));
    acs.restore(tile);
    assert_eq!(acs.tile_state(tile), Some(TileState::Working));
    let mut bus = WheelRecorder(Vec::new());
    for _ in 0..3 {
        acs.step(&mut bus, t, 1.0);
        t = t.add(acs::time::TimeSpan::new(1, 0));
    }
    assert!(
        bus.0.iter().any(|(i, h)| *i == tile && *h != 0.0),
        "restored wheel never commanded: {:?}",
        bus.0
    );
}

/// A tile bus with constant readings: the Sun on tile 1's normal (tile 0 has no ACS device), a field and rates that differ
/// per tile, magnetometers scaled by `field` (0: a stuck-at-zero field); it records the last
/// command of every wheel and coil.
struct ConstantBus {
    field: i16,
    wheels: [Option<f32>; 6],
    coils: [Option<f32>; 6],
}

impl ConstantBus {
    /// The bus with magnetometer scale `field`, nothing commanded yet.
    fn new(field: i16) -> Self {
        Self {
            field,
            wheels: [None; 6],
            coils: [None; 6],
        }
    }

    /// The bus whose field has the on-board model's magnitude at `now` on `orbit` (the loop
    /// refuses a field of any other: `acs_loop::FIELD_MAGNITUDE_TOLERANCE`).
    fn physical(orbit: &acs::orbit::sgp4::Sgp4, now: &acs::time::Epoch<acs::time::Utc>) -> Self {
        let pattern: Vec<[f32; 2]> = (0..6)
            .map(|t| [1.0 + 3.0 * t as f32, -2.0 + t as f32])
            .collect();
        let scale = common::field_scale(&pattern, orbit, now).unwrap();
        Self::new(scale.round() as i16)
    }
}

impl acs::hal::TileBus for ConstantBus {
    fn read_sun(&mut self, tile: usize) -> Result<Option<[i16; 2]>, acs::hal::ErrorKind> {
        Ok((tile == 1).then_some([0, 0]))
    }
    fn read_magnetometer(&mut self, tile: usize) -> Result<[i16; 2], acs::hal::ErrorKind> {
        Ok([
            self.field * (1 + tile as i16 * 3),
            -2 * self.field + tile as i16 * self.field,
        ])
    }
    fn read_gyro(&mut self, tile: usize) -> Result<i16, acs::hal::ErrorKind> {
        Ok(20 - tile as i16 * 7)
    }
    fn set_wheel_momentum(&mut self, tile: usize, h_nms: f32) -> Result<(), acs::hal::ErrorKind> {
        self.wheels[tile] = Some(h_nms);
        Ok(())
    }
    fn set_dipole(&mut self, tile: usize, m: f32) -> Result<(), acs::hal::ErrorKind> {
        self.coils[tile] = Some(m);
        Ok(())
    }
    fn delay_us(&mut self, _: u32) {}
}

/// Issue 19: a law that refuses its input is reported, not turned into a zero command: a
/// tracking target that is not a rotation (NaN) sets `faults.law`, and the wheels hold the
/// momentum they had (they were commanded to zero on any allocation error before).
#[test]
fn refused_law_is_reported_and_the_wheels_hold() {
    use acs::acs_loop::Command;
    use acs::attitude::Quaternion;
    use acs::time::TimeSpan;

    let (_, tle, orbit) = tracking_setup();
    let t0 = tle.epoch.add(TimeSpan::new(60, 0));
    let mut bus = ConstantBus::physical(&orbit, &t0);
    let mut acs = FlightLoop::new(&CONFIG, orbit).unwrap();
    let target = Quaternion::new_normalize(0.5, 0.5, -0.5, 0.5).unwrap();
    acs.command(Command::Track { target }, None, t0).unwrap();
    let mut report = acs::acs_loop::StepReport::empty(Mode::Tracking);
    for k in 0..5 {
        acs.step_into(&mut bus, t0.add(TimeSpan::new(k, 0)), 1.0, &mut report);
        assert!(!report.faults.law, "{:?}", report.faults);
    }
    assert!(report.attitude.is_some(), "{report:?}");
    let held = bus.wheels;
    assert!(held.iter().flatten().any(|h| *h != 0.0), "{held:?}");
    let nan = Quaternion {
        q0: f32::NAN,
        q1: 0.0,
        q2: 0.0,
        q3: 0.0,
    };
    acs.command(Command::Track { target: nan }, None, t0)
        .unwrap();
    acs.step_into(&mut bus, t0.add(TimeSpan::new(5, 0)), 1.0, &mut report);
    assert!(report.faults.law, "{:?}", report.faults);
    assert_eq!(report.faults.bits() & 0x100, 0x100);
    assert_eq!(bus.wheels, held, "the wheels must hold their momentum");
    assert!(bus.coils.iter().flatten().all(|m| m.is_finite()));
    // a valid target again: the fault clears
    acs.command(Command::Track { target }, None, t0).unwrap();
    acs.step_into(&mut bus, t0.add(TimeSpan::new(6, 0)), 1.0, &mut report);
    assert!(!report.faults.law, "{:?}", report.faults);
}

/// Issue 19: magnetometers stuck at zero (a zero field). With a field model (an orbit) the loop
/// refuses the field as a measurement: its magnitude is not the model's (`faults.field`). Without
/// one (no element set) the zero field reaches the momentum dumping, which has no coil solution:
/// the refusal is reported (`faults.law`). Either way the coils stay off, with no NaN.
#[test]
fn zero_field_is_reported() {
    use acs::time::TimeSpan;

    let (_, tle, orbit) = tracking_setup();
    for orbit in [Some(orbit), None] {
        let with_model = orbit.is_some();
        let mut acs = FlightLoop::new(&CONFIG, orbit).unwrap();
        acs.command(acs::acs_loop::Command::SunSafe, None, tle.epoch)
            .unwrap();
        let mut bus = ConstantBus::new(0);
        let t0 = tle.epoch.add(TimeSpan::new(60, 0));
        let mut report = acs::acs_loop::StepReport::empty(Mode::SunSafe);
        for k in 0..3 {
            acs.step_into(&mut bus, t0.add(TimeSpan::new(k, 0)), 1.0, &mut report);
        }
        assert_eq!(report.mode, Mode::SunSafe);
        if with_model {
            assert!(
                report.faults.field && report.b_body_nt.is_none(),
                "{report:?}"
            );
        } else {
            assert!(report.faults.law && !report.faults.field, "{report:?}");
        }
        assert_eq!(report.dipole_body_am2, nalgebra::Vector3::zeros());
        assert!(
            bus.coils.iter().flatten().all(|m| *m == 0.0),
            "{:?}",
            bus.coils
        );
        assert!(
            bus.wheels.iter().flatten().all(|h| h.is_finite()),
            "{:?}",
            bus.wheels
        );
    }
}

/// Issue 19: an allocator that refuses (here every wheel's limit is negative, which the
/// allocator refuses as an invalid wheel) does not send the wheels to zero: no wheel is
/// commanded, they hold the momentum in force, and the refusal is reported (before, every wheel
/// was commanded to zero momentum, unreported).
#[test]
fn refused_allocation_holds_the_wheels() {
    use acs::acs_loop::AcsConfig;
    use acs::time::TimeSpan;

    let (_, tle, orbit) = tracking_setup();
    let config = AcsConfig {
        wheel_limit_nms: -1.0,
        ..CONFIG.clone()
    };
    let mut acs =
        acs::two_node::TwoNodeLoop::<6, { acs::flight::FIELD_COEFFS }>::new(&config, orbit)
            .unwrap();
    acs.command(acs::acs_loop::Command::SunSafe, None, tle.epoch)
        .unwrap();
    let mut bus = ConstantBus::new(100);
    let mut report = acs::acs_loop::StepReport::empty(Mode::SunSafe);
    acs.step_into(
        &mut bus,
        tle.epoch.add(TimeSpan::new(60, 0)),
        1.0,
        &mut report,
    );
    assert!(report.faults.law, "{report:?}");
    assert_eq!(bus.wheels, [None; 6], "no wheel may be sent to zero");
}

/// Issue 19, time base: a jump of the on-board clock (+60 s, then −30 s) is not integrated into
/// the wheels. Before, the step took `now − last` of any size or sign as its time step, and a
/// +60 s correction moved the wheels by 60 periods' worth of torque at once; now a gap outside
/// (0, 2] periods restarts the filter, is reported (`Faults::clock`) and integrates one period:
/// the wheels move as much as they do in one period of a loop started just before (a twin;
/// measured within 1 %, the rest the gyroscopic term of the wheels' different stores).
#[test]
fn clock_jump_is_not_integrated_into_the_wheels() {
    use acs::acs_loop::Command;
    use acs::time::TimeSpan;

    let (_, tle, orbit) = tracking_setup();
    let t0 = tle.epoch.add(TimeSpan::new(60, 0));
    // the target: the attitude the constant readings give at t0 (small errors, no saturation)
    let target = {
        let mut probe = FlightLoop::new(&CONFIG, orbit.clone()).unwrap();
        let mut report = acs::acs_loop::StepReport::empty(Mode::SunSafe);
        let mut bus = ConstantBus::physical(&orbit, &t0);
        probe.step_into(&mut bus, t0, 1.0, &mut report);
        report.attitude.unwrap()
    };
    let start = || {
        let mut acs = FlightLoop::new(&CONFIG, orbit.clone()).unwrap();
        acs.command(Command::Track { target }, None, t0).unwrap();
        let bus = ConstantBus::physical(&orbit, &t0);
        (acs, bus)
    };
    // the largest change of a wheel command in the step at t0 + t s, and the step's faults
    let step = |acs: &mut FlightLoop, bus: &mut ConstantBus, t: i32| {
        let before = bus.wheels;
        let mut report = acs::acs_loop::StepReport::empty(Mode::Tracking);
        acs.step_into(bus, t0.add(TimeSpan::new(t, 0)), 1.0, &mut report);
        let change = before
            .iter()
            .zip(bus.wheels.iter())
            .map(|(a, b)| (b.unwrap_or(0.0) - a.unwrap_or(0.0)).abs())
            .fold(0.0f32, f32::max);
        (change, report.faults)
    };
    let (mut acs, mut bus) = start();
    for t in 0..5 {
        assert!(!step(&mut acs, &mut bus, t).1.clock);
    }
    for t in [64, 34] {
        let (change, faults) = step(&mut acs, &mut bus, t);
        assert!(faults.clock, "{faults:?}");
        let (mut twin, mut twin_bus) = start();
        step(&mut twin, &mut twin_bus, t - 1);
        let (one_period, twin_faults) = step(&mut twin, &mut twin_bus, t);
        assert!(!twin_faults.clock);
        assert!(one_period > 0.0);
        assert!(
            change <= 1.1 * one_period,
            "a clock jump to {t} s moved a wheel by {change} N·m·s (one period: {one_period})"
        );
    }
    // one period a step again: no fault
    assert!(!step(&mut acs, &mut bus, 35).1.clock);
}

/// Issue 19, firmware faults: a loop without an element set (a corrupt one at start-up) is
/// built and flies what needs no reference (detumble, sun-safe), reports `Faults::orbit` every
/// step, and takes an element set later.
#[test]
fn loop_without_elements_detumbles_and_takes_a_set_later() {
    use acs::time::TimeSpan;

    let (_, tle, orbit) = tracking_setup();
    let mut acs = FlightLoop::new(&CONFIG, None).unwrap();
    let mut bus = ConstantBus::new(100);
    let t0 = tle.epoch.add(TimeSpan::new(60, 0));
    let mut report = acs::acs_loop::StepReport::empty(Mode::Detumble);
    for t in 0..3 {
        acs.step_into(&mut bus, t0.add(TimeSpan::new(t, 0)), 1.0, &mut report);
        assert!(report.faults.orbit, "{report:?}");
        assert!(report.b_body_nt.is_some() && report.omega_body_radps.is_some());
    }
    // the rates are low: out of detumble into sun-safe, which needs no reference either: the
    // Sun seen by tile 1 and the gyros drive the wheels
    assert_eq!(report.mode, Mode::SunSafe);
    assert!(report.sun_body.is_some());
    assert!(
        bus.wheels.iter().flatten().any(|h| *h != 0.0),
        "{:?}",
        bus.wheels
    );
    assert!(bus
        .wheels
        .iter()
        .chain(bus.coils.iter())
        .flatten()
        .all(|x| x.is_finite()));
    acs.set_orbit(orbit);
    acs.step_into(&mut bus, t0.add(TimeSpan::new(3, 0)), 1.0, &mut report);
    assert!(!report.faults.orbit, "{report:?}");
}

/// Issue 19, models past their validity: after 2030.0 the loop keeps its field reference (the
/// flight tables' secular variation extrapolated, `Faults::extrapolated`, bit 10), and loses it
/// only after 2035.0 (`Faults::model`).
#[test]
fn field_reference_past_the_tables_is_extrapolated_and_flagged() {
    use acs::time::{Calendar, Epoch, Utc};

    let at = |year: i32| {
        Epoch::<Utc>::from_calendar(Calendar {
            year,
            month: 7,
            day: 1,
            hour: 0,
            minute: 0,
            second: 0,
            nano: 0,
        })
        .unwrap()
    };
    for (year, extrapolated, model) in [
        (2029, false, false),
        (2031, true, false),
        (2036, false, true),
    ] {
        let mut acs = FlightLoop::new(&CONFIG, None).unwrap();
        let mut bus = ConstantBus::new(100);
        let mut report = acs::acs_loop::StepReport::empty(Mode::Detumble);
        acs.step_into(&mut bus, at(year), 1.0, &mut report);
        assert_eq!(
            report.faults.extrapolated, extrapolated,
            "{year}: {report:?}"
        );
        assert_eq!(report.faults.model, model, "{year}: {report:?}");
        assert_eq!(report.faults.bits() & 0x400 != 0, extrapolated);
    }
}
