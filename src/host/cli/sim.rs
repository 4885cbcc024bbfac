//! `acs sim`: closed-loop simulation scenarios with CSV and SVG output.

use std::path::PathBuf;

use super::CliError;
use crate::host::sim::campaign::{self, Campaign, Progress, Summary};
use crate::host::sim::realistic::TruthLevel;
use crate::host::sim::{pil, plan_flight, plot, rehearsal, scenario_file, scenarios, Sample};

/// `--truth`: what the simulator's truth is ([`crate::host::sim::realistic`]).
#[derive(clap::ValueEnum, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Truth {
    /// The simulator before issue #18 (the field is IGRF itself, the scenario's Gaussian sensor
    /// noise, ideal actuators); for the thesis scenarios, the thesis's own noise model.
    Ideal,
    /// Independent field truth, the spacecraft's own fields, albedo, sensors and actuators as
    /// real hardware behaves (`docs/simulator.md`).
    #[default]
    Realistic,
}

impl From<Truth> for TruthLevel {
    fn from(t: Truth) -> Self {
        match t {
            Truth::Ideal => Self::Ideal,
            Truth::Realistic => Self::Realistic,
        }
    }
}

/// Arguments of `acs sim`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Built-in scenario: detumble, thesis-slew, thesis-slew-noisy, sun-safe, tracking,
    /// failed-tile, slew, tracking-eclipse; or a scenario file (JSON, [`scenario_file`]); or plan-flight / plan-flight-wheels (a ground plan flown open loop,
    /// [`plan_flight`]: seed 001's manoeuvre with magnetorquers alone, or with three wheels).
    scenario: String,
    /// Output folder for CSV and SVG files (default: `acs-sim-<scenario>`, with `--pil`
    /// `acs-sim-<scenario>-pil`).
    #[arg(long)]
    out: Option<PathBuf>,
    /// The simulator's truth: `realistic` (default) or `ideal` (the simulator before issue
    /// #18; the thesis scenarios' own noise model).
    #[arg(long, value_enum, default_value_t = Truth::Realistic)]
    truth: Truth,
    /// Processor in the loop: fly the MSP430 flight image in mspdebug's simulator, in lockstep
    /// with the host loop, and stop at the first actuator command that differs ([`pil`]).
    #[arg(long)]
    pil: bool,
    /// With `--pil`: the reference node's flight image.
    #[arg(
        long,
        default_value = "firmware/target/msp430-none-elf/release/acs-reference"
    )]
    elf_reference: PathBuf,
    /// With `--pil`: the attitude node's flight image.
    #[arg(
        long,
        default_value = "firmware/target/msp430-none-elf/attitude/acs-attitude"
    )]
    elf_attitude: PathBuf,
    /// With `--pil`: leave out the link-fault case after the scenario.
    #[arg(long)]
    no_link_faults: bool,
    /// With `--pil`: where to write the run's summary.
    #[arg(long, default_value = "target/msp430/pil.json")]
    pil_json: PathBuf,
    /// A rehearsal: fly the telecommand script SCRIPT (lines `SECONDS PACKET_HEX`) with the
    /// scenario, on the host composition of the two nodes (or with `--pil` the node images)
    /// ([`crate::host::sim::rehearsal`]).
    #[arg(long, value_name = "SCRIPT")]
    tc: Option<PathBuf>,
    /// A rehearsal: write every verification report of the run, back to back as bytes, to
    /// FILE (`acs tm FILE` reads it).
    #[arg(long, value_name = "FILE")]
    tm: Option<PathBuf>,
    /// Monte Carlo campaign: N dispersed runs of the scenario ([`campaign`]).
    #[arg(long)]
    runs: Option<usize>,
    /// The campaign's seed S: run k follows from (S, k) alone.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Threads of a campaign (default: every core); the results do not depend on it.
    #[arg(long)]
    jobs: Option<usize>,
    /// Replays run K of the campaign seeded S, with its full time series (the files of a
    /// single `acs sim`).
    #[arg(long)]
    run: Option<usize>,
    /// Runs only runs A to B−1 of the campaign (a slice for a batch scheduler's job array;
    /// `acs sim merge` combines slices).
    #[arg(long, value_name = "A..B")]
    range: Option<String>,
    /// `acs sim merge DIR... --out DIR`: the slices to combine.
    #[arg(hide = true)]
    dirs: Vec<PathBuf>,
}

