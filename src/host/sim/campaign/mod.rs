//! Monte Carlo verification campaigns (`acs sim SCENARIO --runs N`): the closed-loop
//! requirements of a scenario evaluated over dispersed runs, in parallel, with statistics and
//! plots.
//!
//! Run `k` of a campaign seeded `S` is the scenario dispersed by [`Dispersions::of`] with the
//! draws of [`run_seed`]`(S, k)`, flown by the loop the scenario flies (the flight
//! configuration, unchanged: the loop flies what it believes, the truth is what is dispersed).
//! A run is a pure function of `(S, k)`: the results do not depend on the number of threads,
//! nor on how the campaign is cut into slices ([`merge`]): the per-run CSV, `summary.json` and
//! `summary.md` are byte-identical either way (`tests/campaign.rs`).
//!
//! # Files
//! | file | what |
//! |---|---|
//! | `campaign.json` | scenario, truth, seed, number of runs, the slice's range |
//! | `runs.csv` | one row per run: its seed, whether it met every requirement, each metric ([`requirements`]), the dispersed values ([`dispersion::DRAWN`]), the error if the run could not be flown |
//! | `series.csv` | per run, the pointing error (if the scenario has a target) and the body rate on a grid of [`GRID`] points (the largest value in each interval) |
//! | `summary.json`, `summary.md` | per metric: pass count, pass rate and its 95 % lower confidence bound ([`stats::clopper_pearson_lower`]), percentiles 50/95/99/max (nearest rank), the five worst runs with their seeds |
//! | `pointing_envelope.svg`, `rate_envelope.svg` | median, 95th percentile and maximum over the runs at each grid point |
//! | `hist_<metric>.svg` | histogram of each metric with its limit |
//! | `worst/` | the worst run of the scenario's first requirement replayed with its full time series (the files of `acs sim`) |
//!
//! A slice (`--range A..B`) writes `campaign.json`, `runs.csv` and `series.csv` of its runs;
//! [`merge`] combines slices into the files above.

pub mod dispersion;
pub mod plots;
pub mod requirements;
pub mod stats;

use std::fmt::Write as _;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;

use super::realistic::TruthLevel;
use super::scenarios::{self, Scenario};
use super::{Sample, SimError};

pub use dispersion::Dispersions;
pub use requirements::Metric;

/// Points of the time grid of `series.csv` and the envelopes.
pub const GRID: usize = 100;

/// The confidence level of the pass rates' lower bounds.
pub const CONFIDENCE: f64 = 0.95;

/// What defines a campaign: every run follows from it and the run's index.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Campaign {
    /// Built-in scenario name.
    pub scenario: String,
    /// The simulator's truth.
    pub truth: TruthLevel,
    /// Campaign seed `S`.
    pub seed: u64,
    /// Number of runs `N`.
    pub runs: usize,
}

