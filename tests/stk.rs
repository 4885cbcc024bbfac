//! STK ephemeris reader/writer tests: every reference `.e` file read, written back byte for byte,
//! errors with line numbers, and which epoch the reference rows count from (the `sgp4` crate
//! decides).
//!
//! Run: `cargo test --test stk -- --nocapture` (prints the comparison statistics).
#![cfg(feature = "host")]

mod common;
mod figures;

use acs::host::stk::{self, CoordinateSystem, StateRow, StkEphemeris, StkErrorKind};
use acs::time::{Calendar, Epoch, Utc};
use acs::tle::Tle;

fn reference_files() -> Vec<(String, String)> {
    let dir = common::data_path("sgp4");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "e"))
        .collect();
    files.sort();
    assert_eq!(files.len(), 16, "reference .e files in {}", dir.display());
    files
        .into_iter()
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read_to_string(&p).unwrap())
        })
        .collect()
}

/// The TLE quoted in a reference file's comment ("TLE: line1 | line2").
fn quoted_tle(e: &StkEphemeris) -> Tle {
    let c = &e.comments[0];
    let tle = &c[c.find("TLE: ").unwrap() + 5..];
    let (l1, rest) = tle.split_once(" | ").unwrap();
    Tle::parse(l1, &rest[..69]).unwrap()
}

#[test]
fn reads_every_reference_file() {
    for (name, text) in reference_files() {
        let e = stk::read(&text).unwrap_or_else(|err| panic!("{name}: {err}"));
        assert_eq!(e.version, "stk.v.11.0");
        assert_eq!(e.central_body, "Earth");
        assert_eq!(e.interpolation_method.as_deref(), Some("Lagrange"));
        assert_eq!(e.interpolation_samples_m1, Some(5));
        assert!(e.other_keywords.is_empty());
        let expected_frame = if name.contains("j2000") {
            CoordinateSystem::J2000
        } else {
            CoordinateSystem::TemeOfDate
        };
        assert_eq!(e.coordinate_system, expected_frame, "{name}");
        let (n, t0, t_end) = if name.starts_with("dtusat") {
            (10081, 0.0, 604_800.0) // one week at 60 s
        } else {
            (577, -86_400.0, 259_200.0) // −1 day to +3 days at 600 s
        };
        assert_eq!(e.rows.len(), n, "{name}");
        assert_eq!(e.rows.first().unwrap().t_s, t0, "{name}");
        assert_eq!(e.rows.last().unwrap().t_s, t_end, "{name}");
        // the scenario epoch is within a second of the TLE epoch (see the module doc)
        let tle = quoted_tle(&e);
        let offset = e.scenario_epoch.span_since(&tle.epoch).as_seconds_f64();
        assert!(offset.abs() < 1.0, "{name}: {offset}");
        println!("{name}: ScenarioEpoch − TLE epoch = {offset:+.6} s");
    }
}

#[test]
fn dtusat_header_and_first_row() {
    let text = common::read_data("sgp4/dtusat_wgs72_teme.e");
    let e = stk::read(&text).unwrap();
    let expected = Epoch::<Utc>::from_calendar(Calendar {
        year: 2009,
        month: 6,
        day: 15,
        hour: 4,
        minute: 56,
        second: 45,
        nano: 472_650_000,
    })
    .unwrap();
    assert_eq!(e.scenario_epoch, expected);
    assert_eq!(
        e.rows[0],
        StateRow {
            t_s: 0.0,
            r_m: [-7192627.275324, 456149.117445, 66.030666],
            v_mps: [84.890949006, 1121.477985838, 7350.909624142],
        }
    );
    assert_eq!(
        e.epoch_of(&e.rows[1]).unwrap(),
        expected.add(acs::time::TimeSpan::new(60, 0))
    );
}

