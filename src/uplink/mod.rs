//! Ground uplink: the commands the ground sends the flight loop, as a command code and argument
//! words, decoded and applied on board (issue #17). The node images receive them as PUS-C
//! telecommands, TC\[8,1\] with the code as its function ID, answered with verification reports
//! ([`telecommand`], issue 31; `firmware/src/flight.rs`); the one-image composition, which fits
//! no part, keeps the older mailbox of code and words ([`apply`]). The processor-in-the-loop
//! host takes the same packets on its host loop through the same functions, so both decode
//! every command identically.
//!
//! | code | command | argument words (`u32`) |
//! |---|---|---|
//! | [`kind::SUN_SAFE`] (1) | sun-safe | — |
//! | [`kind::TRACK`] (2) | track an attitude | 0–3: quaternion (f32 bits, scalar first, TEME → body, [`crate::attitude`]) |
//! | [`kind::SLEW`] (3) | slew, then track | 0–3: quaternion; 4: time allowed, s (f32 bits) |
//! | [`kind::ELEMENTS`] (4) | new element set | 0–57: the words of [`Sgp4::to_words`] (`acs elements`) |
//! | [`kind::CLOCK`] (5) | set the clock (UTC) | 0: days since 2000-01-01 (i32); 1: second of day; 2: nanoseconds |
//! | [`kind::MARK_FAILED`] (6) / [`kind::RESTORE`] (7) | mark a tile or a coil failed / restore it | 0: tile (or coil) index; 1: 0 a tile (with its devices and its wheel), 1 a coil ([`crate::attitude_node::health`]) |
//! | [`kind::HOUSEKEEPING`] (8) | housekeeping interval (either node, its own) | 0: control periods between reports, 0 none, at most [`crate::telemetry::MAX_INTERVAL`] |
//!
//! [`apply`] checks the arguments completely before it changes anything: a refused command
//! (a quaternion that is not finite or zero, a time out of range, an unknown tile, an element
//! set with a bad word, a slew the planner refuses) leaves the loop and the clock as they were,
//! and its [`UplinkError`] says why; [`status`] is the telemetry word the firmware reports.

pub mod telecommand;

use core::fmt;

use crate::acs_loop::{AcsError, AcsLoop, Command};
use crate::attitude::Quaternion;
use crate::attitude_node::AttitudeNode;
use crate::orbit::sgp4::{Sgp4, Sgp4Error, ELEMENT_WORDS};
use crate::reference_node::ReferenceNode;
use crate::telemetry::Housekeeping;
use crate::tiles::TileState;
use crate::time::{Epoch, Utc};
use crate::two_node::TwoNodeLoop;

/// Number of argument words (the longest command, an element set).
pub const ARG_WORDS: usize = ELEMENT_WORDS;

/// The command codes (0: none).
pub mod kind {
    /// Back to sun-safe.
    pub const SUN_SAFE: u16 = 1;
    /// Track an attitude.
    pub const TRACK: u16 = 2;
    /// Slew to an attitude, then track it.
    pub const SLEW: u16 = 3;
    /// A new SGP4 element set (initialised on the ground).
    pub const ELEMENTS: u16 = 4;
    /// Set the on-board clock.
    pub const CLOCK: u16 = 5;
    /// Mark a tile failed.
    pub const MARK_FAILED: u16 = 6;
    /// Return a tile to service.
    pub const RESTORE: u16 = 7;
    /// Set the node's housekeeping interval (both nodes: each keeps its own).
    pub const HOUSEKEEPING: u16 = 8;
}

/// Why an uplinked command was refused (the loop and the clock are unchanged).
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum UplinkError {
    /// No command has this code.
    UnknownCommand(u16),
    /// An argument is invalid: a quaternion that is not finite or zero, a time allowed that
    /// is not positive, an epoch out of range, a tile index that does not exist.
    InvalidArgument,
    /// The loop refused the command (a slew that cannot be planned now).
    Refused(AcsError),
    /// The element set is refused at this word ([`Sgp4::from_words`]).
    BadElementWord(u8),
    /// The command belongs to the other node ([`crate::two_node`]: sun-safe and the tiles to
    /// the attitude node; track, slew, elements and clock to the reference node).
    NotThisNode(u16),
    /// A telecommand carries another number of argument words than its command takes
    /// ([`telecommand::arity`]).
    ArgumentCount(u16),
}

