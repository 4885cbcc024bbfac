//! The ground's commands as PUS-C telecommands (issue 31, item 2): each command of
//! [`crate::uplink`] is a TC\[8,1\] *perform a function* (ECSS-E-ST-70-41C 6.8, 8.8.2.1) to the
//! node that owns it, and the node answers with the verification reports of service 1
//! ([`crate::link::pus`]). The node images take each telecommand from their ground mailbox
//! (`acs_firmware::flight::take_telecommand`, `firmware/src/flight.rs`) before their period's
//! work; `docs/operations.md` is the operator's page.
//!
//! # The telecommand
//! A CCSDS space packet on the node's APID ([`REFERENCE_TC_APID`], [`ATTITUDE_TC_APID`]), with
//! the PUS-C TC secondary header (service 8, subtype 1, the acknowledgement flags the ground
//! chooses, its source ID) and this application data, big-endian:
//!
//! | bytes | field |
//! |---|---|
//! | 2 | function ID: the command code ([`crate::uplink::kind`], 1–8) |
//! | 4 × n | the command's argument words, n = [`arity`] of the code (0–58; the words of the mailbox table in [`crate::uplink`]) |
//!
//! # The reports
//! [`take`] decodes the packet ([`decode_tc`]), checks the function ID and the number of words,
//! applies the command with the node's own function ([`crate::uplink::apply_reference`],
//! [`crate::uplink::apply_attitude`]: every argument checked before anything changes), and
//! writes its reports back to back in `out`:
//!
//! | outcome | reports |
//! |---|---|
//! | applied | TM\[1,1\] if the acceptance flag is set, then TM\[1,7\] if the completion flag is set (none if neither) |
//! | refused | TM\[1,2\], always, failure code below; nothing changed |
//!
//! A command completes in the period that takes it, so its acceptance and completion reports
//! leave together; a refused command is refused at acceptance, since its checks all come first.
//!
//! | TM\[1,2\] failure code | reason |
//! |---|---|
//! | 1–7 | the packet layer's ([`pus::PusError::failure_code`]: length, CRC, format, APID, type, PUS version, a service other than TC\[8,1\]) |
//! | `0x100 +` [`UplinkError::status`] | the command's: 0x101 unknown function ID, 0x102 invalid argument, 0x103 refused by the loop, 0x104 the other node's command, 0x105 wrong number of argument words, `0x200 + i` element set refused at word `i` |
//!
//! The failure notice carries no failure data: the code says it all. A packet refused before
//! its header can be trusted is answered with the request ID of its first four bytes (zeros if
//! it has fewer) and destination ID 0.
//!
//! Each report is stamped with the node's packet sequence count for its APID (the caller's
//! [`SequenceCounter`]), message type counter 0 (not counted), the TC's source ID as its
//! destination, and the node's clock when it took the telecommand ([`cuc`]): time status 1 and
//! the clock's CUC time, or time status 0 and time 0 if the node has no clock.
//!
//! [`REFERENCE_TC_APID`]: crate::link::messages::REFERENCE_TC_APID
//! [`ATTITUDE_TC_APID`]: crate::link::messages::ATTITUDE_TC_APID

use crate::link::messages::{ATTITUDE_TC_APID, REFERENCE_TC_APID};
use crate::link::pus::{
    self, decode_tc, failure, tm_packet_len, verification_report, AckFlags, CucTime, RequestId,
    TmHeader, Verification, REQUEST_ID_LEN,
};
use crate::link::sequence::SequenceCounter;
use crate::link::space_packet::Apid;
use crate::time::{Epoch, Utc};

use super::{kind, UplinkError, ARG_WORDS};

