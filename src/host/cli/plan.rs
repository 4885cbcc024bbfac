//! `acs plan FILE --out DIR`: plans a rest-to-rest manoeuvre with seed 001's inverse-dynamics
//! planner ([`crate::host::planner`]) from a JSON description, writes `profile.csv`,
//! `errors.txt` and `plan.svg`, and prints the predicted final errors.
//!
//! Description (every field optional; defaults are seed 001's test case, note 001 §4):
//! ```json
//! {"duration_s": 1500, "knots": 4, "euler_zyx_start_deg": [30, 35, 40],
//!  "euler_zyx_end_deg": [0, 0, 0], "inertia_kgm2": [0.7, 0.7, 0.7], "m_max_am2": 10,
//!  "wheels": {"inertia_kgm2": 8e-4, "max_rpm": 5000, "max_torque_nm": 0.01},
//!  "a_km": 6828.1, "omega0_radps": 1.119e-3, "inc_deg": 51, "greenwich0_deg": 0,
//!  "weights": [1e5, 1e8, 0], "evals": 1500, "restarts": 2, "steps": 1500,
//!  "optimiser": "nelder-mead", "field": "igrf", "start_utc": "2025-01-01T00:00:00Z",
//!  "variable_grid": false}
//! ```
//! `variable_grid`: the interior knot times are optimised too (seed 001 Table 6.5,
//! [`crate::host::planner::Problem::variable_grid`]); `errors.txt` gives the knot times.
//! `field`: `igrf` (default: IGRF-14 degree 13 at the epoch `start_utc` + t, the orbit frame
//! taken as TEME, `greenwich0_deg` unused) or `dipole` (seed 001's rotating tilted dipole, the
//! thesis reproduction; `start_utc` unused).
//! `optimiser`: `nelder-mead` or `pattern-search` (pattern search, then `restarts` Nelder–Mead
//! runs).
//! Euler angles are (ψ, θ, φ) of the 3-2-1 sequence ([`crate::attitude::Euler321`]).

use std::fmt::Write as _;
use std::path::PathBuf;

use plotters::prelude::*;
use serde::Deserialize;

use super::CliError;
use crate::attitude::{Dcm, Euler321, Quaternion};
use crate::host::planner::{plan_with, simulate, Field, Optimiser, Problem, Wheels};

/// Arguments of `acs plan`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// JSON description of the manoeuvre.
    file: PathBuf,
    /// Output folder (default `acs-plan`).
    #[arg(long)]
    out: Option<PathBuf>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct WheelSpec {
    inertia_kgm2: f64,
    max_rpm: f64,
    max_torque_nm: f64,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields, default)]
struct Description {
    duration_s: f64,
    knots: usize,
    euler_zyx_start_deg: [f64; 3],
    euler_zyx_end_deg: [f64; 3],
    inertia_kgm2: [f64; 3],
    m_max_am2: f64,
    wheels: Option<WheelSpec>,
    a_km: f64,
    omega0_radps: Option<f64>,
    inc_deg: f64,
    greenwich0_deg: f64,
    weights: [f64; 3],
    evals: usize,
    restarts: usize,
    steps: usize,
    optimiser: String,
    field: String,
    start_utc: String,
    variable_grid: bool,
}

impl Default for Description {
    fn default() -> Self {
        Self {
            duration_s: 1500.0,
            knots: 4,
            euler_zyx_start_deg: [30.0, 35.0, 40.0],
            euler_zyx_end_deg: [0.0; 3],
            inertia_kgm2: [0.7; 3],
            m_max_am2: 10.0,
            wheels: None,
            a_km: 6828.1,
            omega0_radps: Some(1.1190e-3),
            inc_deg: 51.0,
            greenwich0_deg: 0.0,
            weights: [1e5, 1e8, 0.0],
            evals: 1500,
            restarts: 2,
            steps: 1500,
            optimiser: "nelder-mead".into(),
            field: "igrf".into(),
            start_utc: "2025-01-01T00:00:00Z".into(),
            variable_grid: false,
        }
    }
}

fn quat(e: [f64; 3]) -> Quaternion {
    Dcm::from_euler_321(&Euler321 {
        psi_rad: e[0].to_radians() as f32,
        theta_rad: e[1].to_radians() as f32,
        phi_rad: e[2].to_radians() as f32,
    })
    .to_quaternion()
    .canonical()
}

/// A checked manoeuvre description: what [`plan_with`] is run on.
#[derive(Debug)]
pub struct Request {
    /// The planning problem.
    pub problem: Problem,
    /// The optimiser.
    pub optimiser: Optimiser,
    /// Function evaluations per optimiser run.
    pub evals: usize,
    /// Nelder–Mead restarts.
    pub restarts: usize,
}

