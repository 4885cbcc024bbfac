//! The flight loop on the target: [`acs::flight::OneImageLoop`] over the tile mailboxes
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
//! the argument words into `UPLINK_ARGS`, then the command code into `UPLINK_KIND` (the codes
//! and words of [`acs::uplink`]). Before each step the firmware applies the command
//! ([`acs::uplink::apply`]), clears `UPLINK_KIND` and writes the outcome
//! ([`acs::uplink::status`]: 0 accepted, 1 unknown command, 2 invalid argument, 3 refused by the
//! loop, `0x100 + i` element set refused at word `i`, the elements in use kept) into
//! `UPLINK_STATUS`.
//!
//! The node images take PUS telecommands instead ([`Ground`], [`take_telecommand`]), and hand
//! their telemetry to the ground link packet by packet ([`downlink`]).
//!
//! After each step the firmware publishes the mode (`STEP_MODE`, [`acs::acs_loop::Mode::code`])
//! and the faults (`STEP_FAULTS`, [`acs::acs_loop::Faults::bits`]).

use acs::acs_loop::StepReport;
use acs::attitude::Quaternion;
use acs::flight::{OneImageLoop, CONFIG, CONTROL_PERIOD_S};
use acs::orbit::sgp4::Sgp4;
use acs::time::{Epoch, TimeSpan, Utc};
use acs::link::sequence::SequenceCounter;
use acs::link::space_packet::Apid;
use acs::uplink::telecommand::{self, REPORTS_LEN};
use acs::uplink::{UplinkError, ARG_WORDS};

