//! The flight loop on the target: [`acs::acs_loop::AcsLoop`] over the stubbed tile bus.
//!
//! Shared by the flight firmware (`src/main.rs`, feature `acs-loop`) and the benchmark's "ACS
//! step" case (`src/cases.rs`, group `step`). Configuration: the thesis's cube of six tiles
//! (`acs::tiles::cube_thesis`), three 0.2 A·m² coils, 1 mN·m·s wheels, IGRF degree 8 of the
//! recent-epochs table, SGP4 on the test TLE 00005 (Vallado et al. 2006).

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
pub fn principal_axes_of_diagonal(moments: &[f32; 3]) -> PrincipalAxes {
    let [a, b, c] = *moments;
    let moments = Vec3::new(a, b, c);
    PrincipalAxes {
        e: Mat3::identity(),
        moments,
        inertia_body: Mat3::from_diagonal(&moments),
    }
}

/// Room for the IGRF coefficients of the flight degree (8): 320 B of loop state.
pub const FIELD_COEFFS: usize = acs::env::igrf::coefficient_count(8);

/// The number of tiles of the flight configuration (the thesis's cube): the loop is sized to it.
pub const TILES: usize = 6;

/// The loop with its flight configuration, or `None` if a part of it is invalid.
///
/// Not inlined: its temporaries (configuration, SGP4 initialisation) leave the stack before the
/// control loop starts.
#[inline(never)]
pub fn new_loop() -> Option<AcsLoop<TILES, FIELD_COEFFS>> {
    let axes = principal_axes_of_diagonal(&INERTIA_DIAGONAL);
    let inertia = axes.inertia_body;
    let mut coils = heapless::Vec::new();
    for axis in [Vec3::x(), Vec3::y(), Vec3::z()] {
        coils
            .push(Wheel {
                axis_body: axis,
                limit: 0.2,
                working: true,
            })
            .ok()?;
    }
    let config = AcsConfig {
        tiles: acs::tiles::CUBE_THESIS.iter().copied().collect(),
        axes,
        coils,
        wheel_limit_nms: 1.0e-3,
        bdot: BdotConfig {
            gain: 3.0e4,
            max_dipole_am2: Vec3::from_element(0.2),
        },
        tracking: TrackingGains::from_bandwidth(&inertia, 0.25, 0.9),
        sun_safe: SunSafeGains {
            kp_nm: 2.0 * 0.05 * 0.05 * 0.014,
            kd_nms: 2.0 * 0.05 * 0.014,
        },
        sun_axis_body: Vec3::z(),
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
        igrf_degree: Degree::new(8).ok()?,
        weights: (1.0, 1.0),
        filter_gain: 0.1,
        max_propagation_s: 120.0,
    };
    let orbit = Sgp4::new(&crate::elements::test_tle()?, Gravity::Wgs72).ok()?;
    AcsLoop::new(config, orbit).ok()
}

/// The epoch of control tick `tick` (1 s period) from 2000-06-27 12:00 UTC (near the TLE epoch).
pub fn tick_epoch(tick: u32) -> Option<Epoch<Utc>> {
    Epoch::from_parts(178, 43_200, 0)
        .ok()
        .map(|e| e.add(acs::time::TimeSpan::new(tick as i32, 0)))
}