impl UplinkError {
    /// The telemetry status word: 1 unknown command, 2 invalid argument, 3 refused by the
    /// loop, 4 the other node's command, 5 a telecommand with the wrong number of argument
    /// words, `0x100 + i` element set refused at word `i` (0:
    /// accepted, [`status`]).
    pub fn status(&self) -> u16 {
        match self {
            Self::UnknownCommand(_) => 1,
            Self::InvalidArgument => 2,
            Self::Refused(_) => 3,
            Self::BadElementWord(i) => 0x100 + u16::from(*i),
            Self::NotThisNode(_) => 4,
            Self::ArgumentCount(_) => 5,
        }
    }
}

impl fmt::Display for UplinkError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::UnknownCommand(k) => write!(f, "unknown uplink command {k}"),
            Self::InvalidArgument => write!(f, "invalid uplink argument"),
            Self::Refused(e) => write!(f, "command refused: {e}"),
            Self::BadElementWord(i) => write!(f, "element set refused at word {i}"),
            Self::NotThisNode(k) => write!(f, "uplink command {k} belongs to the other node"),
            Self::ArgumentCount(k) => write!(f, "uplink command {k} with a wrong number of words"),
        }
    }
}

/// The telemetry status of an [`apply`] result: 0 accepted, else [`UplinkError::status`].
pub fn status(result: &Result<(), UplinkError>) -> u16 {
    match result {
        Ok(()) => 0,
        Err(e) => e.status(),
    }
}

/// Argument words 0–3 as a normalised quaternion; `None` if not finite or zero.
fn quaternion(args: &[u32; ARG_WORDS]) -> Option<Quaternion> {
    let [q0, q1, q2, q3, ..] = *args;
    Quaternion::new_normalize(
        f32::from_bits(q0),
        f32::from_bits(q1),
        f32::from_bits(q2),
        f32::from_bits(q3),
    )
}

/// What [`apply`] commands: the one-image loop ([`AcsLoop`]) or the two nodes composed
/// ([`TwoNodeLoop`]), which own the commands as [`crate::two_node`] says.
pub trait UplinkTarget {
    /// Replaces the element set (checked before).
    fn set_orbit(&mut self, orbit: Sgp4);
    /// The run-time state of tile `tile`, `None` if there is no such tile.
    fn tile_state(&self, tile: usize) -> Option<TileState>;
    /// Marks a tile failed.
    fn mark_failed(&mut self, tile: usize);
    /// Returns a tile to service.
    fn restore(&mut self, tile: usize);
    /// Fails a coil (`failed`) or returns it to service; false if there is no such coil.
    fn set_coil_failed(&mut self, coil: usize, failed: bool) -> bool;
    /// Sets the housekeeping interval of the nodes (checked before); false if this loop has
    /// no housekeeping (the one-image [`AcsLoop`]: the command is refused as unknown).
    fn set_housekeeping(&mut self, _periods: u16) -> bool {
        false
    }
    /// A ground command (`attitude`: the last filtered attitude, reference TEME → body, which
    /// a slew is planned from; `now`: the next step's UTC).
    fn command(
        &mut self,
        command: Command,
        attitude: Option<&Quaternion>,
        now: Epoch<Utc>,
    ) -> Result<(), AcsError>;
}

macro_rules! uplink_target {
    ($loop:ident, {$($extra:tt)*}) => {
        impl<const N: usize, const F: usize> UplinkTarget for $loop<'_, N, F> {
            $($extra)*
            fn set_orbit(&mut self, orbit: Sgp4) {
                $loop::set_orbit(self, orbit);
            }
            fn tile_state(&self, tile: usize) -> Option<TileState> {
                $loop::tile_state(self, tile)
            }
            fn mark_failed(&mut self, tile: usize) {
                $loop::mark_failed(self, tile);
            }
            fn restore(&mut self, tile: usize) {
                $loop::restore(self, tile);
            }
            fn set_coil_failed(&mut self, coil: usize, failed: bool) -> bool {
                $loop::set_coil_failed(self, coil, failed)
            }
            fn command(
                &mut self,
                command: Command,
                attitude: Option<&Quaternion>,
                now: Epoch<Utc>,
            ) -> Result<(), AcsError> {
                $loop::command(self, command, attitude, now)
            }
        }
    };
}
uplink_target!(AcsLoop, {});
uplink_target!(TwoNodeLoop, {
    fn set_housekeeping(&mut self, periods: u16) -> bool {
        let p = u32::from(periods);
        self.reference_node_mut().housekeeping_mut().set_interval(p)
            && self.attitude_node_mut().housekeeping_mut().set_interval(p)
    }
});

