//! Every crash the fuzz targets (`fuzz/`, `fuzz/README.md`) found, as a plain test with its
//! input inline; each was fixed.

use acs::env::igrf::{Degree, Igrf, IgrfError, FULL};
use acs::host::cli::igrf::{parse_row, row_output};
use acs::host::cli::CliError;

/// `cli_igrf`: a longitude beyond `fmath::TRIG_LIMIT` (6.5e6 rad) gave a field of NaN as `Ok`,
/// printed as `NaN,NaN,NaN` with exit 0. Now an invalid input naming the field (exit 2).
#[test]
fn igrf_huge_longitude_is_refused_not_nan() {
    let degree = Degree::new(13).unwrap();
    for (line, geocentric) in [
        ("2020,90,333333333333333333333333333333333331,0", false),
        ("2020,45,1e10,400", false),
        ("2025.5,6771,45,1e9", true),
    ] {
        let mut seen = false;
        let values = parse_row(1, line, geocentric, &mut seen).unwrap().unwrap();
        match row_output(1, values, geocentric, degree) {
            Err(e @ CliError::Input(_)) => assert!(e.to_string().contains("lon_deg"), "{e}"),
            other => panic!("{line}: {other:?}"),
        }
    }
    let igrf = Igrf::new(&FULL, 2025.0, degree).unwrap();
    let refused = |r: Result<(), IgrfError>| {
        assert!(
            matches!(
                r,
                Err(IgrfError::AngleOutOfRange {
                    input: "lon_rad",
                    ..
                })
            ),
            "{r:?}"
        )
    };
    refused(igrf.geodetic_ned(0.5, 1e7, 400.0).map(|_| ()));
    refused(igrf.geocentric(6771.0, 1.0, -1e30).map(|_| ()));
    // just below the limit: a finite field
    let n = igrf.geodetic_ned(0.5, 6.5e6, 400.0).unwrap();
    assert!(n.north_nt.is_finite() && n.east_nt.is_finite() && n.down_nt.is_finite());
}