/// The built-in scenario `name`.
fn scenario(name: &str, truth: Truth) -> Result<scenarios::Scenario, CliError> {
    match scenarios::by_name_with(name, truth.into()) {
        Some(s) => s.map_err(|e| CliError::Compute(e.to_string())),
        None if std::path::Path::new(name).is_file() => {
            let text = std::fs::read_to_string(name)
                .map_err(|e| CliError::Input(format!("{name}: {e}")))?;
            scenario_file::parse(&text)
                .map(|s| s.with_truth(truth.into()))
                .map_err(|e| CliError::Input(format!("{name}: {e}")))
        }
        None => Err(CliError::Input(format!(
            "scenario `{name}`: not a built-in scenario ({}) nor a scenario file",
            scenarios::NAMES.join(", ")
        ))),
    }
}

/// Runs `acs sim`.
pub fn run(args: &Args) -> Result<(), CliError> {
    if args.scenario == "merge" {
        return merge_run(args);
    }
    if !args.dirs.is_empty() {
        return Err(CliError::Input(format!(
            "unexpected argument `{}`",
            args.dirs[0].display()
        )));
    }
    let rehearsing = args.tc.is_some() || args.tm.is_some();
    if args.runs.is_some() || args.run.is_some() || args.range.is_some() {
        if rehearsing {
            return Err(CliError::Input(
                "--tc and --tm rehearse one run: not with --runs, --run or --range".into(),
            ));
        }
        return campaign_run(args);
    }
    if args.scenario == "plan-flight" || args.scenario == "plan-flight-wheels" {
        if rehearsing {
            return Err(CliError::Input(format!(
                "--tc and --tm: `{}` is flown open loop, without telecommands",
                args.scenario
            )));
        }
        return plan_flight_run(&args.scenario, args.out.clone());
    }
    let scenario = scenario(&args.scenario, args.truth)?;
    let script = match &args.tc {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .map_err(|e| CliError::Input(format!("{}: {e}", path.display())))?;
            Some(
                rehearsal::parse_script(&text)
                    .map_err(|e| CliError::Input(format!("{}: {e}", path.display())))?,
            )
        }
        None => rehearsing.then(Vec::new),
    };
    if args.pil {
        return pil_run(args, &scenario, script);
    }
    if let Some(script) = script {
        return rehearsal_run(args, &scenario, &script);
    }
    let samples = scenario
        .run()
        .map_err(|e| CliError::Compute(e.to_string()))?;
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("acs-sim-{}", scenario.name)));
    let files = plot::write_all(&dir, &samples).map_err(CliError::Compute)?;
    print_summary(&scenario, &samples, &files, &dir)
}

/// `acs sim SCENARIO --pil`: the run of [`pil::run`], its files, `pil.json` and summary; a
/// difference between image and host is a failure (exit 3) naming the step, the mode and both
/// values.
fn pil_run(
    args: &Args,
    scenario: &scenarios::Scenario,
    script: Option<Vec<rehearsal::ScriptPacket>>,
) -> Result<(), CliError> {
    let script_path = args.tc.as_ref().map(|p| p.display().to_string());
    let options = pil::PilOptions {
        elf_reference: args.elf_reference.clone(),
        elf_attitude: args.elf_attitude.clone(),
        link_faults: !args.no_link_faults,
        script,
        ..pil::PilOptions::default()
    };
    let steps = (scenario.duration_s / scenario.dt_s).round() as usize
        + if options.link_faults {
            pil::LINK_FAULT_STEPS + pil::RECOVERY_STEPS
        } else {
            0
        };
    let started = std::time::Instant::now();
    let run = pil::run(scenario, &options, |k| {
        if k % 60 == 0 || k == steps {
            let rate = k as f64 / started.elapsed().as_secs_f64().max(1e-9);
            eprintln!("pil: step {k}/{steps} ({rate:.1} steps/s)");
        }
    })
    .map_err(|e| match e {
        // a script's line is named with the script
        pil::PilError::Input(m) if m.starts_with("line ") => match &script_path {
            Some(p) => CliError::Input(format!("{p}: {m}")),
            None => CliError::Input(m),
        },
        pil::PilError::Input(m) => CliError::Input(m),
        e => CliError::Compute(e.to_string()),
    })?;
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("acs-sim-{}-pil", scenario.name)));
    let mut files = plot::write_all(&dir, &run.samples).map_err(CliError::Compute)?;
    std::fs::write(dir.join("pil-steps.csv"), pil::steps_csv(&run.steps))
        .map_err(|e| CliError::Compute(format!("{}: {e}", dir.display())))?;
    files.push("pil-steps.csv".into());
    pil::write_summary(&args.pil_json, &run.summary).map_err(CliError::Compute)?;
    print_summary(scenario, &run.samples, &files, &dir)?;
    let s = &run.summary;
    println!("pil_steps: {}", s.steps);
    println!("pil_link_fault_steps: {}", s.link_fault_steps);
    let lf = &s.link_fault;
    println!(
        "pil_link_fault: {} packets dropped, {} corrupted, {} steps without a usable REF, \
         reference clock back {} periods after its reset",
        lf.dropped,
        lf.corrupted,
        lf.steps_without_reference,
        lf.clock_back_after_steps
            .map_or_else(|| "never".to_string(), |n| n.to_string())
    );
    println!("pil_mismatches: {}", s.mismatches);
    for n in &s.nodes {
        let node = n.node.name();
        println!(
            "pil_{node}_cycles: max {}, mean {}",
            n.cycles_max, n.cycles_mean
        );
        for (mode, steps, max, mean) in &n.cycles_by_mode {
            println!(
                "pil_{node}_cycles_{}: steps {steps}, max {max}, mean {mean}",
                mode.to_lowercase()
            );
        }
        if let Some(b) = n.stack_bytes {
            println!("pil_{node}_stack_bytes: {b}");
        }
        println!("pil_{node}_flash_bytes: {}", n.flash_bytes);
        if let Some(c) = n.watchdog_recovery_cycles {
            println!("pil_{node}_watchdog_recovery_cycles: {c}");
        }
    }
    println!("pil_steps_per_s: {:.1}", run.steps_per_s);
    println!("pil_json: {}", args.pil_json.display());
    if let Some(path) = &args.tm {
        write_telemetry(path, &run.telemetry)?;
    }
    match run.mismatch {
        None => Ok(()),
        Some(m) => Err(CliError::Compute(format!(
            "the flight image and the host loop differ at {m}"
        ))),
    }
}