/// The element set of the argument words, checked whole ([`Sgp4::from_words`]) before it
/// replaces the loop's (out of line: the new set's temporaries stay off the other commands'
/// stack).
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
fn set_elements<A: UplinkTarget>(args: &[u32; ARG_WORDS], acs: &mut A) -> Result<(), UplinkError> {
    acs.set_orbit(elements(args)?);
    Ok(())
}

/// The element set of the argument words, checked whole ([`Sgp4::from_words`]).
fn elements(args: &[u32; ARG_WORDS]) -> Result<Sgp4, UplinkError> {
    Sgp4::from_words(args).map_err(|e| match e {
        Sgp4Error::Words { index } => UplinkError::BadElementWord(index),
        _ => UplinkError::BadElementWord(0),
    })
}

/// A slew's time allowed (word 4), finite and positive.
fn within(args: &[u32; ARG_WORDS]) -> Result<f32, UplinkError> {
    let [_, _, _, _, a4, ..] = *args;
    let within_s = f32::from_bits(a4);
    if within_s.is_finite() && within_s > 0.0 {
        Ok(within_s)
    } else {
        Err(UplinkError::InvalidArgument)
    }
}

/// The tile index of argument word 0, if the satellite has that tile.
fn tile(args: &[u32; ARG_WORDS], tiles: usize) -> Result<usize, UplinkError> {
    let [a0, ..] = *args;
    usize::try_from(a0)
        .ok()
        .filter(|t| tiles > *t)
        .ok_or(UplinkError::InvalidArgument)
}

/// Applies a command the reference node owns (track, slew, element set, clock; the others are
/// refused as [`UplinkError::NotThisNode`]) to `node`; `attitude` is the attitude the attitude
/// node last reported (reference TEME → body, [`crate::attitude`]), which a slew is planned
/// from, at the node's clock.
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
pub fn apply_reference<const N: usize, const F: usize>(
    code: u16,
    args: &[u32; ARG_WORDS],
    node: &mut ReferenceNode<'_, N, F>,
    attitude: Option<&Quaternion>,
) -> Result<(), UplinkError> {
    match code {
        // one quaternion for both: one call site on the MSP430
        kind::TRACK | kind::SLEW => {
            let q = quaternion(args).ok_or(UplinkError::InvalidArgument)?;
            if code == kind::TRACK {
                node.track(q);
            } else {
                let within_s = within(args)?;
                let refused = UplinkError::Refused(AcsError::CannotSlew);
                let (attitude, now) = attitude.zip(node.clock()).ok_or(refused)?;
                node.slew(attitude, &q.to_dcm(), within_s, now)
                    .map_err(UplinkError::Refused)?;
            }
        }
        kind::ELEMENTS => set_node_elements(args, node)?,
        kind::CLOCK => {
            let [a0, a1, a2, ..] = *args;
            let utc =
                Epoch::from_parts(a0 as i32, a1, a2).map_err(|_| UplinkError::InvalidArgument)?;
            node.set_clock(utc);
        }
        kind::HOUSEKEEPING => housekeeping(args, node.housekeeping_mut())?,
        kind::SUN_SAFE | kind::MARK_FAILED | kind::RESTORE => {
            return Err(UplinkError::NotThisNode(code))
        }
        _ => return Err(UplinkError::UnknownCommand(code)),
    }
    Ok(())
}

/// The ground's housekeeping interval, word 0, set in `schedule` (refused beyond
/// [`crate::telemetry::MAX_INTERVAL`]).
fn housekeeping(args: &[u32; ARG_WORDS], schedule: &mut Housekeeping) -> Result<(), UplinkError> {
    let [a0, ..] = *args;
    if schedule.set_interval(a0) {
        Ok(())
    } else {
        Err(UplinkError::InvalidArgument)
    }
}

