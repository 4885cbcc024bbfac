//! The `acs` command-line tool: the interface contract of `docs/cli.md`.
//!
//! Exit codes: 0 success, 2 invalid input (the message names the line, column or field),
//! 3 failure of the computation (decayed orbit, model out of range, degenerate geometry) or a
//! subcommand that is not built yet.
//!
//! Subcommands: `propagate`, `sun`, `eclipses`, `igrf`, `attitude`, `demo`, `sim`, `plan`, and
//! `elements` ([`elements`]: a TLE as the 58 checked uplink words of SGP4 initialised on the
//! ground, and the check of words read back, naming the first bad word), `tc` ([`tc`]: a ground
//! command as its PUS-C telecommand) and `tm` ([`tm`]: the nodes' telemetry as CSV).

use std::fmt;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub mod attitude;
mod demo;
mod eclipses;
pub mod elements;
pub mod igrf;
pub mod plan;
mod propagate;
mod sim;
pub mod sun;
pub mod tc;
pub mod tm;

/// What went wrong in a subcommand, and so which exit code the tool returns.
#[derive(Debug)]
pub enum CliError {
    /// Invalid input: exit code 2.
    Input(String),
    /// The computation itself failed: exit code 3.
    Compute(String),
    /// The subcommand is not built yet: exit code 3.
    NotImplemented(&'static str),
}

impl CliError {
    /// The process exit code of this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            Self::Input(_) => 2,
            Self::Compute(_) | Self::NotImplemented(_) => 3,
        }
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Input(m) => write!(f, "invalid input: {m}"),
            Self::Compute(m) => write!(f, "computation failed: {m}"),
            Self::NotImplemented(c) => write!(f, "`acs {c}` is not implemented yet"),
        }
    }
}

/// Attitude determination and control tools for the AraMiS satellite (host build).
#[derive(Parser, Debug)]
#[command(name = "acs", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Propagate a TLE with SGP4 and write an STK ephemeris file to stdout.
    Propagate(propagate::Args),
    /// Sun direction for UTC timestamps read from stdin (CSV on stdout).
    Sun(sun::Args),
    /// Eclipse report of a TLE over a time span: eclipses, sunlit fraction per orbit (CSV).
    Eclipses(eclipses::Args),
    /// IGRF-14 field for points read from stdin (CSV on stdout).
    Igrf(igrf::Args),
    /// Optimal attitude from vector pairs read as JSON from stdin.
    Attitude(attitude::Args),
    /// The seed 000 chapter-12 scenario end to end on simulated tiles.
    Demo(demo::Args),
    /// A closed-loop simulation scenario with CSV and SVG output.
    Sim(sim::Args),
    /// Plan a magnetorquer (+ wheel) slew from a JSON description (seed 001).
    Plan(plan::Args),
    /// SGP4 initialised on the ground: a TLE as the 58 checked uplink words (hex or JSON), or
    /// `--check` of words read back (exit 2 naming the first bad word).
    #[command(
        after_help = "Examples:\n  acs elements --tle dtusat.tle > dtusat.words\n  \
                      acs elements --check dtusat.words\n  \
                      acs elements --tle dtusat.tle --format json | acs elements --check -"
    )]
    Elements(elements::Args),
    /// A ground command as the PUS-C telecommand its node takes (TC[8,1]; hex or bytes).
    #[command(after_help = "Examples:\n  acs tc clock 2026-11-28T06:30:00Z\n  \
                      acs tc slew 0.7071068 0 0.7071068 0 600 --count 12\n  \
                      acs tc mark-failed tile 2 --format bin >> uplink.bin")]
    Tc(tc::Args),
    /// The nodes' telemetry packets (bytes or hex, back to back) as CSV.
    Tm(tm::Args),
}

pub use super::iso_utc_ms;

/// Parses the command line, runs the subcommand and maps its result to an exit code.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // --help and --version print and succeed; usage errors are invalid input.
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::from(2)
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    let result = match cli.command {
        Command::Propagate(a) => propagate::run(&a),
        Command::Sun(a) => sun::run(&a),
        Command::Eclipses(a) => eclipses::run(&a),
        Command::Igrf(a) => igrf::run(&a),
        Command::Attitude(a) => attitude::run(&a),
        Command::Demo(a) => demo::run(&a),
        Command::Sim(a) => sim::run(&a),
        Command::Plan(a) => plan::run(&a),
        Command::Elements(a) => elements::run(&a),
        Command::Tc(a) => tc::run(&a),
        Command::Tm(a) => tm::run(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("acs: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
