//! `acs eclipses`: the mission-analysis eclipse report of a TLE over a time span — what seed 003
//! set out to compute (note 003 §1, §5), done right.
//!
//! `acs eclipses --tle FILE [--start UTC] [--stop UTC | --days N] [--step S]
//! [--shadow conical|cylindrical] [--gravity wgs72|wgs84] [--table all|eclipses|orbits|summary]`
//!
//! - Orbit: the flight SGP4 ([`crate::orbit::sgp4`], TEME); Sun: [`crate::env::sun::precise`]
//!   at each instant (seed 003 used a Sun 100× too fast at the wrong epoch, note 003 §6.1–6.2);
//!   shadow: the conical umbra/penumbra model (default) or seed 003's cylinder
//!   ([`crate::env::eclipse`]).
//! - Events are found on a grid of `--step` seconds (default 10 s) from sign changes of smooth
//!   margins (`c − (a + b)` for the penumbra, `c − (b − a)` for the umbra, the signed distance to
//!   the cylinder, and `z` for ascending nodes), plus a golden-section search at each local
//!   minimum that stays positive (grazing eclipses shorter than the step), and refined by
//!   bisection to 1 ms. The f32 noise of the flight SGP4 and cone geometry (~1e-7 rad) limits
//!   an event time to about 1 ms + 2 s²/D, D being the duration of the umbra (umbra events) or
//!   of the whole shadow (penumbra events): a few ms for ordinary eclipses, 60 ms at a 18 s
//!   grazing one (`cli_grazing_eclipses_shorter_than_the_step` in `tests/eclipse.rs`).
//! - Orbits run from ascending node to ascending node (the pieces before the first and after the
//!   last node are reported as incomplete). The sunlit fraction of an orbit is the time integral
//!   of the visible fraction of the solar disc over the orbit divided by its duration (Simpson
//!   over each penumbra); the overall figure is the same integral over the whole span divided by
//!   the span, never an average of averages (seed 003's "tot." summed to 98.9 %, note 003 §6.11).
//!
//! Output: CSV tables (`#` lines are comments): `eclipses`, `orbits` and a `summary`; times are
//! ISO 8601 UTC to the millisecond. Exit 2 for bad input (file, TLE, times), 3 if SGP4 fails
//! (decay) or a model is out of range.

use std::fmt::Write as _;
use std::io::Write;

use super::sun::parse_utc_iso;
use super::CliError;
use crate::env::eclipse::{cone_geometry, conical, cylindrical_margin_km, EclipseError};
use crate::env::sun::precise;
use crate::orbit::sgp4::{Gravity, Sgp4, Sgp4Error};
use crate::time::{Epoch, TimeSpan, Utc};
use crate::tle::Tle;

/// Longest span accepted, days.
pub const MAX_DAYS: f64 = 366.0;
/// Event times are refined to this many seconds.
const TIME_TOLERANCE_S: f64 = 1e-3;

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

/// Lighting state of a stretch of time.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum Light {
    Sunlit,
    Penumbra,
    Umbra,
}

/// What the models say at one instant.
#[derive(Copy, Clone, Debug)]
struct Sample {
    /// Penumbra margin: < 0 inside the penumbra or umbra (rad, or km for the cylinder).
    pen: f64,
    /// Umbra margin: < 0 inside the umbra.
    umb: f64,
    /// Visible fraction of the solar disc.
    fraction: f64,
    /// TEME z of the spacecraft, km (ascending node when it crosses 0 upwards).
    z_km: f64,
}

impl Sample {
    fn light(&self) -> Light {
        if self.umb < 0.0 {
            Light::Umbra
        } else if self.pen < 0.0 {
            Light::Penumbra
        } else {
            Light::Sunlit
        }
    }
}

/// The orbit, the Sun and the shadow model over the span, as functions of seconds from start.
struct Scene {
    sgp4: Sgp4,
    tle_epoch: Epoch<Utc>,
    start: Epoch<Utc>,
    conical: bool,
}

impl Scene {
    fn epoch(&self, t_s: f64) -> Result<Epoch<Utc>, CliError> {
        let span = TimeSpan::from_seconds_f64(t_s)
            .map_err(|e| CliError::Input(format!("time {t_s} s: {e}")))?;
        Ok(self.start.add(span))
    }

