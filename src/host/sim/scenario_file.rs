//! Scenario files (`acs sim FILE`): a built-in scenario with some of its data replaced, as JSON.
//!
//! ```json
//! {
//!   "base": "tracking",
//!   "duration_s": 11352,
//!   "seed": 9,
//!   "tle": ["1 90101U ...", "2 90101 ..."],
//!   "initial_attitude": [1, 0, 0, 0],
//!   "initial_rate_radps": [0, 0, 0.001],
//!   "target": [0.9, 0.1, 0.2, 0.3],
//!   "commands": [
//!     {"t_s": 1, "track": [0.9, 0.1, 0.2, 0.3]},
//!     {"t_s": 600, "slew": [1, 0, 0, 0], "within_s": 300},
//!     {"t_s": 3000, "sun_safe": true}
//!   ],
//!   "failures": [[2, 600]]
//! }
//! ```
//!
//! Only `base` (a built-in scenario, [`super::scenarios::NAMES`]) is required; every other key
//! replaces that part of it. Attitudes are scalar-first quaternions, reference TEME → body
//! (`v_body = A(q) v_ref`, [`crate::attitude`]), normalised on reading; a zero one is refused.
//! `tle` replaces the orbit of the truth and of the loop, and the run then starts at the element
//! set's epoch (as every built-in flight scenario does); `failures` lists tiles that fail and
//! when (s from the start). The loop still flies the base scenario's satellite (for every flight
//! scenario, the flight configuration itself). Unknown keys are refused, so a misspelt key is
//! an error and not a silent default.

use serde::Deserialize;

use crate::acs_loop::Command;
use crate::attitude::Quaternion;
use crate::linalg::Vec3d;

use super::scenarios::{self, Scenario};

/// A scenario file as read (see the [module docs](self)).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    base: String,
    duration_s: Option<f64>,
    seed: Option<u64>,
    tle: Option<[String; 2]>,
    initial_attitude: Option<[f64; 4]>,
    initial_rate_radps: Option<[f64; 3]>,
    target: Option<Option<[f64; 4]>>,
    commands: Option<Vec<FileCommand>>,
    failures: Option<Vec<(usize, f64)>>,
}

/// One ground command of a scenario file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileCommand {
    t_s: f64,
    track: Option<[f64; 4]>,
    slew: Option<[f64; 4]>,
    within_s: Option<f64>,
    sun_safe: Option<bool>,
}

/// The longest run a file may ask for, s (30 days).
pub const MAX_DURATION_S: f64 = 30.0 * 86_400.0;

/// A unit quaternion from a file's four numbers, or why not.
fn unit(q: &[f64; 4], what: &str) -> Result<[f64; 4], String> {
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    if !n.is_finite() || n < 1e-6 {
        return Err(format!("{what}: not a rotation (norm {n})"));
    }
    Ok([q[0] / n, q[1] / n, q[2] / n, q[3] / n])
}

fn quaternion32(q: &[f64; 4]) -> Quaternion {
    Quaternion {
        q0: q[0] as f32,
        q1: q[1] as f32,
        q2: q[2] as f32,
        q3: q[3] as f32,
    }
}

fn finite_time(t: f64, what: &str) -> Result<f64, String> {
    if t.is_finite() && (0.0..=MAX_DURATION_S).contains(&t) {
        Ok(t)
    } else {
        Err(format!("{what}: {t} s is outside 0 to {MAX_DURATION_S} s"))
    }
}

