//! The tile bus of the firmware, in the HAL's raw formats ([`acs::hal`]), over RAM mailboxes.
//!
//! On the satellite each power tile carries a sun sensor, a two-axis magnetometer, a one-axis
//! gyro, a reaction wheel, and the satellite three magnetorquer coils, reached over the tile
//! bus. In this firmware the bus transactions are RAM mailboxes that the simulator, the
//! processor-in-the-loop host (`acs sim --pil`) or a debugger read and write; everything above
//! them is the flight code. The mailboxes hold exactly what [`acs::hal::TileBus`] returns and
//! takes, so there is one raw tile format:
//!
//! | symbol | type | meaning |
//! |---|---|---|
//! | `TILE_SUN` | `[[i16; 2]; 6]` | sun-sensor angles `(a, b)`, 1e-4 rad |
//! | `TILE_SUN_SEEN` | `u16` | bit `i`: tile `i`'s sensor sees the Sun (clear: `Ok(None)`) |
//! | `TILE_MAG` | `[[i16; 2]; 6]` | magnetometer, tile x and y, 10 nT |
//! | `TILE_GYRO` | `[i16; 6]` | gyro rate about tile z, 1e-4 rad/s |
//! | `TILE_READ_ERRORS` | `u32` | bits `i`, `8 + i`, `16 + i`: tile `i`'s sun sensor, magnetometer, gyro does not answer (the kind: `ERROR_KINDS`) |
//! | `ACTUATOR_REFUSE` | `u16` | bits `i`, `8 + c`: wheel `i`, coil `c` refuses its command |
//! | `CMD_WHEEL_NMS` | `[f32; 6]` | wheel momentum commands, kg·m²/s along tile z |
//! | `CMD_DIPOLE_AM2` | `[f32; 3]` | coil dipole commands, A·m² |
//! | `TILE_WHEEL` | `[i16; 6]` | wheel momentum read-back, 1e-7 kg·m²/s |
//! | `COIL_READ` | `[i16; 3]` | coil dipole read-back, 1e-5 A·m² |
//! | `READBACK_ERRORS` | `u16` | bits `i`, `8 + c`: the read-back of wheel `i`, coil `c` fails (the kind: `ERROR_KINDS`) |
//! | `ERROR_KINDS` | `[u8; 40]` | the kind of each failure above ([`acs::hal::ErrorKind::code`]): entry `b` for bit `b` of `TILE_READ_ERRORS`, `24 + b` for bit `b` of `READBACK_ERRORS`; another value a bus error |

use acs::flight::TILES;
use acs::hal::{ErrorKind, TileBus};

/// Number of magnetorquer coils of the flight configuration.
pub const COILS: usize = 3;

/// Sun-sensor mailbox (written by the bus).
#[no_mangle]
pub static mut TILE_SUN: [[i16; 2]; TILES] = [[0; 2]; TILES];
/// Bit `i` set: tile `i`'s sun sensor sees the Sun.
#[no_mangle]
pub static mut TILE_SUN_SEEN: u16 = 0;
/// Magnetometer mailbox.
#[no_mangle]
pub static mut TILE_MAG: [[i16; 2]; TILES] = [[0; 2]; TILES];
/// Gyro mailbox.
#[no_mangle]
pub static mut TILE_GYRO: [i16; TILES] = [0; TILES];
/// Devices that do not answer (see the [module docs](self)).
#[no_mangle]
pub static mut TILE_READ_ERRORS: u32 = 0;
/// Actuators that refuse their command (see the [module docs](self)).
#[no_mangle]
pub static mut ACTUATOR_REFUSE: u16 = 0;
/// Wheel momentum commands (read by the bus).
#[no_mangle]
pub static mut CMD_WHEEL_NMS: [f32; TILES] = [0.0; TILES];
/// Coil dipole commands (read by the bus).
#[no_mangle]
pub static mut CMD_DIPOLE_AM2: [f32; COILS] = [0.0; COILS];
/// Wheel momentum read-back mailbox.
#[no_mangle]
pub static mut TILE_WHEEL: [i16; TILES] = [0; TILES];
/// Coil dipole read-back mailbox.
#[no_mangle]
pub static mut COIL_READ: [i16; COILS] = [0; COILS];
/// Read-backs that fail (see the [module docs](self)).
#[no_mangle]
pub static mut READBACK_ERRORS: u16 = 0;
/// The kind of each failure of [`TILE_READ_ERRORS`] and [`READBACK_ERRORS`] (see the
/// [module docs](self)).
#[no_mangle]
pub static mut ERROR_KINDS: [u8; ERROR_KINDS_LEN] = [0; ERROR_KINDS_LEN];
/// Entries of [`ERROR_KINDS`]: 24 device bits, then 16 read-back bits.
pub const ERROR_KINDS_LEN: usize = 40;

