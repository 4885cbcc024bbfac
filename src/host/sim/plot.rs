//! CSV time series and SVG plots of a simulation run (plotters' SVG backend).

use std::fmt::Write as _;
use std::path::Path;

use plotters::prelude::*;

use super::Sample;

/// The CSV of a run: one row per control period.
pub fn csv(samples: &[Sample]) -> String {
    let mut out = String::from(
        "t_s,mode,wx_true_radps,wy_true_radps,wz_true_radps,rate_true_degps,pointing_error_deg,estimate_error_deg,hx_nms,hy_nms,hz_nms,mx_am2,my_am2,mz_am2,sun_fraction\n",
    );
    for s in samples {
        let opt = |v: Option<f64>| v.map_or(String::new(), |x| format!("{x:.9e}"));
        let _ = writeln!(
            out,
            "{:.3},{:?},{:.9e},{:.9e},{:.9e},{:.9e},{},{},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.6}",
            s.t_s,
            s.mode,
            s.omega_true.x,
            s.omega_true.y,
            s.omega_true.z,
            s.omega_true.norm().to_degrees(),
            opt(s.pointing_error_deg),
            opt(s.estimate_error_deg),
            s.h_wheels_body.x,
            s.h_wheels_body.y,
            s.h_wheels_body.z,
            s.dipole_am2.x,
            s.dipole_am2.y,
            s.dipole_am2.z,
            s.sun_fraction
        );
    }
    out
}

/// One series of a chart: its name, its (time s, value) points and its colour.
pub type Series<'a> = (&'a str, Vec<(f64, f64)>, RGBColor);

/// One SVG chart of several series against time (minutes), with the eclipse shaded grey.
fn chart(
    path: &Path,
    title: &str,
    y_label: &str,
    samples: &[Sample],
    series: &[Series],
    log_y: bool,
) -> Result<(), String> {
    let t_max = samples.last().map_or(1.0, |s| s.t_s / 60.0).max(1e-3);
    chart_spans(
        path,
        title,
        y_label,
        t_max,
        &eclipse_spans(samples),
        series,
        log_y,
    )
}

/// One SVG chart of several series against time (minutes, to `t_max` min), the spans
/// `shaded` (minutes) grey: [`write_all`]'s charts, and the housekeeping's of `acs tm`.
pub fn chart_spans(
    path: &Path,
    title: &str,
    y_label: &str,
    t_max: f64,
    shaded: &[(f64, f64)],
    series: &[Series],
    log_y: bool,
) -> Result<(), String> {
    let t_max = t_max.max(1e-3);
    let values = series.iter().flat_map(|s| s.1.iter().map(|p| p.1));
    let (mut lo, mut hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    });
    if !lo.is_finite() || !hi.is_finite() {
        lo = 0.0;
        hi = 1.0;
    }
    if log_y {
        lo = lo.max(1e-6);
        hi = hi.max(lo * 10.0);
    } else if hi - lo < 1e-12 {
        hi = lo + 1.0;
    }
    let root = SVGBackend::new(path, (900, 420)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let mut builder = ChartBuilder::on(&root);
    builder
        .caption(title, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(70);
    if log_y {
        let mut c = builder
            .build_cartesian_2d(0.0..t_max, (lo..hi).log_scale())
            .map_err(|e| e.to_string())?;
        c.configure_mesh()
            .x_desc("time [min]")
            .y_desc(y_label)
            .draw()
            .map_err(|e| e.to_string())?;
        shade(&mut c, shaded, lo, hi)?;
        for (name, pts, color) in series {
            let color = *color;
            c.draw_series(LineSeries::new(
                pts.iter().map(|(t, v)| (*t / 60.0, v.max(lo))),
                color,
            ))
            .map_err(|e| e.to_string())?
            .label(*name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], color));
        }
        c.configure_series_labels()
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
    } else {
        let pad = 0.05 * (hi - lo);
        let mut c = builder
            .build_cartesian_2d(0.0..t_max, (lo - pad)..(hi + pad))
            .map_err(|e| e.to_string())?;
        c.configure_mesh()
            .x_desc("time [min]")
            .y_desc(y_label)
            .draw()
            .map_err(|e| e.to_string())?;
        shade(&mut c, shaded, lo - pad, hi + pad)?;
        for (name, pts, color) in series {
            let color = *color;
            c.draw_series(LineSeries::new(
                pts.iter().map(|(t, v)| (*t / 60.0, *v)),
                color,
            ))
            .map_err(|e| e.to_string())?
            .label(*name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], color));
        }
        c.configure_series_labels()
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
    }
    root.present().map_err(|e| e.to_string())
}