/// The seed of run `k` of the campaign seeded `campaign_seed` (SplitMix64 of both).
pub fn run_seed(campaign_seed: u64, k: usize) -> u64 {
    let mix = |mut z: u64| {
        z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    mix(mix(campaign_seed) ^ (k as u64)).max(1)
}

/// The result of one run.
#[derive(Clone, Debug, PartialEq)]
pub struct RunResult {
    /// Index `k` in the campaign.
    pub run: usize,
    /// Its seed ([`run_seed`]).
    pub seed: u64,
    /// The value of each metric ([`requirements::metrics`]); ∞ where something never happened.
    pub values: Vec<f64>,
    /// The dispersed values ([`dispersion::DRAWN`]).
    pub drawn: Vec<f64>,
    /// Pointing error on the grid, degrees (empty without a target).
    pub pointing_deg: Vec<f32>,
    /// Body rate on the grid, °/s.
    pub rate_degps: Vec<f32>,
    /// Why the run could not be flown (its metrics are then ∞: it meets nothing).
    pub error: Option<String>,
}

impl Campaign {
    /// The metrics of the campaign's scenario.
    pub fn metrics(&self) -> Vec<Metric> {
        requirements::metrics(&self.scenario)
    }

    /// Checks the scenario name and the number of runs.
    pub fn validate(&self) -> Result<(), String> {
        if !scenarios::NAMES.contains(&self.scenario.as_str()) {
            return Err(format!(
                "scenario `{}`: campaigns run the built-in scenarios ({})",
                self.scenario,
                scenarios::NAMES.join(", ")
            ));
        }
        if self.runs == 0 {
            return Err("--runs: at least one run".into());
        }
        Ok(())
    }

    /// Run `k` of the campaign: the dispersed scenario and the dispersed values.
    pub fn scenario_of_run(&self, k: usize) -> Result<(Scenario, Vec<f64>), SimError> {
        let mut scenario = scenarios::by_name_with(&self.scenario, self.truth)
            .ok_or_else(|| SimError::Model(format!("no scenario `{}`", self.scenario)))??;
        let drawn = Dispersions::of(&self.scenario).apply(&mut scenario, run_seed(self.seed, k))?;
        Ok((scenario, drawn.to_vec()))
    }

    /// Flies run `k` and returns its samples (the full time series: `--run K`).
    pub fn replay(&self, k: usize) -> Result<(Scenario, Vec<Sample>), SimError> {
        let (scenario, _) = self.scenario_of_run(k)?;
        let samples = scenario.run()?;
        Ok((scenario, samples))
    }

    /// Flies run `k` and evaluates it.
    pub fn run_one(&self, k: usize) -> RunResult {
        let metrics = self.metrics();
        let seed = run_seed(self.seed, k);
        let flown = self
            .scenario_of_run(k)
            .and_then(|(s, drawn)| s.run().map(|samples| (s, drawn, samples)));
        match flown {
            Ok((scenario, drawn, samples)) => RunResult {
                run: k,
                seed,
                values: requirements::evaluate(&metrics, &samples, scenario.dt_s),
                drawn,
                pointing_deg: if scenario.target.is_some() {
                    grid(&samples, |s| s.pointing_error_deg.unwrap_or(f64::NAN))
                } else {
                    vec![]
                },
                rate_degps: grid(&samples, |s| s.omega_true.norm().to_degrees()),
                error: None,
            },
            Err(e) => RunResult {
                run: k,
                seed,
                values: vec![f64::INFINITY; metrics.len()],
                drawn: vec![f64::NAN; dispersion::DRAWN.len()],
                pointing_deg: vec![],
                rate_degps: vec![],
                error: Some(e.to_string()),
            },
        }
    }

    /// Whether a run met every requirement.
    pub fn met(&self, r: &RunResult) -> bool {
        r.error.is_none()
            && self
                .metrics()
                .iter()
                .zip(r.values.iter())
                .all(|(m, v)| m.met(*v))
    }

    /// Flies runs `range` on `jobs` threads (all cores when `None`), in any order, and returns
    /// them in order; `progress` is told after each run whether it met every requirement.
    pub fn run_range(
        &self,
        range: Range<usize>,
        jobs: Option<usize>,
        progress: &(dyn Fn(bool) + Sync),
    ) -> Result<Vec<RunResult>, String> {
        let mut pool = rayon::ThreadPoolBuilder::new();
        if let Some(j) = jobs {
            pool = pool.num_threads(j.max(1));
        }
        let pool = pool.build().map_err(|e| e.to_string())?;
        Ok(pool.install(|| {
            range
                .into_par_iter()
                .map(|k| {
                    let r = self.run_one(k);
                    progress(self.met(&r));
                    r
                })
                .collect()
        }))
    }
}

/// The largest value of `f` over each of [`GRID`] equal intervals of the run (NaN if any is).
fn grid(samples: &[Sample], f: impl Fn(&Sample) -> f64) -> Vec<f32> {
    let n = samples.len();
    (0..GRID)
        .map(|g| {
            let (a, b) = (g * n / GRID, ((g + 1) * n / GRID).max(g * n / GRID + 1));
            samples.get(a..b.min(n)).unwrap_or(&[]).iter().map(&f).fold(
                f64::NEG_INFINITY,
                |m, v| if v.is_nan() { v } else { m.max(v) },
            ) as f32
        })
        .collect()
}

fn truth_of(name: &str) -> Option<TruthLevel> {
    match name {
        "ideal" => Some(TruthLevel::Ideal),
        "realistic" => Some(TruthLevel::Realistic),
        _ => None,
    }
}

/// A float as the files write it: the shortest text that reads back to the same value.
fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:e}")
    } else if x.is_nan() {
        "nan".into()
    } else if x > 0.0 {
        "inf".into()
    } else {
        "-inf".into()
    }
}

