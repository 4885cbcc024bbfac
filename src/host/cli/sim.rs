//! `acs sim`: closed-loop simulation scenarios with CSV and SVG output.

use std::path::PathBuf;

use super::CliError;
use crate::host::sim::{plan_flight, plot, scenarios};

/// Arguments of `acs sim`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Built-in scenario: detumble, thesis-slew, thesis-slew-noisy, sun-safe, tracking,
    /// failed-tile, slew; or plan-flight / plan-flight-wheels (a ground plan flown open loop,
    /// [`plan_flight`]: seed 001's manoeuvre with magnetorquers alone, or with three wheels).
    scenario: String,
    /// Output folder for CSV and SVG files (default: `acs-sim-<scenario>`).
    #[arg(long)]
    out: Option<PathBuf>,
}

/// Runs `acs sim`.
pub fn run(args: &Args) -> Result<(), CliError> {
    if args.scenario == "plan-flight" || args.scenario == "plan-flight-wheels" {
        return plan_flight_run(&args.scenario, args.out.clone());
    }
    let scenario = match scenarios::by_name(&args.scenario) {
        Some(s) => s.map_err(|e| CliError::Compute(e.to_string()))?,
        None => {
            return Err(CliError::Input(format!(
                "scenario `{}`: not a built-in scenario ({}); scenario files are not supported yet",
                args.scenario,
                scenarios::NAMES.join(", ")
            )))
        }
    };
    let samples = scenario
        .run()
        .map_err(|e| CliError::Compute(e.to_string()))?;
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("acs-sim-{}", scenario.name)));
    let files = plot::write_all(&dir, &samples).map_err(CliError::Compute)?;
    let last = samples
        .last()
        .ok_or_else(|| CliError::Compute("no samples".into()))?;
    let max_pointing_tail = samples
        .iter()
        .filter(|s| s.t_s >= 0.5 * last.t_s)
        .filter_map(|s| s.pointing_error_deg)
        .fold(None, |acc: Option<f64>, e| {
            Some(acc.map_or(e, |a| a.max(e)))
        });
    let below = samples
        .iter()
        .find(|s| s.omega_true.norm().to_degrees() < 0.5)
        .map(|s| s.t_s);
    let dark = samples.iter().filter(|s| s.sun_fraction < 0.5).count();
    println!("scenario: {} — {}", scenario.name, scenario.description);
    println!("duration_s: {:.1}", last.t_s + scenario.dt_s);
    println!("control_period_s: {}", scenario.dt_s);
    println!("final_mode: {:?}", last.mode);
    println!(
        "final_rate_degps: {:.9}",
        last.omega_true.norm().to_degrees()
    );
    println!(
        "first_below_0.5_degps_s: {}",
        below.map_or("never".into(), |t| format!("{t:.1}"))
    );
    if let Some(p) = last.pointing_error_deg {
        println!("final_pointing_error_deg: {p:.9}");
    }
    if let Some(p) = max_pointing_tail {
        println!("max_pointing_error_second_half_deg: {p:.9}");
    }
    println!("eclipse_steps: {dark}");
    println!(
        "nan_free: {}",
        samples
            .iter()
            .all(|s| s.omega_true.iter().all(|x| x.is_finite()))
    );
    println!("files: {} in {}", files.join(", "), dir.display());
    Ok(())
}

/// `acs sim plan-flight[-wheels]`: plans [`plan_flight::thesis_case`] (magnetorquers alone) or
/// [`plan_flight::thesis_case_wheels`] (150 s, with three wheels; seed 001 Table 6.6) in the
/// simulator's field and flies it open loop with commands every 0.02 s; prints and writes
/// (`DIR/errors.txt`) the planned and flown final errors.
fn plan_flight_run(name: &str, out: Option<PathBuf>) -> Result<(), CliError> {
    let wheels = name == "plan-flight-wheels";
    let (case, field_step_s) = if wheels {
        (plan_flight::thesis_case_wheels(150.0), 1.0)
    } else {
        (plan_flight::thesis_case(), 5.0)
    };
    let (config, pb) = case.map_err(CliError::Compute)?;
    let f = plan_flight::plan_and_fly(&config, &pb, field_step_s, 400, 1, 0.02)
        .map_err(CliError::Compute)?;
    let what = if wheels {
        "with three wheels"
    } else {
        "with magnetorquers alone"
    };
    let report = format!(
        "scenario: {name} — seed 001 manoeuvre {what}, planned in the simulator's field, flown open loop\nplanned_attitude_error_deg: {:.6e}\nplanned_rate_error_degps: {:.6e}\nflown_attitude_error_deg: {:.6e}\nflown_rate_error_degps: {:.6e}\n",
        f.planned.attitude_error_deg,
        f.planned.rate_error_degps,
        f.flown_attitude_error_deg,
        f.flown_rate_error_degps
    );
    let dir = out.unwrap_or_else(|| PathBuf::from(format!("acs-sim-{name}")));
    std::fs::create_dir_all(&dir).map_err(|e| CliError::Compute(e.to_string()))?;
    std::fs::write(dir.join("errors.txt"), &report)
        .map_err(|e| CliError::Compute(e.to_string()))?;
    print!("{report}");
    Ok(())
}
