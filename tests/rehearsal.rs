//! Rehearsing an operation (issue 31, item 5): `acs sim SCENARIO --tc SCRIPT --tm FILE` flies a
//! time-tagged script of telecommands made with `acs tc` and writes every verification report,
//! which `acs tm` decodes; a malformed script is an input error naming its line. The PIL flies
//! the same script with the node images and writes the same bytes
//! (`the_pil_flies_the_same_bytes`, ignored: it needs the images, `firmware/pil` builds them).
//!
//! Run: `cargo test --release --test rehearsal` (`-- --ignored` for the PIL).
#![cfg(feature = "host")]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use acs::attitude::Dcm;
use acs::host::sim::scenarios::{make_tle, mean_motion_rev_per_day};

fn acs(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_acs"))
        .args(args)
        .output()
        .expect("the acs binary runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A fresh folder for one test.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("acs-rehearsal-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The packet `acs tc ARGS --count N` prints, in hex.
fn tc(args: &[&str], count: u16) -> String {
    let count = count.to_string();
    let mut all = args.to_vec();
    all.extend(["--count", &count]);
    let out = acs(&all);
    assert_eq!(
        out.status.code(),
        Some(0),
        "acs tc {args:?}: {}",
        text(&out.stderr)
    );
    text(&out.stdout).trim().to_string()
}

/// A scenario of 300 s (`tracking` on its own TLE, its track command at 1 s) and a script:
/// the clock, a 20° slew, tile 2 marked failed and restored, a new element set.
fn scenario_and_script(dir: &Path) -> (PathBuf, PathBuf) {
    let (l1, l2) = make_tle(
        90101,
        (25, 79.5),
        97.4,
        90.0,
        0.0,
        0.0,
        mean_motion_rev_per_day(500.0),
    );
    let tle = dir.join("sat.tle");
    std::fs::write(&tle, format!("{l1}\n{l2}\n")).unwrap();
    let scenario = dir.join("scenario.json");
    let json = serde_json::json!({"base": "tracking", "duration_s": 300.0, "tle": [l1, l2]});
    std::fs::write(&scenario, json.to_string()).unwrap();
    // the tracking target, turned 20° about the body x axis
    let q = Dcm::a3(0.6)
        .then(&Dcm::a1(-0.3))
        .then(&Dcm::a1(20f32.to_radians()))
        .to_quaternion();
    let q: Vec<String> = [q.q0, q.q1, q.q2, q.q3]
        .iter()
        .map(|x| format!("{x:.9}"))
        .collect();
    let mut slew = vec!["tc", "slew"];
    slew.extend(q.iter().map(String::as_str));
    slew.push("150");
    let lines = [
        "# a rehearsal: clock, slew, a tile out and back, a new element set".to_string(),
        format!("10 {}", tc(&["tc", "clock", "2025-03-20T12:00:10Z"], 100)),
        String::new(),
        format!("60 {}", tc(&slew, 101)),
        format!("200 {}", tc(&["tc", "mark-failed", "tile", "2"], 102)),
        format!("220.5 {}", tc(&["tc", "restore", "tile", "2"], 103)),
        format!("240 {}", tc(&["tc", "elements", "--tle", path(&tle)], 104)),
    ];
    let script = dir.join("script.txt");
    std::fs::write(&script, lines.join("\n") + "\n").unwrap();
    (scenario, script)
}

/// `acs tm FILE` as (node, report, request sequence count, failure code) per verification
/// report (service 1).
fn reports(tm: &Path) -> Vec<(String, String, u16, String)> {
    let out = acs(&["tm", path(tm)]);
    assert_eq!(out.status.code(), Some(0), "acs tm: {}", text(&out.stderr));
    let csv = text(&out.stdout);
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (node, report, count, code, service) = (
        col("node"),
        col("report"),
        col("request_sequence_count"),
        col("failure_code"),
        col("service"),
    );
    lines
        .filter(|l| l.split(',').nth(service) == Some("1"))
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                f[node].to_string(),
                f[report].to_string(),
                f[count].parse().unwrap(),
                f[code].to_string(),
            )
        })
        .collect()
}