/// Uplink command code (see the [module docs](self)); 0: none.
#[no_mangle]
pub static mut UPLINK_KIND: u16 = 0;
/// Outcome of the last uplink command.
#[no_mangle]
pub static mut UPLINK_STATUS: u16 = 0;
/// Uplink arguments.
#[no_mangle]
pub static mut UPLINK_ARGS: [u32; ARG_WORDS] = [0; ARG_WORDS];
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
/// ([`flight_orbit`]) in `slot`, or leaves `None` there if the configuration is invalid. An
/// element set that does not check out does not stop the loop: it is built without one and
/// detumbles and keeps the Sun on its panel (the laws that need no reference), reporting
/// `Faults::orbit`, until the ground uplinks a set. In place and out of line: the loop is not
/// returned by value, and the element set's temporaries live in this frame only while the loop
/// is built (not under the steps).
#[inline(never)]
#[cfg_attr(target_arch = "msp430", optimize(size))]
pub fn init_loop(slot: &mut Option<OneImageLoop>) {
    *slot = OneImageLoop::new(&CONFIG, flight_orbit()).ok();
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

/// Takes a pending uplink command, if any, and applies it to the loop or the clock
/// (`attitude`: the last filtered attitude, which a slew is planned from).
#[inline(never)]
#[cfg_attr(target_arch = "msp430", optimize(size))]
pub fn take_uplink(acs: &mut OneImageLoop, clock: &mut Epoch<Utc>, attitude: Option<&Quaternion>) {
    // SAFETY: single-threaded firmware, no interrupt touches the mailbox; volatile: written
    // from outside the program.
    let kind = unsafe { core::ptr::read_volatile(&raw const UPLINK_KIND) };
    if kind == 0 {
        return;
    }
    // The arguments are read in place (a copy would take 232 B of stack). The ground writes
    // the mailbox only while the core waits for the next period, never while this reference
    // lives; `black_box` hides the pointer's origin, so the compiler cannot fold the reads to
    // the static's initial value (nothing in the program writes it).
    let mailbox = core::hint::black_box(&raw const UPLINK_ARGS);
    // SAFETY: `mailbox` points to the static, valid and aligned; no write to it while the
    // shared reference lives.
    let args = unsafe { &*mailbox };
    let outcome = acs::uplink::status(&acs::uplink::apply(kind, args, acs, clock, attitude));
    // SAFETY: as above.
    unsafe {
        core::ptr::write_volatile(&raw mut UPLINK_STATUS, outcome);
        core::ptr::write_volatile(&raw mut UPLINK_KIND, 0);
    }
}

/// A node image's ground mailbox: the telecommand the ground (the processor-in-the-loop
/// host, or the communication subsystem's driver) puts there, and the verification reports the
/// node answers with ([`acs::uplink::telecommand`]). The ground writes the packet into `tc`,
/// then its length into `tc_len`; the node takes it before its next period's work
/// ([`take_telecommand`]), writes its reports into `reports` and their length into
/// `reports_len`, and clears `tc_len`. `N`: the node's longest telecommand, even
/// ([`acs::uplink::telecommand::REFERENCE_TC_BYTES`],
/// [`acs::uplink::telecommand::ATTITUDE_TC_BYTES`]).
#[repr(C)]
pub struct Ground<const N: usize> {
    /// Bytes of the telecommand in `tc`; 0: none pending.
    pub tc_len: u16,
    /// Bytes of the reports in `reports` of the last telecommand taken.
    pub reports_len: u16,
    /// The telecommand, a space packet.
    pub tc: [u8; N],
    /// Its verification reports, back to back.
    pub reports: [u8; REPORTS_LEN],
}

impl<const N: usize> Ground<N> {
    /// The mailbox with nothing pending.
    pub const EMPTY: Self = Self {
        tc_len: 0,
        reports_len: 0,
        tc: [0; N],
        reports: [0; REPORTS_LEN],
    };
}

/// Hands the telemetry packet `packet` (a TM\[3,25\] or TM\[5,x\] report,
/// [`acs::telemetry::Downlink`]) to the ground link: [`fw_downlink`] with its address and
/// length.
#[inline(always)]
pub fn downlink(packet: &[u8]) {
    fw_downlink(packet.as_ptr(), packet.len());
}

/// The ground link's entry for a telemetry packet: `len` bytes at `packet`, valid for this
/// call only (the node writes each packet on its stack). The communication subsystem's driver
/// belongs here, as it writes [`Ground`]'s telecommands: it is not part of this firmware, and
/// the processor-in-the-loop host reads each packet at this function's entry (its arguments in
/// R12 and R13, the MSP430 EABI's). The address and length are kept in those registers.
#[no_mangle]
#[inline(never)]
pub extern "C" fn fw_downlink(packet: *const u8, len: usize) {
    // SAFETY: the two moves have no effect; the operands pin the arguments to R12 and R13
    // (read by the processor-in-the-loop host at the entry) and keep the function and its
    // symbol. Not a bare `nop`: the linker's identical code folding would merge this function
    // with `fw_period_start` (the host checks that the two differ).
    #[cfg(target_arch = "msp430")]
    unsafe {
        core::arch::asm!("mov r12, r12", "mov r13, r13", in("r12") packet, in("r13") len)
    };
    #[cfg(not(target_arch = "msp430"))]
    let _ = (packet, len);
}

/// Takes the telecommand pending in `ground`, if any ([`acs::uplink::telecommand::take`], for
/// the node of `apid`, stamped with `clock(node)` at this call and counted by `count`): `apply`
/// applies the command to `node` ([`acs::uplink::apply_reference`] or
/// [`acs::uplink::apply_attitude`]); the reports go to the mailbox. A length beyond the
/// mailbox is taken as an empty packet (refused, reported). `node` and `ground` are passed in,
/// not captured, so that a debugger that calls this again with the same registers (the
/// processor-in-the-loop run, several telecommands in a period) gets each one stamped with the
/// clock as the previous ones left it. True if a telecommand was pending.
#[inline(never)]
#[cfg_attr(target_arch = "msp430", optimize(size))]
pub fn take_telecommand<T, const N: usize>(
    ground: *mut Ground<N>,
    apid: Apid,
    count: &mut SequenceCounter,
    node: &mut T,
    clock: fn(&T) -> Option<Epoch<Utc>>,
    apply: impl FnOnce(&mut T, u16, &[u32; ARG_WORDS]) -> Result<(), UplinkError>,
) -> bool {
    // `black_box` hides the pointer's origin, so the compiler cannot fold the reads to the
    // static's initial value (nothing in the program writes the telecommand).
    let ground = core::hint::black_box(ground);
    // SAFETY: `ground` points to the node's static mailbox, valid and aligned; single-threaded
    // firmware, no interrupt touches it, and the ground writes it only while the core waits
    // for the next period, never while these references live. Volatile: written from outside
    // the program.
    unsafe {
        let len = core::ptr::read_volatile(&raw const (*ground).tc_len);
        if len == 0 {
            return false;
        }
        let tc = &*(&raw const (*ground).tc);
        let reports = &mut *(&raw mut (*ground).reports);
        let packet = tc.get(..usize::from(len)).unwrap_or_default();
        let now = clock(node);
        let n = telecommand::take(packet, apid, now, count, reports, |code, args| {
            apply(node, code, args)
        });
        core::ptr::write_volatile(&raw mut (*ground).reports_len, n as u16);
        core::ptr::write_volatile(&raw mut (*ground).tc_len, 0);
    }
    true
}

/// Publishes a step's mode and faults (`STEP_MODE`, `STEP_FAULTS`) from their codes.
pub fn publish_codes(mode: u16, faults: u16) {
    // SAFETY: single-threaded; volatile: read from outside the program.
    unsafe {
        core::ptr::write_volatile(&raw mut STEP_MODE, mode);
        core::ptr::write_volatile(&raw mut STEP_FAULTS, faults);
    }
}

/// Writes an uplink command as the ground would (the benchmark's commands): the arguments
/// `args` (the rest of the buffer unchanged), then the command code `kind`.
pub fn set_uplink(kind: u16, args: &[u32]) {
    // SAFETY: as in `take_uplink`; each element written through a raw pointer, within the buffer.
    unsafe {
        let base = &raw mut UPLINK_ARGS as *mut u32;
        for (i, a) in args.iter().enumerate().take(ARG_WORDS) {
            core::ptr::write_volatile(base.add(i), *a);
        }
        core::ptr::write_volatile(&raw mut UPLINK_KIND, kind);
    }
}

/// Publishes the step's mode and faults.
pub fn publish(report: &StepReport) {
    // SAFETY: as in `take_uplink`.
    unsafe {
        core::ptr::write_volatile(&raw mut STEP_MODE, report.mode.code());
        core::ptr::write_volatile(&raw mut STEP_FAULTS, report.faults.bits());
    }
}
