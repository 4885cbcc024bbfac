//! `acs elements`: the uplink of SGP4 initialised on the ground (`docs/cli.md`; issue #17,
//! product decision 1).
//!
//! Flight operations initialise SGP4 on the ground and uplink the element set as the
//! [`ELEMENT_WORDS`] checked 32-bit words of [`Sgp4::to_words`]; the board reads them with
//! [`Sgp4::from_words`] and propagates, bit for bit as [`Sgp4::new`] on the same TLE would.
//!
//! # Use
//! ```text
//! acs elements --tle FILE [--gravity wgs72|wgs84] [--format hex|json]
//! acs elements --check FILE            (FILE `-`: stdin)
//! ```
//! - `--tle`: FILE holds one element set, read as `acs propagate` reads it (two lines or a name
//!   line and two lines, checksums verified). stdout: the 58 words one per line as 8 lower-case
//!   hex digits (`hex`, default), or `{"words": ["53340001", ...], "norad": N, "epoch_utc":
//!   "..."}` (`json`; the words as strings of 8 hex digits, the epoch in ISO 8601 UTC with as
//!   many fractional digits, 3, 6 or 9, as make it exact).
//! - `--check`: FILE holds words in either format (JSON when its first line that is not blank
//!   or a `#` comment starts with `{`; blank and `#` lines are ignored in both). Exit 0 and one
//!   line on stdout when the set is intact: `intact: 58 words, satellite N, epoch ..., gravity
//!   wgs72`. Exit 2 naming the first bad word and its line otherwise.
//!
//! Exit codes: 2 for an unreadable or malformed TLE (the parser's [`crate::tle::TleError`]:
//! line, column, field), an element SGP4 refuses as out of range, a refused word set; 3 when
//! SGP4 refuses the element set itself (deep space, sub-orbital), as for `acs propagate`.
//!
//! # What the words carry, and the summary
//! The words are the board's state, nothing more (layout 1 of [`Sgp4::to_words`], tag
//! `0x53340001`): the epoch (words 1–3), the gravity model's constants (words 4–6: Earth
//! radius, `xke`, J₂), the initialised constants and phases, a checksum (word 57). So:
//! - the **epoch** comes from the words (and a JSON `epoch_utc` must agree with it);
//! - the **gravity model** is recognised from words 4–6, compared with the words
//!   [`Sgp4::new`] writes for each model (a set with other constants is refused, word 4–6);
//! - the **satellite number** is not in the words: the board does not need it, and adding it
//!   would change the layout (the lead's, in `src/orbit/sgp4/words.rs`). The JSON form carries
//!   it as `norad` (outside the checksum, like `epoch_utc`); for hex words the summary says
//!   `satellite unknown (not in hex words)`.
//!
//! # Naming the bad word
//! [`Sgp4::from_words`] checks the checksum first, so a corrupted word shows on board as word
//! 57 whatever word it was. The ground can do better, because a set written by `acs elements
//! --tle` is a function of a TLE: the TLE is recovered from the words ([`tle_of`]: epoch, the
//! angles from their fixed-point phases, e, i from cos i₀ and sin i₀, B*, each rounded to the
//! TLE's decimals; the mean motion by secant steps on the exact mean-anomaly rate), and
//! re-initialised. `--check` then looks for the single fault that explains the set:
//! - 58 words, checksum wrong: for each word k, the one value of word k that satisfies the
//!   checksum (it is linear: each word is rotated into it) gives a candidate set;
//! - 57 words: a word inserted at each position, its value solved likewise;
//! - 59 words: each word removed in turn;
//!
//! and names the candidate that is exactly a set of some TLE (the words `Sgp4::new` writes
//! for the recovered TLE). A single-bit flip is always named, with one ambiguity that is in
//! the data: two elements each live in one word alone, the epoch day (word 1) and the node Ω₀
//! (word 19, the high word of its fixed point, whose bits 9–14 are 2.8125°, 5.625°, …, 90°:
//! TLE values). A flip of a low bit there, or of the checksum bit that corresponds, leaves a
//! set one bit from two intact sets, a TLE's and the same TLE with the epoch moved by 2ᵏ days
//! or the node turned by 2⁻ᵏ turn. `--check` then names both words (the earlier first); a
//! JSON `epoch_utc` settles the epoch case.
//!
//! Other errors: a non-hex token names its line and word; more than one wrong word, or a set
//! not made from a TLE, is refused as a checksum failure of word 57 (not located); a
//! consistent set the board refuses names the word [`Sgp4::from_words`] names.

use std::collections::HashMap;
use std::fmt;
use std::io::Read;
use std::path::{Path, PathBuf};

use serde_json::Value;

use super::propagate::{gravity, init_sgp4, read_tle};
use super::CliError;
use crate::orbit::sgp4::{Gravity, Sgp4, ELEMENT_WORDS};
use crate::time::{Epoch, Utc};
use crate::tle::Tle;

