//! `acs sun`: Sun direction for UTC timestamps read from stdin (`docs/cli.md`).
//!
//! stdin: one ISO 8601 UTC timestamp a line (`2009-06-16T00:00:00Z`, fractional seconds allowed;
//! blank lines and `#` comments ignored). stdout: CSV `utc,x,y,z,dist_au`, the geocentric unit
//! vector to the Sun and its distance in AU, numbers with 10 significant digits.
//! `--model thesis`: Schlyter's algorithm (seed 000), in its own equator and mean equinox of date
//! (`--frame` does not apply). `--model precise` (default): the apparent Sun of date in TEME, or
//! rotated to J2000 with `--frame j2000`.

use std::io::{BufRead, Write};

use crate::env::sun::{precise, schlyter, Sun};
use crate::frames::teme_to_j2000_matrix;
use crate::time::{Calendar, Epoch, Utc};

use super::CliError;

/// Arguments of `acs sun`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Sun model.
    #[arg(long, value_parser = ["thesis", "precise"], default_value = "precise")]
    model: String,
    /// Output frame (the `precise` model only).
    #[arg(long, value_parser = ["teme", "j2000"], default_value = "teme")]
    frame: String,
}

/// Parses an ISO 8601 UTC timestamp `YYYY-MM-DDTHH:MM:SS[.fffffffff][Z]` (also with a space
/// instead of `T`, and `+00:00` for `Z`). The error says which field is wrong.
///
/// Public for the fuzz target `cli_sun` (`fuzz/`): each line of `acs sun`'s stdin goes here.
pub fn parse_utc_iso(text: &str) -> Result<Epoch<Utc>, String> {
    let s = text.trim();
    let s = s
        .strip_suffix('Z')
        .or_else(|| s.strip_suffix('z'))
        .or_else(|| s.strip_suffix("+00:00"))
        .unwrap_or(s);
    let (date, time) = s
        .split_once(['T', 't', ' '])
        .ok_or_else(|| format!("`{text}`: expected YYYY-MM-DDTHH:MM:SS[.f]Z"))?;
    let field = |name: &str, v: &str, digits: usize| -> Result<u32, String> {
        if v.len() != digits || !v.bytes().all(|b| b.is_ascii_digit()) {
            return Err(format!("`{text}`: {name} `{v}` is not {digits} digits"));
        }
        v.parse::<u32>()
            .map_err(|_| format!("`{text}`: bad {name} `{v}`"))
    };
    let mut d = date.split('-');
    let (Some(y), Some(mo), Some(da), None) = (d.next(), d.next(), d.next(), d.next()) else {
        return Err(format!("`{text}`: date must be YYYY-MM-DD"));
    };
    let mut t = time.split(':');
    let (Some(h), Some(mi), Some(sec), None) = (t.next(), t.next(), t.next(), t.next()) else {
        return Err(format!("`{text}`: time must be HH:MM:SS[.f]"));
    };
    let (whole, frac) = match sec.split_once('.') {
        Some((w, f)) => (w, Some(f)),
        None => (sec, None),
    };
    let nano = match frac {
        None => 0,
        Some(f) if !f.is_empty() && f.len() <= 9 && f.bytes().all(|b| b.is_ascii_digit()) => {
            let padded = format!("{f:0<9}");
            padded
                .parse::<u32>()
                .map_err(|_| format!("`{text}`: bad fraction of second `{f}`"))?
        }
        Some(f) => {
            return Err(format!(
                "`{text}`: fraction of second `{f}` must be 1 to 9 digits"
            ))
        }
    };
    let year = field("year", y, 4)?;
    let month = field("month", mo, 2)?;
    let day = field("day", da, 2)?;
    let hour = field("hour", h, 2)?;
    let minute = field("minute", mi, 2)?;
    let second = field("second", whole, 2)?;
    let narrow = |name: &str, v: u32| {
        u8::try_from(v).map_err(|_| format!("`{text}`: {name} {v} out of range"))
    };
    let calendar = Calendar {
        year: i32::try_from(year).map_err(|_| format!("`{text}`: bad year"))?,
        month: narrow("month", month)?,
        day: narrow("day", day)?,
        hour: narrow("hour", hour)?,
        minute: narrow("minute", minute)?,
        second: narrow("second", second)?,
        nano,
    };
    let epoch = Epoch::<Utc>::from_calendar(calendar).map_err(|e| format!("`{text}`: {e}"))?;
    // A 23:59:60 must be a real leap second.
    if calendar.second == 60 && calendar.hour == 23 && calendar.minute == 59 {
        epoch
            .tai_minus_utc_s()
            .map_err(|e| format!("`{text}`: {e}"))?;
    } else if calendar.second == 60 {
        return Err(format!("`{text}`: second 60 only at 23:59:60"));
    }
    Ok(epoch)
}