fn parse_num(s: &str) -> Result<f64, String> {
    match s {
        "nan" => Ok(f64::NAN),
        "inf" => Ok(f64::INFINITY),
        "-inf" => Ok(f64::NEG_INFINITY),
        _ => s.parse().map_err(|_| format!("not a number: `{s}`")),
    }
}

fn write(dir: &Path, name: &str, text: &str) -> Result<(), String> {
    std::fs::write(dir.join(name), text).map_err(|e| format!("{}: {e}", dir.join(name).display()))
}

/// Writes a slice's files: `campaign.json`, `runs.csv`, `series.csv` (`results` in order).
pub fn write_slice(
    dir: &Path,
    campaign: &Campaign,
    range: &Range<usize>,
    results: &[RunResult],
) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let meta = serde_json::json!({
        "scenario": campaign.scenario,
        "truth": campaign.truth.name(),
        "seed": campaign.seed,
        "runs": campaign.runs,
        "range": [range.start, range.end],
        "acs": env!("CARGO_PKG_VERSION"),
    });
    write(
        dir,
        "campaign.json",
        &format!(
            "{}\n",
            serde_json::to_string_pretty(&meta).unwrap_or_default()
        ),
    )?;
    let metrics = campaign.metrics();
    let mut runs = String::from("run,seed,met");
    for m in &metrics {
        runs.push(',');
        runs.push_str(m.key);
    }
    for d in dispersion::DRAWN {
        runs.push(',');
        runs.push_str(d);
    }
    runs.push_str(",error\n");
    let mut series = String::from("run,quantity,values\n");
    for r in results {
        let _ = write!(runs, "{},{},{}", r.run, r.seed, u8::from(campaign.met(r)));
        for v in r.values.iter().chain(r.drawn.iter()) {
            runs.push(',');
            runs.push_str(&num(*v));
        }
        runs.push(',');
        if let Some(e) = &r.error {
            runs.push_str(&e.replace([',', '\n'], ";"));
        }
        runs.push('\n');
        for (q, v) in [
            ("pointing_deg", &r.pointing_deg),
            ("rate_degps", &r.rate_degps),
        ] {
            if v.is_empty() {
                continue;
            }
            let _ = write!(series, "{},{q}", r.run);
            for x in v {
                series.push(',');
                series.push_str(&num(f64::from(*x)));
            }
            series.push('\n');
        }
    }
    write(dir, "runs.csv", &runs)?;
    write(dir, "series.csv", &series)
}