    fn sample(&self, t_s: f64) -> Result<Sample, CliError> {
        let epoch = self.epoch(t_s)?;
        let state = self
            .sgp4
            .propagate(epoch.span_since(&self.tle_epoch))
            .map_err(|e| {
                CliError::Compute(format!("SGP4 at {}: {e}", super::iso_utc_ms(&epoch)))
            })?;
        let sun = precise::sun(&epoch)
            .map_err(|e| CliError::Compute(format!("Sun at {}: {e}", super::iso_utc_ms(&epoch))))?;
        let shadow_err = |e: EclipseError| {
            CliError::Compute(format!("shadow at {}: {e}", super::iso_utc_ms(&epoch)))
        };
        let r = state.r_teme_km;
        let z_km = f64::from(r.z);
        if self.conical {
            let g = cone_geometry(&r, &sun).map_err(shadow_err)?;
            let ill = conical(&r, &sun).map_err(shadow_err)?;
            Ok(Sample {
                pen: f64::from(g.penumbra_margin()),
                umb: f64::from(g.umbra_margin()),
                fraction: f64::from(ill.fraction),
                z_km,
            })
        } else {
            let m = f64::from(cylindrical_margin_km(&r, &sun.direction).map_err(shadow_err)?);
            Ok(Sample {
                pen: m,
                umb: m,
                fraction: if m < 0.0 { 0.0 } else { 1.0 },
                z_km,
            })
        }
    }
}

/// Which margin an event belongs to.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum Margin {
    Penumbra,
    Umbra,
    Node,
}

fn margin_value(s: &Sample, m: Margin) -> f64 {
    match m {
        Margin::Penumbra => s.pen,
        Margin::Umbra => s.umb,
        Margin::Node => s.z_km,
    }
}

/// The zero of margin `m` between `t0` and `t1` (opposite signs), by bisection to 1 ms.
fn bisect(scene: &Scene, m: Margin, mut t0: f64, mut t1: f64) -> Result<f64, CliError> {
    let negative0 = margin_value(&scene.sample(t0)?, m) < 0.0;
    for _ in 0..64 {
        if t1 - t0 <= TIME_TOLERANCE_S {
            break;
        }
        let mid = 0.5 * (t0 + t1);
        if (margin_value(&scene.sample(mid)?, m) < 0.0) == negative0 {
            t0 = mid;
        } else {
            t1 = mid;
        }
    }
    Ok(0.5 * (t0 + t1))
}

/// Golden-section search for the minimum of margin `m` on `[a, b]`: `(t, value)`.
fn minimum(scene: &Scene, m: Margin, mut a: f64, mut b: f64) -> Result<(f64, f64), CliError> {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let mut c = b - g * (b - a);
    let mut d = a + g * (b - a);
    let mut fc = margin_value(&scene.sample(c)?, m);
    let mut fd = margin_value(&scene.sample(d)?, m);
    for _ in 0..60 {
        if b - a <= TIME_TOLERANCE_S {
            break;
        }
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = margin_value(&scene.sample(c)?, m);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = margin_value(&scene.sample(d)?, m);
        }
    }
    Ok(if fc < fd { (c, fc) } else { (d, fd) })
}

/// All zero crossings of the margins over `0..=span_s`: `(time, margin)`, sorted.
fn find_events(scene: &Scene, span_s: f64, step_s: f64) -> Result<Vec<(f64, Margin)>, CliError> {
    let n = (span_s / step_s).ceil().max(1.0) as u64;
    let times: Vec<f64> = (0..=n).map(|k| (k as f64 * step_s).min(span_s)).collect();
    let samples = times
        .iter()
        .map(|&t| scene.sample(t))
        .collect::<Result<Vec<_>, _>>()?;
    let margins: &[Margin] = if scene.conical {
        &[Margin::Penumbra, Margin::Umbra, Margin::Node]
    } else {
        &[Margin::Penumbra, Margin::Node]
    };
    let mut events = Vec::new();
    for &m in margins {
        let v: Vec<f64> = samples.iter().map(|s| margin_value(s, m)).collect();
        for k in 1..v.len() {
            let (t0, t1) = (times[k - 1], times[k]);
            let (v0, v1) = (v[k - 1], v[k]);
            let crossed = (v0 < 0.0) != (v1 < 0.0);
            if m == Margin::Node {
                if v0 < 0.0 && v1 >= 0.0 {
                    events.push((bisect(scene, m, t0, t1)?, m));
                }
                continue;
            }
            if crossed {
                events.push((bisect(scene, m, t0, t1)?, m));
            } else if k + 1 < v.len() && v1 >= 0.0 && v0 > v1 && v[k + 1] > v1 {
                // A positive local minimum: the margin may dip below zero between samples.
                let (t_min, v_min) = minimum(scene, m, t0, times[k + 1])?;
                if v_min < 0.0 {
                    events.push((bisect(scene, m, t0, t_min)?, m));
                    events.push((bisect(scene, m, t_min, times[k + 1])?, m));
                }
            }
        }
    }
    events.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok(events)
}