/// `acs sim SCENARIO --tc SCRIPT --tm FILE` without `--pil`: the rehearsal flown on the host
/// composition of the two nodes ([`rehearsal::fly`]), its files and summary, the number of
/// telecommands and reports, and FILE.
fn rehearsal_run(
    args: &Args,
    scenario: &scenarios::Scenario,
    script: &[rehearsal::ScriptPacket],
) -> Result<(), CliError> {
    let run = rehearsal::fly(scenario, script).map_err(|e| match e {
        rehearsal::RehearsalError::Input(m) => match (&args.tc, m.starts_with("line ")) {
            (Some(p), true) => CliError::Input(format!("{}: {m}", p.display())),
            _ => CliError::Input(m),
        },
        e => CliError::Compute(e.to_string()),
    })?;
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("acs-sim-{}", scenario.name)));
    let files = plot::write_all(&dir, &run.samples).map_err(CliError::Compute)?;
    print_summary(scenario, &run.samples, &files, &dir)?;
    let failures = run
        .sent
        .iter()
        .zip(&run.reports)
        .filter(|((_, tc), r)| {
            !r.is_empty() && pil::uplink::outcome(r, tc.node) != pil::uplink::ACCEPTED
        })
        .count();
    let telemetry = run.telemetry();
    println!("rehearsal_telecommands: {}", run.sent.len());
    println!("rehearsal_refused: {failures}");
    println!("rehearsal_tm_bytes: {}", telemetry.len());
    if let Some(path) = &args.tm {
        write_telemetry(path, &telemetry)?;
    }
    Ok(())
}

/// Writes the reports of a rehearsal to `path`, and its name.
fn write_telemetry(path: &std::path::Path, bytes: &[u8]) -> Result<(), CliError> {
    std::fs::write(path, bytes)
        .map_err(|e| CliError::Compute(format!("{}: {e}", path.display())))?;
    println!("tm: {}", path.display());
    Ok(())
}

