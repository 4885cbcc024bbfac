//! `acs eclipses`: the mission-analysis eclipse report of a TLE over a time span — what seed 003
//! set out to compute (note 003 §1, §5), done right.
//!
//! `acs eclipses --tle FILE [--start UTC] [--stop UTC | --days N] [--step S]
//! [--shadow conical|cylindrical] [--gravity wgs72|wgs84] [--table all|eclipses|orbits|summary]`
//!
//! The search (orbit, Sun and shadow models, event finding to 1 ms, orbits from ascending node
//! to ascending node, sunlit fractions) is [`crate::host::eclipse_search`]; this module reads
//! the arguments and prints its results.
//!
//! Output: CSV tables (`#` lines are comments): `eclipses`, `orbits` and a `summary`; times are
//! ISO 8601 UTC to the millisecond. Exit 2 for bad input (file, TLE, times), 3 if SGP4 fails
//! (decay) or a model is out of range.

use std::fmt::Write as _;
use std::io::Write;

use super::sun::parse_utc_iso;
use super::CliError;
use crate::host::eclipse_search::{self, Event, Search, SearchError, Segment, Shadow};
use crate::orbit::sgp4::{Gravity, Sgp4, Sgp4Error};
use crate::tle::Tle;

/// Longest span accepted, days.
pub const MAX_DAYS: f64 = 366.0;

/// Arguments of `acs eclipses`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// File with one element set (two lines, or a name line and two lines).
    #[arg(long)]
    tle: std::path::PathBuf,
    /// Start of the span, ISO 8601 UTC (default: the TLE epoch).
    #[arg(long)]
    start: Option<String>,
    /// End of the span, ISO 8601 UTC (default: start + `--days`).
    #[arg(long, conflicts_with = "days")]
    stop: Option<String>,
    /// Length of the span in days when `--stop` is not given.
    #[arg(long, default_value_t = 1.0)]
    days: f64,
    /// Search step in seconds (0.1..=60); events are then refined to 1 ms.
    #[arg(long, default_value_t = 10.0)]
    step: f64,
    /// Shadow model.
    #[arg(long, value_parser = ["conical", "cylindrical"], default_value = "conical")]
    shadow: String,
    /// SGP4 gravity model.
    #[arg(long, value_parser = ["wgs72", "wgs84"], default_value = "wgs72")]
    gravity: String,
    /// Which tables to print.
    #[arg(long, value_parser = ["all", "eclipses", "orbits", "summary"], default_value = "all")]
    table: String,
}

/// A search failure as the CLI reports it: a time out of range is bad input, the rest a
/// failed computation.
fn cli_error(e: SearchError) -> CliError {
    match e {
        SearchError::Time { .. } | SearchError::Grid { .. } => CliError::Input(e.to_string()),
        _ => CliError::Compute(e.to_string()),
    }
}

/// Runs `acs eclipses`.
pub fn run(args: &Args) -> Result<(), CliError> {
    let path = args.tle.display();
    let text =
        std::fs::read_to_string(&args.tle).map_err(|e| CliError::Input(format!("{path}: {e}")))?;
    let tle = Tle::parse_text(&text).map_err(|e| CliError::Input(format!("{path}: {e}")))?;
    let gravity = match args.gravity.as_str() {
        "wgs84" => Gravity::Wgs84,
        _ => Gravity::Wgs72,
    };
    let sgp4 = Sgp4::new(&tle, gravity).map_err(|e| match e {
        Sgp4Error::Element { .. } => CliError::Input(format!("{path}: {e}")),
        _ => CliError::Compute(format!("{path}: {e}")),
    })?;
    let start = match &args.start {
        Some(s) => parse_utc_iso(s).map_err(|m| CliError::Input(format!("--start: {m}")))?,
        None => tle.epoch,
    };
    let span_s = match &args.stop {
        Some(s) => {
            let stop = parse_utc_iso(s).map_err(|m| CliError::Input(format!("--stop: {m}")))?;
            stop.span_since(&start).as_seconds_f64()
        }
        None => {
            if !args.days.is_finite() {
                return Err(CliError::Input(format!(
                    "--days {} is not finite",
                    args.days
                )));
            }
            args.days * 86_400.0
        }
    };
    if !(span_s > 0.0 && span_s <= MAX_DAYS * 86_400.0) {
        return Err(CliError::Input(format!(
            "the span must be positive and at most {MAX_DAYS} days (got {} days)",
            span_s / 86_400.0
        )));
    }
    if !(0.1..=60.0).contains(&args.step) {
        return Err(CliError::Input(format!(
            "--step {} s outside 0.1..=60",
            args.step
        )));
    }
    let shadow = if args.shadow == "conical" {
        Shadow::Conical
    } else {
        Shadow::Cylindrical
    };
    let search = Search::new(sgp4, tle.epoch, start, shadow);
    let events = search.events(span_s, args.step).map_err(cli_error)?;
    let segs = search.segments(span_s, &events).map_err(cli_error)?;
    let report = render(&search, &tle, args, span_s, &events, &segs)?;
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    out.write_all(report.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| CliError::Compute(format!("cannot write the output: {e}")))
}