/// A stretch of constant lighting.
#[derive(Copy, Clone, Debug)]
struct Segment {
    t0: f64,
    t1: f64,
    light: Light,
    /// ∫ visible fraction dt over the segment, s.
    lit_s: f64,
}

fn segments(
    scene: &Scene,
    span_s: f64,
    events: &[(f64, Margin)],
) -> Result<Vec<Segment>, CliError> {
    let mut cuts: Vec<f64> = std::iter::once(0.0)
        .chain(events.iter().map(|e| e.0))
        .chain(std::iter::once(span_s))
        .collect();
    cuts.dedup_by(|a, b| (*a - *b).abs() < 0.5 * TIME_TOLERANCE_S);
    let mut out = Vec::new();
    for w in cuts.windows(2) {
        let (t0, t1) = (w[0], w[1]);
        if t1 <= t0 {
            continue;
        }
        let light = scene.sample(0.5 * (t0 + t1))?.light();
        let lit_s = match light {
            Light::Sunlit => t1 - t0,
            Light::Umbra => 0.0,
            Light::Penumbra => {
                // Simpson's rule, 32 intervals.
                let n = 32;
                let h = (t1 - t0) / f64::from(n);
                let mut sum = 0.0;
                for i in 0..=n {
                    let weight = if i == 0 || i == n {
                        1.0
                    } else if i % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    sum += weight * scene.sample(t0 + f64::from(i) * h)?.fraction;
                }
                sum * h / 3.0
            }
        };
        out.push(Segment {
            t0,
            t1,
            light,
            lit_s,
        });
    }
    // Merge neighbours of equal lighting (cuts at nodes or at the other margin's events).
    let mut merged: Vec<Segment> = Vec::new();
    for s in out {
        match merged.last_mut() {
            Some(last) if last.light == s.light && last.light != Light::Penumbra => {
                last.t1 = s.t1;
                last.lit_s += s.lit_s;
            }
            _ => merged.push(s),
        }
    }
    Ok(merged)
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
    let scene = Scene {
        sgp4,
        tle_epoch: tle.epoch,
        start,
        conical: args.shadow == "conical",
    };
    let events = find_events(&scene, span_s, args.step)?;
    let segs = segments(&scene, span_s, &events)?;
    let report = render(&scene, &tle, args, span_s, &events, &segs)?;
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    out.write_all(report.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| CliError::Compute(format!("cannot write the output: {e}")))
}

/// One eclipse: a maximal run of non-sunlit segments.
struct Eclipse {
    pen_entry: f64,
    umb_entry: Option<f64>,
    umb_exit: Option<f64>,
    pen_exit: f64,
    umbra_s: f64,
    complete: bool,
}

fn eclipses(segs: &[Segment], span_s: f64) -> Vec<Eclipse> {
    let mut out: Vec<Eclipse> = Vec::new();
    let mut current: Option<Eclipse> = None;
    for s in segs {
        if s.light == Light::Sunlit {
            if let Some(e) = current.take() {
                out.push(e);
            }
            continue;
        }
        let e = current.get_or_insert(Eclipse {
            pen_entry: s.t0,
            umb_entry: None,
            umb_exit: None,
            pen_exit: s.t1,
            umbra_s: 0.0,
            complete: s.t0 > 0.0,
        });
        e.pen_exit = s.t1;
        if s.light == Light::Umbra {
            e.umb_entry.get_or_insert(s.t0);
            e.umb_exit = Some(s.t1);
            e.umbra_s += s.t1 - s.t0;
        }
    }
    if let Some(mut e) = current {
        e.complete &= e.pen_exit < span_s;
        out.push(e);
    }
    out
}