/// Arguments of `acs elements`.
#[derive(clap::Args, Debug)]
#[command(group(
    clap::ArgGroup::new("input").required(true).args(["tle", "check"])
))]
pub struct Args {
    /// Write the uplink words of the one element set in FILE (two lines, or a name line and
    /// two lines).
    #[arg(long, value_name = "FILE")]
    tle: Option<PathBuf>,
    /// Check a word set read back (hex or JSON; `-` for stdin): exit 0 and a summary line when
    /// intact, 2 naming the first bad word otherwise.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["gravity", "format"])]
    check: Option<PathBuf>,
    /// Gravity model of the initialisation.
    #[arg(long, value_parser = ["wgs72", "wgs84"], default_value = "wgs72")]
    gravity: String,
    /// Output: 58 lines of 8 hex digits, or a JSON object with the satellite number and epoch.
    #[arg(long, value_parser = ["hex", "json"], default_value = "hex")]
    format: String,
}

// ---------------------------------------------------------------------------------------------
// The word layout (version 1 of `Sgp4::to_words`, tag 0x53340001), as far as this module reads it

/// Epoch: days since 2000-01-01 (word 1), second of day (2), nanoseconds (3).
const DAY: usize = 1;
const SECOND: usize = 2;
const NANO: usize = 3;
/// The gravity model's Earth radius, `xke` and J₂ (words 4–6).
const GRAVITY: std::ops::Range<usize> = 4..7;
/// Phases: θ₀ as a 64-bit fixed-point fraction of a turn (2⁴⁸ = one turn), high word first,
/// then the rate the same way, then the rate as f32.
const M_AT_EPOCH: usize = 9;
const M_RATE: usize = 11;
const ARGP_AT_EPOCH: usize = 14;
const NODE_AT_EPOCH: usize = 19;
/// f32 constants.
const NO: usize = 29;
const ECCO: usize = 31;
const BSTAR: usize = 32;
const COSIO: usize = 33;
const SINIO: usize = 34;
/// The checksum of words 0–56.
const CHECKSUM: usize = ELEMENT_WORDS - 1;
/// One turn in a phase's fixed point.
const PHASE_ONE: f64 = (1u64 << 48) as f64;

/// The words the TLE is recovered from ([`tle_of`]); the others follow from them.
const SOURCE_WORDS: [usize; 19] = [
    DAY,
    SECOND,
    NANO,
    4,
    5,
    6,
    M_AT_EPOCH,
    M_AT_EPOCH + 1,
    M_RATE,
    M_RATE + 1,
    ARGP_AT_EPOCH,
    ARGP_AT_EPOCH + 1,
    NODE_AT_EPOCH,
    NODE_AT_EPOCH + 1,
    NO,
    ECCO,
    BSTAR,
    COSIO,
    SINIO,
];

/// What each word holds (the symbols of `src/orbit/sgp4/`), for the messages.
pub const WORD_NAMES: [&str; ELEMENT_WORDS] = [
    "format tag",
    "epoch day",
    "epoch second of day",
    "epoch nanoseconds",
    "Earth radius",
    "xke",
    "J2",
    "a0 in km",
    "velocity scale",
    "M0, high word",
    "M0, low word",
    "Mdot fixed point, high word",
    "Mdot fixed point, low word",
    "Mdot",
    "argp0, high word",
    "argp0, low word",
    "argpdot fixed point, high word",
    "argpdot fixed point, low word",
    "argpdot",
    "node0, high word",
    "node0, low word",
    "nodedot fixed point, high word",
    "nodedot fixed point, low word",
    "nodedot",
    "M0 + argp0, high word",
    "M0 + argp0, low word",
    "Mdot + argpdot fixed point, high word",
    "Mdot + argpdot fixed point, low word",
    "Mdot + argpdot",
    "no",
    "ao",
    "ecco",
    "bstar",
    "cosio",
    "sinio",
    "con41",
    "x1mth2",
    "x7thm1",
    "cc1",
    "cc4",
    "nodecf",
    "t2cof",
    "xlcof",
    "aycof",
    "full-drag flag",
    "d2",
    "d3",
    "d4",
    "t3cof",
    "t4cof",
    "t5cof",
    "cc5",
    "omgcof",
    "xmcof",
    "eta",
    "delmo",
    "sinmao",
    "checksum",
];

/// `word k (name)`, or `word k` past the layout (an extra word).
fn word_label(k: usize) -> String {
    match WORD_NAMES.get(k) {
        Some(name) => format!("word {k} ({name})"),
        None => format!("word {k}"),
    }
}

/// The checksum of words 0–56 ([`crate::orbit::sgp4::words_checksum`], as [`Sgp4::to_words`]
/// computes it).
pub fn checksum(body: &[u32]) -> u32 {
    crate::orbit::sgp4::words_checksum(body)
}

/// Sets word `k` to the one value that makes the checksum of `words` right.
fn solve_word(words: &mut [u32; ELEMENT_WORDS], k: usize) {
    let sum = checksum(&words[..CHECKSUM]);
    if k == CHECKSUM {
        words[CHECKSUM] = sum;
    } else {
        let syndrome = sum ^ words[CHECKSUM];
        let shift = (5 * (CHECKSUM - 1 - k) % 32) as u32;
        words[k] ^= syndrome.rotate_right(shift);
    }
}

// ---------------------------------------------------------------------------------------------
// Output

/// The words as 58 lines of 8 lower-case hex digits.
pub fn to_hex(words: &[u32; ELEMENT_WORDS]) -> String {
    words.iter().map(|w| format!("{w:08x}\n")).collect()
}