#[test]
fn writes_every_reference_file_back_byte_for_byte() {
    for (name, text) in reference_files() {
        let e = stk::read(&text).unwrap();
        let written = stk::write(&e);
        if written != text {
            let first = written
                .lines()
                .zip(text.lines())
                .position(|(a, b)| a != b)
                .unwrap_or(0);
            panic!(
                "{name}: line {} differs:\n  {:?}\n  {:?}",
                first + 1,
                written.lines().nth(first),
                text.lines().nth(first)
            );
        }
        assert_eq!(stk::read(&written).unwrap(), e, "{name}");
    }
}

#[test]
fn round_trip_of_a_written_ephemeris() {
    let epoch = Tle::parse(
        "1 27842U 03031C   09166.20608466  .00000024  00000-0  31026-4 0  5778",
        "2 27842  98.7036 176.3713 0009831 124.5029 235.7083 14.20982944309069",
    )
    .unwrap()
    .epoch;
    let mut e = StkEphemeris::new(epoch, CoordinateSystem::J2000);
    e.comments.push("written by a test".to_owned());
    e.other_keywords.push((
        "CoordinateSystemEpoch".to_owned(),
        "01 Jan 2000 12:00:00.000000".to_owned(),
    ));
    for i in 0..5 {
        let t = f64::from(i) * 30.5 - 20.0;
        e.rows.push(StateRow {
            t_s: t,
            r_m: [7e6 + t / 3.0, -1.0 / 3.0, 1e-7],
            v_mps: [-7500.0 / 7.0, t.sin(), -0.0],
        });
    }
    let text = stk::write(&e);
    assert!(
        text.contains("ScenarioEpoch 15 Jun 2009 04:56:45.714624\n"),
        "{text}"
    );
    let back = stk::read(&text).unwrap();
    assert_eq!(back.rows.len(), e.rows.len());
    for (a, b) in back.rows.iter().zip(&e.rows) {
        common::assert_close(a.t_s, b.t_s, 0.5e-6, "t");
        for k in 0..3 {
            common::assert_close(a.r_m[k], b.r_m[k], 0.5e-6, "r");
            common::assert_close(a.v_mps[k], b.v_mps[k], 0.5e-9, "v");
        }
    }
    // once rounded, the file is a fixed point
    assert_eq!(stk::write(&back), text);
    let header_only = StkEphemeris {
        rows: Vec::new(),
        ..back.clone()
    };
    assert_eq!(stk::read(&stk::write(&header_only)).unwrap(), header_only);
}

#[test]
fn dates() {
    let d = stk::parse_date("15 Jun 2009 04:56:45.472650").unwrap();
    assert_eq!(stk::format_date(&d), "15 Jun 2009 04:56:45.472650");
    let d = stk::parse_date("2 Oct 2018 02:28:18.5").unwrap();
    assert_eq!(stk::format_date(&d), "02 Oct 2018 02:28:18.500000");
    let d = stk::parse_date("31 Dec 2016 23:59:60.123456789").unwrap();
    assert_eq!(stk::format_date(&d), "31 Dec 2016 23:59:60.123456789");
    assert_eq!(
        stk::parse_date("01 Jan 2000 00:00:00").unwrap(),
        Epoch::<Utc>::from_parts(0, 0, 0).unwrap()
    );
    for bad in [
        "",
        "15 Jux 2009 04:56:45.0",
        "32 Jan 2009 00:00:00",
        "29 Feb 2009 00:00:00",
        "15 Jun 09 04:56:45",
        "15 Jun 2009 4:56:45",
        "15 Jun 2009 04:56:45.",
        "15 Jun 2009 04:56:45.1234567890",
        "15 Jun 2009 24:00:00",
        "15 Jun 2009 04:56:45 UTC",
        "15 Jun 2009 04:56:-5",
    ] {
        assert_eq!(stk::parse_date(bad), None, "{bad:?}");
    }
}

/// A small valid file, edited by the error tests.
const SMALL: &str = "stk.v.11.0
# comment
BEGIN Ephemeris
NumberOfEphemerisPoints 2
ScenarioEpoch 15 Jun 2009 04:56:45.714624
CentralBody Earth
CoordinateSystem TEMEOfDate
DistanceUnit Meters
EphemerisTimePosVel
0.0 1 2 3 4 5 6
60.0 1 2 3 4 5 6
END Ephemeris
";