/// Reads a slice written by [`write_slice`] (or a whole campaign's folder).
pub fn read_slice(dir: &Path) -> Result<(Campaign, Range<usize>, Vec<RunResult>), String> {
    let read = |name: &str| {
        std::fs::read_to_string(dir.join(name))
            .map_err(|e| format!("{}: {e}", dir.join(name).display()))
    };
    let meta: serde_json::Value = serde_json::from_str(&read("campaign.json")?)
        .map_err(|e| format!("{}: {e}", dir.join("campaign.json").display()))?;
    let field = |k: &str| {
        meta.get(k)
            .ok_or_else(|| format!("{}: no `{k}`", dir.join("campaign.json").display()))
    };
    let bad = |k: &str| format!("{}: bad `{k}`", dir.join("campaign.json").display());
    let campaign = Campaign {
        scenario: field("scenario")?
            .as_str()
            .ok_or_else(|| bad("scenario"))?
            .to_string(),
        truth: field("truth")?
            .as_str()
            .and_then(truth_of)
            .ok_or_else(|| bad("truth"))?,
        seed: field("seed")?.as_u64().ok_or_else(|| bad("seed"))?,
        runs: field("runs")?
            .as_u64()
            .and_then(|n| usize::try_from(n).ok())
            .ok_or_else(|| bad("runs"))?,
    };
    campaign.validate()?;
    let range = field("range")?
        .as_array()
        .and_then(|a| Some(a.first()?.as_u64()? as usize..a.get(1)?.as_u64()? as usize))
        .ok_or_else(|| bad("range"))?;
    let n_metrics = campaign.metrics().len();
    let runs_csv = read("runs.csv")?;
    let mut results = Vec::new();
    for (i, line) in runs_csv.lines().enumerate().skip(1) {
        let cells: Vec<&str> = line.split(',').collect();
        let where_ = || format!("{}: line {}", dir.join("runs.csv").display(), i + 1);
        if cells.len() != 3 + n_metrics + dispersion::DRAWN.len() + 1 {
            return Err(format!("{}: {} columns", where_(), cells.len()));
        }
        let nums = cells[3..cells.len() - 1]
            .iter()
            .map(|c| parse_num(c))
            .collect::<Result<Vec<f64>, String>>()
            .map_err(|e| format!("{}: {e}", where_()))?;
        let error = cells
            .last()
            .filter(|e| !e.is_empty())
            .map(|e| e.to_string());
        results.push(RunResult {
            run: cells[0].parse().map_err(|_| where_())?,
            seed: cells[1].parse().map_err(|_| where_())?,
            values: nums[..n_metrics].to_vec(),
            drawn: nums[n_metrics..].to_vec(),
            pointing_deg: vec![],
            rate_degps: vec![],
            error,
        });
    }
    let series = read("series.csv")?;
    for (i, line) in series.lines().enumerate().skip(1) {
        let mut cells = line.split(',');
        let where_ = || format!("{}: line {}", dir.join("series.csv").display(), i + 1);
        let run: usize = cells
            .next()
            .and_then(|c| c.parse().ok())
            .ok_or_else(where_)?;
        let quantity = cells.next().ok_or_else(where_)?;
        let values = cells
            .map(|c| parse_num(c).map(|v| v as f32))
            .collect::<Result<Vec<f32>, String>>()
            .map_err(|e| format!("{}: {e}", where_()))?;
        let r = results
            .iter_mut()
            .find(|r| r.run == run)
            .ok_or_else(|| format!("{}: run {run} not in runs.csv", where_()))?;
        match quantity {
            "pointing_deg" => r.pointing_deg = values,
            "rate_degps" => r.rate_degps = values,
            q => return Err(format!("{}: unknown quantity `{q}`", where_())),
        }
    }
    let expected: Vec<usize> = range.clone().collect();
    let found: Vec<usize> = results.iter().map(|r| r.run).collect();
    if expected != found {
        return Err(format!(
            "{}: runs.csv does not hold runs {}..{} in order",
            dir.display(),
            range.start,
            range.end
        ));
    }
    Ok((campaign, range, results))
}

/// Combines slices (folders of [`write_slice`]) of one campaign, which together must hold every
/// run once, into the campaign's files in `out`: byte-identical to the campaign run in one piece.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<(Campaign, Vec<RunResult>), String> {
    let mut campaign: Option<Campaign> = None;
    let mut slices = Vec::new();
    for d in dirs {
        let (c, range, results) = read_slice(d)?;
        if let Some(first) = &campaign {
            if *first != c {
                return Err(format!(
                    "{}: a slice of another campaign ({} {} seed {} runs {}, not {} {} seed {} runs {})",
                    d.display(),
                    c.scenario,
                    c.truth.name(),
                    c.seed,
                    c.runs,
                    first.scenario,
                    first.truth.name(),
                    first.seed,
                    first.runs
                ));
            }
        }
        campaign = Some(c);
        slices.push((range, results));
    }
    let campaign = campaign.ok_or("merge: no slice given")?;
    slices.sort_by_key(|(r, _)| r.start);
    let mut next = 0;
    let mut all = Vec::with_capacity(campaign.runs);
    for (range, results) in slices {
        if range.start != next {
            return Err(if range.start < next {
                format!("merge: run {} is in two slices", range.start)
            } else {
                format!("merge: runs {next}..{} are in no slice", range.start)
            });
        }
        next = range.end;
        all.extend(results);
    }
    if next != campaign.runs {
        return Err(format!(
            "merge: runs {next}..{} are in no slice",
            campaign.runs
        ));
    }
    write_campaign(out, &campaign, &all)?;
    Ok((campaign, all))
}