/// The words as the JSON object of cli.md: `{"words": [...], "norad": N, "epoch_utc": "..."}`,
/// the words as strings of 8 hex digits, one a line.
pub fn to_json(words: &[u32; ELEMENT_WORDS], norad: u32, epoch: &Epoch<Utc>) -> String {
    let list: Vec<String> = words.iter().map(|w| format!("    \"{w:08x}\"")).collect();
    format!(
        "{{\n  \"words\": [\n{}\n  ],\n  \"norad\": {norad},\n  \"epoch_utc\": \"{}\"\n}}\n",
        list.join(",\n"),
        iso_utc(epoch)
    )
}

/// An epoch in ISO 8601 UTC, exactly: 3, 6 or 9 fractional digits, as few as are exact (a TLE
/// epoch, a multiple of 10⁻⁸ day = 864 µs, needs 6).
pub fn iso_utc(e: &Epoch<Utc>) -> String {
    let c = e.to_calendar();
    let frac = if c.nano.is_multiple_of(1_000_000) {
        format!("{:03}", c.nano / 1_000_000)
    } else if c.nano.is_multiple_of(1_000) {
        format!("{:06}", c.nano / 1_000)
    } else {
        format!("{:09}", c.nano)
    };
    format!(
        "{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{frac}Z",
        c.year, c.month, c.day, c.hour, c.minute, c.second
    )
}

/// The name of a gravity model as `--gravity` spells it.
fn gravity_name(g: Gravity) -> &'static str {
    match g {
        Gravity::Wgs72 => "wgs72",
        Gravity::Wgs84 => "wgs84",
    }
}

// ---------------------------------------------------------------------------------------------
// Reading a word set

/// A word set as read by `--check`.
#[derive(Clone, Debug, PartialEq)]
pub struct WordSet {
    /// The words in order.
    pub words: Vec<u32>,
    /// Where each word was read: `line N` (hex) or `` `words[i]` `` (JSON).
    pub places: Vec<String>,
    /// Read from the JSON form.
    pub json: bool,
    /// The JSON form's `norad`.
    pub norad: Option<u32>,
    /// The JSON form's `epoch_utc`.
    pub epoch_utc: Option<Epoch<Utc>>,
}

/// What is wrong with a word set.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Fault {
    /// Not a word set: a line or entry that is not 8 hex digits, malformed JSON, no words.
    Syntax,
    /// A wrong word: the set is intact with another value there.
    Corrupt,
    /// A missing word: the set is intact with a word inserted there.
    Missing,
    /// One word too many: the set is intact without it.
    Extra,
    /// The checksum (or the count) is wrong and no single wrong, missing or extra word
    /// explains it.
    Unlocated,
    /// A consistent set (checksum right) with a word the board refuses
    /// ([`Sgp4::from_words`]) or gravity constants of neither model.
    Invalid,
    /// A field of the JSON form other than the words (`norad`, `epoch_utc`).
    Metadata,
}

/// Why `--check` refuses a word set.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Refusal {
    /// What kind of fault.
    pub fault: Fault,
    /// The words at fault, the first bad word first (more than one only when the data cannot
    /// tell them apart; empty when the fault is not in a word).
    pub words: Vec<usize>,
    /// The message (names the line or entry and the word).
    pub message: String,
}

impl WordSet {
    /// Where word `k` was read (`end of input` past the last word).
    fn place(&self, k: usize) -> String {
        self.places
            .get(k)
            .cloned()
            .unwrap_or_else(|| "end of input".into())
    }
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl Refusal {
    fn new(fault: Fault, words: Vec<usize>, message: String) -> Self {
        Self {
            fault,
            words,
            message,
        }
    }
}

/// A token of exactly 8 hex digits as a word.
fn hex_word(token: &str) -> Option<u32> {
    if token.len() == 8 && token.bytes().all(|b| b.is_ascii_hexdigit()) {
        u32::from_str_radix(token, 16).ok()
    } else {
        None
    }
}

/// Whether a line is blank or a `#` comment (ignored, cli.md).
fn ignored(line: &str) -> bool {
    let t = line.trim();
    t.is_empty() || t.starts_with('#')
}

/// Reads a word set in either format (JSON when the first line that is not blank or a comment
/// starts with `{`).
///
/// # Errors
/// [`Fault::Syntax`] naming the line (hex) or entry (JSON): a token that is not 8 hex digits,
/// two tokens on a line, malformed JSON, a missing or mistyped field, no words at all.
pub fn parse_words(text: &str) -> Result<WordSet, Refusal> {
    let json = text
        .lines()
        .find(|l| !ignored(l))
        .is_some_and(|l| l.trim_start().starts_with('{'));
    let set = if json {
        parse_json(text)?
    } else {
        parse_hex(text)?
    };
    if set.words.is_empty() {
        return Err(Refusal::new(
            Fault::Syntax,
            vec![0],
            format!("no words: {ELEMENT_WORDS} expected"),
        ));
    }
    Ok(set)
}

fn parse_hex(text: &str) -> Result<WordSet, Refusal> {
    let mut words = Vec::new();
    let mut places = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if ignored(line) {
            continue;
        }
        let place = format!("line {}", i + 1);
        let k = words.len();
        let token = line.trim();
        let word = hex_word(token).ok_or_else(|| {
            let what = if token.split_whitespace().nth(1).is_some() {
                "more than one token (one word a line)".to_string()
            } else {
                "not 8 hex digits".to_string()
            };
            Refusal::new(
                Fault::Syntax,
                vec![k],
                format!(
                    "{place}: `{}` is {what}: {} unreadable",
                    token.chars().take(40).collect::<String>(),
                    word_label(k)
                ),
            )
        })?;
        words.push(word);
        places.push(place);
    }
    Ok(WordSet {
        words,
        places,
        json: false,
        norad: None,
        epoch_utc: None,
    })
}