/// Formats a number with 10 significant digits (enough to round-trip f32).
pub(super) fn num(x: f32) -> String {
    format!("{:.9e}", f64::from(x))
}

/// Runs `acs sun`.
pub fn run(args: &Args) -> Result<(), CliError> {
    let thesis_model = args.model == "thesis";
    let j2000 = !thesis_model && args.frame == "j2000";
    let stdin = std::io::stdin();
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let io = |e: std::io::Error| CliError::Compute(format!("I/O: {e}"));
    writeln!(out, "utc,x,y,z,dist_au").map_err(io)?;
    for (index, line) in stdin.lock().lines().enumerate() {
        let line_no = index + 1;
        let line = line.map_err(|e| CliError::Input(format!("line {line_no}: {e}")))?;
        let text = line.trim();
        if text.is_empty() || text.starts_with('#') {
            continue;
        }
        let epoch =
            parse_utc_iso(text).map_err(|m| CliError::Input(format!("line {line_no}: {m}")))?;
        let result: Result<Sun, _> = if thesis_model {
            schlyter::sun(&epoch)
        } else {
            precise::sun(&epoch)
        };
        let sun =
            result.map_err(|e| CliError::Compute(format!("line {line_no}: `{text}`: {e}")))?;
        let d = if j2000 {
            // TEME → J2000 (IAU-76/80, crate::frames) in f64, at the instant's TT.
            let tt = epoch
                .to_tt_extrapolated()
                .map_err(|e| CliError::Compute(format!("line {line_no}: `{text}`: {e}")))?;
            let m = teme_to_j2000_matrix::<f64>(&tt);
            let v = m * sun.direction.cast::<f64>();
            (v / v.norm()).cast::<f32>()
        } else {
            sun.direction
        };
        writeln!(
            out,
            "{text},{},{},{},{}",
            num(d.x),
            num(d.y),
            num(d.z),
            num(sun.distance_au)
        )
        .map_err(io)?;
    }
    out.flush().map_err(io)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_rejects() {
        let e = parse_utc_iso("2009-06-16T00:00:00Z").unwrap();
        assert_eq!(e.to_calendar().year, 2009);
        let e = parse_utc_iso("2016-12-31T23:59:60.5Z").unwrap();
        assert_eq!(e.nano(), 500_000_000);
        let e = parse_utc_iso("2005-09-23T22:43:44.126Z").unwrap();
        assert_eq!(e.nano(), 126_000_000);
        for bad in [
            "",
            "2009-06-16",
            "2009-6-16T00:00:00Z",
            "2009-06-16T24:00:00Z",
            "2009-02-30T00:00:00Z",
            "2009-06-16T00:00:00.Z",
            "2009-06-16T00:00:00.1234567890Z",
            "2015-12-31T23:59:60Z",
            "2009-06-16T00:00:60Z",
            "+009-06-16T00:00:00Z",
            "2009-06-16T00:00:00+01:00",
            "1800-01-01T00:00:00Z",
            "２００９-06-16T00:00:00Z",
        ] {
            assert!(parse_utc_iso(bad).is_err(), "{bad}");
        }
    }
}