/// Writes a whole campaign's files (`results`: every run, in order) into `dir`, replaying the
/// worst run of the first requirement into `dir/worst`.
pub fn write_campaign(
    dir: &Path,
    campaign: &Campaign,
    results: &[RunResult],
) -> Result<(), String> {
    write_slice(dir, campaign, &(0..campaign.runs), results)?;
    let summary = Summary::of(campaign, results);
    write(
        dir,
        "summary.json",
        &format!(
            "{}\n",
            serde_json::to_string_pretty(&summary.json()).unwrap_or_default()
        ),
    )?;
    write(dir, "summary.md", &summary.markdown())?;
    plots::write_all(dir, campaign, results, &summary)?;
    if let Some(worst) = summary.worst_run() {
        let (_, samples) = campaign.replay(worst).map_err(|e| e.to_string())?;
        super::plot::write_all(&dir.join("worst"), &samples)?;
    }
    Ok(())
}

/// The statistics of one metric over a campaign.
#[derive(Clone, Debug, PartialEq)]
pub struct MetricSummary {
    /// The metric.
    pub metric: Metric,
    /// Runs that met it (all of them without a requirement).
    pub passes: usize,
    /// Lower bound of the pass rate at [`CONFIDENCE`].
    pub lower_bound: f64,
    /// Percentiles 50, 95, 99 and the maximum.
    pub percentiles: [f64; 4],
    /// The five worst runs: (run, seed, value), the largest values first.
    pub worst: Vec<(usize, u64, f64)>,
}

/// The statistics of a campaign.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// The campaign.
    pub campaign: Campaign,
    /// Runs that met every requirement.
    pub all_met: usize,
    /// Runs that could not be flown.
    pub errors: usize,
    /// Per metric.
    pub metrics: Vec<MetricSummary>,
}

impl Summary {
    /// The statistics of `results` (every run of `campaign`).
    pub fn of(campaign: &Campaign, results: &[RunResult]) -> Self {
        let n = results.len();
        let metrics = campaign
            .metrics()
            .into_iter()
            .enumerate()
            .map(|(i, metric)| {
                let value = |r: &RunResult| r.values.get(i).copied().unwrap_or(f64::NAN);
                let passes = results
                    .iter()
                    .filter(|r| r.error.is_none() && metric.met(value(r)))
                    .count();
                let mut sorted: Vec<f64> = results.iter().map(value).collect();
                sorted.sort_by(f64::total_cmp);
                let p = |q| stats::percentile(&sorted, q).unwrap_or(f64::NAN);
                let mut by_value: Vec<&RunResult> = results.iter().collect();
                by_value.sort_by(|a, b| value(b).total_cmp(&value(a)).then(a.run.cmp(&b.run)));
                MetricSummary {
                    lower_bound: stats::clopper_pearson_lower(passes, n, 1.0 - CONFIDENCE),
                    passes,
                    percentiles: [p(50.0), p(95.0), p(99.0), p(100.0)],
                    worst: by_value
                        .iter()
                        .take(5)
                        .map(|r| (r.run, r.seed, value(r)))
                        .collect(),
                    metric,
                }
            })
            .collect();
        Self {
            campaign: campaign.clone(),
            all_met: results.iter().filter(|r| campaign.met(r)).count(),
            errors: results.iter().filter(|r| r.error.is_some()).count(),
            metrics,
        }
    }

    /// The run replayed as the worst: the worst of the scenario's first requirement after "no
    /// NaN" (or of "no NaN" if it has none).
    pub fn worst_run(&self) -> Option<usize> {
        self.metrics
            .iter()
            .skip(1)
            .find(|m| m.metric.limit.is_some())
            .or_else(|| self.metrics.first())
            .and_then(|m| m.worst.first())
            .map(|w| w.0)
    }

    /// The command that reproduces the campaign.
    pub fn command(&self) -> String {
        let c = &self.campaign;
        format!(
            "acs sim {} --truth {} --runs {} --seed {} --out DIR",
            c.scenario,
            c.truth.name(),
            c.runs,
            c.seed
        )
    }