/// The kind of the failure in entry `i` of [`ERROR_KINDS`] (a bus error for a code that is not
/// a kind's).
fn error_kind(i: usize) -> ErrorKind {
    element(&raw const ERROR_KINDS, i)
        .and_then(ErrorKind::from_code)
        .unwrap_or(ErrorKind::Bus)
}

/// Bit `i` of `mask` (false beyond 31).
fn bit(mask: u32, i: usize) -> bool {
    mask & 1u32.checked_shl(i as u32).unwrap_or(0) != 0
}

/// Element `i` of a mailbox array, `None` beyond its end; one volatile read of that element
/// only (a volatile read of the whole array is unrolled into a move per word).
fn element<T: Copy, const L: usize>(mailbox: *const [T; L], i: usize) -> Option<T> {
    if i >= L {
        return None;
    }
    // SAFETY: `mailbox` is one of this module's statics (valid, aligned, never referenced:
    // single-threaded firmware, no interrupt touches the mailboxes), `i < L`; volatile: written
    // from outside the program.
    Some(unsafe { core::ptr::read_volatile((mailbox as *const T).add(i)) })
}

/// Writes element `i` of a mailbox array; `Err(DeviceAbsent)` beyond its end.
fn set_element<T, const L: usize>(
    mailbox: *mut [T; L],
    i: usize,
    value: T,
) -> Result<(), ErrorKind> {
    if i >= L {
        return Err(ErrorKind::DeviceAbsent);
    }
    // SAFETY: as in `element`.
    unsafe { core::ptr::write_volatile((mailbox as *mut T).add(i), value) };
    Ok(())
}

/// The read error of device bit `i` of [`TILE_READ_ERRORS`], if set (its kind from
/// [`ERROR_KINDS`]).
fn read_error(i: usize) -> Result<(), ErrorKind> {
    // SAFETY: single-threaded firmware, no interrupt touches the mailboxes; volatile: written
    // from outside the program.
    let errors = unsafe { core::ptr::read_volatile(&raw const TILE_READ_ERRORS) };
    if bit(errors, i) {
        Err(error_kind(i))
    } else {
        Ok(())
    }
}

/// The read-back error of bit `i` of [`READBACK_ERRORS`], if set.
fn readback_error(i: usize) -> Result<(), ErrorKind> {
    // SAFETY: as in `read_error`.
    let errors = unsafe { core::ptr::read_volatile(&raw const READBACK_ERRORS) };
    if bit(u32::from(errors), i) {
        Err(error_kind(24 + i))
    } else {
        Ok(())
    }
}

/// True if actuator bit `i` of [`ACTUATOR_REFUSE`] is set.
fn refuses(i: usize) -> bool {
    // SAFETY: as in `read_error`.
    let refuse = unsafe { core::ptr::read_volatile(&raw const ACTUATOR_REFUSE) };
    bit(u32::from(refuse), i)
}

/// The tile bus over the mailboxes.
pub struct MailboxBus;