/// The telecommands' service: function management.
pub const SERVICE: u8 = 8;
/// Their subtype: perform a function.
pub const SUBTYPE: u8 = 1;
/// Bytes of the function ID.
pub const FUNCTION_ID_LEN: usize = 2;
/// The longest telecommand (an element set): 6 + 5 + 2 + 4 × 58 + 2 = 247 B.
pub const MAX_TC_LEN: usize = pus::TC_OVERHEAD + FUNCTION_ID_LEN + 4 * ARG_WORDS;
/// The attitude node image's telecommand mailbox (`docs/operations.md`), B: its
/// longest command's packet (sun-safe, mark failed, restore: 23 B) with room for a track or
/// slew (35 B), which it answers as the other node's; even, so the field after it is aligned.
pub const ATTITUDE_TC_BYTES: usize = pus::TC_OVERHEAD + FUNCTION_ID_LEN + 4 * 5 + 1;
/// The reference node image's telecommand mailbox, B: [`MAX_TC_LEN`], made even.
pub const REFERENCE_TC_BYTES: usize = MAX_TC_LEN + 1;
/// The most [`take`] writes: TM\[1,1\] and TM\[1,7\], 25 B each (a TM\[1,2\] is 27 B).
pub const REPORTS_LEN: usize = 2 * tm_packet_len(REQUEST_ID_LEN);

/// The type of an argument word, as the node reads its bits.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum WordType {
    /// IEEE 754 single precision.
    F32,
    /// Two's complement.
    I32,
    /// Unsigned.
    U32,
}

/// One argument of a command: a word, or several of the same meaning (the element set).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Argument {
    /// Its name in the packet dictionary.
    pub name: &'static str,
    /// Its type.
    pub word: WordType,
    /// How many words.
    pub count: usize,
    /// Its unit, empty if none.
    pub unit: &'static str,
    /// What it is.
    pub description: &'static str,
}

/// A command of the ground, as the packet dictionary describes it ([`COMMANDS`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Definition {
    /// Its mnemonic.
    pub name: &'static str,
    /// Its function ID ([`crate::uplink::kind`]).
    pub code: u16,
    /// The APID of the node that owns it.
    pub apid: Apid,
    /// What it does.
    pub description: &'static str,
    /// Its arguments, in order: their words add up to [`arity`] of the code.
    pub arguments: &'static [Argument],
}

const fn word(
    name: &'static str,
    word: WordType,
    unit: &'static str,
    description: &'static str,
) -> Argument {
    Argument {
        name,
        word,
        count: 1,
        unit,
        description,
    }
}

/// The quaternion of a track or slew: scalar first, TEME → body ([`crate::attitude`]).
const QUATERNION: [Argument; 4] = [
    word(
        "Q0",
        WordType::F32,
        "",
        "attitude quaternion, scalar part (TEME to body)",
    ),
    word("Q1", WordType::F32, "", "attitude quaternion, x"),
    word("Q2", WordType::F32, "", "attitude quaternion, y"),
    word("Q3", WordType::F32, "", "attitude quaternion, z"),
];

/// The index and kind of a part (mark failed, restore).
const PART: [Argument; 2] = [
    word("INDEX", WordType::U32, "", "tile or coil index"),
    word(
        "PART",
        WordType::U32,
        "",
        "0 a tile (with its devices and its wheel), 1 a coil",
    ),
];