/// The element set of the argument words, checked whole, for the reference node (out of line:
/// the new set's temporaries stay off the slew's stack).
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
fn set_node_elements<const N: usize, const F: usize>(
    args: &[u32; ARG_WORDS],
    node: &mut ReferenceNode<'_, N, F>,
) -> Result<(), UplinkError> {
    node.set_orbit(elements(args)?);
    Ok(())
}

/// Applies a command the attitude node owns (sun-safe, mark a tile failed or restore it; the
/// others are refused as [`UplinkError::NotThisNode`]) to `node`.
#[cfg_attr(target_arch = "msp430", optimize(size))]
pub fn apply_attitude<const N: usize>(
    code: u16,
    args: &[u32; ARG_WORDS],
    node: &mut AttitudeNode<'_, N>,
) -> Result<(), UplinkError> {
    match code {
        kind::SUN_SAFE => node.sun_safe(),
        kind::MARK_FAILED | kind::RESTORE => {
            let failed = code == kind::MARK_FAILED;
            let [a0, a1, ..] = *args;
            match a1 {
                0 if failed => node.mark_failed(tile(args, node.tiles().len())?),
                0 => node.restore(tile(args, node.tiles().len())?),
                1 if usize::try_from(a0).is_ok_and(|c| node.set_coil_failed(c, failed)) => {}
                _ => return Err(UplinkError::InvalidArgument),
            }
        }
        kind::HOUSEKEEPING => housekeeping(args, node.housekeeping_mut())?,
        kind::TRACK | kind::SLEW | kind::ELEMENTS | kind::CLOCK => {
            return Err(UplinkError::NotThisNode(code))
        }
        _ => return Err(UplinkError::UnknownCommand(code)),
    }
    Ok(())
}

/// Applies command `code` with argument words `args` to the loop or the clock (see the
/// [module docs](self)); `attitude` is the last filtered attitude (reference TEME → body,
/// [`crate::attitude`]), which a slew is planned from.
#[cfg_attr(target_arch = "msp430", optimize(size))]
pub fn apply<A: UplinkTarget>(
    code: u16,
    args: &[u32; ARG_WORDS],
    acs: &mut A,
    clock: &mut Epoch<Utc>,
    attitude: Option<&Quaternion>,
) -> Result<(), UplinkError> {
    let [a0, a1, a2, _, a4, ..] = *args;
    let command = match code {
        kind::SUN_SAFE => Command::SunSafe,
        kind::TRACK => Command::Track {
            target: quaternion(args).ok_or(UplinkError::InvalidArgument)?,
        },
        kind::SLEW => {
            let within_s = f32::from_bits(a4);
            match quaternion(args) {
                Some(q) if within_s.is_finite() && within_s > 0.0 => Command::Slew {
                    target: q.to_dcm(),
                    within_s,
                },
                _ => return Err(UplinkError::InvalidArgument),
            }
        }
        kind::ELEMENTS => return set_elements(args, acs),
        kind::CLOCK => {
            *clock =
                Epoch::from_parts(a0 as i32, a1, a2).map_err(|_| UplinkError::InvalidArgument)?;
            return Ok(());
        }
        kind::HOUSEKEEPING => {
            let mut schedule = Housekeeping::new();
            housekeeping(args, &mut schedule)?;
            return if acs.set_housekeeping(schedule.interval()) {
                Ok(())
            } else {
                Err(UplinkError::UnknownCommand(code))
            };
        }
        kind::MARK_FAILED | kind::RESTORE => {
            let failed = code == kind::MARK_FAILED;
            let index = usize::try_from(a0).map_err(|_| UplinkError::InvalidArgument)?;
            match a1 {
                0 if acs.tile_state(index).is_some() => {
                    if failed {
                        acs.mark_failed(index);
                    } else {
                        acs.restore(index);
                    }
                }
                1 if acs.set_coil_failed(index, failed) => {}
                _ => return Err(UplinkError::InvalidArgument),
            }
            return Ok(());
        }
        _ => return Err(UplinkError::UnknownCommand(code)),
    };
    acs.command(command, attitude, *clock)
        .map_err(UplinkError::Refused)
}
