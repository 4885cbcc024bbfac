//! Eclipse and orbit events of a TLE over a time span, for mission analysis (what seed 003 set
//! out to compute, note 003 §1, §5, done right); `acs eclipses` prints them.
//!
//! - Orbit: the flight SGP4 ([`crate::orbit::sgp4`], TEME); Sun: [`crate::env::sun::precise`]
//!   at each instant (seed 003 used a Sun 100× too fast at the wrong epoch, note 003 §6.1–6.2);
//!   shadow: the conical umbra/penumbra model or seed 003's cylinder ([`crate::env::eclipse`]),
//!   [`Shadow`].
//! - Events ([`Search::events`]) are found on a grid of `step_s` seconds from sign changes of
//!   smooth margins (`c − (a + b)` for the penumbra, `c − (b − a)` for the umbra, the signed
//!   distance to the cylinder, and `z` for ascending nodes), plus a golden-section search at each
//!   local minimum that stays positive (grazing eclipses shorter than the step), and refined by
//!   bisection to 1 ms ([`TIME_TOLERANCE_S`]). The f32 noise of the flight SGP4 and cone
//!   geometry (~1e-7 rad) limits an event time to about 1 ms + 2 s²/D, D being the duration of
//!   the umbra (umbra events) or of the whole shadow (penumbra events): a few ms for ordinary
//!   eclipses, 60 ms at a 18 s grazing one (`cli_grazing_eclipses_shorter_than_the_step` in
//!   `tests/eclipse.rs`).
//! - The events cut the span into [`Segment`]s of constant lighting ([`Search::segments`]);
//!   [`eclipses`] groups them into eclipses, [`orbits`] into orbits from ascending node to
//!   ascending node (the pieces before the first and after the last node are incomplete). The
//!   sunlit fraction of an orbit is the time integral of the visible fraction of the solar disc
//!   over the orbit divided by its duration (Simpson over each penumbra); the overall figure
//!   ([`Summary`]) is the same integral over the whole span divided by the span, never an
//!   average of averages (seed 003's "tot." summed to 98.9 %, note 003 §6.11).
//!
//! Times are seconds from the start of the span ([`Search::epoch`] turns them into epochs).

use std::fmt;

use crate::env::eclipse::{cone_geometry, conical, cylindrical_margin_km, EclipseError};
use crate::env::sun::{precise, SunError};
use crate::orbit::sgp4::{Sgp4, Sgp4Error};
use crate::time::{Epoch, TimeError, TimeSpan, Utc};

/// Event times are refined to this many seconds.
pub const TIME_TOLERANCE_S: f64 = 1e-3;

/// Shadow model of the search.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Shadow {
    /// Conical umbra and penumbra ([`crate::env::eclipse::conical`]).
    Conical,
    /// Seed 003's cylinder ([`crate::env::eclipse::cylindrical_margin_km`]): no penumbra.
    Cylindrical,
}

/// Why the search failed at some instant.
#[derive(Copy, Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum SearchError {
    /// `t_s` seconds from the start is not a representable time span.
    Time {
        /// Seconds from the start of the span.
        t_s: f64,
        /// The time error.
        error: TimeError,
    },
    /// SGP4 failed (decay) at `epoch`.
    Sgp4 {
        /// The instant.
        epoch: Epoch<Utc>,
        /// The SGP4 error.
        error: Sgp4Error,
    },
    /// The Sun model is out of range at `epoch`.
    Sun {
        /// The instant.
        epoch: Epoch<Utc>,
        /// The Sun model's error.
        error: SunError,
    },
    /// The shadow model refused its input at `epoch`.
    Shadow {
        /// The instant.
        epoch: Epoch<Utc>,
        /// The shadow model's error.
        error: EclipseError,
    },
    /// The span or the step is not finite and positive.
    Grid {
        /// The span, s.
        span_s: f64,
        /// The step, s.
        step_s: f64,
    },
}

