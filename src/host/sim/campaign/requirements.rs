//! The closed-loop requirements of `docs/closed-loop.md`, evaluated on one run, and the metrics
//! reported beside them: the same definitions as `tests/closed_loop.rs`.
//!
//! | scenario | requirement | metric |
//! |---|---|---|
//! | every one | no NaN | samples with a non-finite truth rate, dipole, wheel momentum or error (≤ 0) |
//! | every one | (reported) | fallbacks: steps at which Slew or Tracking fell back to SunSafe |
//! | every one | (reported) | peak of the wheels' total momentum (body), mN·m·s |
//! | `detumble` | < 0.5°/s within 3 orbits | time of the first step below 0.5°/s (≤ 3 orbits), rate at the end (< 0.5°/s) |
//! | `tracking` | < 0.1° within one orbit and after | first step below 0.1° (< 1 orbit); worst error from 600 s later (from 600 s if never below) to the end (< 0.1°; ∞ if no step is left) |
//! | `tracking`, `failed-tile`, `tracking-eclipse` | (reported) | worst pointing error from 1 200 s on (`worst_from_1200s_deg`; issue #30's goal for `tracking`: p99 ≤ 1.2° over a campaign) |
//! | `tracking` | (reported) | RMS pointing error from 1 200 s on |
//! | `failed-tile` | still converges | error at the end (< 0.5°) |
//! | `slew` | the plan, flown in closed loop, ends within 1° (issue #30), then converges | error at the end of the plan (≤ 1°), at the end (< 0.5°) |
//! | `thesis-slew`, `thesis-slew-noisy` | ≤ 0.15°, ≤ 0.45° at the end of the plan | error where Slew hands over to Tracking (∞ if the plan never completes) |
//! | `sun-safe` | no NaN, actuators safe or gyro/magnetometer laws in the umbra | attitudes measured in the umbra (≤ 0); seconds of umbra and the rate at the end (reported) |
//! | `tracking-eclipse` | (reported: issue #30's goals, not requirements) | worst pointing error after the first orbit in the umbra and in sunlight; seconds of umbra |
//!
//! `worst_from_1200s_deg` is a metric, not a requirement: issue #30 states its goal for
//! `tracking` as a campaign statistic (p99 ≤ 1.2°), which `summary.md`/`summary.json` give as the
//! metric's p99; a per-run limit would instead fold it into every run's "met". The scenarios
//! that end by 1 200 s (`slew`, 1 200 s; the thesis slews, 240 s) do not have it: their window
//! holds one step or none. Where the window is empty it is ∞ ("never happened").

use crate::acs_loop::Mode;

use super::super::Sample;

/// How a metric is compared with its limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bound {
    /// Met when the metric is below the limit.
    Below,
    /// Met when the metric is at most the limit.
    AtMost,
}

/// One metric of a run, with its requirement (a limit) or none (reported only).
#[derive(Clone, Debug, PartialEq)]
pub struct Metric {
    /// Column name in `runs.csv` and key in `summary.json`.
    pub key: &'static str,
    /// What it is, for `summary.md`.
    pub text: &'static str,
    /// The requirement: the bound and the limit; `None`: reported only.
    pub limit: Option<(Bound, f64)>,
}

impl Metric {
    /// Whether `value` meets the requirement (always, without one; never when not finite and
    /// limited, ∞ standing for "never happened").
    pub fn met(&self, value: f64) -> bool {
        match self.limit {
            None => true,
            Some((Bound::Below, l)) => value < l,
            Some((Bound::AtMost, l)) => value <= l,
        }
    }

    /// The requirement as text: `< 0.1`, `≤ 17028`, or `—`.
    pub fn limit_text(&self) -> String {
        match self.limit {
            None => "—".into(),
            Some((Bound::Below, l)) => format!("< {l}"),
            Some((Bound::AtMost, l)) => format!("≤ {l}"),
        }
    }
}

/// One orbit of the scenarios, s (94.6 min at 500 km).
pub const ORBIT_S: f64 = 94.6 * 60.0;

const NAN: Metric = Metric {
    key: "nan_samples",
    text: "samples with a NaN (no NaN)",
    limit: Some((Bound::AtMost, 0.0)),
};
const FALLBACKS: Metric = Metric {
    key: "fallbacks",
    text: "falls back from Slew or Tracking to SunSafe",
    limit: None,
};
const WORST_FROM_1200S: Metric = Metric {
    key: "worst_from_1200s_deg",
    text: "worst pointing error from 1 200 s on, °",
    limit: None,
};
const H_PEAK: Metric = Metric {
    key: "h_peak_mnms",
    text: "peak of the wheels' total momentum, mN·m·s",
    limit: None,
};