impl TileBus for MailboxBus {
    fn read_sun(&mut self, tile: usize) -> Result<Option<[i16; 2]>, ErrorKind> {
        read_error(tile)?;
        let angles = element(&raw const TILE_SUN, tile).ok_or(ErrorKind::DeviceAbsent)?;
        // SAFETY: as in `read_error`.
        let seen = unsafe { core::ptr::read_volatile(&raw const TILE_SUN_SEEN) };
        Ok(bit(u32::from(seen), tile).then_some(angles))
    }
    fn read_magnetometer(&mut self, tile: usize) -> Result<[i16; 2], ErrorKind> {
        read_error(8 + tile)?;
        element(&raw const TILE_MAG, tile).ok_or(ErrorKind::DeviceAbsent)
    }
    fn read_gyro(&mut self, tile: usize) -> Result<i16, ErrorKind> {
        read_error(16 + tile)?;
        element(&raw const TILE_GYRO, tile).ok_or(ErrorKind::DeviceAbsent)
    }
    fn set_wheel_momentum(&mut self, tile: usize, h_nms: f32) -> Result<(), ErrorKind> {
        if refuses(tile) {
            return Err(ErrorKind::OutOfRange);
        }
        set_element(&raw mut CMD_WHEEL_NMS, tile, h_nms)
    }
    fn set_dipole(&mut self, coil: usize, m_am2: f32) -> Result<(), ErrorKind> {
        if refuses(8 + coil) {
            return Err(ErrorKind::OutOfRange);
        }
        set_element(&raw mut CMD_DIPOLE_AM2, coil, m_am2)
    }
    fn read_wheel_momentum(&mut self, tile: usize) -> Result<Option<i16>, ErrorKind> {
        readback_error(tile)?;
        element(&raw const TILE_WHEEL, tile)
            .map(Some)
            .ok_or(ErrorKind::DeviceAbsent)
    }
    fn read_coil_dipole(&mut self, coil: usize) -> Result<Option<i16>, ErrorKind> {
        readback_error(8 + coil)?;
        element(&raw const COIL_READ, coil)
            .map(Some)
            .ok_or(ErrorKind::DeviceAbsent)
    }
    /// The part's busy wait (`acs_firmware::CycleDelay`): the simulator counts its cycles. On
    /// the host (the benchmark's expected results, `bench-host`, which shares this file) there
    /// is nothing to wait for.
    fn delay_us(&mut self, us: u32) {
        #[cfg(target_arch = "msp430")]
        embedded_hal::delay::DelayNs::delay_us(&mut crate::CycleDelay, us);
        #[cfg(not(target_arch = "msp430"))]
        let _ = us;
    }
}

/// Switches every magnetorquer off. The wheels keep the momentum they were last commanded
/// (stopping a momentum-carrying wheel would spin the satellite): the safe state of the loop
/// ([`acs::acs_loop::AcsLoop::safe`]), here without any state a fault may have corrupted.
pub fn coils_off() {
    // SAFETY: as in `read_error`.
    unsafe { core::ptr::write_volatile(&raw mut CMD_DIPOLE_AM2, [0.0; COILS]) }
}

/// Writes the sensor mailboxes as the bus would deliver them (the benchmark's readings): Sun
/// angles and the tiles that see the Sun (bit mask), magnetometer and gyro; no read errors.
pub fn set_readings(
    sun: [[i16; 2]; TILES],
    sun_seen: u16,
    mag: [[i16; 2]; TILES],
    gyro: [i16; TILES],
) {
    // SAFETY: as in `read_error`.
    unsafe {
        core::ptr::write_volatile(&raw mut TILE_SUN, sun);
        core::ptr::write_volatile(&raw mut TILE_SUN_SEEN, sun_seen);
        core::ptr::write_volatile(&raw mut TILE_MAG, mag);
        core::ptr::write_volatile(&raw mut TILE_GYRO, gyro);
        core::ptr::write_volatile(&raw mut TILE_READ_ERRORS, 0);
    }
}
