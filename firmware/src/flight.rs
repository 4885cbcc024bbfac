//! The flight loop on the target: [`acs::flight::FlightLoop`] over the tile mailboxes
//! ([`crate::tiles`]), the ground uplink, and the on-board clock.
//!
//! Shared by the flight firmware (`src/main.rs`) and the benchmark's "ACS step" cases
//! (`src/cases.rs`, group `step`). The configuration is [`acs::flight::CONFIG`], the one the
//! host simulator flies; the element set at reset is the flight element set initialised on the
//! ground ([`crate::flight_elements`]; with feature `onboard-init`, SGP4 initialised on board
//! from the TLE of [`crate::elements::flight_tle`]).
//!
//! # Uplink mailbox
//! The ground (the processor-in-the-loop host, or the communication subsystem's driver) writes
//! the arguments into `UPLINK_ARGS`, then the command code into `UPLINK_KIND`. Before each step
//! the firmware takes the command, clears `UPLINK_KIND` and writes the outcome into
//! `UPLINK_STATUS`:
//!
//! | `UPLINK_KIND` | command | `UPLINK_ARGS` (u32 words) |
//! |---|---|---|
//! | 1 | sun-safe | — |
//! | 2 | track an attitude | 0–3: quaternion (f32 bits, scalar first, TEME → body) |
//! | 3 | slew, then track | 0–3: quaternion; 4: time allowed, s (f32 bits) |
//! | 4 | new element set | 0–57: the words of `Sgp4::to_words` (`acs elements`) |
//! | 5 | set the clock (UTC) | 0: days since 2000-01-01 (i32); 1: second of day; 2: nanoseconds |
//! | 6 / 7 | mark tile failed / restore it | 0: tile index |
//!
//! | `UPLINK_STATUS` | meaning |
//! |---|---|
//! | 0 | accepted |
//! | 1 | unknown command |
//! | 2 | invalid argument (a quaternion that is not finite or zero, a time out of range, a tile index) |
//! | 3 | refused by the loop (a slew that cannot be planned now) |
//! | `0x100 + i` | element set refused: word `i` is bad (the elements in use are kept) |
//!
//! After each step the firmware publishes the mode (`STEP_MODE`: 0 detumble, 1 sun-safe,
//! 2 slew, 3 tracking) and the faults (`STEP_FAULTS`, [`acs::acs_loop::Faults::bits`]).

use acs::acs_loop::{Command, Mode, StepReport};
use acs::attitude::Quaternion;
use acs::flight::{FlightLoop, CONFIG, CONTROL_PERIOD_S};
use acs::orbit::sgp4::{Sgp4, ELEMENT_WORDS};
use acs::time::{Epoch, TimeSpan, Utc};

/// Uplink command code (see the [module docs](self)); 0: none.
#[no_mangle]
pub static mut UPLINK_KIND: u16 = 0;
/// Outcome of the last uplink command.
#[no_mangle]
pub static mut UPLINK_STATUS: u16 = 0;
/// Uplink arguments.
#[no_mangle]
pub static mut UPLINK_ARGS: [u32; ELEMENT_WORDS] = [0; ELEMENT_WORDS];
/// Mode after the last step.
#[no_mangle]
pub static mut STEP_MODE: u16 = 0;
/// Faults of the last step.
#[no_mangle]
pub static mut STEP_FAULTS: u16 = 0;

/// The UTC epoch of the on-board clock at reset, 2025-03-20 12:00 (the flight element set's
/// epoch) until the ground sets it.
pub const RESET_EPOCH: (i32, u32) = (9_210, 43_200);

/// The on-board clock at reset.
pub fn reset_clock() -> Option<Epoch<Utc>> {
    Epoch::from_parts(RESET_EPOCH.0, RESET_EPOCH.1, 0).ok()
}

/// One control period.
pub const PERIOD: TimeSpan = TimeSpan::from_whole_seconds(CONTROL_PERIOD_S as i32);

/// Builds the loop over the flight configuration and the element set at reset
/// ([`flight_orbit`]) in `slot`, or leaves `None` there if a part of it is invalid. In place
/// and out of line: the loop is not returned by value, and the element set's temporaries live
/// in this frame only while the loop is built (not under the steps).
#[inline(never)]
#[optimize(size)]
pub fn init_loop(slot: &mut Option<FlightLoop>) {
    *slot = flight_orbit().and_then(|orbit| FlightLoop::new(&CONFIG, orbit).ok());
}

/// SGP4 on the flight element set initialised on the ground: the board checks and reads the
/// words (`firmware/bench-host` checks them against `Sgp4::new` on the host).
#[cfg(not(feature = "onboard-init"))]
pub fn flight_orbit() -> Option<Sgp4> {
    Sgp4::from_words(&crate::flight_elements::FLIGHT_ELEMENT_WORDS).ok()
}

/// SGP4 initialised on board from the flight TLE (feature `onboard-init`, for larger parts).
#[cfg(feature = "onboard-init")]
pub fn flight_orbit() -> Option<Sgp4> {
    Sgp4::new(
        &crate::elements::flight_tle()?,
        acs::orbit::sgp4::Gravity::Wgs72,
    )
    .ok()
}