#[track_caller]
fn assert_error(text: &str, line: usize, kind: StkErrorKind) {
    let e = stk::read(text).unwrap_err();
    assert_eq!((e.line, &e.kind), (line, &kind), "{e}");
    assert!(e.to_string().contains(&format!("line {line}")));
}

#[test]
fn small_file_reads() {
    let e = stk::read(SMALL).unwrap();
    assert_eq!(e.rows.len(), 2);
    assert_eq!(e.interpolation_method, None);
    // CRLF line ends and blank lines are fine
    let crlf = SMALL.replace('\n', "\r\n\r\n");
    assert_eq!(stk::read(&crlf).unwrap(), e);
}

#[test]
fn errors_name_the_line() {
    assert_error(
        "BEGIN Ephemeris\n",
        1,
        StkErrorKind::NotStkFile {
            found: "BEGIN Ephemeris".into(),
        },
    );
    assert_error("", 1, StkErrorKind::NotStkFile { found: "".into() });
    assert_error(
        &SMALL.replace("BEGIN Ephemeris", "BEGIN Attitude"),
        3,
        StkErrorKind::ExpectedBegin {
            found: "BEGIN Attitude".into(),
        },
    );
    assert_error(
        &SMALL.replace("CentralBody Earth", "CoordinateSystem J2000"),
        7,
        StkErrorKind::DuplicateKeyword {
            keyword: "CoordinateSystem".into(),
        },
    );
    assert_error(
        &SMALL.replace("04:56:45.714624", "04:61:45.714624"),
        5,
        StkErrorKind::BadValue {
            keyword: "ScenarioEpoch".into(),
            value: "15 Jun 2009 04:61:45.714624".into(),
        },
    );
    assert_error(
        &SMALL.replace("Points 2", "Points two"),
        4,
        StkErrorKind::BadValue {
            keyword: "NumberOfEphemerisPoints".into(),
            value: "two".into(),
        },
    );
    assert_error(
        &SMALL.replace("Meters", "Kilometers"),
        8,
        StkErrorKind::Unsupported {
            keyword: "DistanceUnit".into(),
            value: "Kilometers".into(),
        },
    );
    assert_error(
        &SMALL.replace("EphemerisTimePosVel", "EphemerisTimePos"),
        9,
        StkErrorKind::Unsupported {
            keyword: "data format".into(),
            value: "EphemerisTimePos".into(),
        },
    );
    assert_error(
        &SMALL.replace("ScenarioEpoch 15 Jun 2009 04:56:45.714624\n", ""),
        8,
        StkErrorKind::MissingKeyword {
            keyword: "ScenarioEpoch",
        },
    );
    assert_error(
        &SMALL.replace("CoordinateSystem TEMEOfDate\n", ""),
        8,
        StkErrorKind::MissingKeyword {
            keyword: "CoordinateSystem",
        },
    );
    assert_error(
        &SMALL.replace("60.0 1 2 3 4 5 6", "60.0 1 2 3 4 5"),
        11,
        StkErrorKind::FieldCount { found: 6 },
    );
    assert_error(
        &SMALL.replace("60.0 1 2 3 4 5 6", "60.0 1 2 3 4 5 6 7"),
        11,
        StkErrorKind::FieldCount { found: 8 },
    );
    assert_error(
        &SMALL.replace("60.0 1 2 3 4 5 6", "60.0 1 2 x 4 5 6"),
        11,
        StkErrorKind::BadNumber {
            field: 4,
            text: "x".into(),
        },
    );
    assert_error(
        &SMALL.replace("60.0 1 2 3 4 5 6", "60.0 1 2 3 NaN 5 6"),
        11,
        StkErrorKind::BadNumber {
            field: 5,
            text: "NaN".into(),
        },
    );
    assert_error(
        &SMALL.replace("60.0 1", "0.0 1"),
        11,
        StkErrorKind::TimeNotIncreasing {
            previous_s: 0.0,
            t_s: 0.0,
        },
    );
    assert_error(
        &SMALL.replace("Points 2", "Points 3"),
        12,
        StkErrorKind::PointCount {
            declared: 3,
            found: 2,
        },
    );
    assert_error(
        &SMALL.replace("END Ephemeris\n", ""),
        11,
        StkErrorKind::MissingEnd,
    );
    assert_error(
        &format!("{SMALL}0.0 1 2 3 4 5 6\n"),
        13,
        StkErrorKind::TrailingText {
            found: "0.0 1 2 3 4 5 6".into(),
        },
    );
}