fn parse_json(text: &str) -> Result<WordSet, Refusal> {
    let syntax = |m: String| Refusal::new(Fault::Syntax, Vec::new(), m);
    let metadata = |m: String| Refusal::new(Fault::Metadata, Vec::new(), m);
    // comment lines blanked, not removed: the parser's line numbers stay the file's
    let cleaned: Vec<&str> = text
        .lines()
        .map(|l| if ignored(l) { "" } else { l })
        .collect();
    let doc: Value = serde_json::from_str(&cleaned.join("\n")).map_err(|e| {
        syntax(format!(
            "line {}, column {}: not JSON: {e}",
            e.line(),
            e.column()
        ))
    })?;
    let list = doc
        .get("words")
        .ok_or_else(|| syntax("missing field `words`".into()))?
        .as_array()
        .ok_or_else(|| syntax("`words` is not an array".into()))?;
    let mut words = Vec::with_capacity(list.len());
    let mut places = Vec::with_capacity(list.len());
    for (k, v) in list.iter().enumerate() {
        let place = format!("`words[{k}]`");
        let word = v.as_str().and_then(hex_word).ok_or_else(|| {
            let shown: String = v.to_string().chars().take(40).collect();
            Refusal::new(
                Fault::Syntax,
                vec![k],
                format!(
                    "{place}: {shown} is not a string of 8 hex digits: {} unreadable",
                    word_label(k)
                ),
            )
        })?;
        words.push(word);
        places.push(place);
    }
    let norad = doc
        .get("norad")
        .ok_or_else(|| metadata("missing field `norad`".into()))?;
    let norad = norad
        .as_u64()
        .and_then(|n| u32::try_from(n).ok())
        .ok_or_else(|| metadata(format!("`norad` {norad} is not a satellite number")))?;
    let epoch = doc
        .get("epoch_utc")
        .ok_or_else(|| metadata("missing field `epoch_utc`".into()))?;
    let epoch = epoch
        .as_str()
        .ok_or_else(|| metadata(format!("`epoch_utc` {epoch} is not a string")))
        .and_then(|s| {
            super::sun::parse_utc_iso(s).map_err(|m| metadata(format!("`epoch_utc`: {m}")))
        })?;
    Ok(WordSet {
        words,
        places,
        json: true,
        norad: Some(norad),
        epoch_utc: Some(epoch),
    })
}

// ---------------------------------------------------------------------------------------------
// The gravity model and the TLE behind a set of words

/// A near-Earth element set whose only use is to learn the words a gravity model writes into
/// words 0 and 4–6 (the format tag and the model's constants, the same for any element set).
fn probe() -> Option<Tle> {
    Some(Tle {
        name: None,
        catalog_number: 0,
        classification: b'U',
        international_designator: heapless::String::new(),
        epoch: Epoch::from_parts(3_500, 0, 0).ok()?,
        mean_motion_dot: 0.0,
        mean_motion_ddot: 0.0,
        bstar: 0.0,
        ephemeris_type: 0,
        element_set_number: 0,
        inclination_deg: 51.6,
        raan_deg: 10.0,
        eccentricity: 0.001,
        arg_perigee_deg: 20.0,
        mean_anomaly_deg: 30.0,
        mean_motion_rev_per_day: 15.5,
        revolution_number: 0,
    })
}

/// The words [`Sgp4::new`] writes for the [`probe`] with `gravity` (computed once).
fn probe_words(gravity: Gravity) -> Option<[u32; ELEMENT_WORDS]> {
    type Probes = [Option<[u32; ELEMENT_WORDS]>; 2];
    static PROBES: std::sync::OnceLock<Probes> = std::sync::OnceLock::new();
    let words = |g| {
        probe()
            .and_then(|t| Sgp4::new(&t, g).ok())
            .map(|s| s.to_words())
    };
    let probes = PROBES.get_or_init(|| [words(Gravity::Wgs72), words(Gravity::Wgs84)]);
    match gravity {
        Gravity::Wgs72 => probes[0],
        Gravity::Wgs84 => probes[1],
    }
}

/// The gravity model whose constants are words 4–6, or the first of them that matches
/// neither model.
pub fn gravity_of(words: &[u32; ELEMENT_WORDS]) -> Result<Gravity, usize> {
    let mut first_bad = GRAVITY.start;
    for g in [Gravity::Wgs72, Gravity::Wgs84] {
        let Some(model) = probe_words(g) else {
            continue;
        };
        match GRAVITY.clone().find(|&k| words[k] != model[k]) {
            None => return Ok(g),
            Some(k) => first_bad = first_bad.max(k),
        }
    }
    Err(first_bad)
}