/// Per orbit (ascending node to ascending node): `(t0, t1, complete, lit_s, umbra_s, penumbra_s)`.
fn orbits(
    segs: &[Segment],
    span_s: f64,
    events: &[(f64, Margin)],
) -> Vec<(f64, f64, bool, f64, f64, f64)> {
    let nodes: Vec<f64> = events
        .iter()
        .filter(|e| e.1 == Margin::Node)
        .map(|e| e.0)
        .collect();
    let bounds: Vec<f64> = std::iter::once(0.0)
        .chain(nodes.iter().copied())
        .chain(std::iter::once(span_s))
        .collect();
    let mut out = Vec::new();
    for (i, w) in bounds.windows(2).enumerate() {
        let (t0, t1) = (w[0], w[1]);
        if t1 - t0 < TIME_TOLERANCE_S {
            continue;
        }
        let complete = i > 0 && i + 2 < bounds.len();
        let (mut lit, mut umb, mut pen) = (0.0, 0.0, 0.0);
        for s in segs {
            let a = s.t0.max(t0);
            let b = s.t1.min(t1);
            if b <= a {
                continue;
            }
            let share = (b - a) / (s.t1 - s.t0);
            match s.light {
                Light::Sunlit => lit += b - a,
                Light::Umbra => umb += b - a,
                Light::Penumbra => {
                    pen += b - a;
                    lit += s.lit_s * share;
                }
            }
        }
        out.push((t0, t1, complete, lit, umb, pen));
    }
    out
}

fn render(
    scene: &Scene,
    tle: &Tle,
    args: &Args,
    span_s: f64,
    events: &[(f64, Margin)],
    segs: &[Segment],
) -> Result<String, CliError> {
    let at = |t: f64| -> Result<String, CliError> {
        let ms = (t * 1000.0).round() / 1000.0;
        Ok(super::iso_utc_ms(&scene.epoch(ms)?))
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
    let ecl = eclipses(segs, span_s);
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
                at(e.pen_entry)?,
                opt(e.umb_entry)?,
                opt(e.umb_exit)?,
                at(e.pen_exit)?,
                e.umbra_s,
                e.pen_exit - e.pen_entry,
                e.complete
            )
            .map_err(w)?;
        }
    }
    let orb = orbits(segs, span_s, events);
    if all || args.table == "orbits" {
        writeln!(o, "# orbits from ascending node to ascending node; sunlit_fraction = ∫ visible solar fraction dt / duration").map_err(w)?;
        writeln!(
            o,
            "orbit,start_utc,end_utc,duration_min,sunlit_fraction,umbra_s,penumbra_s,complete"
        )
        .map_err(w)?;
        for (i, (t0, t1, complete, lit, umb, pen)) in orb.iter().enumerate() {
            writeln!(
                o,
                "{},{},{},{:.4},{:.6},{:.3},{:.3},{}",
                i,
                at(*t0)?,
                at(*t1)?,
                (t1 - t0) / 60.0,
                lit / (t1 - t0),
                umb,
                pen,
                complete
            )
            .map_err(w)?;
        }
    }
    if all || args.table == "summary" {
        let lit_total: f64 = segs.iter().map(|s| s.lit_s).sum();
        let umb_total: f64 = segs
            .iter()
            .filter(|s| s.light == Light::Umbra)
            .map(|s| s.t1 - s.t0)
            .sum();
        let fractions: Vec<f64> = orb
            .iter()
            .filter(|x| x.2)
            .map(|x| x.3 / (x.1 - x.0))
            .collect();
        let longest = ecl
            .iter()
            .filter(|e| e.complete)
            .map(|e| e.pen_exit - e.pen_entry)
            .fold(0.0, f64::max);
        writeln!(o, "# summary").map_err(w)?;
        writeln!(o, "quantity,value").map_err(w)?;
        writeln!(o, "span_days,{:.6}", span_s / 86_400.0).map_err(w)?;
        writeln!(o, "sunlit_fraction,{:.6}", lit_total / span_s).map_err(w)?;
        writeln!(o, "umbra_fraction,{:.6}", umb_total / span_s).map_err(w)?;
        writeln!(o, "eclipses,{}", ecl.len()).map_err(w)?;
        writeln!(o, "complete_orbits,{}", fractions.len()).map_err(w)?;
        if let (Some(min), Some(max)) = (
            fractions.iter().copied().reduce(f64::min),
            fractions.iter().copied().reduce(f64::max),
        ) {
            writeln!(o, "orbit_sunlit_fraction_min,{min:.6}").map_err(w)?;
            writeln!(o, "orbit_sunlit_fraction_max,{max:.6}").map_err(w)?;
        }
        writeln!(o, "longest_complete_eclipse_s,{longest:.3}").map_err(w)?;
    }
    Ok(o)
}