impl fmt::Display for SearchError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Time { t_s, error } => write!(f, "time {t_s} s: {error}"),
            Self::Sgp4 { epoch, error } => {
                write!(f, "SGP4 at {}: {error}", super::iso_utc_ms(epoch))
            }
            Self::Sun { epoch, error } => write!(f, "Sun at {}: {error}", super::iso_utc_ms(epoch)),
            Self::Shadow { epoch, error } => {
                write!(f, "shadow at {}: {error}", super::iso_utc_ms(epoch))
            }
            Self::Grid { span_s, step_s } => {
                write!(
                    f,
                    "span {span_s} s and step {step_s} s must be finite and positive"
                )
            }
        }
    }
}

impl std::error::Error for SearchError {}

/// Lighting state of a stretch of time.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Light {
    /// The whole solar disc is visible.
    Sunlit,
    /// Part of the solar disc is visible.
    Penumbra,
    /// None of the solar disc is visible.
    Umbra,
}

/// What the models say at one instant.
#[derive(Copy, Clone, Debug)]
pub struct Sample {
    /// Penumbra margin: < 0 inside the penumbra or umbra (rad, or km for the cylinder).
    pub penumbra_margin: f64,
    /// Umbra margin: < 0 inside the umbra (equal to the penumbra margin for the cylinder).
    pub umbra_margin: f64,
    /// Visible fraction of the solar disc.
    pub fraction: f64,
    /// TEME z of the spacecraft, km (ascending node when it crosses 0 upwards).
    pub z_km: f64,
}

impl Sample {
    /// The lighting state the margins give.
    pub fn light(&self) -> Light {
        if self.umbra_margin < 0.0 {
            Light::Umbra
        } else if self.penumbra_margin < 0.0 {
            Light::Penumbra
        } else {
            Light::Sunlit
        }
    }

    /// The value of the margin whose zero crossings are events of `kind`.
    pub fn margin(&self, kind: EventKind) -> f64 {
        match kind {
            EventKind::Penumbra => self.penumbra_margin,
            EventKind::Umbra => self.umbra_margin,
            EventKind::Node => self.z_km,
        }
    }
}

/// Which margin an event is a zero of.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum EventKind {
    /// Penumbra entry or exit (the shadow's for the cylinder).
    Penumbra,
    /// Umbra entry or exit.
    Umbra,
    /// Ascending node (TEME z crossing 0 upwards).
    Node,
}

/// A zero crossing of a margin.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Event {
    /// Seconds from the start of the span.
    pub t_s: f64,
    /// Which margin.
    pub kind: EventKind,
}

/// The orbit, the Sun and the shadow model over the span, as functions of seconds from start.
#[derive(Clone, Debug)]
pub struct Search {
    sgp4: Sgp4,
    tle_epoch: Epoch<Utc>,
    start: Epoch<Utc>,
    shadow: Shadow,
}

impl Search {
    /// The search over the orbit of `sgp4` (initialised from elements of epoch `tle_epoch`)
    /// from `start`.
    pub fn new(sgp4: Sgp4, tle_epoch: Epoch<Utc>, start: Epoch<Utc>, shadow: Shadow) -> Self {
        Self {
            sgp4,
            tle_epoch,
            start,
            shadow,
        }
    }

    /// The instant `t_s` seconds from the start.
    pub fn epoch(&self, t_s: f64) -> Result<Epoch<Utc>, SearchError> {
        let span =
            TimeSpan::from_seconds_f64(t_s).map_err(|error| SearchError::Time { t_s, error })?;
        Ok(self.start.add(span))
    }

