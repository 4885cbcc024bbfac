//! Helpers shared by the fuzz targets (included with `#[path]`; not every target uses all).
#![allow(dead_code)]

use acs::orbit::sgp4::{Gravity, Sgp4};
use acs::time::TimeSpan;
use acs::tle::{checksum, Tle};
use arbitrary::{Arbitrary, Unstructured};

/// The fields of a TLE, each drawn within its columns' range, formatted by [`TleFields::lines`]
/// into two lines with correct checksums: most of them parse, so the fuzzer reaches SGP4.
#[derive(Arbitrary, Debug)]
pub struct TleFields {
    catalog: u32,
    yy: u8,
    day: u16,
    day_frac: u32,
    ndot: (bool, u32),
    nddot: (bool, u32, bool, u8),
    bstar: (bool, u32, bool, u8),
    elset: u16,
    inc: u32,
    raan: u32,
    ecc: u32,
    argp: u32,
    ma: u32,
    n_whole: u8,
    n_frac: u32,
    rev: u32,
}

fn sign(neg: bool) -> char {
    if neg {
        '-'
    } else {
        ' '
    }
}

fn angle(x: u32, max: u32) -> String {
    let x = x % (max * 10_000 + 1);
    format!("{:3}.{:04}", x / 10_000, x % 10_000)
}

fn with_checksum(line: String) -> String {
    let c = checksum(line.as_bytes());
    format!("{line}{c}")
}

impl TleFields {
    /// Line 1 and line 2, 69 columns each, checksums correct.
    pub fn lines(&self) -> (String, String) {
        let cat = self.catalog % 100_000;
        let l1 = format!(
            "1 {cat:05}U 25001A   {:02}{:03}.{:08} {}.{:08} {}{:05}{}{} {}{:05}{}{} 0 {:4}",
            self.yy % 100,
            self.day % 367,
            self.day_frac % 100_000_000,
            sign(self.ndot.0),
            self.ndot.1 % 100_000_000,
            sign(self.nddot.0),
            self.nddot.1 % 100_000,
            if self.nddot.2 { '-' } else { '+' },
            self.nddot.3 % 10,
            sign(self.bstar.0),
            self.bstar.1 % 100_000,
            if self.bstar.2 { '-' } else { '+' },
            self.bstar.3 % 10,
            self.elset % 10_000,
        );
        let l2 = format!(
            "2 {cat:05} {} {} {:07} {} {} {:2}.{:08}{:5}",
            angle(self.inc, 180),
            angle(self.raan, 360),
            self.ecc % 10_000_000,
            angle(self.argp, 360),
            angle(self.ma, 360),
            self.n_whole % 100,
            self.n_frac % 100_000_000,
            self.rev % 100_000,
        );
        (with_checksum(l1), with_checksum(l2))
    }
}

/// A LEO element set every test of the crate uses (`tests/uplink.rs`).
pub fn orbit() -> Sgp4 {
    let tle = Tle::parse(
        "1 90101U 25001A   25079.50000000  .00000000  00000-0  00000-0 0  9997",
        "2 90101  97.4000  90.0000 0001000   0.0000   0.0000 15.21936487    10",
    )
    .expect("the reference element set parses");
    Sgp4::new(&tle, Gravity::Wgs72).expect("the reference element set initialises")
}

/// An uplink command: a code and its argument words, the element words mostly those of a real
/// element set with fuzzed changes (so that the checked path is reached, not only the
/// checksum's refusal).
pub fn uplink_command(
    u: &mut Unstructured,
) -> arbitrary::Result<(u16, [u32; acs::uplink::ARG_WORDS])> {
    let mut args = [0u32; acs::uplink::ARG_WORDS];
    let code: u16 = match u.int_in_range(0u8..=8)? {
        8 => u.arbitrary()?,
        c => u16::from(c),
    };
    if code == acs::uplink::kind::ELEMENTS && u.arbitrary::<bool>()? {
        args = orbit().to_words();
        let edits: u8 = u.int_in_range(0..=3)?;
        for _ in 0..edits {
            let i = u.choose_index(args.len() - 1)?;
            args[i] = u.arbitrary()?;
        }
        if u.arbitrary::<bool>()? {
            let (body, last) = args.split_at_mut(acs::uplink::ARG_WORDS - 1);
            last[0] = acs::orbit::sgp4::words_checksum(body);
        }
    } else {
        let n = u.int_in_range(0..=6usize)?;
        for w in args.iter_mut().take(n) {
            *w = match u.int_in_range(0u8..=3)? {
                0 => u.arbitrary()?,
                1 => u.arbitrary::<f32>()?.to_bits(),
                2 => f32::from(u.arbitrary::<i8>()?).to_bits(),
                _ => u32::from(u.arbitrary::<u8>()?),
            };
        }
    }
    Ok((code, args))
}

/// Checks every field of a step report: finite, a unit attitude.
pub fn check_report(r: &acs::acs_loop::StepReport) {
    assert!(r.is_finite(), "{r:?}");
    for q in [r.attitude, r.measured_attitude].iter().flatten() {
        let n = (q.q0 * q.q0 + q.q1 * q.q1 + q.q2 * q.q2 + q.q3 * q.q3).sqrt();
        // a normalised f32 quaternion: its norm within a few ulp of 1 (1e-5 is ~80 ulp, room
        // for the filter's renormalisation after a step); a NaN fails
        assert!((n - 1.0).abs() < 1e-5, "{r:?}");
    }
    if let Some(f) = r.sun_fraction {
        assert!((0.0..=1.0).contains(&f), "{r:?}");
    }
}

/// `s` and `twin` (the same set read back from its words) propagate alike over `span` (an error
/// compared by its text: a NaN inside it is unequal to itself); an accepted state is finite, and
/// so is one of `s` at an arbitrary split time drawn from `u`.
pub fn check_propagation(s: &Sgp4, twin: &Sgp4, span: TimeSpan, u: &mut Unstructured, what: &str) {
    let finite = |st: &acs::orbit::TemeState| {
        st.r_teme_km
            .iter()
            .chain(st.v_teme_kmps.iter())
            .all(|x| x.is_finite())
    };
    let a = s.propagate(span);
    assert_eq!(
        format!("{a:?}"),
        format!("{:?}", twin.propagate(span)),
        "{what}: the words propagate as the set"
    );
    if let Ok(st) = a {
        assert!(finite(&st), "{what}: {span:?}: {st:?}");
    }
    if let Ok(m) = u.arbitrary::<(f32, f32)>() {
        if let Ok(st) = s.propagate_split(m.0, m.1) {
            assert!(finite(&st), "{what}: split {m:?}: {st:?}");
        }
    }
}