/// The metrics of the built-in scenario `name`, requirements first.
pub fn metrics(name: &str) -> Vec<Metric> {
    let own: Vec<Metric> = match name {
        "detumble" => vec![
            Metric {
                key: "detumble_time_s",
                text: "first below 0.5°/s, s (within 3 orbits)",
                limit: Some((Bound::AtMost, 3.0 * ORBIT_S)),
            },
            Metric {
                key: "final_rate_degps",
                text: "rate at 3 orbits, °/s",
                limit: Some((Bound::Below, 0.5)),
            },
        ],
        "tracking" => vec![
            Metric {
                key: "settling_time_s",
                text: "first below 0.1°, s (within one orbit)",
                limit: Some((Bound::Below, ORBIT_S)),
            },
            Metric {
                key: "error_after_settling_deg",
                text: "worst pointing error from 600 s after settling, °",
                limit: Some((Bound::Below, 0.1)),
            },
            Metric {
                key: "rms_from_1200s_deg",
                text: "RMS pointing error from 1 200 s on, °",
                limit: None,
            },
            Metric {
                text: "worst pointing error from 1 200 s on, ° (issue #30's goal: p99 ≤ 1.2°)",
                ..WORST_FROM_1200S
            },
        ],
        "failed-tile" => vec![
            Metric {
                key: "final_error_deg",
                text: "pointing error at the end of the orbit, ° (still converges)",
                limit: Some((Bound::Below, 0.5)),
            },
            WORST_FROM_1200S,
        ],
        "tracking-eclipse" => vec![
            WORST_FROM_1200S,
            Metric {
                key: "worst_umbra_after_orbit_deg",
                text: "worst pointing error in the umbra after the first orbit, ° (issue #30's goals: ideal ≤ 0.5°, realistic ≤ 3°)",
                limit: None,
            },
            Metric {
                key: "worst_sunlit_after_orbit_deg",
                text: "worst pointing error in sunlight after the first orbit, ° (issue #30's goal: ideal ≤ 0.5°)",
                limit: None,
            },
            Metric {
                key: "umbra_s",
                text: "seconds of umbra",
                limit: None,
            },
        ],
        "slew" => vec![
            Metric {
                key: "plan_end_error_deg",
                text: "pointing error at the end of the plan, ° (issue #30: the plan flown in closed loop on the flight wheels)",
                limit: Some((Bound::AtMost, 1.0)),
            },
            Metric {
                key: "final_error_deg",
                text: "pointing error at the end, ° (converges after the plan)",
                limit: Some((Bound::Below, 0.5)),
            },
        ],
        "thesis-slew" => vec![Metric {
            key: "plan_end_error_deg",
            text: "pointing error at the end of the plan, °",
            limit: Some((Bound::AtMost, 0.15)),
        }],
        "thesis-slew-noisy" => vec![Metric {
            key: "plan_end_error_deg",
            text: "pointing error at the end of the plan, °",
            limit: Some((Bound::AtMost, 0.45)),
        }],
        "sun-safe" => vec![
            Metric {
                key: "attitudes_in_umbra",
                text: "attitudes measured (the filter started) in the umbra (safe or gyro/magnetometer laws there)",
                limit: Some((Bound::AtMost, 0.0)),
            },
            Metric {
                key: "umbra_s",
                text: "seconds of umbra",
                limit: None,
            },
            Metric {
                key: "final_rate_degps",
                text: "rate at the end, °/s",
                limit: None,
            },
        ],
        _ => vec![],
    };
    let mut all = vec![NAN];
    all.extend(own);
    all.push(FALLBACKS);
    all.push(H_PEAK);
    all
}

/// The pointing error of each sample (∞ where a scenario without a target is asked).
fn pointing(s: &Sample) -> f64 {
    s.pointing_error_deg.unwrap_or(f64::INFINITY)
}

/// The value of each of `metrics` on the samples of one run of `dt_s` periods.
pub fn evaluate(metrics: &[Metric], samples: &[Sample], dt_s: f64) -> Vec<f64> {
    metrics
        .iter()
        .map(|m| value(m.key, samples, dt_s))
        .collect()
}