/// Parses and checks a manoeuvre description (the JSON of the [module docs](self)), including
/// that the field is defined over the whole manoeuvre; the error is what `acs plan` reports
/// (a JSON error names `source`, the file). Public for the fuzz target `cli_plan` (`fuzz/`).
pub fn request(text: &str, source: &str) -> Result<Request, CliError> {
    let d: Description = serde_json::from_str(text).map_err(|e| {
        CliError::Input(format!(
            "{source}: line {} column {}: {e}",
            e.line(),
            e.column()
        ))
    })?;
    let scalars = [
        d.duration_s,
        d.m_max_am2,
        d.a_km,
        d.inc_deg,
        d.greenwich0_deg,
    ];
    let all = d
        .euler_zyx_start_deg
        .iter()
        .chain(&d.euler_zyx_end_deg)
        .chain(&d.inertia_kgm2)
        .chain(&d.weights)
        .chain(&scalars);
    let bad = all.clone().any(|x| !x.is_finite())
        || d.duration_s <= 0.0
        || d.m_max_am2 <= 0.0
        || d.inertia_kgm2.iter().any(|i| *i <= 0.0)
        || d.a_km < 6378.0
        || !(3..=crate::host::planner::MAX_KNOTS).contains(&d.knots)
        || d.steps == 0
        || d.steps > 1_000_000;
    if bad {
        return Err(CliError::Input(
            "duration_s, m_max_am2, inertia must be positive, a_km above the Earth, knots 3..=16, \
             steps 1..=1e6, all finite"
                .into(),
        ));
    }
    let wheels = match &d.wheels {
        None => None,
        Some(w) if w.inertia_kgm2 > 0.0 && w.max_rpm > 0.0 && w.max_torque_nm > 0.0 => {
            Some(Wheels {
                inertia_kgm2: w.inertia_kgm2,
                max_speed_radps: w.max_rpm * std::f64::consts::PI / 30.0,
                max_torque_nm: w.max_torque_nm,
            })
        }
        Some(_) => {
            return Err(CliError::Input(
                "wheels: every limit must be positive".into(),
            ))
        }
    };
    let field = match d.field.as_str() {
        "igrf" => Field::Igrf {
            start: super::sun::parse_utc_iso(&d.start_utc)
                .map_err(|e| CliError::Input(format!("start_utc: {e}")))?,
        },
        "dipole" => Field::Dipole,
        f => return Err(CliError::Input(format!("field `{f}`: use igrf or dipole"))),
    };
    let pb = Problem {
        inertia_kgm2: d.inertia_kgm2,
        m_max_am2: d.m_max_am2,
        wheels,
        a_km: d.a_km,
        omega0_radps: d.omega0_radps,
        inc_rad: d.inc_deg.to_radians(),
        greenwich0_rad: d.greenwich0_deg.to_radians(),
        q_start: quat(d.euler_zyx_start_deg),
        q_end: quat(d.euler_zyx_end_deg),
        duration_s: d.duration_s,
        knots: d.knots,
        dt_s: d.duration_s / d.steps as f64,
        weights: d.weights,
        field,
        variable_grid: d.variable_grid,
    };
    // The field must be defined over the whole manoeuvre (IGRF: date range, altitude).
    for t in [0.0, d.duration_s] {
        pb.field_nt(t)
            .map_err(|e| CliError::Input(format!("field at t = {t} s: {e}")))?;
    }
    let optimiser = match d.optimiser.as_str() {
        "nelder-mead" => Optimiser::NelderMead,
        "pattern-search" => Optimiser::PatternSearch,
        o => {
            return Err(CliError::Input(format!(
                "optimiser `{o}`: use nelder-mead or pattern-search"
            )))
        }
    };
    Ok(Request {
        problem: pb,
        optimiser,
        evals: d.evals,
        restarts: d.restarts,
    })
}

