//! The plots of a campaign (SVG, plotters): percentile envelopes over time and histograms of the
//! metrics with their limits.

use std::path::Path;

use plotters::prelude::*;

use super::stats::percentile;
use super::{Campaign, RunResult, Summary, GRID};

/// Writes the envelopes and the histograms into `dir`; returns the files written.
pub fn write_all(
    dir: &Path,
    campaign: &Campaign,
    results: &[RunResult],
    summary: &Summary,
) -> Result<Vec<String>, String> {
    let scenario = crate::host::sim::scenarios::by_name(&campaign.scenario)
        .ok_or("unknown scenario")?
        .map_err(|e| e.to_string())?;
    let duration_min = scenario.duration_s / 60.0;
    let mut files = Vec::new();
    let pointing: Vec<&[f32]> = results
        .iter()
        .map(|r| r.pointing_deg.as_slice())
        .filter(|v| !v.is_empty())
        .collect();
    if !pointing.is_empty() {
        envelope(
            &dir.join("pointing_envelope.svg"),
            &format!(
                "{}: pointing error over {} runs",
                campaign.scenario, campaign.runs
            ),
            "pointing error [deg]",
            &pointing,
            duration_min,
        )?;
        files.push("pointing_envelope.svg".to_string());
    }
    let rates: Vec<&[f32]> = results
        .iter()
        .map(|r| r.rate_degps.as_slice())
        .filter(|v| !v.is_empty())
        .collect();
    if !rates.is_empty() {
        envelope(
            &dir.join("rate_envelope.svg"),
            &format!(
                "{}: body rate over {} runs",
                campaign.scenario, campaign.runs
            ),
            "rate [deg/s]",
            &rates,
            duration_min,
        )?;
        files.push("rate_envelope.svg".to_string());
    }
    for (i, m) in summary.metrics.iter().enumerate() {
        let values: Vec<f64> = results
            .iter()
            .filter_map(|r| r.values.get(i).copied())
            .collect();
        let name = format!("hist_{}.svg", m.metric.key);
        histogram(
            &dir.join(&name),
            &format!("{} ({} runs)", m.metric.text, campaign.runs),
            &values,
            m.metric.limit.map(|l| l.1),
        )?;
        files.push(name);
    }
    Ok(files)
}

/// Median, 95th percentile and maximum over the runs at each grid point, log scale.
fn envelope(
    path: &Path,
    title: &str,
    y_label: &str,
    runs: &[&[f32]],
    duration_min: f64,
) -> Result<(), String> {
    let mut curves: [Vec<(f64, f64)>; 3] = [vec![], vec![], vec![]];
    for g in 0..GRID {
        let mut v: Vec<f64> = runs
            .iter()
            .filter_map(|r| r.get(g))
            .map(|x| f64::from(*x))
            .filter(|x| !x.is_nan())
            .collect();
        v.sort_by(f64::total_cmp);
        let t = (g as f64 + 1.0) / GRID as f64 * duration_min;
        for (c, q) in curves.iter_mut().zip([50.0, 95.0, 100.0]) {
            if let Some(x) = percentile(&v, q) {
                c.push((t, x.max(1e-6)));
            }
        }
    }
    let hi = curves
        .iter()
        .flatten()
        .map(|p| p.1)
        .filter(|x| x.is_finite())
        .fold(1e-5, f64::max);
    let lo = curves
        .iter()
        .flatten()
        .map(|p| p.1)
        .fold(hi, f64::min)
        .max(1e-6);
    let root = SVGBackend::new(path, (900, 420)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let mut c = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..duration_min, (lo * 0.9..hi * 1.1).log_scale())
        .map_err(|e| e.to_string())?;
    c.configure_mesh()
        .x_desc("time [min]")
        .y_desc(y_label)
        .draw()
        .map_err(|e| e.to_string())?;
    for (curve, (name, color)) in curves.iter().zip([
        ("median", BLUE),
        ("95th percentile", GREEN),
        ("maximum", RED),
    ]) {
        c.draw_series(LineSeries::new(curve.iter().copied(), color))
            .map_err(|e| e.to_string())?
            .label(name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], color));
    }
    c.configure_series_labels()
        .border_style(BLACK)
        .draw()
        .map_err(|e| e.to_string())?;
    root.present().map_err(|e| e.to_string())
}

/// A histogram of the finite `values` in 40 bins, with the `limit` drawn in red; the count of
/// values that are not finite ("never") is in the caption.
fn histogram(path: &Path, title: &str, values: &[f64], limit: Option<f64>) -> Result<(), String> {
    let finite: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    let never = values.len() - finite.len();
    let (mut lo, mut hi) = finite
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(*x), b.max(*x))
        });
    if let Some(l) = limit.filter(|l| l.is_finite()) {
        lo = lo.min(l);
        hi = hi.max(l);
    }
    if !lo.is_finite() || !hi.is_finite() {
        (lo, hi) = (0.0, 1.0);
    }
    if hi - lo < 1e-12 * hi.abs().max(1.0) {
        (lo, hi) = (lo - 0.5 * lo.abs().max(1.0), hi + 0.5 * hi.abs().max(1.0));
    }
    const BINS: usize = 40;
    let width = (hi - lo) / BINS as f64;
    let mut counts = [0usize; BINS];
    for x in &finite {
        let b = (((x - lo) / width) as usize).min(BINS - 1);
        counts[b] += 1;
    }
    let top = counts.iter().copied().max().unwrap_or(0).max(1);
    let title = if never > 0 {
        format!("{title}; {never} never / not finite")
    } else {
        title.to_string()
    };
    let root = SVGBackend::new(path, (900, 420)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let mut c = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(60)
        .build_cartesian_2d(lo..hi, 0usize..top + top / 10 + 1)
        .map_err(|e| e.to_string())?;
    c.configure_mesh()
        .y_desc("runs")
        .draw()
        .map_err(|e| e.to_string())?;
    c.draw_series(counts.iter().enumerate().map(|(i, n)| {
        let x0 = lo + i as f64 * width;
        Rectangle::new([(x0, 0), (x0 + width, *n)], BLUE.mix(0.6).filled())
    }))
    .map_err(|e| e.to_string())?;
    if let Some(l) = limit.filter(|l| l.is_finite()) {
        c.draw_series(LineSeries::new(vec![(l, 0), (l, top + top / 10 + 1)], RED))
            .map_err(|e| e.to_string())?
            .label("requirement")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], RED));
        c.configure_series_labels()
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
    }
    root.present().map_err(|e| e.to_string())
}
