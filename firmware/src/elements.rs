//! The orbital elements the flight firmware and the benchmark use: Vallado's test satellite
//! for the SGP4 benchmark cases, and the flight loop's orbit (within the on-board IGRF model's
//! 2025–2030 range, `acs::env::igrf::FLIGHT`).

use acs::time::Epoch;

/// The test TLE of Vallado et al. (2006), satellite 00005, built field by field (parsing text
/// pulls f64 decimal parsing, about 20 KB, into the image):
/// ```text
/// 1 00005U 58002B   00179.78495062  .00000023  00000-0  28098-4 0  4753
/// 2 00005  34.2682 348.7242 1859667 331.7664  19.3264 10.82419157413667
/// ```
pub fn test_tle() -> Option<acs::tle::Tle> {
    Epoch::from_tle_epoch(0, 179, 78_495_062)
        .ok()
        .map(|epoch| acs::tle::Tle {
            name: None,
            catalog_number: 5,
            classification: b'U',
            international_designator: heapless::String::new(),
            epoch,
            mean_motion_dot: 0.000_000_23,
            mean_motion_ddot: 0.0,
            bstar: 0.280_98e-4,
            ephemeris_type: 0,
            element_set_number: 475,
            inclination_deg: 34.268_2,
            raan_deg: 348.724_2,
            eccentricity: 0.185_966_7,
            arg_perigee_deg: 331.766_4,
            mean_anomaly_deg: 19.326_4,
            mean_motion_rev_per_day: 10.824_191_574,
            revolution_number: 41_366,
        })
}

/// The flight loop's element set: the `tracking` scenario's dawn-dusk orbit of the simulator
/// (`acs::host::sim::scenarios::tracking`: 500 km, 97.4°, RAAN 90°, near-circular, B* = 0),
/// epoch 2025-03-20 12:00 UTC, inside the on-board IGRF model (`FLIGHT`, 2025–2030). Built
/// field by field like [`test_tle`]; `firmware/bench-host` checks it against the text:
/// ```text
/// 1 90101U 25001A   25079.50000000  .00000000  00000-0  00000-0 0  9997
/// 2 90101  97.4000  90.0000 0001000   0.0000   0.0000 15.21936487    10
/// ```
pub fn flight_tle() -> Option<acs::tle::Tle> {
    Epoch::from_tle_epoch(25, 79, 50_000_000)
        .ok()
        .map(|epoch| acs::tle::Tle {
            name: None,
            catalog_number: 90_101,
            classification: b'U',
            international_designator: heapless::String::new(),
            epoch,
            mean_motion_dot: 0.0,
            mean_motion_ddot: 0.0,
            bstar: 0.0,
            ephemeris_type: 0,
            element_set_number: 999,
            inclination_deg: 97.4,
            raan_deg: 90.0,
            eccentricity: 0.000_1,
            arg_perigee_deg: 0.0,
            mean_anomaly_deg: 0.0,
            mean_motion_rev_per_day: 15.219_364_87,
            revolution_number: 1,
        })
}