    /// The models `t_s` seconds from the start.
    pub fn sample(&self, t_s: f64) -> Result<Sample, SearchError> {
        let epoch = self.epoch(t_s)?;
        let state = self
            .sgp4
            .propagate(epoch.span_since(&self.tle_epoch))
            .map_err(|error| SearchError::Sgp4 { epoch, error })?;
        let sun = precise::sun(&epoch).map_err(|error| SearchError::Sun { epoch, error })?;
        let shadow_err = |error: EclipseError| SearchError::Shadow { epoch, error };
        let r = state.r_teme_km;
        let z_km = f64::from(r.z);
        match self.shadow {
            Shadow::Conical => {
                let g = cone_geometry(&r, &sun).map_err(shadow_err)?;
                let ill = conical(&r, &sun).map_err(shadow_err)?;
                Ok(Sample {
                    penumbra_margin: f64::from(g.penumbra_margin()),
                    umbra_margin: f64::from(g.umbra_margin()),
                    fraction: f64::from(ill.fraction),
                    z_km,
                })
            }
            Shadow::Cylindrical => {
                let m = f64::from(cylindrical_margin_km(&r, &sun.direction).map_err(shadow_err)?);
                Ok(Sample {
                    penumbra_margin: m,
                    umbra_margin: m,
                    fraction: if m < 0.0 { 0.0 } else { 1.0 },
                    z_km,
                })
            }
        }
    }

    /// The zero of margin `kind` between `t0` and `t1` (opposite signs), by bisection to 1 ms.
    fn bisect(&self, kind: EventKind, mut t0: f64, mut t1: f64) -> Result<f64, SearchError> {
        let negative0 = self.sample(t0)?.margin(kind) < 0.0;
        for _ in 0..64 {
            if t1 - t0 <= TIME_TOLERANCE_S {
                break;
            }
            let mid = 0.5 * (t0 + t1);
            if (self.sample(mid)?.margin(kind) < 0.0) == negative0 {
                t0 = mid;
            } else {
                t1 = mid;
            }
        }
        Ok(0.5 * (t0 + t1))
    }

    /// Golden-section search for the minimum of margin `kind` on `[a, b]`: `(t, value)`.
    fn minimum(&self, kind: EventKind, mut a: f64, mut b: f64) -> Result<(f64, f64), SearchError> {
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let mut c = b - g * (b - a);
        let mut d = a + g * (b - a);
        let mut fc = self.sample(c)?.margin(kind);
        let mut fd = self.sample(d)?.margin(kind);
        for _ in 0..60 {
            if b - a <= TIME_TOLERANCE_S {
                break;
            }
            if fc < fd {
                b = d;
                d = c;
                fd = fc;
                c = b - g * (b - a);
                fc = self.sample(c)?.margin(kind);
            } else {
                a = c;
                c = d;
                fc = fd;
                d = a + g * (b - a);
                fd = self.sample(d)?.margin(kind);
            }
        }
        Ok(if fc < fd { (c, fc) } else { (d, fd) })
    }

    /// All zero crossings of the margins over `0..=span_s`, searched on a grid of `step_s`
    /// seconds (see the module docs), sorted by time.
    pub fn events(&self, span_s: f64, step_s: f64) -> Result<Vec<Event>, SearchError> {
        if !(span_s.is_finite() && span_s > 0.0 && step_s.is_finite() && step_s > 0.0) {
            return Err(SearchError::Grid { span_s, step_s });
        }
        let n = (span_s / step_s).ceil().max(1.0) as u64;
        let times: Vec<f64> = (0..=n).map(|k| (k as f64 * step_s).min(span_s)).collect();
        let samples = times
            .iter()
            .map(|&t| self.sample(t))
            .collect::<Result<Vec<_>, _>>()?;
        let kinds: &[EventKind] = match self.shadow {
            Shadow::Conical => &[EventKind::Penumbra, EventKind::Umbra, EventKind::Node],
            Shadow::Cylindrical => &[EventKind::Penumbra, EventKind::Node],
        };
        let mut events = Vec::new();
        for &kind in kinds {
            let at = |t_s: f64| Event { t_s, kind };
            let v: Vec<f64> = samples.iter().map(|s| s.margin(kind)).collect();
            for k in 1..v.len() {
                let (t0, t1) = (times[k - 1], times[k]);
                let (v0, v1) = (v[k - 1], v[k]);
                let crossed = (v0 < 0.0) != (v1 < 0.0);
                if kind == EventKind::Node {
                    if v0 < 0.0 && v1 >= 0.0 {
                        events.push(at(self.bisect(kind, t0, t1)?));
                    }
                    continue;
                }
                if crossed {
                    events.push(at(self.bisect(kind, t0, t1)?));
                } else if k + 1 < v.len() && v1 >= 0.0 && v0 > v1 && v[k + 1] > v1 {
                    // A positive local minimum: the margin may dip below zero between samples.
                    let (t_min, v_min) = self.minimum(kind, t0, times[k + 1])?;
                    if v_min < 0.0 {
                        events.push(at(self.bisect(kind, t0, t_min)?));
                        events.push(at(self.bisect(kind, t_min, times[k + 1])?));
                    }
                }
            }
        }
        events.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
        Ok(events)
    }