/// Every command the ground sends: the source of the packet dictionary
/// (`ground/cosmos`, [`crate::uplink`]'s table), checked against [`arity`] and the codes by
/// the tests.
pub const COMMANDS: [Definition; 9] = [
    Definition {
        name: "SUN_SAFE",
        code: kind::SUN_SAFE,
        apid: ATTITUDE_TC_APID,
        description: "back to sun-safe",
        arguments: &[],
    },
    Definition {
        name: "TRACK",
        code: kind::TRACK,
        apid: REFERENCE_TC_APID,
        description: "track an attitude",
        arguments: &QUATERNION,
    },
    Definition {
        name: "SLEW",
        code: kind::SLEW,
        apid: REFERENCE_TC_APID,
        description: "slew to an attitude, then track it",
        arguments: &[
            QUATERNION[0],
            QUATERNION[1],
            QUATERNION[2],
            QUATERNION[3],
            word("WITHIN", WordType::F32, "s", "time allowed"),
        ],
    },
    Definition {
        name: "ELEMENTS",
        code: kind::ELEMENTS,
        apid: REFERENCE_TC_APID,
        description: "a new SGP4 element set, initialised on the ground (acs elements)",
        arguments: &[Argument {
            name: "WORDS",
            word: WordType::U32,
            count: ARG_WORDS,
            unit: "",
            description: "the words of Sgp4::to_words",
        }],
    },
    Definition {
        name: "CLOCK",
        code: kind::CLOCK,
        apid: REFERENCE_TC_APID,
        description: "set the on-board clock (UTC)",
        arguments: &[
            word("DAY", WordType::I32, "d", "days since 2000-01-01"),
            word("SECOND", WordType::U32, "s", "second of the day"),
            word("NANO", WordType::U32, "ns", "nanoseconds"),
        ],
    },
    Definition {
        name: "MARK_FAILED",
        code: kind::MARK_FAILED,
        apid: ATTITUDE_TC_APID,
        description: "mark a tile or a coil failed",
        arguments: &PART,
    },
    Definition {
        name: "RESTORE",
        code: kind::RESTORE,
        apid: ATTITUDE_TC_APID,
        description: "return a tile or a coil to service",
        arguments: &PART,
    },
    Definition {
        name: "REF_HOUSEKEEPING",
        code: kind::HOUSEKEEPING,
        apid: REFERENCE_TC_APID,
        description: "set the reference node's housekeeping interval",
        arguments: &HOUSEKEEPING,
    },
    Definition {
        name: "ATT_HOUSEKEEPING",
        code: kind::HOUSEKEEPING,
        apid: ATTITUDE_TC_APID,
        description: "set the attitude node's housekeeping interval",
        arguments: &HOUSEKEEPING,
    },
];

/// The housekeeping interval (both nodes own the command, each for itself).
const HOUSEKEEPING: [Argument; 1] = [word(
    "PERIODS",
    WordType::U32,
    "periods",
    "control periods between housekeeping reports: 0 none, at most 3600 (reset: 10)",
)];

/// The number of argument words of command `code`, `None` for an unknown code.
pub const fn arity(code: u16) -> Option<usize> {
    match code {
        kind::SUN_SAFE => Some(0),
        kind::TRACK => Some(4),
        kind::SLEW => Some(5),
        kind::ELEMENTS => Some(ARG_WORDS),
        kind::CLOCK => Some(3),
        kind::MARK_FAILED | kind::RESTORE => Some(2),
        kind::HOUSEKEEPING => Some(1),
        _ => None,
    }
}

/// The CUC time of the TM time field ([`pus::CucTime`]: seconds since the clock's epoch
/// 2000-01-01T00:00 UTC, day 0 of [`Epoch`], and 2⁻¹⁶ s), and the time reference status: 1
/// with a clock, 0 (and time 0) without one or before the epoch. The fraction is the
/// nanoseconds over 15 259, within one unit (15.3 µs) below the exact fraction
/// (`cuc_fraction_bound`).
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
pub fn cuc(clock: Option<Epoch<Utc>>) -> (CucTime, u8) {
    match clock {
        // within the 32-bit count: no overflow
        Some(t) if t.day() >= 0 && CUC_DAYS > t.day() => (
            CucTime {
                seconds: t.day() as u32 * 86_400 + t.second_of_day(),
                fraction: (t.nano() / 15_259) as u16,
            },
            1,
        ),
        _ => (CucTime::default(), 0),
    }
}

/// The days of the CUC's 32-bit seconds count, whole (to 2136-02-06).
const CUC_DAYS: i32 = (u32::MAX / 86_400) as i32;

/// The command code and argument words of an accepted telecommand's application data.
fn command(data: &[u8], args: &mut [u32; ARG_WORDS]) -> Result<u16, UplinkError> {
    let ([f0, f1], words) = data
        .split_first_chunk::<FUNCTION_ID_LEN>()
        .map(|(f, w)| (*f, w))
        .ok_or(UplinkError::UnknownCommand(0))?;
    let code = u16::from_be_bytes([f0, f1]);
    let n = arity(code).ok_or(UplinkError::UnknownCommand(code))?;
    if words.len() != 4 * n {
        return Err(UplinkError::ArgumentCount(code));
    }
    for (a, w) in args.iter_mut().zip(words.chunks_exact(4)) {
        let [b0, b1, b2, b3] = *w.first_chunk::<4>().unwrap_or(&[0; 4]);
        *a = u32::from_be_bytes([b0, b1, b2, b3]);
    }
    Ok(code)
}

