//! Monte Carlo campaigns (`acs sim SCENARIO --runs N`, `acs::host::sim::campaign`): results
//! that do not depend on the number of threads nor on slicing, runs reproducible alone,
//! dispersions within their declared distributions, and the command line's refusals; and
//! scenario files (`acs sim FILE`).

use std::path::{Path, PathBuf};
use std::process::Command;

use acs::host::sim::campaign::{self, dispersion::DRAWN, Campaign, Dispersions};
use acs::host::sim::realistic::TruthLevel;
use acs::host::sim::scenarios;

fn temp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("acs-campaign-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// A small campaign of the shortest scenario (the thesis slew, 240 s).
fn small() -> Campaign {
    Campaign {
        scenario: "thesis-slew-noisy".into(),
        truth: TruthLevel::Realistic,
        seed: 42,
        runs: 6,
    }
}

const FILES: [&str; 5] = [
    "campaign.json",
    "runs.csv",
    "series.csv",
    "summary.json",
    "summary.md",
];

fn same_files(a: &Path, b: &Path) {
    for f in FILES {
        let (x, y) = (
            std::fs::read(a.join(f)).unwrap(),
            std::fs::read(b.join(f)).unwrap(),
        );
        assert!(
            x == y,
            "{f} differs between {} and {}",
            a.display(),
            b.display()
        );
    }
}

#[test]
fn results_do_not_depend_on_jobs_nor_on_slices() {
    let c = small();
    let one = c.run_range(0..c.runs, Some(1), &|_| {}).unwrap();
    let two = c.run_range(0..c.runs, Some(2), &|_| {}).unwrap();
    assert_eq!(one, two);
    let (d1, d2) = (temp("jobs1"), temp("jobs2"));
    campaign::write_campaign(&d1, &c, &one).unwrap();
    campaign::write_campaign(&d2, &c, &two).unwrap();
    same_files(&d1, &d2);

    // three slices, given out of order, merge into the same files
    let slices: Vec<PathBuf> = [(4, 6), (0, 1), (1, 4)]
        .iter()
        .map(|&(a, b)| {
            let d = temp(&format!("slice{a}"));
            let r = c.run_range(a..b, Some(2), &|_| {}).unwrap();
            campaign::write_slice(&d, &c, &(a..b), &r).unwrap();
            d
        })
        .collect();
    let merged = temp("merged");
    let (mc, mr) = campaign::merge(&slices, &merged).unwrap();
    assert_eq!(mc, c);
    assert_eq!(mr, one);
    same_files(&d1, &merged);

    // a gap or an overlap is refused
    let gap = campaign::merge(&slices[..2], &temp("gap")).unwrap_err();
    assert!(gap.contains("in no slice"), "{gap}");
    let twice = [slices[1].clone(), slices[2].clone(), slices[2].clone()];
    let overlap = campaign::merge(&twice, &temp("overlap")).unwrap_err();
    assert!(overlap.contains("two slices"), "{overlap}");
    for d in slices.iter().chain([&d1, &d2, &merged]) {
        let _ = std::fs::remove_dir_all(d);
    }
}

#[test]
fn a_run_replays_alone() {
    let c = small();
    let all = c.run_range(0..c.runs, None, &|_| {}).unwrap();
    let k = 3;
    let alone = Campaign {
        runs: 1_000,
        ..c.clone()
    }
    .run_one(k);
    assert_eq!(alone, all[k]);
    // and its full time series gives the same metrics
    let (scenario, samples) = c.replay(k).unwrap();
    let values = campaign::requirements::evaluate(&c.metrics(), &samples, scenario.dt_s);
    assert_eq!(values, all[k].values);
}

/// `worst_from_1200s_deg` (issue #30): a column of `runs.csv` and a metric of `summary.json` and
/// `summary.md` for `tracking`, and each run's value is the worst pointing error from 1 200 s on
/// of that run's samples, replayed alone (`--run K`).
#[test]
fn worst_from_1200s_is_written_and_is_the_replayed_runs() {
    const KEY: &str = "worst_from_1200s_deg";
    for name in ["tracking", "failed-tile", "tracking-eclipse"] {
        let c = Campaign {
            scenario: name.into(),
            ..small()
        };
        assert!(c.metrics().iter().any(|m| m.key == KEY), "{name}");
    }
    let c = Campaign {
        scenario: "tracking".into(),
        truth: TruthLevel::Realistic,
        seed: 7,
        runs: 3,
    };
    let results = c.run_range(0..c.runs, None, &|_| {}).unwrap();
    let d = temp("worst-from-1200s");
    campaign::write_campaign(&d, &c, &results).unwrap();
    let runs = std::fs::read_to_string(d.join("runs.csv")).unwrap();
    let mut lines = runs.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = header
        .iter()
        .position(|h| *h == KEY)
        .expect("the column is in runs.csv");
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), c.runs);
    for k in [0, 2] {
        let (_, samples) = c.replay(k).unwrap();
        let direct = samples
            .iter()
            .filter(|s| s.t_s >= 1200.0)
            .map(|s| s.pointing_error_deg.unwrap())
            .fold(f64::NEG_INFINITY, f64::max);
        assert!(direct.is_finite() && direct > 0.0, "{direct}");
        let written: f64 = rows[k][column].parse().unwrap();
        assert_eq!(written, direct, "run {k}");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("summary.json")).unwrap()).unwrap();
    let metric = summary["metrics"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["key"] == KEY)
        .expect("the metric is in summary.json");
    assert!(metric["requirement"].is_null(), "reported, not required");
    let max = results
        .iter()
        .map(|r| r.values[header.iter().position(|h| *h == KEY).unwrap() - 3])
        .fold(f64::NEG_INFINITY, f64::max);
    // summary.json writes 17 significant digits: the last may round
    let written = metric["max"].as_f64().unwrap();
    assert!(
        (written - max).abs() <= 1e-14 * max.abs(),
        "{written} {max}"
    );
    let md = std::fs::read_to_string(d.join("summary.md")).unwrap();
    assert!(md.contains(&format!("(`{KEY}`)")), "{md}");
    let _ = std::fs::remove_dir_all(&d);
}

