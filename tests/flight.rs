//! The flight configuration (`acs::flight`): what the firmware flies is a valid loop
//! configuration, and its hand-written constants are what the general routines compute.

use acs::control::principal_axes::principal_axes;
use acs::flight::{principal_axes_of_diagonal, FlightLoop, CONFIG, INERTIA_DIAGONAL_KGM2};
use acs::linalg::{Mat3, Vec3};

mod common;

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
    let orbit = common::flight_orbit();
    let acs = FlightLoop::new(&CONFIG, orbit).unwrap();
    assert_eq!(acs.tiles().len(), acs::flight::TILES);
    // the flight degree is the flight tables' (decision 3 of #17): the full model since issue
    // #29 (degree 8, 80 coefficients, before), and the loop has room for its coefficients
    assert_eq!(acs::flight::IGRF_DEGREE.get(), 13);
    assert_eq!(acs::flight::FIELD_COEFFS, 195);
    assert_eq!(CONFIG.igrf_degree, acs::flight::IGRF_DEGREE);
    assert!(core::ptr::eq(
        CONFIG.igrf_model.model(),
        &acs::env::igrf::FLIGHT
    ));
}