/// Prints the summary metrics of a run (and the files written into `dir`).
fn print_summary(
    scenario: &scenarios::Scenario,
    samples: &[Sample],
    files: &[String],
    dir: &std::path::Path,
) -> Result<(), CliError> {
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
    println!("truth: {}", scenario.truth().name());
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

/// `A..B` of `--range`.
fn parse_range(text: &str, runs: usize) -> Result<std::ops::Range<usize>, CliError> {
    let bad = || {
        CliError::Input(format!(
            "--range `{text}`: expected A..B with A < B ≤ --runs ({runs})"
        ))
    };
    let (a, b) = text.split_once("..").ok_or_else(bad)?;
    let (a, b): (usize, usize) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    if a >= b || b > runs {
        return Err(bad());
    }
    Ok(a..b)
}

/// `acs sim SCENARIO --runs N [--seed S] [--jobs J] [--run K] [--range A..B] --out DIR`.
fn campaign_run(args: &Args) -> Result<(), CliError> {
    if args.pil {
        return Err(CliError::Input(
            "--pil flies one run: not with --runs, --run or --range".into(),
        ));
    }
    let out = args
        .out
        .clone()
        .ok_or_else(|| CliError::Input("a campaign needs --out DIR".into()))?;
    let campaign = Campaign {
        scenario: args.scenario.clone(),
        truth: args.truth.into(),
        seed: args.seed,
        runs: args.runs.unwrap_or(usize::MAX),
    };
    if args.jobs == Some(0) {
        return Err(CliError::Input("--jobs: at least one".into()));
    }
    if let Some(k) = args.run {
        if args.range.is_some() {
            return Err(CliError::Input(
                "--run replays one run: not with --range".into(),
            ));
        }
        if args.runs.is_some_and(|n| k >= n) {
            return Err(CliError::Input(format!(
                "--run {k}: the campaign has runs 0..{}",
                campaign.runs
            )));
        }
        campaign.validate().map_err(CliError::Input)?;
        let (scenario, drawn) = campaign
            .scenario_of_run(k)
            .map_err(|e| CliError::Compute(e.to_string()))?;
        let samples = scenario
            .run()
            .map_err(|e| CliError::Compute(e.to_string()))?;
        let files = plot::write_all(&out, &samples).map_err(CliError::Compute)?;
        print_summary(&scenario, &samples, &files, &out)?;
        println!(
            "campaign_run: {k} (seed {}, run seed {})",
            campaign.seed,
            campaign::run_seed(campaign.seed, k)
        );
        let metrics = campaign.metrics();
        let values = campaign::requirements::evaluate(&metrics, &samples, scenario.dt_s);
        for (m, v) in metrics.iter().zip(values.iter()) {
            let verdict = match m.limit {
                None => String::new(),
                Some(_) if m.met(*v) => format!(" (met: {})", m.limit_text()),
                Some(_) => format!(" (NOT met: {})", m.limit_text()),
            };
            println!("{}: {v}{verdict}", m.key);
        }
        for (d, v) in campaign::dispersion::DRAWN.iter().zip(drawn.iter()) {
            println!("dispersed_{d}: {v}");
        }
        return Ok(());
    }
    if args.runs.is_none() {
        return Err(CliError::Input(
            "--range: a slice of a campaign of --runs N".into(),
        ));
    }
    campaign.validate().map_err(CliError::Input)?;
    let range = match &args.range {
        Some(r) => parse_range(r, campaign.runs)?,
        None => 0..campaign.runs,
    };
    let total = range.len();
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(total as u64),
        indicatif::ProgressDrawTarget::stderr(),
    );
    if let Ok(style) = indicatif::ProgressStyle::with_template(
        "{prefix} [{bar:30}] {pos}/{len} runs, {msg}, {per_sec}, ETA {eta}",
    ) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_prefix(format!("campaign {}", campaign.scenario));
    bar.set_message("0 failed");
    let progress = Progress::default();
    let started = std::time::Instant::now();
    let results = campaign
        .run_range(range.clone(), args.jobs, &|met| {
            let (_, failed) = progress.count(met);
            if !met {
                bar.set_message(format!("{failed} failed"));
            }
            bar.inc(1);
        })
        .map_err(CliError::Compute)?;
    bar.finish_and_clear();
    let seconds = started.elapsed().as_secs_f64();
    let jobs = args.jobs.unwrap_or_else(rayon::current_num_threads);
    eprintln!(
        "campaign {}: {total} runs in {seconds:.1} s on {jobs} jobs ({:.1} runs/s)",
        campaign.scenario,
        total as f64 / seconds.max(1e-9)
    );
    if range.len() == campaign.runs {
        campaign::write_campaign(&out, &campaign, &results).map_err(CliError::Compute)?;
        print!("{}", Summary::of(&campaign, &results).markdown());
    } else {
        campaign::write_slice(&out, &campaign, &range, &results).map_err(CliError::Compute)?;
        let failed = results.iter().filter(|r| !campaign.met(r)).count();
        println!(
            "slice {}..{} of campaign {} (seed {}, {} runs): {} runs, {failed} missed a requirement; files: campaign.json, runs.csv, series.csv in {}",
            range.start,
            range.end,
            campaign.scenario,
            campaign.seed,
            campaign.runs,
            total,
            out.display()
        );
    }
    Ok(())
}

/// `acs sim merge DIR... --out DIR`.
fn merge_run(args: &Args) -> Result<(), CliError> {
    let out = args
        .out
        .clone()
        .ok_or_else(|| CliError::Input("merge needs --out DIR".into()))?;
    if args.dirs.is_empty() {
        return Err(CliError::Input("merge: no slice folder given".into()));
    }
    let (campaign, results) = campaign::merge(&args.dirs, &out).map_err(CliError::Input)?;
    print!("{}", Summary::of(&campaign, &results).markdown());
    Ok(())
}