/// Which epoch do the reference rows count from? Propagate the quoted TLE with the `sgp4` crate
/// (WGS-72 for the `wgs72` files, WGS-84 for `dtusat_wgs84_teme.e`) at `tsince = t/60` minutes
/// from the TLE epoch, and at `(t + ScenarioEpoch − TLE epoch)/60` from the header's epoch.
#[test]
fn reference_rows_count_from_the_tle_epoch() {
    let mut tle_epoch = common::Stats::new("|Δr| rows vs sgp4 crate, t from the TLE epoch, m");
    let mut header_epoch = common::Stats::new("|Δr| rows vs sgp4 crate, t from ScenarioEpoch, m");
    let mut velocity = common::Stats::new("|Δv| rows vs sgp4 crate, t from the TLE epoch, m/s");
    for (name, text) in reference_files() {
        if name.contains("j2000") {
            continue; // same rows rotated; frames' tests use them
        }
        let e = stk::read(&text).unwrap();
        let c = &e.comments[0];
        let tle = &c[c.find("TLE: ").unwrap() + 5..];
        let (l1, rest) = tle.split_once(" | ").unwrap();
        let elements =
            sgp4::Elements::from_tle(None, l1.as_bytes(), &rest.as_bytes()[..69]).unwrap();
        let constants = if name.contains("wgs84") {
            sgp4::Constants::from_elements(&elements).unwrap()
        } else {
            sgp4::Constants::from_elements_afspc_compatibility_mode(&elements).unwrap()
        };
        let ours = quoted_tle(&e);
        let offset_s = e.scenario_epoch.span_since(&ours.epoch).as_seconds_f64();
        for row in &e.rows {
            let at = format!("{name} t={}", row.t_s);
            let p = constants
                .propagate(sgp4::MinutesSinceEpoch(row.t_s / 60.0))
                .unwrap();
            let dr = distance_m(p.position, row.r_m);
            tle_epoch.add(dr, &at);
            velocity.add(distance_m(p.velocity, row.v_mps), &at);
            let q = constants
                .propagate(sgp4::MinutesSinceEpoch((row.t_s + offset_s) / 60.0))
                .unwrap();
            header_epoch.add(distance_m(q.position, row.r_m), &at);
        }
    }
    figures::figure("stk.sgp4_crate.max_m", tle_epoch.max());
    figures::figure("stk.sgp4_crate.rms_m", tle_epoch.rms());
    figures::figure("stk.sgp4_crate.velocity_max_mps", velocity.max());
    tle_epoch.print();
    velocity.print();
    header_epoch.print();
    // The TLE-epoch reading matches to the sgp4 crate's agreement with Vallado's code; the
    // header's epoch is off by ~0.1–0.6 s of flight (hundreds of metres to kilometres).
    // Measured: 2.0e-6 m and 1.7e-9 m/s (the files print 1e-6 m and 1e-9 m/s).
    assert!(tle_epoch.max() < 1e-5, "{tle_epoch}");
    assert!(velocity.max() < 1e-8, "{velocity}");
    assert!(header_epoch.max() > 1000.0, "{header_epoch}");
}

/// |a_km · 1000 − b_m|
fn distance_m(a_km: [f64; 3], b_m: [f64; 3]) -> f64 {
    a_km.iter()
        .zip(b_m)
        .map(|(a, b)| (a * 1000.0 - b).powi(2))
        .sum::<f64>()
        .sqrt()
}