#[test]
fn a_script_is_flown_and_every_command_accepted_and_completed() {
    let dir = folder("fly");
    let (scenario, script) = scenario_and_script(&dir);
    let tm = dir.join("run.tm");
    let out = acs(&[
        "sim",
        path(&scenario),
        "--tc",
        path(&script),
        "--tm",
        path(&tm),
        "--out",
        path(&dir.join("out")),
    ]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}{stdout}", text(&out.stderr));
    // the element set and the clock (counts 0, 1), the track (2), the script's five
    assert!(stdout.contains("rehearsal_telecommands: 8\n"), "{stdout}");
    assert!(stdout.contains("rehearsal_refused: 0\n"), "{stdout}");
    assert!(
        stdout.contains(&format!("tm: {}\n", tm.display())),
        "{stdout}"
    );
    assert!(dir.join("out/run.csv").is_file());
    let got = reports(&tm);
    let expected = [
        ("reference", 0),
        ("reference", 1),
        ("reference", 2),
        ("reference", 100),
        ("reference", 101),
        ("attitude", 102),
        ("attitude", 103),
        ("reference", 104),
    ];
    assert_eq!(got.len(), 2 * expected.len(), "{got:?}");
    for (pair, (node, count)) in got.chunks(2).zip(expected) {
        for (r, report) in pair.iter().zip(["accepted", "completed"]) {
            assert_eq!(
                (r.0.as_str(), r.1.as_str(), r.2, r.3.as_str()),
                (node, report, count, ""),
                "{got:?}"
            );
        }
    }
    // the nodes' housekeeping, every 10 periods from the first: tile 2 out of service from its
    // MARK_FAILED (taken in period 200) until its RESTORE (220.5 s: taken in period 221), so in
    // the reports after the steps of periods 200, 210 and 220 (STEP, the next step's number:
    // 201, 211, 221)
    let hk = dir.join("hk");
    let out = acs(&["tm", path(&tm), "--out", path(&hk)]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let table = |name: &str| -> (Vec<String>, Vec<Vec<String>>) {
        let csv = std::fs::read_to_string(hk.join(name)).unwrap();
        let mut lines = csv.lines();
        let header = lines
            .next()
            .unwrap()
            .split(',')
            .map(str::to_string)
            .collect();
        let rows = lines
            .map(|l| l.split(',').map(str::to_string).collect())
            .collect();
        (header, rows)
    };
    let (header, rows) = table("attitude_hk.csv");
    assert_eq!(rows.len(), 30, "300 periods, a report every 10");
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let (step, state) = (col("STEP"), col("TILE_STATE_2"));
    let out_of_service: Vec<u32> = rows
        .iter()
        .filter(|r| r[state].parse::<u8>().unwrap() & 1 != 0)
        .map(|r| r[step].parse().unwrap())
        .collect();
    assert_eq!(out_of_service, [201, 211, 221], "{out_of_service:?}");
    let (_, rows) = table("reference_hk.csv");
    assert_eq!(rows.len(), 30);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_packet_for_no_node_is_refused_by_the_attitude_node() {
    let dir = folder("apid");
    let (scenario, _) = scenario_and_script(&dir);
    // a sun-safe to APID 0x052: the attitude node refuses it (4: another node's APID); a
    // track sent to the attitude node is the other node's command (0x104)
    let sun_safe = tc(&["tc", "sun-safe"], 5);
    let mut bytes: Vec<u8> = (0..sun_safe.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&sun_safe[i..i + 2], 16).unwrap())
        .collect();
    bytes[1] = 0x52;
    // its CRC again (ECSS-E-ST-70-41C B.1), so that its APID is what is wrong
    let n = bytes.len() - 2;
    let crc = bytes[..n].iter().fold(0xFFFFu16, |mut crc, b| {
        crc ^= u16::from(*b) << 8;
        for _ in 0..8 {
            crc = if crc & 0x8000 != 0 {
                crc << 1 ^ 0x1021
            } else {
                crc << 1
            };
        }
        crc
    });
    bytes[n..].copy_from_slice(&crc.to_be_bytes());
    let stray: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
    let script = dir.join("stray.txt");
    std::fs::write(&script, format!("3 {stray}\n")).unwrap();
    let tm = dir.join("stray.tm");
    let out = acs(&[
        "sim",
        path(&scenario),
        "--tc",
        path(&script),
        "--tm",
        path(&tm),
        "--out",
        path(&dir.join("out")),
    ]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}{stdout}", text(&out.stderr));
    assert!(stdout.contains("rehearsal_refused: 1\n"), "{stdout}");
    let got = reports(&tm);
    let last = got.last().unwrap();
    assert_eq!(
        (last.0.as_str(), last.1.as_str(), last.3.as_str()),
        ("attitude", "acceptance failed", "0x004"),
        "{got:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_bad_script_is_an_input_error_naming_its_line() {
    let dir = folder("bad");
    let (scenario, _) = scenario_and_script(&dir);
    let sun_safe = tc(&["tc", "sun-safe"], 0);
    // 15 + 22 B: one byte beyond the attitude node's mailbox
    let long = format!("{sun_safe}{}", "00".repeat(22));
    let cases = [
        (format!("# x\n\n{sun_safe}\n"), "line 3: expected `SECONDS PACKET_HEX`"),
        (format!("10 {sun_safe} 1\n"), "line 1: expected"),
        (format!("soon {sun_safe}\n"), "line 1: time `soon`"),
        (format!("-1 {sun_safe}\n"), "line 1: time `-1`"),
        (format!("nan {sun_safe}\n"), "line 1: time `nan`"),
        ("10 zz\n".to_string(), "line 1: packet: `z`"),
        ("10 123\n".to_string(), "line 1: packet: an odd number"),
        (
            format!("10 {long}\n"),
            "line 1: a packet of 37 B for the attitude node does not fit its telecommand mailbox (36 B)",
        ),
        (
            format!("1 {sun_safe}\n300 {sun_safe}\n"),
            "line 2: time 300 s is after the start of the scenario's last period (299 s)",
        ),
    ];
    for (script, want) in cases {
        let file = dir.join("bad.txt");
        std::fs::write(&file, &script).unwrap();
        let out = acs(&[
            "sim",
            path(&scenario),
            "--tc",
            path(&file),
            "--out",
            path(&dir.join("out")),
        ]);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{script}: {stderr}");
        assert!(stderr.contains(want), "{script}: {stderr}");
        assert!(stderr.contains("bad.txt"), "{stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
    // no such script; a rehearsal of a campaign or of a scenario that is not the flight
    // configuration
    let missing = dir.join("missing.txt");
    for args in [
        vec!["sim", path(&scenario), "--tc", path(&missing)],
        vec![
            "sim", "tracking", "--runs", "2", "--tm", "x.tm", "--out", "x",
        ],
        vec!["sim", "thesis-slew", "--tm", "x.tm", "--out", "x"],
        vec!["sim", "plan-flight", "--tm", "x.tm"],
    ] {
        let out = acs(&args);
        assert_eq!(
            out.status.code(),
            Some(2),
            "{args:?}: {}",
            text(&out.stderr)
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The same script through the two node images (`acs sim ... --pil`): the reports the images
/// write are byte for byte the host run's. Needs `mspdebug` and both images
/// (`firmware/pil` builds them; `ACS_ELF_REFERENCE`, `ACS_ELF_ATTITUDE` override where).
#[test]
#[ignore]
fn the_pil_flies_the_same_bytes() {
    let dir = folder("pil");
    let (scenario, script) = scenario_and_script(&dir);
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let image = |var: &str, default: &str| {
        std::env::var(var).map_or_else(|_| root.join(default), PathBuf::from)
    };
    let reference = image(
        "ACS_ELF_REFERENCE",
        "firmware/target/msp430-none-elf/release/acs-reference",
    );
    let attitude = image(
        "ACS_ELF_ATTITUDE",
        "firmware/target/msp430-none-elf/attitude/acs-attitude",
    );
    let host = dir.join("host.tm");
    let out = acs(&[
        "sim",
        path(&scenario),
        "--tc",
        path(&script),
        "--tm",
        path(&host),
        "--out",
        path(&dir.join("host")),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let pil = dir.join("pil.tm");
    let out = acs(&[
        "sim",
        path(&scenario),
        "--pil",
        "--elf-reference",
        path(&reference),
        "--elf-attitude",
        path(&attitude),
        "--tc",
        path(&script),
        "--tm",
        path(&pil),
        "--out",
        path(&dir.join("pil")),
        "--pil-json",
        path(&dir.join("pil.json")),
    ]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}{stdout}", text(&out.stderr));
    assert!(stdout.contains("pil_mismatches: 0\n"), "{stdout}");
    let (host, pil) = (std::fs::read(&host).unwrap(), std::fs::read(&pil).unwrap());
    assert_eq!(
        reports(&dir.join("host.tm")).len(),
        16,
        "eight commands, two reports each"
    );
    assert!(
        host.len() > 30 * (169 + 66),
        "and both nodes' housekeeping, 30 reports each"
    );
    assert!(
        host == pil,
        "the images' reports and telemetry differ from the host run's"
    );
    // the run itself: the same samples up to the first slew command (60 s), as the PIL's
    // module docs say of a plain run; here the host run flies the nodes as the images do, so
    // every step is the same
    let (a, b) = (
        std::fs::read_to_string(dir.join("host/run.csv")).unwrap(),
        std::fs::read_to_string(dir.join("pil/run.csv")).unwrap(),
    );
    assert_eq!(a, b, "run.csv differs between the host run and the PIL");
    let _ = std::fs::remove_dir_all(&dir);
}
