//! `acs igrf`: IGRF-14 field at points read from stdin (`docs/cli.md`).
//!
//! stdin: CSV `decimal_year,lat_deg,lon_deg,alt_km` (geodetic WGS-84) or, with `--geocentric`,
//! `decimal_year,r_km,colat_deg,lon_deg`; an optional header line (a first line with no
//! number in it); blank lines and `#` lines ignored. stdout: CSV `north_nt,east_nt,down_nt` or
//! `br_nt,btheta_nt,bphi_nt`, 9 significant digits. Exit 2 for bad input (line and field
//! named), 3 for a date outside the model.

use std::io::{self, BufRead, Write};

use super::CliError;
use crate::env::igrf::{Degree, Igrf, IgrfError, FULL};

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
pub fn run(args: &Args) -> Result<(), CliError> {
    let degree = Degree::new(args.degree)
        .map_err(|e| CliError::Input(format!("--degree {}: {e}", args.degree)))?;
    let stdin = io::stdin();
    let stdout = io::stdout();
    let mut out = io::BufWriter::new(stdout.lock());
    let write_err = |e: io::Error| CliError::Compute(format!("writing stdout: {e}"));
    let header = if args.geocentric {
        "br_nt,btheta_nt,bphi_nt"
    } else {
        "north_nt,east_nt,down_nt"
    };
    writeln!(out, "{header}").map_err(write_err)?;
    let mut seen_content = false;
    for (index, line) in stdin.lock().lines().enumerate() {
        let line_no = index + 1;
        let line =
            line.map_err(|e| CliError::Input(format!("line {line_no}: cannot read: {e}")))?;
        let Some(values) = parse_row(line_no, &line, args.geocentric, &mut seen_content)? else {
            continue;
        };
        let row = row_output(line_no, values, args.geocentric, degree)?;
        writeln!(out, "{},{},{}", sig9(row[0]), sig9(row[1]), sig9(row[2])).map_err(write_err)?;
    }
    out.flush().map_err(write_err)
}

/// The names of the four input fields.
fn field_names(geocentric: bool) -> [&'static str; 4] {
    if geocentric {
        ["decimal_year", "r_km", "colat_deg", "lon_deg"]
    } else {
        ["decimal_year", "lat_deg", "lon_deg", "alt_km"]
    }
}

/// Parses line `line_no` of `acs igrf`'s stdin: `Ok(None)` for a blank line, a `#` comment or
/// the header (a first line with content and no number in it; `seen_content` records whether
/// a line with content came before, and is updated), else the row's four finite numbers.
/// Public for the fuzz target `cli_igrf` (`fuzz/`).
pub fn parse_row(
    line_no: usize,
    line: &str,
    geocentric: bool,
    seen_content: &mut bool,
) -> Result<Option<[f64; 4]>, CliError> {
    let fields = field_names(geocentric);
    let text = line.trim();
    if text.is_empty() || text.starts_with('#') {
        return Ok(None);
    }
    let first_content = !*seen_content;
    *seen_content = true;
    let cells: Vec<&str> = text.split(',').map(str::trim).collect();
    if first_content && cells.iter().all(|c| c.parse::<f64>().is_err()) {
        return Ok(None); // header
    }
    if cells.len() != fields.len() {
        return Err(CliError::Input(format!(
            "line {line_no}: expected {} fields ({}), found {}",
            fields.len(),
            fields.join(","),
            cells.len()
        )));
    }
    let mut values = [0.0_f64; 4];
    for ((value, cell), name) in values.iter_mut().zip(&cells).zip(&fields) {
        *value = cell
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| {
                CliError::Input(format!(
                    "line {line_no}, field {name}: `{cell}` is not a finite number"
                ))
            })?;
    }
    Ok(Some(values))
}

/// The output row of `acs igrf` for the input row `values` of line `line_no`: the field's
/// three components, or the error the tool reports. Public for the fuzz target `cli_igrf`.
pub fn row_output(
    line_no: usize,
    values: [f64; 4],
    geocentric: bool,
    degree: Degree,
) -> Result<[f32; 3], CliError> {
    let [year, a, b, c] = values;
    evaluate(geocentric, degree, year, a, b, c)
        .map_err(|e| classify(e, line_no, &field_names(geocentric)))
}

/// The field at one input row, as the three output numbers.
fn evaluate(
    geocentric: bool,
    degree: Degree,
    year: f64,
    a: f64,
    b: f64,
    c: f64,
) -> Result<[f32; 3], IgrfError> {
    let igrf = Igrf::new(&FULL, year as f32, degree)?;
    if geocentric {
        let s = igrf.geocentric(a as f32, b.to_radians() as f32, c.to_radians() as f32)?;
        Ok([s.br_nt, s.btheta_nt, s.bphi_nt])
    } else {
        let n = igrf.geodetic_ned(a.to_radians() as f32, b.to_radians() as f32, c as f32)?;
        Ok([n.north_nt, n.east_nt, n.down_nt])
    }
}

/// A date outside the model is a failure of the computation (exit 3); anything else about a
/// row is invalid input (exit 2), with the line and field named.
fn classify(e: IgrfError, line_no: usize, fields: &[&str; 4]) -> CliError {
    let geocentric = fields[1] == "r_km";
    let field = match e {
        IgrfError::DateOutOfRange { .. } => {
            return CliError::Compute(format!("line {line_no}, field decimal_year: {e}"))
        }
        IgrfError::BelowSurface { .. } if geocentric => "r_km",
        IgrfError::BelowSurface { .. } => "alt_km",
        IgrfError::AngleOutOfRange { input, .. } | IgrfError::NotFinite { input, .. } => {
            match input {
                "decimal_year" => "decimal_year",
                "r_km" => "r_km",
                "colat_rad" => "colat_deg",
                "lat_rad" => "lat_deg",
                "lon_rad" => "lon_deg",
                "alt_km" => "alt_km",
                other => other,
            }
        }
        _ => "row",
    };
    CliError::Input(format!("line {line_no}, field {field}: {e}"))
}

/// `x` with 9 significant digits (enough to round-trip an f32).
fn sig9(x: f32) -> String {
    let x = f64::from(x);
    if x == 0.0 {
        return "0.00000000".to_string();
    }
    let exponent = x.abs().log10().floor() as i32;
    if (-5..15).contains(&exponent) {
        let decimals = (8 - exponent).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.8e}")
    }
}

#[cfg(test)]
#[allow(clippy::excessive_precision)]
mod tests {
    use super::sig9;

    #[test]
    fn nine_significant_digits() {
        assert_eq!(sig9(17559.5535), "17559.5527"); // the f32 nearest 17559.5535
        assert_eq!(sig9(-0.001_234_567_9), "-0.00123456796");
        assert_eq!(sig9(0.0), "0.00000000");
        assert_eq!(sig9(123_456_790.0), "123456792");
        assert_eq!(sig9(1e-30), "1.00000000e-30");
        for x in [17559.5535_f32, -48340.0868, 3.25, 1e-7, 6.0e12] {
            assert_eq!(sig9(x).parse::<f32>().unwrap(), x);
        }
    }
}