/// A phase's fixed-point pair (words `k`, `k + 1`) as an i64.
fn fixed(words: &[u32; ELEMENT_WORDS], k: usize) -> i64 {
    ((u64::from(words[k]) << 32) | u64::from(words[k + 1])) as i64
}

/// A phase's θ₀ as a TLE angle: degrees in 0..360, rounded to the TLE's 4 decimals (the fixed
/// point holds it to 10⁻¹² degree).
fn tle_angle(words: &[u32; ELEMENT_WORDS], k: usize) -> f64 {
    let deg = (fixed(words, k) as f64 / PHASE_ONE * 360.0).rem_euclid(360.0);
    let m = (deg * 1e4).round();
    if m >= 3_600_000.0 {
        0.0
    } else {
        m / 1e4
    }
}

/// The Kozai mean motion (rev/day) whose un-Kozai'd value is `no` (rad/min), in f64, by
/// fixed-point iteration of Vallado's `initl` (a start for the exact search).
fn kozai_rev_per_day(no: f64, ecc: f64, cosio: f64, xke: f64, j2: f64) -> f64 {
    let omeosq = 1.0 - ecc * ecc;
    let d1 = 0.75 * j2 * (3.0 * cosio * cosio - 1.0) / (omeosq.sqrt() * omeosq);
    let mut n = no;
    for _ in 0..4 {
        let ak = (xke / n).powf(2.0 / 3.0);
        let del = d1 / (ak * ak);
        let adel = ak * (1.0 - del * del - del * (1.0 / 3.0 + 134.0 * del * del / 81.0));
        let del = d1 / (adel * adel);
        n = no * (1.0 + del);
    }
    n * 1440.0 / std::f64::consts::TAU
}

/// The element set, gravity model and words of [`recover`].
type Recovered = (Tle, Gravity, [u32; ELEMENT_WORDS]);

/// The TLE the words point to, and the words [`Sgp4::new`] writes for it (equal to `words` when
/// the set is a TLE's, intact). `None` when the words cannot be a TLE's: gravity constants of
/// neither model, an epoch off the TLE's 10⁻⁸-day grid or outside 1957–2056, a mean motion the
/// search does not find.
fn recover(words: &[u32; ELEMENT_WORDS]) -> Option<Recovered> {
    let gravity = gravity_of(words).ok()?;
    let epoch = Epoch::<Utc>::from_parts(words[DAY] as i32, words[SECOND], words[NANO]).ok()?;
    let ns_of_day = u64::from(words[SECOND]) * 1_000_000_000 + u64::from(words[NANO]);
    if !ns_of_day.is_multiple_of(864_000) || !(1957..=2056).contains(&epoch.to_calendar().year) {
        return None;
    }
    let f = |k: usize| f64::from(f32::from_bits(words[k]));
    let eccentricity = (f(ECCO) * 1e7).round() / 1e7;
    let inclination_deg = (f(SINIO).atan2(f(COSIO)).to_degrees() * 1e4).round() / 1e4;
    // B*: five significant digits (0.NNNNNe±E); the nearest decimal, read back as the parser
    // reads it (both correctly rounded)
    let b = f32::from_bits(words[BSTAR]);
    let bstar = if b == 0.0 {
        f64::from(b)
    } else {
        format!("{:.4e}", f64::from(b)).parse().ok()?
    };
    let mut tle = Tle {
        epoch,
        bstar,
        inclination_deg,
        raan_deg: tle_angle(words, NODE_AT_EPOCH),
        eccentricity,
        arg_perigee_deg: tle_angle(words, ARGP_AT_EPOCH),
        mean_anomaly_deg: tle_angle(words, M_AT_EPOCH),
        mean_motion_rev_per_day: 0.0,
        ..probe()?
    };
    // the mean motion (8 decimals): secant steps on the mean-anomaly rate, an exact 48-bit
    // fraction that grows with n, smoothly (about 2 000 units per 10⁻⁸ rev/day; over the
    // 10⁻⁷ uncertainty of the start the secant is off by far less than one step)
    let model = probe_words(gravity)?;
    let n0 = kozai_rev_per_day(
        f(NO),
        eccentricity,
        f(COSIO),
        f64::from(f32::from_bits(model[5])),
        f64::from(f32::from_bits(model[6])),
    );
    if !(n0.is_finite() && n0 > 0.0 && n0 < 100.0) {
        return None;
    }
    let target = fixed(words, M_RATE);
    let mut at = |m: i64| -> Option<(i64, [u32; ELEMENT_WORDS])> {
        tle.mean_motion_rev_per_day = m as f64 / 1e8;
        let w = Sgp4::new(&tle, gravity).ok()?.to_words();
        Some((fixed(&w, M_RATE), w))
    };
    let (mut m0, mut m1) = ((n0 * 1e8).round() as i64, (n0 * 1e8).round() as i64 + 1_000);
    let (mut k0, _) = at(m0)?;
    let (mut k1, mut w1) = at(m1)?;
    for _ in 0..6 {
        if k1 == target {
            break;
        }
        if k1 == k0 {
            return None;
        }
        let step = ((target - k1) as f64 * (m1 - m0) as f64 / (k1 - k0) as f64).round();
        if !(step.is_finite() && step != 0.0 && step.abs() <= 1e7) {
            return None;
        }
        (m0, k0) = (m1, k1);
        m1 += step as i64;
        (k1, w1) = at(m1)?;
    }
    tle.mean_motion_rev_per_day = m1 as f64 / 1e8;
    Some((tle, gravity, w1))
}