/// Uplink status codes.
mod status {
    pub const ACCEPTED: u16 = 0;
    pub const UNKNOWN: u16 = 1;
    pub const INVALID: u16 = 2;
    pub const REFUSED: u16 = 3;
    pub const BAD_WORD: u16 = 0x100;
}

/// The uplink argument `i` (0 beyond the buffer).
fn arg(i: usize) -> u32 {
    crate::tiles::element(&raw const UPLINK_ARGS, i).unwrap_or(0)
}

/// The quaternion of uplink arguments 0–3, normalised; `None` if not finite or zero.
fn arg_quaternion() -> Option<Quaternion> {
    Quaternion::new_normalize(
        f32::from_bits(arg(0)),
        f32::from_bits(arg(1)),
        f32::from_bits(arg(2)),
        f32::from_bits(arg(3)),
    )
}

/// Takes a pending uplink command, if any, and applies it to the loop or the clock
/// (`attitude`: the last filtered attitude, which a slew is planned from).
#[inline(never)]
#[optimize(size)]
pub fn take_uplink(acs: &mut FlightLoop, clock: &mut Epoch<Utc>, attitude: Option<&Quaternion>) {
    // SAFETY: as in `arg`.
    let kind = unsafe { core::ptr::read_volatile(&raw const UPLINK_KIND) };
    if kind == 0 {
        return;
    }
    let outcome = match kind {
        1 => acs
            .command(Command::SunSafe, attitude, *clock)
            .map_or(status::REFUSED, |_| status::ACCEPTED),
        2 => match arg_quaternion() {
            Some(target) => acs
                .command(Command::Track { target }, attitude, *clock)
                .map_or(status::REFUSED, |_| status::ACCEPTED),
            None => status::INVALID,
        },
        3 => match (arg_quaternion(), f32::from_bits(arg(4))) {
            (Some(q), within_s) if within_s.is_finite() && within_s > 0.0 => {
                let command = Command::Slew {
                    target: q.to_dcm(),
                    within_s,
                };
                acs.command(command, attitude, *clock)
                    .map_or(status::REFUSED, |_| status::ACCEPTED)
            }
            _ => status::INVALID,
        },
        4 => take_elements(acs),
        5 => match Epoch::from_parts(arg(0) as i32, arg(1), arg(2)) {
            Ok(t) => {
                *clock = t;
                status::ACCEPTED
            }
            Err(_) => status::INVALID,
        },
        6 | 7 => {
            let tile = arg(0) as usize;
            if acs.tile_state(tile).is_none() {
                status::INVALID
            } else {
                if kind == 6 {
                    acs.mark_failed(tile);
                } else {
                    acs.restore(tile);
                }
                status::ACCEPTED
            }
        }
        _ => status::UNKNOWN,
    };
    // SAFETY: as in `arg`.
    unsafe {
        core::ptr::write_volatile(&raw mut UPLINK_STATUS, outcome);
        core::ptr::write_volatile(&raw mut UPLINK_KIND, 0);
    }
}

/// An uplinked element set: checked completely (`Sgp4::from_words`) before it replaces the
/// one in use, which is kept if any word is bad.
#[inline(never)]
#[optimize(size)]
fn take_elements(acs: &mut FlightLoop) -> u16 {
    // Read in place (a copy would take 232 B of stack). The ground writes the mailbox only
    // while the core waits for the next period, never while this reference lives; `black_box`
    // hides the pointer's origin, so the compiler cannot fold the reads to the static's initial
    // value (nothing in the program writes it).
    let mailbox = core::hint::black_box(&raw const UPLINK_ARGS);
    // SAFETY: `mailbox` points to the static, valid and aligned; no write to it while the
    // shared reference lives (single-threaded, no interrupt touches it).
    let words = unsafe { &*mailbox };
    match Sgp4::from_words(words) {
        Ok(orbit) => {
            acs.set_orbit(orbit);
            status::ACCEPTED
        }
        Err(acs::orbit::sgp4::Sgp4Error::Words { index }) => status::BAD_WORD + u16::from(index),
        Err(_) => status::BAD_WORD,
    }
}

/// Writes an uplink command as the ground would (the benchmark's commands): the arguments
/// `args` (the rest of the buffer unchanged), then the command code `kind`.
pub fn set_uplink(kind: u16, args: &[u32]) {
    // SAFETY: as in `arg`; each element written through a raw pointer after a bounds check.
    unsafe {
        let base = &raw mut UPLINK_ARGS as *mut u32;
        for (i, a) in args.iter().enumerate().take(ELEMENT_WORDS) {
            core::ptr::write_volatile(base.add(i), *a);
        }
        core::ptr::write_volatile(&raw mut UPLINK_KIND, kind);
    }
}

/// Publishes the step's mode and faults.
pub fn publish(report: &StepReport) {
    let mode = match report.mode {
        Mode::Detumble => 0,
        Mode::SunSafe => 1,
        Mode::Slew => 2,
        Mode::Tracking => 3,
    };
    // SAFETY: as in `arg`.
    unsafe {
        core::ptr::write_volatile(&raw mut STEP_MODE, mode);
        core::ptr::write_volatile(&raw mut STEP_FAULTS, report.faults.bits());
    }
}