/// The eclipses of a run (sunlit fraction under one half), minutes.
fn eclipse_spans(samples: &[Sample]) -> Vec<(f64, f64)> {
    let mut start: Option<f64> = None;
    let mut spans = Vec::new();
    for s in samples {
        let dark = s.sun_fraction < 0.5;
        match (dark, start) {
            (true, None) => start = Some(s.t_s / 60.0),
            (false, Some(t0)) => {
                spans.push((t0, s.t_s / 60.0));
                start = None;
            }
            _ => {}
        }
    }
    if let (Some(t0), Some(last)) = (start, samples.last()) {
        spans.push((t0, last.t_s / 60.0));
    }
    spans
}

fn shade<DB: DrawingBackend, Y: Ranged<ValueType = f64>>(
    c: &mut ChartContext<'_, DB, Cartesian2d<plotters::coord::types::RangedCoordf64, Y>>,
    spans: &[(f64, f64)],
    lo: f64,
    hi: f64,
) -> Result<(), String> {
    let grey = RGBColor(225, 225, 225).filled();
    c.draw_series(
        spans
            .iter()
            .map(|(a, b)| Rectangle::new([(*a, lo), (*b, hi)], grey)),
    )
    .map_err(|e| e.to_string())?;
    Ok(())
}

/// Writes `run.csv` and the SVG plots (body rates, pointing error, wheel momenta, dipoles) of a
/// run into `dir`.
pub fn write_all(dir: &Path, samples: &[Sample]) -> Result<Vec<String>, String> {
    std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
    std::fs::write(dir.join("run.csv"), csv(samples)).map_err(|e| e.to_string())?;
    let pick = |f: &dyn Fn(&Sample) -> Option<f64>| -> Vec<(f64, f64)> {
        samples
            .iter()
            .filter_map(|s| f(s).map(|v| (s.t_s, v)))
            .collect()
    };
    let mut written = vec!["run.csv".to_string()];
    chart(
        &dir.join("rates.svg"),
        "Body rates (truth)",
        "rate [deg/s]",
        samples,
        &[
            ("ωx", pick(&|s| Some(s.omega_true.x.to_degrees())), RED),
            ("ωy", pick(&|s| Some(s.omega_true.y.to_degrees())), GREEN),
            ("ωz", pick(&|s| Some(s.omega_true.z.to_degrees())), BLUE),
        ],
        false,
    )?;
    written.push("rates.svg".into());
    if samples
        .iter()
        .any(|s| s.pointing_error_deg.is_some() || s.estimate_error_deg.is_some())
    {
        chart(
            &dir.join("attitude_error.svg"),
            "Attitude errors",
            "error [deg]",
            samples,
            &[
                (
                    "pointing (truth vs target)",
                    pick(&|s| s.pointing_error_deg),
                    RED,
                ),
                (
                    "estimate (filter vs truth)",
                    pick(&|s| s.estimate_error_deg),
                    BLUE,
                ),
            ],
            true,
        )?;
        written.push("attitude_error.svg".into());
    }
    chart(
        &dir.join("wheels.svg"),
        "Wheel momentum (body)",
        "h [kg·m²/s]",
        samples,
        &[
            ("hx", pick(&|s| Some(s.h_wheels_body.x)), RED),
            ("hy", pick(&|s| Some(s.h_wheels_body.y)), GREEN),
            ("hz", pick(&|s| Some(s.h_wheels_body.z)), BLUE),
        ],
        false,
    )?;
    written.push("wheels.svg".into());
    chart(
        &dir.join("dipoles.svg"),
        "Commanded dipole (body)",
        "m [A·m²]",
        samples,
        &[
            ("mx", pick(&|s| Some(f64::from(s.dipole_am2.x))), RED),
            ("my", pick(&|s| Some(f64::from(s.dipole_am2.y))), GREEN),
            ("mz", pick(&|s| Some(f64::from(s.dipole_am2.z))), BLUE),
        ],
        false,
    )?;
    written.push("dipoles.svg".into());
    Ok(written)
}