/// The scenario a file describes (JSON text; see the [module docs](self)); every refusal names
/// the key.
pub fn parse(text: &str) -> Result<Scenario, String> {
    let f: File = serde_json::from_str(text).map_err(|e| e.to_string())?;
    let mut s = match scenarios::by_name(&f.base) {
        Some(s) => s.map_err(|e| e.to_string())?,
        None => {
            return Err(format!(
                "base: `{}` is not a built-in scenario ({})",
                f.base,
                scenarios::NAMES.join(", ")
            ))
        }
    };
    s.description = "a scenario file on a built-in base";
    if let Some(d) = f.duration_s {
        let d = finite_time(d, "duration_s")?;
        if d < s.dt_s {
            return Err(format!(
                "duration_s: {d} s is shorter than one period ({} s)",
                s.dt_s
            ));
        }
        s.duration_s = d;
    }
    if let Some(seed) = f.seed {
        s.sim.seed = seed;
    }
    if let Some([l1, l2]) = f.tle {
        let tle = crate::tle::Tle::parse(&l1, &l2).map_err(|e| format!("tle: {e}"))?;
        s.sim.start = tle.epoch;
        s.sim.tle = (l1, l2);
        s.orbit().map_err(|e| format!("tle: {e}"))?;
    }
    if let Some(q) = f.initial_attitude {
        s.initial.0 = unit(&q, "initial_attitude")?;
    }
    if let Some(w) = f.initial_rate_radps {
        let w = Vec3d::new(w[0], w[1], w[2]);
        // the gyros' word ends at 3.28 rad/s
        if !w.iter().all(|x| x.is_finite()) || w.norm() > 3.2 {
            return Err(format!(
                "initial_rate_radps: {} rad/s is beyond the gyros' ±3.2 rad/s",
                w.norm()
            ));
        }
        s.initial.1 = w;
    }
    if let Some(t) = f.target {
        s.target = t.map(|q| unit(&q, "target")).transpose()?;
    }
    if let Some(cs) = f.commands {
        let mut out = Vec::with_capacity(cs.len());
        for (i, c) in cs.iter().enumerate() {
            let what = format!("commands[{i}]");
            let t = finite_time(c.t_s, &format!("{what}.t_s"))?;
            let command = match (c.track, c.slew, c.sun_safe) {
                (Some(q), None, None) => Command::Track {
                    target: quaternion32(&unit(&q, &format!("{what}.track"))?),
                },
                (None, Some(q), None) => {
                    let within = c.within_s.ok_or(format!("{what}: a slew needs within_s"))?;
                    let within = finite_time(within, &format!("{what}.within_s"))?;
                    Command::Slew {
                        target: quaternion32(&unit(&q, &format!("{what}.slew"))?).to_dcm(),
                        within_s: within as f32,
                    }
                }
                (None, None, Some(true)) => Command::SunSafe,
                _ => {
                    return Err(format!(
                        "{what}: exactly one of track, slew or \"sun_safe\": true"
                    ))
                }
            };
            if c.within_s.is_some() && c.slew.is_none() {
                return Err(format!("{what}: within_s belongs to a slew"));
            }
            out.push((t, command));
        }
        s.commands = out;
    }
    if let Some(failures) = f.failures {
        for (tile, t) in &failures {
            if *tile >= s.sim.tiles.len() {
                return Err(format!(
                    "failures: tile {tile} (the satellite has {})",
                    s.sim.tiles.len()
                ));
            }
            finite_time(*t, "failures")?;
        }
        s.sim.failures = failures;
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_base_alone_is_the_built_in_scenario() {
        let s = parse(r#"{"base": "tracking"}"#).unwrap();
        let b = scenarios::tracking(None).unwrap();
        assert_eq!(s.name, "tracking");
        assert_eq!(s.duration_s, b.duration_s);
        assert_eq!(s.initial.0, b.initial.0);
        assert_eq!(s.target, b.target);
        assert_eq!(s.commands.len(), b.commands.len());
    }

    #[test]
    fn keys_replace_their_part() {
        let s = parse(
            r#"{"base": "sun-safe", "duration_s": 600, "seed": 3,
                "initial_attitude": [2, 0, 0, 0], "initial_rate_radps": [0, 0, 0.01],
                "target": [0, 1, 0, 0],
                "commands": [{"t_s": 10, "track": [0, 0, 1, 0]},
                             {"t_s": 20, "slew": [1, 0, 0, 0], "within_s": 100},
                             {"t_s": 30, "sun_safe": true}],
                "failures": [[1, 50]]}"#,
        )
        .unwrap();
        assert_eq!(s.name, "sun-safe");
        assert_eq!(s.duration_s, 600.0);
        assert_eq!(s.sim.seed, 3);
        assert_eq!(s.initial.0, [1.0, 0.0, 0.0, 0.0]);
        assert_eq!(s.target, Some([0.0, 1.0, 0.0, 0.0]));
        assert_eq!(s.commands.len(), 3);
        assert!(matches!(s.commands[2].1, Command::SunSafe));
        assert_eq!(s.sim.failures, vec![(1, 50.0)]);
    }

    #[test]
    fn refusals_name_the_key() {
        for (text, key) in [
            (r#"{"base": "nope"}"#, "base"),
            (r#"{"base": "tracking", "duration": 5}"#, "unknown field"),
            (r#"{"base": "tracking", "duration_s": -1}"#, "duration_s"),
            (r#"{"base": "tracking", "duration_s": 0.5}"#, "duration_s"),
            (
                r#"{"base": "tracking", "initial_attitude": [0, 0, 0, 0]}"#,
                "initial_attitude",
            ),
            (
                r#"{"base": "tracking", "initial_rate_radps": [9, 0, 0]}"#,
                "initial_rate_radps",
            ),
            (
                r#"{"base": "tracking", "commands": [{"t_s": 1}]}"#,
                "commands[0]",
            ),
            (
                r#"{"base": "tracking", "commands": [{"t_s": 1, "slew": [1, 0, 0, 0]}]}"#,
                "within_s",
            ),
            (
                r#"{"base": "tracking", "commands": [{"t_s": 1, "track": [1, 0, 0, 0], "within_s": 3}]}"#,
                "within_s",
            ),
            (r#"{"base": "tracking", "failures": [[9, 1]]}"#, "failures"),
            (r#"{"base": "tracking", "tle": ["1 2", "3 4"]}"#, "tle"),
        ] {
            let Err(e) = parse(text) else {
                panic!("{text}: accepted")
            };
            assert!(e.contains(key), "{text}: {e}");
        }
    }
}