    /// The span `0..=span_s` cut at `events` (from [`Search::events`]) into stretches of
    /// constant lighting, neighbours of equal lighting merged (penumbrae are kept apart).
    pub fn segments(&self, span_s: f64, events: &[Event]) -> Result<Vec<Segment>, SearchError> {
        let mut cuts: Vec<f64> = std::iter::once(0.0)
            .chain(events.iter().map(|e| e.t_s))
            .chain(std::iter::once(span_s))
            .collect();
        cuts.dedup_by(|a, b| (*a - *b).abs() < 0.5 * TIME_TOLERANCE_S);
        let mut out = Vec::new();
        for w in cuts.windows(2) {
            let (t0, t1) = (w[0], w[1]);
            if t1 <= t0 {
                continue;
            }
            let light = self.sample(0.5 * (t0 + t1))?.light();
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
                        sum += weight * self.sample(t0 + f64::from(i) * h)?.fraction;
                    }
                    sum * h / 3.0
                }
            };
            out.push(Segment {
                t0_s: t0,
                t1_s: t1,
                light,
                lit_s,
            });
        }
        // Merge neighbours of equal lighting (cuts at nodes or at the other margin's events).
        let mut merged: Vec<Segment> = Vec::new();
        for s in out {
            match merged.last_mut() {
                Some(last) if last.light == s.light && last.light != Light::Penumbra => {
                    last.t1_s = s.t1_s;
                    last.lit_s += s.lit_s;
                }
                _ => merged.push(s),
            }
        }
        Ok(merged)
    }
}

/// A stretch of constant lighting.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Segment {
    /// Start, seconds from the start of the span.
    pub t0_s: f64,
    /// End, seconds from the start of the span.
    pub t1_s: f64,
    /// The lighting.
    pub light: Light,
    /// ∫ visible fraction dt over the segment, s.
    pub lit_s: f64,
}

/// One eclipse: a maximal run of non-sunlit segments (times in seconds from the start).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Eclipse {
    /// Penumbra entry (shadow entry for the cylinder).
    pub penumbra_entry_s: f64,
    /// Umbra entry, if the eclipse has an umbra.
    pub umbra_entry_s: Option<f64>,
    /// Umbra exit, if the eclipse has an umbra.
    pub umbra_exit_s: Option<f64>,
    /// Penumbra exit (shadow exit for the cylinder).
    pub penumbra_exit_s: f64,
    /// Time in the umbra, s.
    pub umbra_s: f64,
    /// Whether the eclipse lies wholly inside the span.
    pub complete: bool,
}