/// The TLE elements (epoch, mean elements, B*) and gravity model from which [`Sgp4::new`]
/// writes exactly `words`, when there are such; the other fields of the [`Tle`] (satellite
/// number, name, ṅ, n̈, …) are not in the words and are zero.
pub fn tle_of(words: &[u32; ELEMENT_WORDS]) -> Option<(Tle, Gravity)> {
    recover(words)
        .filter(|(.., w)| w == words)
        .map(|(tle, g, _)| (tle, g))
}

/// Whether candidate sets are TLE sets, with the recovery remembered by source words.
struct Recoveries {
    by_source: HashMap<[u32; SOURCE_WORDS.len()], Option<[u32; ELEMENT_WORDS]>>,
}

impl Recoveries {
    fn new() -> Self {
        Self {
            by_source: HashMap::new(),
        }
    }

    /// Whether `words` is exactly the set of a TLE (and so one the board accepts).
    fn is_tle_set(&mut self, words: &[u32; ELEMENT_WORDS]) -> bool {
        if Sgp4::from_words(words).is_err() {
            return false;
        }
        let key = SOURCE_WORDS.map(|k| words[k]);
        let made = *self
            .by_source
            .entry(key)
            .or_insert_with(|| recover(words).map(|(.., w)| w));
        made.as_ref() == Some(words)
    }
}

// ---------------------------------------------------------------------------------------------
// Checking

/// An intact word set.
#[derive(Clone, Debug, PartialEq)]
pub struct Intact {
    /// The propagator the board makes of it ([`Sgp4::from_words`]).
    pub sgp4: Sgp4,
    /// The gravity model of its constants.
    pub gravity: Gravity,
    /// The satellite number (JSON form only: the words do not carry it).
    pub norad: Option<u32>,
}

impl Intact {
    /// The one-line summary `--check` prints.
    pub fn summary(&self) -> String {
        let satellite = match self.norad {
            Some(n) => format!("satellite {n}"),
            None => "satellite unknown (not in hex words)".to_string(),
        };
        format!(
            "intact: {ELEMENT_WORDS} words, {satellite}, epoch {}, gravity {}",
            iso_utc(&self.sgp4.epoch()),
            gravity_name(self.gravity)
        )
    }
}

/// Checks a word set read back: intact when there are [`ELEMENT_WORDS`] words, the checksum is
/// right, [`Sgp4::from_words`] accepts them, the gravity constants are a model's and a JSON
/// `epoch_utc` is the words' epoch.
///
/// # Errors
/// The first bad word (module docs, "Naming the bad word").
pub fn check(set: &WordSet) -> Result<Intact, Refusal> {
    let Ok(words) = <[u32; ELEMENT_WORDS]>::try_from(set.words.as_slice()) else {
        return Err(locate(set));
    };
    if checksum(&words[..CHECKSUM]) != words[CHECKSUM] {
        return Err(locate(set));
    }
    let sgp4 = Sgp4::from_words(&words).map_err(|e| {
        let k = match e {
            crate::orbit::sgp4::Sgp4Error::Words { index } => usize::from(index),
            _ => 0,
        };
        let expected = match (k, probe_words(Gravity::Wgs72)) {
            (0, Some(model)) => format!(", {:08x} expected", model[0]),
            _ => String::new(),
        };
        Refusal::new(
            Fault::Invalid,
            vec![k],
            format!(
                "{}: {} = {:08x} is refused by the board ({e}{expected})",
                set.place(k),
                word_label(k),
                words[k]
            ),
        )
    })?;
    let gravity = gravity_of(&words).map_err(|k| {
        Refusal::new(
            Fault::Invalid,
            vec![k],
            format!(
                "{}: {} = {:08x} is neither WGS-72's nor WGS-84's (words {}–{} are the \
                 gravity model's constants)",
                set.place(k),
                word_label(k),
                words[k],
                GRAVITY.start,
                GRAVITY.end - 1
            ),
        )
    })?;
    if let Some(e) = set.epoch_utc {
        if e != sgp4.epoch() {
            return Err(Refusal::new(
                Fault::Metadata,
                Vec::new(),
                format!(
                    "`epoch_utc` {} is not the epoch of the words, {} (words 1–3)",
                    iso_utc(&e),
                    iso_utc(&sgp4.epoch())
                ),
            ));
        }
    }
    Ok(Intact {
        sgp4,
        gravity,
        norad: set.norad,
    })
}

/// [`parse_words`] then [`check`].
///
/// # Errors
/// As those.
pub fn check_text(text: &str) -> Result<Intact, Refusal> {
    check(&parse_words(text)?)
}

/// A candidate explanation of a faulty set: the fault, the word, the intact set it gives.
struct Candidate {
    fault: Fault,
    word: usize,
    set: [u32; ELEMENT_WORDS],
}

