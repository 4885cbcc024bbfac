//! `acs igrf`: IGRF-14 field at points read from stdin.

use super::CliError;

/// Arguments of `acs igrf`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Input is `decimal_year,r_km,colat_deg,lon_deg` and output `br_nt,btheta_nt,bphi_nt`.
    #[arg(long)]
    geocentric: bool,
    /// Maximum degree of the expansion (1..=13).
    #[arg(long, default_value_t = 13)]
    degree: u8,
}

/// Runs `acs igrf`.
pub fn run(_args: &Args) -> Result<(), CliError> {
    Err(CliError::NotImplemented("igrf"))
}
