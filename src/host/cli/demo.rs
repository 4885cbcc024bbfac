//! `acs demo`: the seed 000 chapter-12 scenario end to end on simulated tiles.

use super::CliError;

/// Arguments of `acs demo` (none yet).
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Runs `acs demo`.
pub fn run(_args: &Args) -> Result<(), CliError> {
    Err(CliError::NotImplemented("demo"))
}
