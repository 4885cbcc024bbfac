//! The flight loop on the target: [`acs::acs_loop::AcsLoop`] over the stubbed tile bus.
//!
//! Shared by the flight firmware (`src/main.rs`, feature `acs-loop`) and the benchmark's "ACS
//! step" case (`src/cases.rs`, group `step`). Configuration: the thesis's cube of six tiles
//! (`acs::tiles::CUBE_THESIS`), three 0.2 A·m² coils, 1 mN·m·s wheels, IGRF degree 8 of the
//! recent-epochs table, SGP4 on the flight element set (`crate::elements::flight_tle`).

use acs::acs_loop::{AcsConfig, AcsLoop};
use acs::control::bdot::BdotConfig;
use acs::control::principal_axes::PrincipalAxes;
use acs::control::slew::SlewLimits;
use acs::control::sun_safe::SunSafeGains;
use acs::control::tracking::TrackingGains;
use acs::control::wheels::Wheel;
use acs::env::igrf::{Degree, RECENT};
use acs::hal::{ErrorKind, TileBus};
use acs::linalg::{Mat3, Vec3};
use acs::orbit::sgp4::{Gravity, Sgp4};
use acs::time::{Epoch, Utc};

/// Raw sensor mailboxes (written by the simulator or a debugger), one entry per tile.
#[no_mangle]
pub static mut RAW_SUN: [[i16; 2]; 6] = [[0; 2]; 6];
/// Raw magnetometer mailbox.
#[no_mangle]
pub static mut RAW_MAG: [[i16; 2]; 6] = [[0; 2]; 6];
/// Raw gyro mailbox.
#[no_mangle]
pub static mut RAW_GYRO: [i16; 6] = [0; 6];

/// Writes the sensor mailboxes (what the tile drivers would deliver): raw Sun angles (1e-4 rad),
/// magnetometer components (10 nT) and gyro rates (1e-4 rad/s), one entry per tile.
pub fn set_mailboxes(sun: [[i16; 2]; 6], mag: [[i16; 2]; 6], gyro: [i16; 6]) {
    // SAFETY: single-threaded firmware; volatile: read by the bus as if written from outside.
    unsafe {
        core::ptr::write_volatile(&raw mut RAW_SUN, sun);
        core::ptr::write_volatile(&raw mut RAW_MAG, mag);
        core::ptr::write_volatile(&raw mut RAW_GYRO, gyro);
    }
}

/// The tile bus over the RAM mailboxes (`crate::tiles` for the commands).
pub struct MailboxBus;

impl TileBus for MailboxBus {
    fn read_sun(&mut self, tile: usize) -> Result<Option<[i16; 2]>, ErrorKind> {
        // SAFETY: single-threaded firmware; volatile: written from outside.
        let all = unsafe { core::ptr::read_volatile(&raw const RAW_SUN) };
        all.get(tile)
            .copied()
            .map(Some)
            .ok_or(ErrorKind::DeviceAbsent)
    }
    fn read_magnetometer(&mut self, tile: usize) -> Result<[i16; 2], ErrorKind> {
        // SAFETY: as above.
        let all = unsafe { core::ptr::read_volatile(&raw const RAW_MAG) };
        all.get(tile).copied().ok_or(ErrorKind::DeviceAbsent)
    }
    fn read_gyro(&mut self, tile: usize) -> Result<i16, ErrorKind> {
        // SAFETY: as above.
        let all = unsafe { core::ptr::read_volatile(&raw const RAW_GYRO) };
        all.get(tile).copied().ok_or(ErrorKind::DeviceAbsent)
    }
    fn set_wheel_momentum(&mut self, tile: usize, h_nms: f32) -> Result<(), ErrorKind> {
        crate::tiles::command_one(tile, Some(h_nms), None).ok_or(ErrorKind::DeviceAbsent)
    }
    fn set_dipole(&mut self, tile: usize, m_am2: f32) -> Result<(), ErrorKind> {
        crate::tiles::command_one(tile, None, Some(m_am2)).ok_or(ErrorKind::DeviceAbsent)
    }
}

/// The principal moments of inertia, kg·m²: the body axes are principal axes.
pub const INERTIA_DIAGONAL: [f32; 3] = [0.010, 0.012, 0.014];

/// The principal axes of a diagonal inertia tensor: `E = I`, the moments in body-axis order (what
/// [`acs::control::principal_axes::principal_axes`] returns for it, checked on the host by
/// `firmware/bench-host`), without its eigen-decomposition (3 KB of flash) on board.
pub const fn principal_axes_of_diagonal(moments: &[f32; 3]) -> PrincipalAxes {
    let [a, b, c] = *moments;
    PrincipalAxes {
        e: Mat3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
        moments: Vec3::new(a, b, c),
        inertia_body: Mat3::new(a, 0.0, 0.0, 0.0, b, 0.0, 0.0, 0.0, c),
    }
}