    /// `summary.json`.
    pub fn json(&self) -> serde_json::Value {
        let f = |x: f64| {
            if x.is_finite() {
                serde_json::json!(x)
            } else {
                serde_json::json!(num(x))
            }
        };
        let c = &self.campaign;
        let runs = c.runs;
        serde_json::json!({
            "scenario": c.scenario,
            "truth": c.truth.name(),
            "seed": c.seed,
            "runs": runs,
            "command": self.command(),
            "confidence": CONFIDENCE,
            "all_requirements": {
                "passes": self.all_met,
                "pass_rate": self.all_met as f64 / runs.max(1) as f64,
                "lower_bound": stats::clopper_pearson_lower(self.all_met, runs, 1.0 - CONFIDENCE),
            },
            "errors": self.errors,
            "metrics": self.metrics.iter().map(|m| serde_json::json!({
                "key": m.metric.key,
                "text": m.metric.text,
                "requirement": m.metric.limit.map(|_| m.metric.limit_text()),
                "passes": m.metric.limit.map(|_| m.passes),
                "pass_rate": m.metric.limit.map(|_| m.passes as f64 / runs.max(1) as f64),
                "lower_bound": m.metric.limit.map(|_| m.lower_bound),
                "p50": f(m.percentiles[0]),
                "p95": f(m.percentiles[1]),
                "p99": f(m.percentiles[2]),
                "max": f(m.percentiles[3]),
                "worst": m.worst.iter().map(|(r, s, v)| serde_json::json!({"run": r, "seed": s, "value": f(*v)})).collect::<Vec<_>>(),
            })).collect::<Vec<_>>(),
        })
    }

    /// `summary.md`.
    pub fn markdown(&self) -> String {
        let c = &self.campaign;
        let n = c.runs.max(1);
        let pct = |x: f64| format!("{:.2} %", 100.0 * x);
        let mut s = format!(
            "# Campaign `{}` ({} truth), {} runs, seed {}\n\n`{}`\n\n",
            c.scenario,
            c.truth.name(),
            c.runs,
            c.seed,
            self.command()
        );
        let _ = writeln!(
            s,
            "Every requirement met by {} of {} runs ({}; {:.0} % lower bound {}). Runs that could not be flown: {}.\n",
            self.all_met,
            c.runs,
            pct(self.all_met as f64 / n as f64),
            CONFIDENCE * 100.0,
            pct(stats::clopper_pearson_lower(self.all_met, c.runs, 1.0 - CONFIDENCE)),
            self.errors
        );
        s.push_str("| metric | requirement | met | pass rate | 95 % lower bound | p50 | p95 | p99 | max | worst runs (run: value) |\n|---|---|---|---|---|---|---|---|---|---|\n");
        for m in &self.metrics {
            let v = |x: f64| {
                if x.is_finite() {
                    format!("{x:.4}")
                } else {
                    num(x)
                }
            };
            let (met, rate, lb) = match m.metric.limit {
                Some(_) => (
                    format!("{}/{}", m.passes, c.runs),
                    pct(m.passes as f64 / n as f64),
                    pct(m.lower_bound),
                ),
                None => ("—".into(), "—".into(), "—".into()),
            };
            let worst = m
                .worst
                .iter()
                .map(|(r, _, x)| format!("{r}: {}", v(*x)))
                .collect::<Vec<_>>()
                .join(", ");
            let _ = writeln!(
                s,
                "| {} (`{}`) | {} | {met} | {rate} | {lb} | {} | {} | {} | {} | {worst} |",
                m.metric.text,
                m.metric.key,
                m.metric.limit_text(),
                v(m.percentiles[0]),
                v(m.percentiles[1]),
                v(m.percentiles[2]),
                v(m.percentiles[3]),
            );
        }
        let _ = writeln!(
            s,
            "\nRun `k` replays alone with `acs sim {} --truth {} --seed {} --run k --out DIR`; the dispersions are in `runs.csv` and in `acs::host::sim::campaign::dispersion`.",
            c.scenario,
            c.truth.name(),
            c.seed
        );
        s
    }
}

/// A progress counter for [`Campaign::run_range`]: runs done and failed.
#[derive(Debug, Default)]
pub struct Progress {
    /// Runs done.
    pub done: AtomicUsize,
    /// Runs that missed a requirement.
    pub failed: AtomicUsize,
}

impl Progress {
    /// Counts one run.
    pub fn count(&self, met: bool) -> (usize, usize) {
        let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        let failed = if met {
            self.failed.load(Ordering::Relaxed)
        } else {
            self.failed.fetch_add(1, Ordering::Relaxed) + 1
        };
        (done, failed)
    }
}