fn render(
    search: &Search,
    tle: &Tle,
    args: &Args,
    span_s: f64,
    events: &[Event],
    segs: &[Segment],
) -> Result<String, CliError> {
    let at = |t: f64| -> Result<String, CliError> {
        let ms = (t * 1000.0).round() / 1000.0;
        Ok(super::iso_utc_ms(&search.epoch(ms).map_err(cli_error)?))
    };
    let name = tle.name.as_ref().map_or("", |n| n.as_str());
    let mut o = String::new();
    let w = |e: std::fmt::Error| CliError::Compute(format!("format: {e}"));
    writeln!(
        o,
        "# acs eclipses: {name} (NORAD {}), SGP4 {}, {} shadow, Sun: env::sun::precise",
        tle.catalog_number,
        args.gravity.to_uppercase(),
        args.shadow
    )
    .map_err(w)?;
    writeln!(
        o,
        "# span {} .. {} ({:.3} days), search step {} s, events refined to 1 ms",
        at(0.0)?,
        at(span_s)?,
        span_s / 86_400.0,
        args.step
    )
    .map_err(w)?;
    let all = args.table == "all";
    let ecl = eclipse_search::eclipses(segs, span_s);
    if all || args.table == "eclipses" {
        writeln!(
            o,
            "# eclipses (penumbra columns equal the umbra ones for the cylinder; empty: no umbra)"
        )
        .map_err(w)?;
        writeln!(o, "eclipse,penumbra_entry_utc,umbra_entry_utc,umbra_exit_utc,penumbra_exit_utc,umbra_s,shadow_s,complete").map_err(w)?;
        for (i, e) in ecl.iter().enumerate() {
            let opt =
                |t: Option<f64>| -> Result<String, CliError> { t.map_or(Ok(String::new()), at) };
            writeln!(
                o,
                "{},{},{},{},{},{:.3},{:.3},{}",
                i + 1,
                at(e.penumbra_entry_s)?,
                opt(e.umbra_entry_s)?,
                opt(e.umbra_exit_s)?,
                at(e.penumbra_exit_s)?,
                e.umbra_s,
                e.penumbra_exit_s - e.penumbra_entry_s,
                e.complete
            )
            .map_err(w)?;
        }
    }
    let orb = eclipse_search::orbits(segs, span_s, events);
    if all || args.table == "orbits" {
        writeln!(o, "# orbits from ascending node to ascending node; sunlit_fraction = ∫ visible solar fraction dt / duration").map_err(w)?;
        writeln!(
            o,
            "orbit,start_utc,end_utc,duration_min,sunlit_fraction,umbra_s,penumbra_s,complete"
        )
        .map_err(w)?;
        for (i, r) in orb.iter().enumerate() {
            let (t0, t1) = (r.t0_s, r.t1_s);
            writeln!(
                o,
                "{},{},{},{:.4},{:.6},{:.3},{:.3},{}",
                i,
                at(t0)?,
                at(t1)?,
                (t1 - t0) / 60.0,
                r.lit_s / (t1 - t0),
                r.umbra_s,
                r.penumbra_s,
                r.complete
            )
            .map_err(w)?;
        }
    }
    if all || args.table == "summary" {
        let sum = eclipse_search::summary(segs, span_s, &ecl, &orb);
        writeln!(o, "# summary").map_err(w)?;
        writeln!(o, "quantity,value").map_err(w)?;
        writeln!(o, "span_days,{:.6}", span_s / 86_400.0).map_err(w)?;
        writeln!(o, "sunlit_fraction,{:.6}", sum.sunlit_fraction).map_err(w)?;
        writeln!(o, "umbra_fraction,{:.6}", sum.umbra_fraction).map_err(w)?;
        writeln!(o, "eclipses,{}", ecl.len()).map_err(w)?;
        writeln!(o, "complete_orbits,{}", sum.complete_orbits).map_err(w)?;
        if let Some((min, max)) = sum.orbit_sunlit_fraction_range {
            writeln!(o, "orbit_sunlit_fraction_min,{min:.6}").map_err(w)?;
            writeln!(o, "orbit_sunlit_fraction_max,{max:.6}").map_err(w)?;
        }
        writeln!(
            o,
            "longest_complete_eclipse_s,{:.3}",
            sum.longest_complete_eclipse_s
        )
        .map_err(w)?;
    }
    Ok(o)
}
