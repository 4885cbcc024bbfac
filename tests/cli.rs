//! The `acs` binary against `docs/cli.md`: `--help` lists every subcommand, usage errors exit
//! 2, a subcommand that is not built yet exits 3 with a clear message, and `acs propagate` writes
//! an STK file that `host::stk::read` reads back with the TLE epoch as `ScenarioEpoch`.
//!
//! Run: `cargo test --test cli`.
#![cfg(feature = "host")]

mod common;

use std::process::{Command, Output};

/// The subcommands of cli.md.
const SUBCOMMANDS: [&str; 9] = [
    "propagate",
    "sun",
    "igrf",
    "attitude",
    "demo",
    "sim",
    "elements",
    "tc",
    "tm",
];

fn acs(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_acs"))
        .args(args)
        .output()
        .expect("the acs binary runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn help_lists_every_subcommand() {
    let out = acs(&["--help"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let help = text(&out.stdout);
    for sub in SUBCOMMANDS {
        // clap lists each subcommand at the start of an indented line
        assert!(
            help.lines().any(|l| l.trim_start().starts_with(sub)),
            "`acs --help` does not list {sub}:\n{help}"
        );
        let out = acs(&[sub, "--help"]);
        assert_eq!(out.status.code(), Some(0), "acs {sub} --help");
    }
    assert_eq!(acs(&["--version"]).status.code(), Some(0));
}

#[test]
fn usage_errors_exit_2() {
    for args in [
        &[][..],
        &["no-such-subcommand"][..],
        &["--no-such-flag"][..],
        &["propagate"][..], // required flags missing
        &[
            "propagate",
            "--tle",
            "x.tle",
            "--start",
            "0",
            "--stop",
            "1",
            "--step",
            "one",
        ][..],
        &["sim"][..], // scenario missing
    ] {
        let out = acs(args);
        assert_eq!(
            out.status.code(),
            Some(2),
            "acs {args:?}: {}",
            text(&out.stderr)
        );
        assert!(!out.stderr.is_empty(), "acs {args:?} explains the error");
    }
}

/// `acs demo` takes no input: it either runs (0) or is not built yet (3, saying so).
#[test]
fn demo_runs_or_says_it_is_not_built() {
    let out = acs(&["demo"]);
    let stderr = text(&out.stderr);
    match out.status.code() {
        Some(0) => {}
        Some(3) => assert!(
            stderr.contains("not implemented yet") || stderr.contains("computation failed"),
            "{stderr}"
        ),
        other => panic!("acs demo exited {other:?}: {stderr}"),
    }
}

/// A missing input file is invalid input (2), and the message names it.
#[test]
fn missing_tle_file_exits_2() {
    let out = acs(&[
        "propagate",
        "--tle",
        "/nonexistent/x.tle",
        "--start",
        "0",
        "--stop",
        "1",
        "--step",
        "1",
    ]);
    let stderr = text(&out.stderr);
    match out.status.code() {
        Some(2) => assert!(stderr.contains("x.tle"), "{stderr}"),
        // allowed only while propagate is not built
        Some(3) => assert!(stderr.contains("not implemented yet"), "{stderr}"),
        other => panic!("exit {other:?}: {stderr}"),
    }
}

/// `acs propagate` output is an STK file this crate reads back: `ScenarioEpoch` = the TLE epoch,
/// rows every step from the TLE epoch, TEME, metres (cli.md).
#[test]
fn propagate_output_reads_back() {
    let tle_path = common::data_path("sgp4/dtusat.tle");
    let out = acs(&[
        "propagate",
        "--tle",
        tle_path.to_str().unwrap(),
        "--start",
        "0",
        "--stop",
        "10",
        "--step",
        "1",
    ]);
    let stderr = text(&out.stderr);
    if out.status.code() == Some(3) && stderr.contains("not implemented yet") {
        return;
    }
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    let e = acs::host::stk::read(&text(&out.stdout)).unwrap();
    let tle = acs::tle::Tle::parse_text(&common::read_data("sgp4/dtusat.tle")).unwrap();
    assert_eq!(e.scenario_epoch, tle.epoch);
    assert_eq!(e.central_body, "Earth");
    assert_eq!(
        e.coordinate_system,
        acs::host::stk::CoordinateSystem::TemeOfDate
    );
    assert_eq!(e.rows.len(), 11);
    for (i, row) in e.rows.iter().enumerate() {
        assert_eq!(row.t_s, 60.0 * i as f64);
    }
    // the first row is the TLE epoch's state: the reference's t = 0 row (which counts from the
    // TLE epoch, see host::stk) to the flight SGP4's accuracy, far below the 1.8 km that a
    // 0.24 s epoch error would give
    let reference = acs::host::stk::read(&common::read_data("sgp4/dtusat_wgs72_teme.e")).unwrap();
    let (a, b) = (e.rows[0].r_m, reference.rows[0].r_m);
    let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
    println!("acs propagate t=0 vs reference: {d:.3} m");
    assert!(d < 100.0, "{d} m");
}

/// `acs sim plan-flight-wheels` plans seed 001's wheel-assisted manoeuvre and flies it: the
/// flown error is the planned one plus the zero-order hold (`docs/planning.md`, "Flying a plan").
#[test]
fn sim_plan_flight_wheels_reports_planned_and_flown_errors() {
    let dir = std::env::temp_dir().join(format!("acs-cli-pfw-{}", std::process::id()));
    let out = acs(&["sim", "plan-flight-wheels", "--out", dir.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report = std::fs::read_to_string(dir.join("errors.txt")).unwrap();
    let value = |key: &str| -> f64 {
        report
            .lines()
            .find_map(|l| l.strip_prefix(key))
            .and_then(|v| v.trim().parse().ok())
            .unwrap()
    };
    let planned = value("planned_attitude_error_deg:");
    let flown = value("flown_attitude_error_deg:");
    assert!(planned < 1e-4, "{report}");
    assert!((flown - planned).abs() < 2e-3, "{report}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `acs sim SCENARIO --truth ideal|realistic`: realistic by default, named on stdout; the ideal
/// truth is a different run (the realistic truth's albedo, fields and devices change the
/// figures); another value is a usage error.
#[test]
fn sim_truth_option() {
    let run = |extra: &[&str]| {
        let dir = std::env::temp_dir().join(format!(
            "acs-cli-truth-{}-{}",
            std::process::id(),
            extra.join("")
        ));
        let mut args = vec!["sim", "slew", "--out", dir.to_str().unwrap()];
        args.extend_from_slice(extra);
        let out = acs(&args);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let csv = std::fs::read_to_string(dir.join("run.csv")).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        (text(&out.stdout), csv)
    };
    let (default, default_csv) = run(&[]);
    let (realistic, realistic_csv) = run(&["--truth", "realistic"]);
    let (ideal, ideal_csv) = run(&["--truth", "ideal"]);
    assert!(default.contains("truth: realistic"), "{default}");
    assert!(realistic.contains("truth: realistic"));
    assert!(ideal.contains("truth: ideal"), "{ideal}");
    assert_eq!(default_csv, realistic_csv);
    assert_ne!(default_csv, ideal_csv);
    let out = acs(&["sim", "slew", "--truth", "perfect"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
}

/// `acs sim --pil` without a node's flight image, or with a file that is not an MSP430 image, is
/// invalid input (exit 2) naming the file; the run itself needs mspdebug (`firmware/pil`).
#[test]
fn sim_pil_needs_a_flight_image() {
    let missing = std::env::temp_dir().join("acs-cli-no-such-image.elf");
    let out = acs(&[
        "sim",
        "tracking",
        "--pil",
        "--elf-reference",
        missing.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(text(&out.stderr).contains("acs-cli-no-such-image.elf"));
    // the host tool itself: an ELF, but 64-bit
    let out = acs(&[
        "sim",
        "tracking",
        "--pil",
        "--elf-reference",
        env!("CARGO_BIN_EXE_acs"),
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(text(&out.stderr).contains("not a 32-bit little-endian ELF"));
}
