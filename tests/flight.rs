//! The flight configuration (`acs::flight`): what the firmware flies is a valid loop
//! configuration, and its hand-written constants are what the general routines compute.

use acs::control::principal_axes::principal_axes;
use acs::flight::{principal_axes_of_diagonal, FlightLoop, CONFIG, INERTIA_DIAGONAL_KGM2};
use acs::linalg::{Mat3, Vec3};
use acs::orbit::sgp4::{Gravity, Sgp4};

/// The principal axes written as constants are those the eigen-decomposition gives.
#[test]
fn principal_axes_of_the_diagonal_inertia() {
    let d = INERTIA_DIAGONAL_KGM2;
    let inertia = Mat3::from_diagonal(&Vec3::new(d[0], d[1], d[2]));
    assert_eq!(
        principal_axes(&inertia).ok(),
        Some(principal_axes_of_diagonal(&d))
    );
}

/// The loop accepts the flight configuration (every value finite and consistent, the IGRF
/// coefficients fit the loop's room).
#[test]
fn flight_loop_builds() {
    let tle = acs::tle::Tle::parse(
        "1 90101U 25001A   25079.50000000  .00000000  00000-0  00000-0 0  9997",
        "2 90101  97.4000  90.0000 0001000   0.0000   0.0000 15.21936487    10",
    )
    .unwrap();
    let orbit = Sgp4::new(&tle, Gravity::Wgs72).unwrap();
    let acs = FlightLoop::new(&CONFIG, orbit).unwrap();
    assert_eq!(acs.tiles().len(), acs::flight::TILES);
    // the flight degree is the flight tables' (decision 3 of #17), and the loop holds its
    // coefficients
    assert_eq!(acs::flight::IGRF_DEGREE.get(), 8);
    assert_eq!(acs::flight::FIELD_COEFFS, 80);
}