/// Runs `acs plan`.
pub fn run(args: &Args) -> Result<(), CliError> {
    let text = std::fs::read_to_string(&args.file)
        .map_err(|e| CliError::Input(format!("{}: {e}", args.file.display())))?;
    let Request {
        problem: pb,
        optimiser,
        evals,
        restarts,
    } = request(&text, &args.file.display().to_string())?;
    let (p, outcome) = plan_with(&pb, optimiser, evals, restarts).map_err(CliError::Compute)?;
    let (_, samples) = simulate(&pb, &p, 1).map_err(CliError::Compute)?;
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("acs-plan"));
    std::fs::create_dir_all(&dir).map_err(|e| CliError::Compute(e.to_string()))?;
    let mut csv = String::from(
        "t_s,q0_plan,q1_plan,q2_plan,q3_plan,q0_sim,q1_sim,q2_sim,q3_sim,wx_plan_radps,wy_plan_radps,wz_plan_radps,wx_sim_radps,wy_sim_radps,wz_sim_radps,mx_am2,my_am2,mz_am2,hdot_x_nm,hdot_y_nm,hdot_z_nm,hx_nms,hy_nms,hz_nms\n",
    );
    for s in &samples {
        let c = &s.cmd;
        let q = c.q_plan;
        let _ = writeln!(
            csv,
            "{:.3},{},{},{},{},{:.12},{:.12},{:.12},{:.12},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
            s.t_s, q.q0, q.q1, q.q2, q.q3, s.q[0], s.q[1], s.q[2], s.q[3],
            c.omega_plan[0], c.omega_plan[1], c.omega_plan[2], s.omega[0], s.omega[1], s.omega[2],
            c.dipole_am2[0], c.dipole_am2[1], c.dipole_am2[2],
            c.wheel_torque_nm[0], c.wheel_torque_nm[1], c.wheel_torque_nm[2],
            s.h_rw[0], s.h_rw[1], s.h_rw[2]
        );
    }
    let n_qv = 3 * pb.knots.saturating_sub(2);
    let (qv, grid) = p.split_at(n_qv.min(p.len()));
    let knots: Vec<String> = qv
        .chunks(3)
        .map(|c| format!("({:.8}, {:.8}, {:.8})", c[0], c[1], c[2]))
        .collect();
    let times: Vec<String> = pb
        .knot_times(grid)
        .iter()
        .map(|t| format!("{t:.3}"))
        .collect();
    let report = format!(
        "final_attitude_error_deg: {:.6e}\nfinal_rate_error_degps: {:.6e}\ncost: {:.6e}\nlost_torque_integral_n2m2s: {:.6e}\nmax_dipole_am2: {:.6}\nmax_wheel_speed_rpm: {:.3}\ninterior_knots_qv: {}\nknot_times_s: {}\n",
        outcome.attitude_error_deg,
        outcome.rate_error_degps,
        outcome.cost,
        outcome.lost_integral,
        outcome.max_dipole_am2,
        outcome.max_wheel_speed_radps * 30.0 / std::f64::consts::PI,
        knots.join(" "),
        times.join(" ")
    );
    std::fs::write(dir.join("profile.csv"), csv).map_err(|e| CliError::Compute(e.to_string()))?;
    std::fs::write(dir.join("errors.txt"), &report)
        .map_err(|e| CliError::Compute(e.to_string()))?;
    svg(&dir.join("plan.svg"), &samples).map_err(CliError::Compute)?;
    print!("{report}");
    Ok(())
}

fn svg(path: &std::path::Path, samples: &[crate::host::planner::Sample]) -> Result<(), String> {
    let root = SVGBackend::new(path, (900, 700)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (top, bottom) = root.split_vertically(350);
    let t_max = samples.last().map_or(1.0, |s| s.t_s.max(1e-9));
    let colors = [RED, GREEN, BLUE, BLACK];
    let mut c = ChartBuilder::on(&top)
        .caption(
            "attitude: planned (solid) and simulated (dots)",
            ("sans-serif", 16),
        )
        .margin(10)
        .x_label_area_size(30)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..t_max, -1.05..1.05)
        .map_err(|e| e.to_string())?;
    c.configure_mesh()
        .x_desc("time [s]")
        .y_desc("q")
        .draw()
        .map_err(|e| e.to_string())?;
    for (i, color) in colors.iter().enumerate() {
        let plan = samples.iter().map(|s| {
            let q = s.cmd.q_plan;
            (s.t_s, [q.q0, q.q1, q.q2, q.q3][i] as f64)
        });
        c.draw_series(LineSeries::new(plan, color))
            .map_err(|e| e.to_string())?
            .label(format!("q{i}"))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], color));
        let step = (samples.len() / 60).max(1);
        c.draw_series(
            samples
                .iter()
                .step_by(step)
                .map(|s| Circle::new((s.t_s, s.q[i]), 2, color.filled())),
        )
        .map_err(|e| e.to_string())?;
    }
    c.configure_series_labels()
        .border_style(BLACK)
        .draw()
        .map_err(|e| e.to_string())?;
    let m_max = samples
        .iter()
        .flat_map(|s| s.cmd.dipole_am2)
        .fold(1e-9f64, |a, m| a.max(m.abs()));
    let mut c = ChartBuilder::on(&bottom)
        .caption("dipole command [A·m²]", ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(30)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..t_max, -1.05 * m_max..1.05 * m_max)
        .map_err(|e| e.to_string())?;
    c.configure_mesh()
        .x_desc("time [s]")
        .y_desc("m")
        .draw()
        .map_err(|e| e.to_string())?;
    for (i, color) in colors.iter().take(3).enumerate() {
        c.draw_series(LineSeries::new(
            samples.iter().map(|s| (s.t_s, s.cmd.dipole_am2[i])),
            color,
        ))
        .map_err(|e| e.to_string())?
        .label(["m_x", "m_y", "m_z"][i])
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], color));
    }
    c.configure_series_labels()
        .border_style(BLACK)
        .draw()
        .map_err(|e| e.to_string())?;
    root.present().map_err(|e| e.to_string())
}