/// Takes the telecommand `packet` for the node of `apid` (see the [module docs](self)):
/// decodes it, applies it with `apply` (the command code and its argument words; the words
/// beyond the command's are 0), and writes its verification reports to `out`; returns the
/// bytes written. `clock` is the node's clock as it takes the packet, `count` its TM sequence
/// counter (one count per report). Never panics, whatever the bytes.
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
pub fn take(
    packet: &[u8],
    apid: Apid,
    clock: Option<Epoch<Utc>>,
    count: &mut SequenceCounter,
    out: &mut [u8; REPORTS_LEN],
    apply: impl FnOnce(u16, &[u32; ARG_WORDS]) -> Result<(), UplinkError>,
) -> usize {
    let mut args = [0u32; ARG_WORDS];
    let (source, outcome) = match decode_tc(packet, apid) {
        Err(e) => (0, Err(e.failure_code())),
        Ok(tc) => (
            tc.source_id,
            if (tc.service, tc.subtype) != (SERVICE, SUBTYPE) {
                Err(failure::MESSAGE_TYPE)
            } else {
                command(tc.app_data, &mut args)
                    .and_then(|code| apply(code, &args))
                    .map(|()| tc.ack)
                    .map_err(|e| failure::COMMAND + e.status())
            },
        ),
    };
    // the reports, in their order: a failure alone, or the successes the flags ask for
    let (code, ack) = match outcome {
        Err(code) => (code, AckFlags::NONE),
        Ok(ack) => (0, ack),
    };
    let reports = [
        (code != 0, Verification::AcceptanceFailed { code }),
        (ack.contains(AckFlags::ACCEPTANCE), Verification::Accepted),
        (ack.contains(AckFlags::COMPLETION), Verification::Completed),
    ];
    let (time, time_status) = cuc(clock);
    // the packet's first four bytes as received, zeros if it has fewer
    let request = RequestId::of_packet(packet).unwrap_or(RequestId {
        packet_id: 0,
        sequence_control: 0,
    });
    let mut written = 0;
    for (_, report) in reports.iter().filter(|(sent, _)| *sent) {
        let header = TmHeader {
            apid,
            sequence_count: count.next_count(),
            time_status,
            message_counter: 0,
            destination_id: source,
            time,
        };
        let rest = out.get_mut(written..).unwrap_or_default();
        // out holds both reports: never an error
        written += verification_report(&header, request, report, rest).unwrap_or(0);
    }
    written
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The CUC fraction: within one unit below the exact 2⁻¹⁶ s fraction, over every
    /// millisecond and the nanoseconds next to the ends.
    #[test]
    fn cuc_fraction_bound() {
        let check = |nano: u32| {
            let t = Epoch::from_parts(1, 2, nano).ok();
            let (cuc, status) = cuc(t);
            assert_eq!((cuc.seconds, status), (86_402, 1));
            let exact = (u64::from(nano) << 16) / 1_000_000_000;
            let got = u64::from(cuc.fraction);
            assert!(got <= exact && exact - got <= 1, "{nano}: {got} {exact}");
        };
        for ms in 0..1000 {
            check(ms * 1_000_000);
        }
        for nano in (0..1000).chain(999_999_000..1_000_000_000) {
            check(nano);
        }
    }

    #[test]
    fn the_definitions_are_the_codes_and_their_words() {
        let mut codes: [u16; 9] = COMMANDS.map(|d| d.code);
        codes.sort_unstable();
        assert_eq!(codes, [1, 2, 3, 4, 5, 6, 7, 8, 8]);
        for d in COMMANDS {
            let words: usize = d.arguments.iter().map(|a| a.count).sum();
            assert_eq!(Some(words), arity(d.code), "{}", d.name);
        }
        assert!(arity(0).is_none() && arity(9).is_none());
    }

    #[test]
    fn cuc_without_a_clock() {
        assert_eq!(cuc(None), (CucTime::default(), 0));
        assert_eq!(
            cuc(Epoch::from_parts(-1, 0, 0).ok()),
            (CucTime::default(), 0)
        );
    }
}