/// The eclipses of `segs` (from [`Search::segments`] over `0..=span_s`).
pub fn eclipses(segs: &[Segment], span_s: f64) -> Vec<Eclipse> {
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
            penumbra_entry_s: s.t0_s,
            umbra_entry_s: None,
            umbra_exit_s: None,
            penumbra_exit_s: s.t1_s,
            umbra_s: 0.0,
            complete: s.t0_s > 0.0,
        });
        e.penumbra_exit_s = s.t1_s;
        if s.light == Light::Umbra {
            e.umbra_entry_s.get_or_insert(s.t0_s);
            e.umbra_exit_s = Some(s.t1_s);
            e.umbra_s += s.t1_s - s.t0_s;
        }
    }
    if let Some(mut e) = current {
        e.complete &= e.penumbra_exit_s < span_s;
        out.push(e);
    }
    out
}

/// One orbit, from ascending node to ascending node (times in seconds from the start).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Orbit {
    /// Start (a node, or the start of the span).
    pub t0_s: f64,
    /// End (a node, or the end of the span).
    pub t1_s: f64,
    /// Whether both ends are nodes.
    pub complete: bool,
    /// ∫ visible fraction dt over the orbit, s.
    pub lit_s: f64,
    /// Time in the umbra, s.
    pub umbra_s: f64,
    /// Time in the penumbra, s.
    pub penumbra_s: f64,
}

/// The orbits of the span `0..=span_s`, cut at the ascending nodes of `events`, with the
/// lighting of `segs` (from [`Search::events`] and [`Search::segments`]).
pub fn orbits(segs: &[Segment], span_s: f64, events: &[Event]) -> Vec<Orbit> {
    let nodes: Vec<f64> = events
        .iter()
        .filter(|e| e.kind == EventKind::Node)
        .map(|e| e.t_s)
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
            let a = s.t0_s.max(t0);
            let b = s.t1_s.min(t1);
            if b <= a {
                continue;
            }
            let share = (b - a) / (s.t1_s - s.t0_s);
            match s.light {
                Light::Sunlit => lit += b - a,
                Light::Umbra => umb += b - a,
                Light::Penumbra => {
                    pen += b - a;
                    lit += s.lit_s * share;
                }
            }
        }
        out.push(Orbit {
            t0_s: t0,
            t1_s: t1,
            complete,
            lit_s: lit,
            umbra_s: umb,
            penumbra_s: pen,
        });
    }
    out
}

/// The whole span's figures.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Summary {
    /// ∫ visible fraction dt over the span, divided by the span.
    pub sunlit_fraction: f64,
    /// Time in the umbra over the span.
    pub umbra_fraction: f64,
    /// Number of complete orbits.
    pub complete_orbits: usize,
    /// The lowest and highest sunlit fraction of a complete orbit, if there is one.
    pub orbit_sunlit_fraction_range: Option<(f64, f64)>,
    /// The longest complete eclipse (penumbra entry to exit), s; 0 if none.
    pub longest_complete_eclipse_s: f64,
}

/// The figures of the span `0..=span_s` from its segments, eclipses and orbits.
pub fn summary(segs: &[Segment], span_s: f64, ecl: &[Eclipse], orb: &[Orbit]) -> Summary {
    let lit_total: f64 = segs.iter().map(|s| s.lit_s).sum();
    let umb_total: f64 = segs
        .iter()
        .filter(|s| s.light == Light::Umbra)
        .map(|s| s.t1_s - s.t0_s)
        .sum();
    let fractions: Vec<f64> = orb
        .iter()
        .filter(|x| x.complete)
        .map(|x| x.lit_s / (x.t1_s - x.t0_s))
        .collect();
    let longest = ecl
        .iter()
        .filter(|e| e.complete)
        .map(|e| e.penumbra_exit_s - e.penumbra_entry_s)
        .fold(0.0, f64::max);
    let range = match (
        fractions.iter().copied().reduce(f64::min),
        fractions.iter().copied().reduce(f64::max),
    ) {
        (Some(min), Some(max)) => Some((min, max)),
        _ => None,
    };
    Summary {
        sunlit_fraction: lit_total / span_s,
        umbra_fraction: umb_total / span_s,
        complete_orbits: fractions.len(),
        orbit_sunlit_fraction_range: range,
        longest_complete_eclipse_s: longest,
    }
}
