//! `acs attitude`: optimal attitude from vector pairs (JSON in, JSON out).

use super::CliError;

/// Arguments of `acs attitude`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Solver.
    #[arg(long, value_parser = ["svd", "quest", "triad"], default_value = "svd")]
    method: String,
}

/// Runs `acs attitude`.
pub fn run(_args: &Args) -> Result<(), CliError> {
    Err(CliError::NotImplemented("attitude"))
}