fn value(key: &str, samples: &[Sample], dt_s: f64) -> f64 {
    let last = samples.last();
    match key {
        "nan_samples" => samples.iter().filter(|s| !finite(s)).count() as f64,
        "fallbacks" => samples
            .windows(2)
            .filter(|w| {
                matches!(w[0].mode, Mode::Slew | Mode::Tracking) && w[1].mode == Mode::SunSafe
            })
            .count() as f64,
        "h_peak_mnms" => samples
            .iter()
            .map(|s| s.h_wheels_body.norm() * 1e3)
            .fold(0.0, f64::max),
        "detumble_time_s" => samples
            .iter()
            .find(|s| s.omega_true.norm().to_degrees() < 0.5)
            .map_or(f64::INFINITY, |s| s.t_s),
        "final_rate_degps" => last.map_or(f64::INFINITY, |s| s.omega_true.norm().to_degrees()),
        "settling_time_s" => samples
            .iter()
            .find(|s| pointing(s) < 0.1)
            .map_or(f64::INFINITY, |s| s.t_s),
        "error_after_settling_deg" => {
            let from = samples
                .iter()
                .find(|s| pointing(s) < 0.1)
                .map_or(0.0, |s| s.t_s)
                + 600.0;
            // a run that settles less than 600 s before its end has no "after": ∞ (not met),
            // never the 0 of an empty window
            samples
                .iter()
                .filter(|s| s.t_s > from)
                .map(pointing)
                .reduce(f64::max)
                .unwrap_or(f64::INFINITY)
        }
        "rms_from_1200s_deg" => {
            let v: Vec<f64> = samples
                .iter()
                .filter(|s| s.t_s >= 1200.0)
                .map(pointing)
                .collect();
            (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt()
        }
        "worst_from_1200s_deg" => worst(samples.iter().filter(|s| s.t_s >= 1200.0)),
        "worst_umbra_after_orbit_deg" => worst(
            samples
                .iter()
                .filter(|s| s.t_s > ORBIT_S + 0.5 * dt_s && s.sun_fraction == 0.0),
        ),
        "worst_sunlit_after_orbit_deg" => worst(
            samples
                .iter()
                .filter(|s| s.t_s > ORBIT_S + 0.5 * dt_s && s.sun_fraction > 0.0),
        ),
        "final_error_deg" => last.map_or(f64::INFINITY, pointing),
        "plan_end_error_deg" => samples
            .windows(2)
            .find(|w| w[0].mode == Mode::Slew && w[1].mode == Mode::Tracking)
            .map_or(f64::INFINITY, |w| pointing(&w[1])),
        "attitudes_in_umbra" => samples
            .iter()
            .filter(|s| s.sun_fraction == 0.0 && s.report.measured_attitude.is_some())
            .count() as f64,
        "umbra_s" => samples.iter().filter(|s| s.sun_fraction == 0.0).count() as f64 * dt_s,
        _ => f64::NAN,
    }
}

/// The worst pointing error of `samples`; ∞ when there is none (an empty window has no "worst",
/// never the 0 of an empty fold).
fn worst<'a>(samples: impl Iterator<Item = &'a Sample>) -> f64 {
    samples
        .map(pointing)
        .reduce(f64::max)
        .unwrap_or(f64::INFINITY)
}

/// Whether a sample is free of NaN (the closed-loop tests' check).
fn finite(s: &Sample) -> bool {
    s.omega_true.iter().all(|x| x.is_finite())
        && s.dipole_am2.iter().all(|x| x.is_finite())
        && s.report.h_wheels_body.iter().all(|x| x.is_finite())
        && s.pointing_error_deg.is_none_or(f64::is_finite)
        && s.estimate_error_deg.is_none_or(f64::is_finite)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::acs_loop::StepReport;
    use crate::linalg::{Vec3, Vec3d};

    /// A `tracking` sample at `t_s` with pointing error `error_deg`.
    fn sample(t_s: f64, error_deg: f64) -> Sample {
        Sample {
            t_s,
            mode: Mode::Tracking,
            omega_true: Vec3d::zeros(),
            pointing_error_deg: Some(error_deg),
            estimate_error_deg: Some(error_deg),
            h_wheels_body: Vec3d::zeros(),
            dipole_am2: Vec3::zeros(),
            sun_fraction: 1.0,
            report: StepReport::empty(Mode::Tracking),
        }
    }

    /// The worst error after settling of a one-orbit run that first falls below 0.1° at
    /// `settle_s` (1° before, 0.05° after).
    fn after_settling(settle_s: f64) -> f64 {
        let samples: Vec<Sample> = (1..=ORBIT_S as u32)
            .map(f64::from)
            .map(|t| sample(t, if t < settle_s { 1.0 } else { 0.05 }))
            .collect();
        value("error_after_settling_deg", &samples, 1.0)
    }

    #[test]
    fn error_after_settling_needs_a_step_after_the_window() {
        let metric = &metrics("tracking")[2];
        assert_eq!(metric.key, "error_after_settling_deg");
        assert_eq!(after_settling(1000.0), 0.05);
        assert!(metric.met(after_settling(1000.0)));
        // settled 400 s before the end: no "after" was flown, not met (it was 0, met, before)
        assert_eq!(after_settling(ORBIT_S - 400.0), f64::INFINITY);
        assert!(!metric.met(after_settling(ORBIT_S - 400.0)));
    }

    #[test]
    fn worst_from_1200s_is_the_largest_error_of_its_window() {
        for name in ["tracking", "failed-tile", "tracking-eclipse"] {
            assert!(metrics(name)
                .iter()
                .any(|m| m.key == "worst_from_1200s_deg" && m.limit.is_none()));
        }
        for name in ["slew", "thesis-slew", "detumble", "sun-safe"] {
            assert!(metrics(name)
                .iter()
                .all(|m| m.key != "worst_from_1200s_deg"));
        }
        // 3° before 1 200 s, 0.2° after but 0.7° at 1 200 s itself (the window's first step)
        let samples: Vec<Sample> = (1..=2000)
            .map(f64::from)
            .map(|t| {
                sample(
                    t,
                    match t {
                        t if t < 1200.0 => 3.0,
                        1200.0 => 0.7,
                        _ => 0.2,
                    },
                )
            })
            .collect();
        assert_eq!(value("worst_from_1200s_deg", &samples, 1.0), 0.7);
        // a run that ends before 1 200 s has no window: ∞, not 0
        assert_eq!(
            value("worst_from_1200s_deg", &samples[..1000], 1.0),
            f64::INFINITY
        );
    }
}