/// The candidates for a set of `words.len()` words whose checksum or count is wrong: one word
/// changed, inserted or removed (module docs).
fn candidates(words: &[u32]) -> Vec<Candidate> {
    let mut out = Vec::new();
    match words.len() {
        n if n == ELEMENT_WORDS => {
            for k in 0..ELEMENT_WORDS {
                let mut set = [0; ELEMENT_WORDS];
                set.copy_from_slice(words);
                solve_word(&mut set, k);
                out.push(Candidate {
                    fault: Fault::Corrupt,
                    word: k,
                    set,
                });
            }
        }
        n if n + 1 == ELEMENT_WORDS => {
            for k in 0..ELEMENT_WORDS {
                let mut v = words.to_vec();
                v.insert(k, 0);
                let mut set = [0; ELEMENT_WORDS];
                set.copy_from_slice(&v);
                solve_word(&mut set, k);
                out.push(Candidate {
                    fault: Fault::Missing,
                    word: k,
                    set,
                });
            }
        }
        n if n == ELEMENT_WORDS + 1 => {
            for k in 0..n {
                let mut v = words.to_vec();
                v.remove(k);
                let mut set = [0; ELEMENT_WORDS];
                set.copy_from_slice(&v);
                out.push(Candidate {
                    fault: Fault::Extra,
                    word: k,
                    set,
                });
            }
        }
        _ => {}
    }
    out
}

/// The refusal of a set whose checksum or count is wrong: the one fault that makes it a TLE's
/// intact set, else the checksum or the count.
fn locate(set: &WordSet) -> Refusal {
    let words = &set.words;
    let mut recoveries = Recoveries::new();
    let mut found: Vec<Candidate> = candidates(words)
        .into_iter()
        .filter(|c| recoveries.is_tle_set(&c.set))
        .collect();
    // a JSON epoch (outside the checksum) decides between sets of different epochs
    if let Some(e) = set.epoch_utc {
        let same_epoch = |c: &Candidate| {
            Epoch::<Utc>::from_parts(c.set[DAY] as i32, c.set[SECOND], c.set[NANO]).ok() == Some(e)
        };
        if found.iter().any(same_epoch) {
            found.retain(same_epoch);
        }
    }
    // a missing or extra word in a run of equal words: the same set from each position of
    // the run; the first position is where the set first departs from it
    found.dedup_by(|b, a| a.set == b.set && a.fault == b.fault);
    let place = |k: usize| set.place(k);
    match found.as_slice() {
        [c] => {
            let k = c.word;
            match c.fault {
                Fault::Corrupt => {
                    let (read, good) = (words[k], c.set[k]);
                    Refusal::new(
                        Fault::Corrupt,
                        vec![k],
                        format!(
                            "{}: {} is corrupt: read {read:08x}, the set is intact with \
                             {good:08x} ({} bit{} differ{})",
                            place(k),
                            word_label(k),
                            (read ^ good).count_ones(),
                            if (read ^ good).count_ones() == 1 {
                                ""
                            } else {
                                "s"
                            },
                            if (read ^ good).count_ones() == 1 {
                                "s"
                            } else {
                                ""
                            },
                        ),
                    )
                }
                Fault::Missing => {
                    let at = if k < words.len() {
                        format!("before {}", place(k))
                    } else {
                        format!("after {}", place(words.len() - 1))
                    };
                    Refusal::new(
                        Fault::Missing,
                        vec![k],
                        format!(
                            "{} words, {ELEMENT_WORDS} expected: {} is missing ({at}): the set is \
                             intact with {:08x} inserted there",
                            words.len(),
                            word_label(k),
                            c.set[k]
                        ),
                    )
                }
                _ => Refusal::new(
                    Fault::Extra,
                    vec![k],
                    format!(
                        "{} words, {ELEMENT_WORDS} expected: {} (word {k}, {:08x}) is one word \
                         too many: the set is intact without it",
                        words.len(),
                        place(k),
                        words[k]
                    ),
                ),
            }
        }
        [_, ..] if found.iter().all(|c| c.fault == Fault::Corrupt) => {
            let epoch_of = |c: &Candidate| {
                Epoch::<Utc>::from_parts(c.set[DAY] as i32, c.set[SECOND], c.set[NANO])
                    .map(|e| iso_utc(&e))
                    .unwrap_or_default()
            };
            let which: Vec<String> = found
                .iter()
                .map(|c| format!("{}: {}", place(c.word), word_label(c.word)))
                .collect();
            let epochs_differ = found.iter().any(|c| epoch_of(c) != epoch_of(&found[0]));
            let sets: Vec<String> = found
                .iter()
                .map(|c| {
                    let epoch = if epochs_differ {
                        format!(", epoch {}", epoch_of(c))
                    } else {
                        String::new()
                    };
                    format!(
                        "with word {} = {:08x} (read {:08x}){epoch}",
                        c.word, c.set[c.word], words[c.word]
                    )
                })
                .collect();
            Refusal::new(
                Fault::Corrupt,
                found.iter().map(|c| c.word).collect(),
                format!(
                    "{} is corrupt: the set is one word from {} intact sets, which the words \
                     alone cannot tell apart: {}",
                    which.join(", or "),
                    found.len(),
                    sets.join("; ")
                ),
            )
        }
        _ => unlocated(set),
    }
}

