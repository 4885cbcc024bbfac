//! `acs elements` against `docs/cli.md` and issue #17 (decision 1): every reference element
//! set that SGP4 accepts goes TLE → words → `--check` in both formats and both gravity models,
//! and the board's propagator from the words (`Sgp4::from_words`) is bit for bit that of the TLE
//! (`Sgp4::new`); `--check` refuses every single-bit flip naming the flipped word, a truncated
//! set, a missing, extra or unreadable word naming it, garbage; a bad TLE exits 2 with the
//! parser's error.
//!
//! Run: `cargo test --release --test cli_elements -- --nocapture` (prints the counts).
#![cfg(feature = "host")]

mod common;

use std::path::PathBuf;
use std::process::{Command, Output, Stdio};

use acs::host::cli::elements::{self, Fault, Refusal};
use acs::orbit::sgp4::{Gravity, Sgp4, Sgp4Error, ELEMENT_WORDS};
use acs::time::TimeSpan;
use acs::tle::{Checksum, Tle};

const GRAVITIES: [(Gravity, &str); 2] = [(Gravity::Wgs72, "wgs72"), (Gravity::Wgs84, "wgs84")];

fn acs(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_acs"))
        .args(args)
        .output()
        .expect("the acs binary runs")
}

fn acs_stdin(args: &[&str], input: &str) -> Output {
    use std::io::Write;
    let mut child = Command::new(env!("CARGO_BIN_EXE_acs"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the acs binary runs");
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.as_bytes())
        .unwrap();
    child.wait_with_output().unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A file in the temporary directory, unique to this test process.
fn temp(name: &str, contents: &[u8]) -> PathBuf {
    let path = std::env::temp_dir().join(format!("acs-elements-{}-{name}", std::process::id()));
    std::fs::write(&path, contents).unwrap();
    path
}

/// One reference element set: its text as a TLE file (the name line when the file has one),
/// and the set parsed with checksums ignored (some `SGP4-VER.TLE` cases were hand-edited).
struct RefSet {
    label: String,
    file_text: String,
    tle: Tle,
}

/// Every element set of `tests/data/sgp4/`.
fn reference_sets() -> Vec<RefSet> {
    let mut out = Vec::new();
    for file in ["SGP4-VER.TLE", "catalogue.tle", "dtusat.tle"] {
        let content = common::read_data(&format!("sgp4/{file}"));
        let lines: Vec<&str> = content.lines().collect();
        for (i, l) in lines.iter().enumerate() {
            if !l.starts_with("1 ") {
                continue;
            }
            let l2 = lines[i + 1];
            let name = i
                .checked_sub(1)
                .map(|j| lines[j])
                .filter(|n| !n.starts_with('#') && !n.starts_with("2 ") && !n.trim().is_empty());
            let file_text = match name {
                Some(n) => format!("{n}\n{l}\n{l2}\n"),
                None => format!("{l}\n{l2}\n"),
            };
            let tle = Tle::parse_with(None, l, l2, Checksum::Ignore)
                .unwrap_or_else(|e| panic!("{file}: {e}\n{l}\n{l2}"));
            out.push(RefSet {
                label: format!("{file} #{}", tle.catalog_number),
                file_text,
                tle,
            });
        }
    }
    assert!(out.len() >= 46, "{} reference sets", out.len());
    out
}

/// The reference sets SGP4 accepts (with checksums ignored), with their words per model.
fn accepted_sets() -> Vec<(RefSet, Gravity, [u32; ELEMENT_WORDS])> {
    let mut out = Vec::new();
    for set in reference_sets() {
        for (g, _) in GRAVITIES {
            if let Ok(sgp4) = Sgp4::new(&set.tle, g) {
                let words = sgp4.to_words();
                out.push((
                    RefSet {
                        label: format!("{} {g:?}", set.label),
                        file_text: set.file_text.clone(),
                        tle: set.tle.clone(),
                    },
                    g,
                    words,
                ));
            }
        }
    }
    out
}

/// The words of `acs elements` hex output: 58 lines of exactly 8 hex digits.
fn hex_words(stdout: &str) -> Vec<u32> {
    stdout
        .lines()
        .map(|l| {
            assert!(
                l.len() == 8 && l.bytes().all(|b| b.is_ascii_hexdigit()),
                "not a hex word: `{l}`"
            );
            u32::from_str_radix(l, 16).unwrap()
        })
        .collect()
}

/// Position and velocity bits, or the error, at `t_min` after the epoch.
type Bits = Result<([u32; 3], [u32; 3]), Sgp4Error>;

fn state_bits(sgp4: &Sgp4, t_min: f64) -> Bits {
    let s = sgp4.propagate(TimeSpan::from_minutes_f64(t_min).unwrap())?;
    let (r, v) = (s.r_teme_km, s.v_teme_kmps);
    Ok((
        [r.x.to_bits(), r.y.to_bits(), r.z.to_bits()],
        [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()],
    ))
}

/// The expected `--check` summary of an intact set.
fn summary(norad: Option<u32>, tle: &Tle, gravity: &str) -> String {
    let satellite = match norad {
        Some(n) => format!("satellite {n}"),
        None => "satellite unknown (not in hex words)".to_string(),
    };
    format!(
        "intact: 58 words, {satellite}, epoch {}, gravity {gravity}",
        elements::iso_utc(&tle.epoch)
    )
}

/// TLE → words → `--check`, through the binary, for every reference set and both gravity
/// models, in both formats; the board's propagator from the words is the TLE's bit for bit.
#[test]
fn every_reference_set_round_trips() {
    let (mut intact, mut refused_tle, mut refused_sgp4) = (0, 0, 0);
    for set in reference_sets() {
        let file = temp("set.tle", set.file_text.as_bytes());
        let file = file.to_str().unwrap();
        let parsed = Tle::parse_text(&set.file_text);
        for (g, gname) in GRAVITIES {
            let hex = acs(&["elements", "--tle", file, "--gravity", gname]);
            let json = acs(&[
                "elements",
                "--tle",
                file,
                "--gravity",
                gname,
                "--format",
                "json",
            ]);
            let what = format!("{} {gname}", set.label);
            let tle = match &parsed {
                Err(e) => {
                    // a hand-edited case whose checksum was not updated: the parser's error
                    for out in [&hex, &json] {
                        assert_eq!(out.status.code(), Some(2), "{what}");
                        assert!(text(&out.stderr).contains(&e.to_string()), "{what}");
                    }
                    refused_tle += 1;
                    continue;
                }
                Ok(tle) => tle,
            };
            let sgp4 = match Sgp4::new(tle, g) {
                Err(e) => {
                    let code = if matches!(e, Sgp4Error::Element { .. }) {
                        2
                    } else {
                        3
                    };
                    for out in [&hex, &json] {
                        assert_eq!(out.status.code(), Some(code), "{what}");
                        assert!(text(&out.stderr).contains(&e.to_string()), "{what}");
                    }
                    refused_sgp4 += 1;
                    continue;
                }
                Ok(s) => s,
            };
            assert_eq!(hex.status.code(), Some(0), "{what}: {}", text(&hex.stderr));
            assert_eq!(
                json.status.code(),
                Some(0),
                "{what}: {}",
                text(&json.stderr)
            );
            let expected = sgp4.to_words();
            let words = hex_words(&text(&hex.stdout));
            assert_eq!(words, expected, "{what}");
            assert_eq!(elements::checksum(&words[..57]), words[57], "{what}");

            let doc: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
            let json_words: Vec<u32> = doc["words"]
                .as_array()
                .unwrap()
                .iter()
                .map(|w| u32::from_str_radix(w.as_str().unwrap(), 16).unwrap())
                .collect();
            assert_eq!(json_words, expected, "{what}");
            assert_eq!(doc["norad"].as_u64(), Some(u64::from(tle.catalog_number)));
            assert_eq!(
                doc["epoch_utc"].as_str(),
                Some(elements::iso_utc(&tle.epoch).as_str())
            );

            // the board's propagator from the words: bit for bit the TLE's
            let words: [u32; ELEMENT_WORDS] = words.try_into().unwrap();
            let board = Sgp4::from_words(&words).unwrap();
            assert_eq!(board, sgp4, "{what}");
            for t in [
                -1440.0, -0.5, 0.0, 0.25, 1.0, 97.5, 360.0, 1440.0, 4320.0, 10080.0,
            ] {
                assert_eq!(
                    state_bits(&board, t),
                    state_bits(&sgp4, t),
                    "{what} at {t} min"
                );
            }

            // the words read back: intact, with the summary
            for (out, norad, name) in [
                (&hex, None, "words.hex"),
                (&json, Some(tle.catalog_number), "words.json"),
            ] {
                let back = temp(name, &out.stdout);
                let check = acs(&["elements", "--check", back.to_str().unwrap()]);
                assert_eq!(
                    check.status.code(),
                    Some(0),
                    "{what}: {}",
                    text(&check.stderr)
                );
                assert_eq!(text(&check.stdout).trim_end(), summary(norad, tle, gname));
            }
            // and from stdin
            let check = acs_stdin(&["elements", "--check", "-"], &text(&json.stdout));
            assert_eq!(
                check.status.code(),
                Some(0),
                "{what}: {}",
                text(&check.stderr)
            );
            intact += 1;
        }
    }
    println!(
        "acs elements: {intact} set-and-model round trips, {refused_tle} refused by the TLE \
         parser (exit 2), {refused_sgp4} by SGP4"
    );
    assert!(intact >= 2 * 20, "{intact}");
}

/// The TLE behind the words is recovered exactly (what `--check` uses to name a bad word),
/// for every reference set SGP4 accepts, both models.
#[test]
fn the_tle_is_recovered_from_the_words() {
    let sets = accepted_sets();
    for (set, g, words) in &sets {
        let (tle, gravity) =
            elements::tle_of(words).unwrap_or_else(|| panic!("{}: not recovered", set.label));
        let t = &set.tle;
        // 360° and 0° are the same angle (SGP4 reduces them to the same words)
        let angle = |a: f64| if a == 360.0 { 0.0 } else { a };
        assert_eq!(gravity, *g, "{}", set.label);
        assert_eq!(tle.epoch, t.epoch, "{}", set.label);
        assert_eq!(tle.inclination_deg, t.inclination_deg, "{}", set.label);
        assert_eq!(tle.raan_deg, angle(t.raan_deg), "{}", set.label);
        assert_eq!(tle.eccentricity, t.eccentricity, "{}", set.label);
        assert_eq!(
            tle.arg_perigee_deg,
            angle(t.arg_perigee_deg),
            "{}",
            set.label
        );
        assert_eq!(
            tle.mean_anomaly_deg,
            angle(t.mean_anomaly_deg),
            "{}",
            set.label
        );
        assert_eq!(
            tle.mean_motion_rev_per_day, t.mean_motion_rev_per_day,
            "{}",
            set.label
        );
        assert_eq!(tle.bstar, t.bstar, "{}", set.label);
    }
    println!(
        "TLE recovered from the words: {} set-and-model pairs",
        sets.len()
    );
}

/// The refusal of `words` written as hex.
fn refusal_hex(words: &[u32]) -> Refusal {
    let text: String = words.iter().map(|w| format!("{w:08x}\n")).collect();
    elements::check_text(&text).unwrap_err()
}

/// Asserts that `r` names word `k` as corrupt: alone, or together with the checksum (word 57)
/// when the data cannot tell them apart: a word that alone carries an element, the epoch day
/// (word 1) or the node's high word (word 19), against the checksum.
#[track_caller]
fn assert_names_corrupt(r: &Refusal, k: usize, what: &str) {
    assert_eq!(r.fault, Fault::Corrupt, "{what}: {r}");
    if r.words.len() == 1 {
        assert_eq!(r.words, [k], "{what}: {r}");
    } else {
        assert!(r.words == [1, 57] || r.words == [19, 57], "{what}: {r}");
        assert!(r.words.contains(&k), "{what}: {r}");
    }
    assert!(r.message.contains(&format!("word {k} (")), "{what}: {r}");
}

/// Every single-bit flip of every word is refused naming the flipped word: all 58 × 32 flips
/// for DTUSAT (full drag) and a low-perigee set (simplified drag), both models, hex and JSON
/// (the JSON epoch settles the epoch-day/checksum ambiguity, not the node's); one flip a word
/// for every other reference set.
#[test]
fn every_single_bit_flip_is_named() {
    let sets = accepted_sets();
    let full =
        |(set, ..): &&(RefSet, Gravity, [u32; ELEMENT_WORDS])| set.tle.catalog_number == 27842;
    let simplified = |(.., w): &&(RefSet, Gravity, [u32; ELEMENT_WORDS])| w[44] == 0;
    let simplified_norad = sets
        .iter()
        .find(simplified)
        .expect("a reference set with simplified drag")
        .0
        .tle
        .catalog_number;
    let (mut flips, mut ambiguous) = (0, 0);
    for (i, (set, _, words)) in sets.iter().enumerate() {
        let all = set.tle.catalog_number == 27842 || set.tle.catalog_number == simplified_norad;
        for k in 0..ELEMENT_WORDS {
            let bits: Vec<u32> = if all {
                (0..32).collect()
            } else {
                vec![((7 * k + i) % 32) as u32]
            };
            for b in bits {
                let mut bad = *words;
                bad[k] ^= 1 << b;
                let what = format!("{} word {k} bit {b}", set.label);
                let r = refusal_hex(&bad);
                assert_names_corrupt(&r, k, &what);
                assert!(
                    r.message.contains(&format!("line {}", k + 1)),
                    "{what}: {r}"
                );
                ambiguous += usize::from(r.words.len() > 1);
                flips += 1;
                if all {
                    // the JSON form: its epoch says which epoch is right
                    let json = elements::to_json(&bad, set.tle.catalog_number, &set.tle.epoch);
                    let r = elements::check_text(&json).unwrap_err();
                    assert_names_corrupt(&r, k, &format!("{what} (JSON)"));
                    assert_ne!(r.words, [1, 57], "{what} (JSON): the epoch tells");
                }
            }
        }
    }
    assert!(sets.iter().filter(full).count() == 2);
    println!(
        "{flips} single-bit flips named ({ambiguous} together with the checksum: the epoch day \
         or the node's high word, which the words cannot tell from it)"
    );
}

/// A missing word (the set truncated, or a word dropped), an extra word (garbage inserted, a
/// word repeated) and two wrong words: the word named is where the set first departs from the
/// intact one.
#[test]
fn missing_and_extra_words_are_named() {
    for (set, _, words) in accepted_sets()
        .iter()
        .filter(|(s, ..)| [27842, 5, 88888].contains(&s.tle.catalog_number))
    {
        // a repeated value makes positions in its run equivalent: the first one is named
        let run_start = |k: usize| {
            let mut j = k;
            while j > 0 && words[j - 1] == words[k] {
                j -= 1;
            }
            j
        };
        for k in 0..ELEMENT_WORDS {
            let mut v = words.to_vec();
            v.remove(k);
            let r = refusal_hex(&v);
            let what = format!("{}: word {k} dropped", set.label);
            assert_eq!(
                (r.fault, r.words.clone()),
                (Fault::Missing, vec![run_start(k)]),
                "{what}: {r}"
            );

            let mut v = words.to_vec();
            v.insert(k, 0xdead_beef);
            let r = refusal_hex(&v);
            let what = format!("{}: garbage before word {k}", set.label);
            assert_eq!(
                (r.fault, r.words.clone()),
                (Fault::Extra, vec![k]),
                "{what}: {r}"
            );
            assert!(
                r.message.contains(&format!("line {}", k + 1)),
                "{what}: {r}"
            );

            let mut v = words.to_vec();
            v.insert(k, words[k]);
            let r = refusal_hex(&v);
            let what = format!("{}: word {k} repeated", set.label);
            assert_eq!(
                (r.fault, r.words.clone()),
                (Fault::Extra, vec![run_start(k)]),
                "{what}: {r}"
            );
        }
        let r = refusal_hex(&words[..57]);
        assert_eq!(
            (r.fault, r.words.clone()),
            (Fault::Missing, vec![57]),
            "{r}"
        );
        let r = refusal_hex(&words[..40]);
        assert_eq!(
            (r.fault, r.words.clone()),
            (Fault::Unlocated, vec![40]),
            "{r}"
        );
        let mut v = words.to_vec();
        v.extend([1, 2]);
        let r = refusal_hex(&v);
        assert_eq!(
            (r.fault, r.words.clone()),
            (Fault::Unlocated, vec![58]),
            "{r}"
        );
        let mut v = *words;
        v[10] ^= 1;
        v[40] ^= 1 << 20;
        let r = refusal_hex(&v);
        assert_eq!(
            (r.fault, r.words.clone()),
            (Fault::Unlocated, vec![57]),
            "{r}"
        );
    }
}

/// Sets with the right checksum that the board refuses, or of neither gravity model, or whose
/// JSON epoch is not theirs: the word (or field) at fault.
#[test]
fn consistent_but_wrong_sets_are_refused() {
    let tle = Tle::parse_text(&common::read_data("sgp4/dtusat.tle")).unwrap();
    let words = Sgp4::new(&tle, Gravity::Wgs72).unwrap().to_words();
    let resum = |mut w: [u32; ELEMENT_WORDS]| {
        w[57] = elements::checksum(&w[..57]);
        w
    };
    for (k, value) in [
        (0, 0x5334_0002),
        (44, 2),
        (31, 0x7fc0_0000),
        (4, 0x45c7_5000),
    ] {
        let mut w = words;
        w[k] = value;
        let r = refusal_hex(&resum(w));
        assert_eq!((r.fault, r.words.clone()), (Fault::Invalid, vec![k]), "{r}");
        assert!(
            r.message.contains(&format!("line {}: word {k} (", k + 1)),
            "{r}"
        );
    }
    // the JSON epoch is the words' epoch, the satellite number a number
    let json = elements::to_json(&words, 27842, &tle.epoch);
    assert!(elements::check_text(&json).is_ok());
    let other = json.replace("45.714624Z", "45.714Z");
    let r = elements::check_text(&other).unwrap_err();
    assert_eq!(r.fault, Fault::Metadata, "{r}");
    assert!(r.message.contains("epoch_utc"), "{r}");
    let r =
        elements::check_text(&json.replace("\"norad\": 27842", "\"norad\": \"x\"")).unwrap_err();
    assert_eq!(r.fault, Fault::Metadata, "{r}");
}

/// Garbage: unreadable tokens name their line and word; JSON errors their place; nothing
/// panics.
#[test]
fn garbage_is_refused() {
    let tle = Tle::parse_text(&common::read_data("sgp4/dtusat.tle")).unwrap();
    let words = Sgp4::new(&tle, Gravity::Wgs72).unwrap().to_words();
    let hex = elements::to_hex(&words);
    let mut lines: Vec<String> = hex.lines().map(str::to_string).collect();
    for (token, k) in [
        ("zz", 12),
        ("5334001", 0),
        ("0534000011", 3),
        ("0x533400", 7),
        ("00000d7d 0", 9),
    ] {
        let keep = lines[k].clone();
        lines[k] = token.to_string();
        let r = elements::check_text(&lines.join("\n")).unwrap_err();
        assert_eq!((r.fault, r.words.clone()), (Fault::Syntax, vec![k]), "{r}");
        assert!(r.message.contains(&format!("line {}", k + 1)), "{r}");
        lines[k] = keep;
    }
    // comments and blank lines are ignored; the line numbers are the file's
    let commented = format!("# uplink\n\n{hex}");
    assert!(elements::check_text(&commented).is_ok());
    let r = elements::check_text(&commented.replace("00000d7d", "0000gd7d")).unwrap_err();
    assert!(r.message.starts_with("line 4: "), "{r}");
    for garbage in [
        "",
        "\n# nothing\n",
        "hello",
        "{",
        "{}",
        "{\"words\": 3}",
        "{\"words\": [\"53340001\", 5]}",
        "[1, 2, 3]",
        "\u{0}\u{1}\u{2}",
        "ffffffff\nffffffff\n",
    ] {
        let r = elements::check_text(garbage).unwrap_err();
        assert!(!r.message.is_empty(), "{garbage:?}");
    }
    // through the binary: exit 2, the file and the line named
    for (name, contents, needle) in [
        ("garbage.bin", &b"\x00\xff\xfe hello"[..], "line 1"),
        ("truncated.hex", &hex.as_bytes()[..hex.len() - 9], "word 57"),
        (
            "nonhex.hex",
            hex.replacen("00000d7d", "00000d7x", 1).as_bytes(),
            "line 2",
        ),
    ] {
        let path = temp(name, contents);
        let out = acs(&["elements", "--check", path.to_str().unwrap()]);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: {stderr}");
        assert!(
            stderr.contains(name) && stderr.contains(needle),
            "{name}: {stderr}"
        );
    }
}

/// A single-bit flip through the binary: exit 2, the line and the word named.
#[test]
fn check_names_the_flipped_word_through_the_binary() {
    let tle_path = common::data_path("sgp4/dtusat.tle");
    let out = acs(&["elements", "--tle", tle_path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0));
    let mut words = hex_words(&text(&out.stdout));
    words[31] ^= 1 << 3;
    let path = temp(
        "flip.hex",
        words
            .iter()
            .map(|w| format!("{w:08x}\n"))
            .collect::<String>()
            .as_bytes(),
    );
    let out = acs(&["elements", "--check", path.to_str().unwrap()]);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("line 32: word 31 (ecco) is corrupt"),
        "{stderr}"
    );
}

/// A bad TLE exits 2 with the parser's error (line, column, field); a deep-space set exits 3
/// (SGP4 refuses it), as for `acs propagate`; usage errors exit 2.
#[test]
fn bad_input_exit_codes() {
    let good = common::read_data("sgp4/dtusat.tle");
    for (name, bad) in [
        ("checksum.tle", good.replace("0  5778", "0  5779")),
        (
            "shifted.tle",
            good.replace("27842U 03031C ", "27842U 03031C"),
        ),
        (
            "one-line.tle",
            good.lines().take(2).collect::<Vec<_>>().join("\n"),
        ),
    ] {
        let expected = Tle::parse_text(&bad).unwrap_err().to_string();
        let path = temp(name, bad.as_bytes());
        let out = acs(&["elements", "--tle", path.to_str().unwrap()]);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: {stderr}");
        assert!(
            stderr.contains(&expected) && stderr.contains(name),
            "{name}: {stderr}"
        );
        assert!(out.stdout.is_empty(), "{name}");
    }
    let out = acs(&["elements", "--tle", "/nonexistent/x.tle"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("x.tle"));

    let deep = "1 11801U          80230.29629788  .01431103  00000-0  14311-1      13\n\
                2 11801  46.7916 230.4354 7318036  47.4722  10.4117  2.28537848    13\n";
    let path = temp("deep.tle", deep.as_bytes());
    let out = acs(&["elements", "--tle", path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(3), "{}", text(&out.stderr));
    assert!(text(&out.stderr).contains("deep-space"));

    let tle = common::data_path("sgp4/dtusat.tle");
    let tle = tle.to_str().unwrap();
    for args in [
        &["elements"][..],
        &["elements", "--tle", tle, "--check", tle][..],
        &["elements", "--check", tle, "--gravity", "wgs84"][..],
        &["elements", "--check", tle, "--format", "json"][..],
        &["elements", "--tle", tle, "--format", "xml"][..],
        &["elements", "--tle", tle, "--gravity", "egm96"][..],
    ] {
        let out = acs(args);
        assert_eq!(out.status.code(), Some(2), "acs {args:?}");
        assert!(!out.stderr.is_empty(), "acs {args:?}");
    }
}