/// Room for the IGRF coefficients of the flight degree (8): 320 B of loop state.
pub const FIELD_COEFFS: usize = acs::env::igrf::coefficient_count(8);

/// The number of tiles of the flight configuration (the thesis's cube): the loop is sized to it.
pub const TILES: usize = 6;

/// The flight degree of the IGRF model (checked at compile time).
const IGRF_DEGREE: Degree = match Degree::new(8) {
    Ok(d) => d,
    Err(_) => panic!("the flight IGRF degree must be 1..=13"),
};

/// One working magnetorquer coil along the body axis `(x, y, z)`, 0.2 A·m².
const fn coil(x: f32, y: f32, z: f32) -> Wheel {
    Wheel {
        axis_body: Vec3::new(x, y, z),
        limit: 0.2,
        working: true,
    }
}

/// The flight configuration, a `static` in flash: the loop borrows it, so only the loop's
/// run-time state takes RAM (the configuration is 572 B on the MSP430).
pub static CONFIG: AcsConfig<TILES> = {
    let axes = principal_axes_of_diagonal(&INERTIA_DIAGONAL);
    AcsConfig {
        tiles: heapless::Vec::from_array(acs::tiles::CUBE_THESIS),
        tracking: TrackingGains::from_bandwidth(&axes.inertia_body, 0.25, 0.9),
        axes,
        coils: heapless::Vec::from_array([
            coil(1.0, 0.0, 0.0),
            coil(0.0, 1.0, 0.0),
            coil(0.0, 0.0, 1.0),
        ]),
        wheel_limit_nms: 1.0e-3,
        bdot: BdotConfig {
            gain: 3.0e4,
            max_dipole_am2: Vec3::new(0.2, 0.2, 0.2),
        },
        sun_safe: SunSafeGains {
            kp_nm: 2.0 * 0.05 * 0.05 * 0.014,
            kd_nms: 2.0 * 0.05 * 0.014,
        },
        sun_axis_body: Vec3::new(0.0, 0.0, 1.0),
        slew_limits: SlewLimits {
            l_max: 1.0e-3,
            l_min: 1e-7,
            t_min: 0.3,
            default_fraction: 0.85,
            wheels_per_axis: [1, 2, 2],
        },
        slew_pause_s: 5.0,
        control_period_s: 1.0,
        dumping_gain_per_s: 1e-3,
        detumble_enter_radps: 0.5,
        detumble_exit_radps: 0.008_7,
        igrf_model: &RECENT,
        igrf_degree: IGRF_DEGREE,
        weights: (1.0, 1.0),
        filter_gain: 0.1,
        max_propagation_s: 120.0,
    }
};

/// Builds the loop over the flight configuration [`CONFIG`] and `orbit` in `slot` (in place: the
/// loop is not returned by value), or leaves `None` there if a part of it is invalid.
#[inline(never)]
pub fn init_loop(slot: &mut Option<AcsLoop<'static, TILES, FIELD_COEFFS>>, orbit: Sgp4) {
    *slot = AcsLoop::new(&CONFIG, orbit).ok();
}

/// SGP4 initialised on the flight element set (not inlined: its temporaries leave the stack
/// before the loop's state is built).
#[cfg(not(feature = "ground-init"))]
#[inline(never)]
pub fn flight_orbit() -> Option<Sgp4> {
    Sgp4::new(&crate::elements::flight_tle()?, Gravity::Wgs72).ok()
}

/// SGP4 on the flight element set initialised on the ground (`ground-init`: `Sgp4::new` ran on
/// the host, `firmware/bench-host` checks the words; the board checks and reads them).
#[cfg(feature = "ground-init")]
#[inline(never)]
pub fn flight_orbit() -> Option<Sgp4> {
    let _ = Gravity::Wgs72;
    Sgp4::from_words(&crate::flight_elements::FLIGHT_ELEMENT_WORDS).ok()
}

/// The epoch of control tick `tick` (1 s period) from 2025-03-20 12:00 UTC, the flight element
/// set's epoch ([`crate::elements::flight_tle`]; `firmware/bench-host` checks they agree).
pub fn tick_epoch(tick: u32) -> Option<Epoch<Utc>> {
    Epoch::from_parts(9_210, 43_200, 0)
        .ok()
        .map(|e| e.add(acs::time::TimeSpan::new(tick as i32, 0)))
}