/// Every scenario's dispersions draw within their declared distributions, and change the
/// truth, not the loop's configuration.
#[test]
fn dispersions_within_their_distributions() {
    for name in scenarios::NAMES {
        let d = Dispersions::of(name);
        let nominal = scenarios::by_name(name).unwrap().unwrap();
        for seed in 1..30u64 {
            let mut s = scenarios::by_name(name).unwrap().unwrap();
            let drawn = d.apply(&mut s, seed).unwrap();
            assert_eq!(drawn.len(), DRAWN.len());
            for scale in &drawn[2..5] {
                assert!((scale - 1.0).abs() <= d.inertia_moments, "{name}: {scale}");
            }
            let days = drawn[8];
            match d.epoch {
                campaign::dispersion::EpochDispersion::SunSynchronous(span)
                | campaign::dispersion::EpochDispersion::Start(span) => {
                    assert!((0.0..span).contains(&days), "{name}: {days}")
                }
            }
            let (lo, hi) = d.density_factor;
            assert!((lo..=hi).contains(&drawn[9]), "{name}: {}", drawn[9]);
            assert_eq!(s.sim.seed, seed);
            assert!(s.sim.inertia != nominal.sim.inertia);
            // the truth's inertia stays symmetric positive definite
            let i = s.sim.inertia;
            assert!((i - i.transpose()).abs().max() < 1e-15);
            assert!(i.symmetric_eigenvalues().iter().all(|e| *e > 0.0));
            // the loop flies the same configuration
            assert_eq!(
                format!("{:?}", s.flight.config()),
                format!("{:?}", nominal.flight.config())
            );
            // the element set still initialises and its epoch is the start
            s.orbit().unwrap();
        }
    }
}

fn acs(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_acs"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn command_line_refuses_bad_campaigns() {
    let d = temp("cli");
    let out = d.to_str().unwrap();
    for args in [
        vec!["sim", "tracking", "--runs", "0", "--out", out],
        vec![
            "sim", "tracking", "--runs", "10", "--range", "5..3", "--out", out,
        ],
        vec![
            "sim", "tracking", "--runs", "10", "--range", "5..11", "--out", out,
        ],
        vec![
            "sim", "tracking", "--runs", "10", "--run", "10", "--out", out,
        ],
        vec!["sim", "tracking", "--runs", "10"],
        vec!["sim", "plan-flight", "--runs", "10", "--out", out],
        vec![
            "sim", "tracking", "--runs", "10", "--jobs", "0", "--out", out,
        ],
        vec!["sim", "merge", "--out", out],
        vec!["sim", "merge", "/nonexistent-slice", "--out", out],
    ] {
        let (code, err) = acs(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
    }
    // a slice and its merge through the command line
    let slice = temp("cli-slice");
    let (code, err) = acs(&[
        "sim",
        "thesis-slew-noisy",
        "--runs",
        "2",
        "--range",
        "0..2",
        "--seed",
        "7",
        "--out",
        slice.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let merged = temp("cli-merged");
    let (code, err) = acs(&[
        "sim",
        "merge",
        slice.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(merged.join("summary.md").exists() && merged.join("worst/run.csv").exists());
    for p in [&d, &slice, &merged] {
        let _ = std::fs::remove_dir_all(p);
    }
}

/// `acs sim FILE` (`acs::host::sim::scenario_file`): a file on a built-in base runs like it,
/// with its replacements; a bad file exits 2 naming the key.
#[test]
fn scenario_files() {
    let dir = temp("file");
    std::fs::create_dir_all(&dir).unwrap();
    let good = dir.join("short.json");
    std::fs::write(
        &good,
        r#"{"base": "tracking", "duration_s": 120, "commands": [{"t_s": 1, "sun_safe": true}]}"#,
    )
    .unwrap();
    let out = dir.join("out");
    let run = Command::new(env!("CARGO_BIN_EXE_acs"))
        .args([
            "sim",
            good.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(stdout.contains("duration_s: 120.0"), "{stdout}");
    assert!(stdout.contains("final_mode: SunSafe"), "{stdout}");
    let bad = dir.join("bad.json");
    std::fs::write(&bad, r#"{"base": "tracking", "duration_s": -3}"#).unwrap();
    let (code, err) = acs(&["sim", bad.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("duration_s"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