/// The refusal when no single fault explains the set: the checksum (58 words), the first
/// missing word (fewer) or the first extra word (more).
fn unlocated(set: &WordSet) -> Refusal {
    let n = set.words.len();
    if n == ELEMENT_WORDS {
        Refusal::new(
            Fault::Unlocated,
            vec![CHECKSUM],
            format!(
                "{}: {} {:08x} does not match words 0–{}: the set is corrupt, and no single \
                 wrong word makes it intact",
                set.place(CHECKSUM),
                word_label(CHECKSUM),
                set.words[CHECKSUM],
                CHECKSUM - 1
            ),
        )
    } else if n < ELEMENT_WORDS {
        Refusal::new(
            Fault::Unlocated,
            vec![n],
            format!(
                "{n} words, {ELEMENT_WORDS} expected: the set ends after {} ({}): {} and after \
                 are missing (no single missing word makes it intact)",
                set.place(n.saturating_sub(1)),
                word_label(n.saturating_sub(1)),
                word_label(n)
            ),
        )
    } else {
        Refusal::new(
            Fault::Unlocated,
            vec![ELEMENT_WORDS],
            format!(
                "{n} words, {ELEMENT_WORDS} expected: {} (word {ELEMENT_WORDS}) and after are \
                 too many (no single extra word makes the set intact)",
                set.place(ELEMENT_WORDS)
            ),
        )
    }
}

// ---------------------------------------------------------------------------------------------
// The command

/// Reads FILE (`-`: stdin) as UTF-8 text; exit 2 naming the file, and the line of a byte that
/// is not UTF-8.
fn read_text(path: &Path) -> Result<String, CliError> {
    let name = path.display();
    let mut bytes = Vec::new();
    let read = if path.as_os_str() == "-" {
        std::io::stdin().read_to_end(&mut bytes).map(|_| ())
    } else {
        std::fs::read(path).map(|b| bytes = b)
    };
    read.map_err(|e| CliError::Input(format!("{name}: {e}")))?;
    String::from_utf8(bytes).map_err(|e| {
        let good = e.utf8_error().valid_up_to();
        let line = 1 + e.as_bytes()[..good].iter().filter(|&&b| b == b'\n').count();
        CliError::Input(format!("{name}: line {line}: not UTF-8 text"))
    })
}

/// Runs `acs elements`.
pub fn run(args: &Args) -> Result<(), CliError> {
    match (&args.tle, &args.check) {
        (Some(path), None) => {
            let tle = read_tle(path)?;
            let sgp4 = init_sgp4(&tle, gravity(&args.gravity), path)?;
            let words = sgp4.to_words();
            let out = if args.format == "json" {
                to_json(&words, tle.catalog_number, &tle.epoch)
            } else {
                to_hex(&words)
            };
            print!("{out}");
            Ok(())
        }
        (None, Some(path)) => {
            let text = read_text(path)?;
            let intact = check_text(&text)
                .map_err(|r| CliError::Input(format!("{}: {r}", path.display())))?;
            println!("{}", intact.summary());
            Ok(())
        }
        _ => Err(CliError::Input(
            "give one of --tle FILE and --check FILE".into(),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solved_word_satisfies_the_checksum() {
        let mut words = probe_words(Gravity::Wgs72).unwrap();
        assert_eq!(checksum(&words[..CHECKSUM]), words[CHECKSUM]);
        for k in 0..ELEMENT_WORDS {
            let mut bad = words;
            bad[k] ^= 0x0102_0304;
            solve_word(&mut bad, k);
            assert_eq!(bad, words, "word {k}");
        }
        words[7] ^= 1;
        assert_ne!(checksum(&words[..CHECKSUM]), words[CHECKSUM]);
    }

    #[test]
    fn iso_utc_is_exact() {
        let e = Epoch::<Utc>::from_parts(0, 43_200, 0).unwrap();
        assert_eq!(iso_utc(&e), "2000-01-01T12:00:00.000Z");
        let e = Epoch::<Utc>::from_parts(0, 1, 864_000).unwrap();
        assert_eq!(iso_utc(&e), "2000-01-01T00:00:01.000864Z");
        let e = Epoch::<Utc>::from_parts(0, 1, 1).unwrap();
        assert_eq!(iso_utc(&e), "2000-01-01T00:00:01.000000001Z");
        assert_eq!(super::super::sun::parse_utc_iso(&iso_utc(&e)), Ok(e));
    }

    #[test]
    fn the_probe_is_a_near_earth_set_of_both_models() {
        let a = probe_words(Gravity::Wgs72).unwrap();
        let b = probe_words(Gravity::Wgs84).unwrap();
        assert_eq!(gravity_of(&a), Ok(Gravity::Wgs72));
        assert_eq!(gravity_of(&b), Ok(Gravity::Wgs84));
        assert!(GRAVITY.clone().all(|k| a[k] != b[k]));
        assert_eq!(
            tle_of(&a).map(|(t, g)| (t.mean_motion_rev_per_day, g)),
            Some((15.5, Gravity::Wgs72))
        );
    }
}
