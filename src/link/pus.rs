//! ECSS PUS-C packets: the ground's telecommands in, the nodes' reports out (issue 31, items 2
//! and 3).
//!
//! The Packet Utilisation Standard, ECSS-E-ST-70-41C (15 April 2016), puts a *secondary header*
//! at the start of a CCSDS space packet's user data (CCSDS 133.0-B-2 §4.1.4.2), then the
//! application data. This module reads the telecommand (TC) secondary header and writes the
//! telemetry (TM) one, on caller-provided byte buffers, with no allocation; the primary header
//! and the CRC are [`space_packet`]'s ([`space_packet::decode`], [`space_packet::encode_in_place`])
//! and [`crc16`](crate::link::crc16)'s, not repeated here. The ground tool builds and reads the
//! same bytes with the `spacepackets` crate (tests: `tests/pus.rs`, both ways).
//!
//! # The two secondary headers
//! Big-endian, most significant bit first. ECSS numbers a field's bits from 0 for its most
//! significant (first transmitted) bit.
//!
//! | TC secondary header (5 B) | bits | ECSS-E-ST-70-41C | here |
//! |---|---:|---|---|
//! | TC packet PUS version number | 4 | 7.4.4.1c | 2 (PUS-C); anything else refused ([`PusError::Version`]) |
//! | acknowledgement flags | 4 | 7.4.4.1d | [`AckFlags`]: bit 3 (the last) acceptance, bit 0 (the first) completion |
//! | service type ID | 8 | 7.4.4.1e, 5.3.3 | [`Telecommand::service`] |
//! | message subtype ID | 8 | 7.4.4.1f | [`Telecommand::subtype`] |
//! | source ID | 16 | 7.4.4.1g | [`Telecommand::source_id`] |
//! | (spare) | 0 | 7.4.4.1h | none: this mission's TC header has no spare field |
//!
//! | TM secondary header (13 B) | bits | ECSS-E-ST-70-41C | here |
//! |---|---:|---|---|
//! | TM packet PUS version number | 4 | 7.4.3.1c | 2 |
//! | spacecraft time reference status | 4 | 7.4.3.1d | [`TmHeader::time_status`] (0–15, the clock's state: the caller's) |
//! | service type ID | 8 | 7.4.3.1e | 1, 3, 5 |
//! | message subtype ID | 8 | 7.4.3.1f | see below |
//! | message type counter | 16 | 7.4.3.1g | [`TmHeader::message_counter`] (the caller's count for this destination and type) |
//! | destination ID | 16 | 7.4.3.1h | [`TmHeader::destination_id`] |
//! | time | 48 | 7.4.3.1i | [`CucTime`]: CUC, 4 octets of seconds, 2 of fraction, preamble implicit |
//!
//! The packet error control (CRC-16, annex B.1) is always present (7.4.3.2, 7.4.4.2).
//! Clause numbers of ECSS-E-ST-70-41C: 7.4.3 the TM packet, 7.4.4 the TC packet (their
//! requirement letters in field order), clause 6 the services' requirements (6.1 request
//! verification, 6.3 housekeeping, 6.5 event reporting), clause 8 their messages (8.1, 8.3, 8.5).
//! The standard's text was not at hand when this was written: the clause numbers are those an
//! independent implementation cites for the same fields (its PUS version at 7.4.3.1c and
//! 7.4.4.1c, its acknowledgement flags at 7.4.4.1d with acceptance in the last bit), not read
//! from the standard; the field layouts are checked against `spacepackets` (`tests/pus.rs`).
//!
//! ## Why the time field is CUC 4+2
//! CCSDS 301.0-B-4 §3.2's unsegmented code (CUC) is a binary count of seconds and binary
//! fractions: the on-board clock's own form (a seconds counter and a timer), so writing it costs
//! two big-endian stores and no calendar arithmetic on the node, where the CDS code (days,
//! milliseconds) would need a division. Four octets of seconds last 136 years from any epoch;
//! two octets of fraction resolve 2⁻¹⁶ s = 15.3 µs, far finer than the 1 s control step and the
//! UART's 1 ms a byte. Three octets of seconds would last 194 days, too short for a mission; one
//! octet of fraction (3.9 ms) would still order the reports, but the second keeps both parts
//! whole 16-bit words of the MSP430 for one byte a packet. The preamble (P-field) is implicit,
//! as ECSS-E-ST-70-41C allows for the packet time field, and not sent: [`CUC_P_FIELD`] is
//! what it would be (`0x2E`: CUC, agency-defined epoch, 4 + 2 octets), for the packet dictionary.
//! The epoch is the on-board clock's, the mission's choice (with this crate's clock, day 0 of
//! [`crate::time::Epoch`], 2000-01-01T00:00); the ground maps it to UTC with the clock's
//! correlation.
//!
//! # Telecommands: [`decode_tc`]
//! Takes exactly one packet (as the link delivers it) and the node's APID; refuses, in this
//! order, what [`space_packet::decode`] refuses ([`PusError::Packet`]: length, CRC, version,
//! segmentation, APID), a telemetry packet ([`PusError::WrongPacketType`]), a packet without the
//! secondary header flag ([`PusError::NoSecondaryHeader`]), a data field shorter than the
//! secondary header ([`PusError::TooShort`]) and a PUS version other than 2
//! ([`PusError::Version`]). It hands back the [`Telecommand`]: its [`RequestId`], ack flags,
//! service, subtype, source ID and application data (a slice of the packet). Which services and
//! subtypes a node serves is the node's business: it answers an unknown one with
//! [`Telecommand::not_served`] in a TM\[1,2\]. Every refusal has a [`PusError::failure_code`]
//! for that report; a packet refused before its header could be trusted still has the
//! [`RequestId`] of its first four bytes ([`RequestId::of_packet`]).
//!
//! # Reports: [`verification_report`], [`housekeeping_report`], [`event_report`]
//! Each writes one whole TM packet (primary header, secondary header, application data, CRC) to
//! the start of `out` and returns its length, [`tm_packet_len`]`(application data)`:
//!
//! | report | ECSS-E-ST-70-41C | application data |
//! |---|---|---|
//! | TM\[1,1\] successful acceptance | 6.1, 8.1.2.1 | request ID (4 B) |
//! | TM\[1,2\] failed acceptance | 6.1, 8.1.2.2 | request ID, failure code (16 bits) |
//! | TM\[1,7\] successful completion of execution | 6.1, 8.1.2.7 | request ID |
//! | TM\[1,8\] failed completion of execution | 6.1, 8.1.2.8 | request ID, failure code |
//! | TM\[3,25\] housekeeping parameter report | 6.3, 8.3.2 | structure ID (16 bits), parameter values (the caller's bytes) |
//! | TM\[5,1..4\] informative / low / medium / high severity event report | 6.5, 8.5.2.1–8.5.2.4 | event definition ID (16 bits), auxiliary data |
//!
//! The request ID is the TC's packet ID and packet sequence control, the first four bytes of the
//! TC as received (6.1: packet version number, type, secondary header flag, APID, sequence
//! flags, sequence count). The failure code, the structure ID and the event ID are enumerations
//! whose width the mission chooses; here all three are 16 bits (one MSP430 word), declared once
//! for the packet dictionary. On error `out` is unchanged.
//!
//! ```
//! use acs::link::pus::{decode_tc, encode_tc, verification_report, AckFlags, CucTime, TcHeader,
//!     TmHeader, Verification, tm_packet_len, REQUEST_ID_LEN};
//! use acs::link::space_packet::{packet_len, Apid};
//! let apid = Apid::new(0x42).unwrap();
//! // the ground: TC\[17,1\] (are you alive), acceptance and completion to be reported
//! let tc = TcHeader { apid, sequence_count: 9, ack: AckFlags::ACCEPTANCE.with(AckFlags::COMPLETION),
//!     service: 17, subtype: 1, source_id: 3 };
//! let mut packet = [0u8; 13];
//! let n = encode_tc(&tc, &[], &mut packet).unwrap();
//! // the node
//! let request = decode_tc(&packet[..n], apid).unwrap();
//! assert_eq!((request.service, request.subtype, request.app_data), (17, 1, &[][..]));
//! let tm = TmHeader { apid, sequence_count: 0, time_status: 0, message_counter: 0,
//!     destination_id: request.source_id, time: CucTime { seconds: 812_345_678, fraction: 0x8000 } };
//! let mut report = [0u8; tm_packet_len(REQUEST_ID_LEN)];
//! let n = verification_report(&tm, request.request_id, &Verification::Accepted, &mut report).unwrap();
//! assert_eq!(n, 25);
//! ```
//!
//! # Left out, deliberately
//! - Services other than 1, 3 and 5, and their telecommands (3's create/enable/rate requests,
//!   5's enable/disable): the node dispatches on [`Telecommand::service`] and parses its own
//!   application data.
//! - TM\[1,3..6\] (start and progress of execution): every command of this ACS completes within
//!   the step that accepts it, so acceptance and completion say everything.
//! - The message type counter's bookkeeping (one count per destination and type): a caller's
//!   `u16`, 0 if the mission does not count.
//! - Segmented packets, packets without a CRC, the TC spare field, a transmitted P-field: all
//!   refused or never written.
//!
//! # Flash and stack
//! Linked into both node images with [`crate::uplink::telecommand::take`] (nightly-2026-05-20,
//! the flight builds: `acs-reference` at opt-level "s", `acs-attitude` at "z", LTO,
//! `fg4619-map`), the decoder, service 1 and the node's handling cost 1 452 B on the reference
//! node and 1 492 B on the attitude node when they replaced the mailbox uplink (44 400 → 45 852 B
//! and 44 404 → 45 896 B; paid for since by smaller code elsewhere: `docs/operations.md`). By
//! symbol, as the images fly: the node's `take` 1 240 and 1 488 B (the checks, the command's
//! words, its application inlined, the CUC time, the reports), [`space_packet::decode`] out of
//! line 334 and 342 B (the link's message decoding, which had inlined it, shrank), the
//! mailbox's handling (`acs_firmware::flight::take_telecommand`) 158 and 132 B. Services 3 and 5
//! measured 348 B more with a probe. No constant tables. Static RAM +66 B and −146 B (the
//! mailboxes: 248 B and 36 B of telecommand, 50 B of reports, for 232 B of argument words).
//!
//! [`space_packet`]: crate::link::space_packet
//! [`space_packet::decode`]: crate::link::space_packet::decode
//! [`space_packet::encode_in_place`]: crate::link::space_packet::encode_in_place

use core::fmt;

use super::space_packet::{
    self, encode_in_place, encoded_len, Apid, PacketError, PacketHeader, PacketType,
    PRIMARY_HEADER_LEN,
};

/// The PUS version number of ECSS-E-ST-70-41C (PUS-C) in both secondary headers.
pub const PUS_VERSION: u8 = 2;
/// Bytes of the TC secondary header.
pub const TC_SECONDARY_HEADER_LEN: usize = 5;
/// Bytes of the TM time field ([`CucTime`]: 4 octets of seconds, 2 of fraction).
pub const TIME_LEN: usize = 6;
/// Bytes of the TM secondary header: version and time status, service, subtype, message type
/// counter, destination ID, time.
pub const TM_SECONDARY_HEADER_LEN: usize = 7 + TIME_LEN;
/// Bytes a TM packet adds to its application data: primary header, secondary header, CRC.
pub const TM_OVERHEAD: usize = space_packet::OVERHEAD + TM_SECONDARY_HEADER_LEN;
/// Bytes a TC packet adds to its application data.
pub const TC_OVERHEAD: usize = space_packet::OVERHEAD + TC_SECONDARY_HEADER_LEN;
/// Bytes of a request ID (packet ID and packet sequence control).
pub const REQUEST_ID_LEN: usize = 4;
/// The P-field a CUC reader needs for [`CucTime`] (not transmitted): `0` (no extension),
/// `010` (CUC with an agency-defined epoch), `11` (4 octets of seconds), `10` (2 of fraction).
pub const CUC_P_FIELD: u8 = 0x2E;

/// The length of the TM packet that carries `app_data_len` bytes of application data: for
/// sizing buffers.
pub const fn tm_packet_len(app_data_len: usize) -> usize {
    app_data_len + TM_OVERHEAD
}

/// The service types of this module's reports.
pub mod service {
    /// Request verification.
    pub const VERIFICATION: u8 = 1;
    /// Housekeeping.
    pub const HOUSEKEEPING: u8 = 3;
    /// Event reporting.
    pub const EVENT: u8 = 5;
    /// TM\[3,25\]: the housekeeping parameter report's subtype.
    pub const HOUSEKEEPING_REPORT: u8 = 25;
}

/// The four acknowledgement flags of a telecommand (7.4.4.1d): which verification reports the
/// sender asks for. In ECSS bit numbering (bit 0 first), bit 3, the field's least significant
/// bit, asks for acceptance and bit 0, its most significant, for completion (the layout of
/// PUS-A's table, kept by PUS-C).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct AckFlags(u8);

impl AckFlags {
    /// No report asked for.
    pub const NONE: AckFlags = AckFlags(0);
    /// Successful acceptance (TM\[1,1\]); failures are always reported.
    pub const ACCEPTANCE: AckFlags = AckFlags(0b0001);
    /// Successful start of execution (TM\[1,3\]).
    pub const START: AckFlags = AckFlags(0b0010);
    /// Successful progress of execution (TM\[1,5\]).
    pub const PROGRESS: AckFlags = AckFlags(0b0100);
    /// Successful completion of execution (TM\[1,7\]).
    pub const COMPLETION: AckFlags = AckFlags(0b1000);
    /// All four.
    pub const ALL: AckFlags = AckFlags(0b1111);

    /// The flags of the field's 4 bits (the low 4 bits of `bits`).
    pub const fn from_bits(bits: u8) -> AckFlags {
        AckFlags(bits & 0x0F)
    }

    /// The field's 4 bits.
    pub const fn bits(self) -> u8 {
        self.0
    }

    /// These flags and `other`'s.
    pub const fn with(self, other: AckFlags) -> AckFlags {
        AckFlags(self.0 | other.0)
    }

    /// Whether every flag of `other` is set.
    pub const fn contains(self, other: AckFlags) -> bool {
        self.0 & other.0 == other.0
    }
}

/// A telecommand's request ID: its packet ID (version, type, secondary header flag, APID) and
/// packet sequence control (sequence flags, count), its first four bytes as received, which
/// every verification report repeats (ECSS-E-ST-70-41C 6.1).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RequestId {
    /// The packet ID: the primary header's first 16 bits.
    pub packet_id: u16,
    /// The packet sequence control: its next 16 bits.
    pub sequence_control: u16,
}

impl RequestId {
    /// The request ID of the first four bytes of `packet`, whatever they hold, `None` for fewer
    /// than four bytes: for the TM\[1,2\] of a packet [`decode_tc`] refused before its header
    /// could be trusted (a CRC or length error), as 6.1 asks for a request that could not be
    /// accepted.
    pub fn of_packet(packet: &[u8]) -> Option<RequestId> {
        let [p0, p1, s0, s1] = *packet.first_chunk::<REQUEST_ID_LEN>()?;
        Some(RequestId {
            packet_id: u16::from_be_bytes([p0, p1]),
            sequence_control: u16::from_be_bytes([s0, s1]),
        })
    }

    /// Its four bytes, as a report carries them.
    pub fn to_bytes(self) -> [u8; REQUEST_ID_LEN] {
        let [p0, p1] = self.packet_id.to_be_bytes();
        let [s0, s1] = self.sequence_control.to_be_bytes();
        [p0, p1, s0, s1]
    }
}

/// A decoded telecommand ([`decode_tc`]): a slice of the packet, nothing copied.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Telecommand<'a> {
    /// Its request ID, for the verification reports.
    pub request_id: RequestId,
    /// The reports the sender asks for.
    pub ack: AckFlags,
    /// The service type ID.
    pub service: u8,
    /// The message subtype ID.
    pub subtype: u8,
    /// The source ID: who sent it (the destination ID of its reports).
    pub source_id: u16,
    /// The application data (between the secondary header and the CRC).
    pub app_data: &'a [u8],
}

impl Telecommand<'_> {
    /// The refusal of a telecommand whose service and subtype the node does not serve, for its
    /// TM\[1,2\] ([`PusError::UnknownMessageType`], failure code [`failure::MESSAGE_TYPE`]).
    pub fn not_served(&self) -> PusError {
        PusError::UnknownMessageType {
            service: self.service,
            subtype: self.subtype,
        }
    }
}

/// The fields of a telecommand a sender chooses ([`encode_tc`]: the ground, tests, the PIL).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TcHeader {
    /// The APID of the application process it is for.
    pub apid: Apid,
    /// The sender's packet sequence count, 0–16383.
    pub sequence_count: u16,
    /// The reports asked for.
    pub ack: AckFlags,
    /// The service type ID.
    pub service: u8,
    /// The message subtype ID.
    pub subtype: u8,
    /// The source ID.
    pub source_id: u16,
}

/// A time of the on-board clock as the TM time field carries it (CCSDS 301.0-B-4 §3.2, CUC
/// with 4 octets of seconds and 2 of binary fraction, P-field [`CUC_P_FIELD`] implicit).
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CucTime {
    /// Whole seconds since the clock's epoch.
    pub seconds: u32,
    /// The fraction of the second, in units of 2⁻¹⁶ s.
    pub fraction: u16,
}

/// The fields of a TM packet that a reporting node chooses; the service, subtype and
/// application data are the report's.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TmHeader {
    /// The reporting application process.
    pub apid: Apid,
    /// Its packet sequence count, 0–16383 ([`crate::link::sequence`]).
    pub sequence_count: u16,
    /// The spacecraft time reference status, 0–15 (7.4.3.1d; 0 if the mission does not use
    /// it); anything larger is refused ([`PusError::TimeStatus`]).
    pub time_status: u8,
    /// The message type counter (7.4.3.1g).
    pub message_counter: u16,
    /// The destination ID: the source ID of the telecommand a report answers.
    pub destination_id: u16,
    /// When the report was made.
    pub time: CucTime,
}

/// A TM\[1,x\] verification report's kind and, for a failure, its failure notice.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Verification {
    /// TM\[1,1\]: the request passed its checks.
    Accepted,
    /// TM\[1,2\]: the request was refused (nothing changed).
    AcceptanceFailed {
        /// Why ([`PusError::failure_code`], or the command's own codes).
        code: u16,
    },
    /// TM\[1,7\]: the request was carried out.
    Completed,
    /// TM\[1,8\]: the request failed while being carried out.
    CompletionFailed {
        /// Why.
        code: u16,
    },
}

impl Verification {
    /// The report's message subtype: 1, 2, 7 or 8.
    pub fn subtype(&self) -> u8 {
        match self {
            Self::Accepted => 1,
            Self::AcceptanceFailed { .. } => 2,
            Self::Completed => 7,
            Self::CompletionFailed { .. } => 8,
        }
    }
}

/// An event report's severity: its TM\[5,x\] subtype (ECSS-E-ST-70-41C 6.5).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum Severity {
    /// TM\[5,1\] informative event report (a mode change, a fault cleared).
    Informative = 1,
    /// TM\[5,2\] low severity anomaly report.
    Low = 2,
    /// TM\[5,3\] medium severity anomaly report.
    Medium = 3,
    /// TM\[5,4\] high severity anomaly report.
    High = 4,
}

/// Why a packet is not an acceptable telecommand, or why a report could not be written.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum PusError {
    /// The space packet layer's refusal ([`space_packet::decode`] or
    /// [`space_packet::encode`]: length, CRC, version, segmentation, APID, buffer, count).
    Packet(PacketError),
    /// Decoding: a packet of the other type (a telemetry packet where a telecommand was
    /// expected, or the reverse).
    WrongPacketType,
    /// Decoding: the secondary header flag is not set.
    NoSecondaryHeader,
    /// Decoding: the user data is shorter than the secondary header.
    TooShort {
        /// Bytes of user data (secondary header and application data).
        len: usize,
    },
    /// Decoding: a PUS version other than 2.
    Version(u8),
    /// Encoding: a spacecraft time reference status beyond 4 bits.
    TimeStatus(u8),
    /// A service and subtype the receiving node does not serve (the caller's verdict, for its
    /// TM\[1,2\]).
    UnknownMessageType {
        /// The service type ID.
        service: u8,
        /// The message subtype ID.
        subtype: u8,
    },
}

impl From<PacketError> for PusError {
    fn from(e: PacketError) -> PusError {
        PusError::Packet(e)
    }
}

/// The failure codes of TM\[1,2\] for the refusals of this layer ([`PusError::failure_code`]).
/// A command's own refusals take codes from [`failure::COMMAND`] up.
pub mod failure {
    /// The packet's length field disagrees with its length, or it is too short.
    pub const LENGTH: u16 = 1;
    /// The CRC does not match.
    pub const CRC: u16 = 2;
    /// A packet version other than 0, or a segmented packet.
    pub const PACKET_FORMAT: u16 = 3;
    /// Another application process's packet.
    pub const APID: u16 = 4;
    /// Not a telecommand, or no secondary header.
    pub const PACKET_TYPE: u16 = 5;
    /// A PUS version other than 2.
    pub const PUS_VERSION: u16 = 6;
    /// A service or subtype the node does not serve.
    pub const MESSAGE_TYPE: u16 = 7;
    /// Anything else of this layer (an encoding error).
    pub const OTHER: u16 = 8;
    /// The first code of the commands' own refusals (their application data's checks).
    pub const COMMAND: u16 = 0x100;
}

impl PusError {
    /// The failure code of the TM\[1,2\] that reports this refusal ([`failure`]).
    pub fn failure_code(&self) -> u16 {
        match self {
            Self::Packet(PacketError::TooShort { .. } | PacketError::LengthMismatch { .. })
            | Self::TooShort { .. } => failure::LENGTH,
            Self::Packet(PacketError::Crc { .. }) => failure::CRC,
            Self::Packet(PacketError::Version(_) | PacketError::SequenceFlags(_)) => {
                failure::PACKET_FORMAT
            }
            Self::Packet(PacketError::WrongApid { .. }) => failure::APID,
            Self::WrongPacketType | Self::NoSecondaryHeader => failure::PACKET_TYPE,
            Self::Version(_) => failure::PUS_VERSION,
            Self::UnknownMessageType { .. } => failure::MESSAGE_TYPE,
            _ => failure::OTHER,
        }
    }
}

impl fmt::Display for PusError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Packet(e) => write!(f, "{e}"),
            Self::WrongPacketType => write!(f, "a packet of the other type (TM or TC)"),
            Self::NoSecondaryHeader => write!(f, "no PUS secondary header"),
            Self::TooShort { len } => {
                write!(
                    f,
                    "{len} bytes of user data: shorter than the secondary header"
                )
            }
            Self::Version(v) => write!(f, "PUS version {v}, not 2"),
            Self::TimeStatus(s) => write!(f, "time reference status {s} beyond 4 bits"),
            Self::UnknownMessageType { service, subtype } => {
                write!(f, "TC[{service},{subtype}] not served")
            }
        }
    }
}

/// The telecommand in `packet` (exactly one space packet), if it is an intact PUS-C
/// telecommand for `apid`. Errors, in this order: [`PusError::Packet`] (what
/// [`space_packet::decode`] refuses), [`PusError::WrongPacketType`],
/// [`PusError::NoSecondaryHeader`], [`PusError::TooShort`], [`PusError::Version`].
#[cfg_attr(target_arch = "msp430", optimize(size))]
pub fn decode_tc(packet: &[u8], apid: Apid) -> Result<Telecommand<'_>, PusError> {
    let (header, data) = space_packet::decode(packet, apid)?;
    if header.packet_type != PacketType::Telecommand {
        return Err(PusError::WrongPacketType);
    }
    if !header.secondary_header {
        return Err(PusError::NoSecondaryHeader);
    }
    let ([v, service, subtype, i0, i1], app_data) = data
        .split_first_chunk::<TC_SECONDARY_HEADER_LEN>()
        .map(|(h, rest)| (*h, rest))
        .ok_or(PusError::TooShort { len: data.len() })?;
    let version = v >> 4;
    if version != PUS_VERSION {
        return Err(PusError::Version(version));
    }
    // decode accepted at least the primary header: the request ID is there
    let request_id = RequestId::of_packet(packet).ok_or(PusError::TooShort { len: 0 })?;
    Ok(Telecommand {
        request_id,
        ack: AckFlags::from_bits(v),
        service,
        subtype,
        source_id: u16::from_be_bytes([i0, i1]),
        app_data,
    })
}

/// The primary header fields of a TM packet of `header`.
#[inline(always)]
fn tm_primary(header: &TmHeader) -> PacketHeader {
    PacketHeader {
        packet_type: PacketType::Telemetry,
        secondary_header: true,
        apid: header.apid,
        sequence_count: header.sequence_count,
    }
}

/// The TM secondary header of `header` for `service` and `subtype`; refused
/// ([`PusError::TimeStatus`]) for a time reference status beyond 4 bits.
#[inline(always)]
fn secondary_header(
    header: &TmHeader,
    service: u8,
    subtype: u8,
) -> Result<[u8; TM_SECONDARY_HEADER_LEN], PusError> {
    if header.time_status > 0x0F {
        return Err(PusError::TimeStatus(header.time_status));
    }
    let [c0, c1] = header.message_counter.to_be_bytes();
    let [d0, d1] = header.destination_id.to_be_bytes();
    let [t0, t1, t2, t3] = header.time.seconds.to_be_bytes();
    let [f0, f1] = header.time.fraction.to_be_bytes();
    Ok([
        (PUS_VERSION << 4) | header.time_status,
        service,
        subtype,
        c0,
        c1,
        d0,
        d1,
        t0,
        t1,
        t2,
        t3,
        f0,
        f1,
    ])
}

/// Writes the TM packet of `header`, service `service`, subtype `subtype` and application data
/// `prefix` followed by `data` to the start of `out`; returns its length
/// ([`tm_packet_len`]`(prefix.len() + data.len())`). The common writer of the three reports
/// (a report's fixed fields in `prefix`, the caller's bytes in `data`, so neither is copied
/// twice), public for reports of other services. Errors: [`PusError::TimeStatus`], then
/// [`space_packet::encode`]'s ([`PusError::Packet`]: count, length, buffer); on error `out` is
/// unchanged.
#[cfg_attr(target_arch = "msp430", optimize(size))]
pub fn encode_tm(
    header: &TmHeader,
    service: u8,
    subtype: u8,
    prefix: &[u8],
    data: &[u8],
    out: &mut [u8],
) -> Result<usize, PusError> {
    let secondary = secondary_header(header, service, subtype)?;
    let primary = tm_primary(header);
    let app_len = prefix.len().saturating_add(data.len());
    let data_len = app_len.saturating_add(TM_SECONDARY_HEADER_LEN);
    encoded_len(&primary, data_len, out.len())?;
    // encoded_len checked that out holds the packet: these writes all land
    if let Some((sec, app)) = out
        .get_mut(PRIMARY_HEADER_LEN..)
        .and_then(|u| u.split_first_chunk_mut::<TM_SECONDARY_HEADER_LEN>())
    {
        *sec = secondary;
        let (head, tail) = app.split_at_mut_checked(prefix.len()).unwrap_or_default();
        for (o, b) in head.iter_mut().zip(prefix) {
            *o = *b;
        }
        for (o, b) in tail.iter_mut().zip(data) {
            *o = *b;
        }
    }
    Ok(encode_in_place(&primary, data_len, out)?)
}

/// Writes the verification report TM\[1,1\], \[1,2\], \[1,7\] or \[1,8\] (`report`) on the
/// telecommand `request` to the start of `out`; returns its length ([`tm_packet_len`] of 4
/// bytes for a success, 6 for a failure: this mission's failure notices carry no failure data,
/// the code says it all). Errors as [`encode_tm`]. Written through [`finish_tm`], which the
/// node images' housekeeping and event reports share, not [`encode_tm`]'s general path.
#[cfg_attr(target_arch = "msp430", optimize(size))]
pub fn verification_report(
    header: &TmHeader,
    request: RequestId,
    report: &Verification,
    out: &mut [u8],
) -> Result<usize, PusError> {
    let code = match report {
        Verification::Accepted | Verification::Completed => None,
        Verification::AcceptanceFailed { code } | Verification::CompletionFailed { code } => {
            Some(*code)
        }
    };
    let app_len = if code.is_some() { 6 } else { REQUEST_ID_LEN };
    let [p0, p1, s0, s1] = request.to_bytes();
    let [c0, c1] = code.unwrap_or(0).to_be_bytes();
    finish_tm(
        header,
        service::VERIFICATION,
        report.subtype(),
        &[p0, p1, s0, s1, c0, c1],
        app_len,
        out,
    )
}

/// Bytes before a TM packet's application data: the primary and secondary headers.
pub const TM_DATA_OFFSET: usize = PRIMARY_HEADER_LEN + TM_SECONDARY_HEADER_LEN;

/// Writes the TM packet of `header`, service `service`, subtype `subtype` with `app_len` bytes
/// of application data that `fill` writes in place (it gets the packet's application data
/// field, `app_len` bytes at [`TM_DATA_OFFSET`]) to the start of `out`; returns its length.
/// For the reports of fixed layout ([`crate::telemetry`]): no copy, no intermediate buffer.
/// Errors as [`encode_tm`]; `fill` is called only if `out` holds the packet, and on error `out`
/// holds at most the application data.
#[inline(always)]
pub fn encode_tm_in_place(
    header: &TmHeader,
    service: u8,
    subtype: u8,
    app_len: usize,
    out: &mut [u8],
    fill: impl FnOnce(&mut [u8]),
) -> Result<usize, PusError> {
    // the CRC's two bytes must follow the data: else finish_tm refuses the buffer
    if out.len() >= TM_DATA_OFFSET.saturating_add(app_len).saturating_add(2) {
        if let Some(app) = out
            .get_mut(TM_DATA_OFFSET..)
            .and_then(|a| a.get_mut(..app_len))
        {
            fill(app);
        }
    }
    finish_tm(header, service, subtype, &[], app_len, out)
}

/// Completes the TM packet at the start of `out` of `header`, `service` and `subtype` with
/// `app_len` bytes of application data at [`TM_DATA_OFFSET`], the first of them copied from
/// `data` (at most `app_len`; the others the caller wrote there): its headers, the copy, and
/// its CRC; returns its length. Out of line: the one copy of the headers' code for the
/// verification reports and every report of fixed layout ([`encode_tm_in_place`]). Errors as
/// [`encode_tm`], checked before anything is written.
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
pub fn finish_tm(
    header: &TmHeader,
    service: u8,
    subtype: u8,
    data: &[u8],
    app_len: usize,
    out: &mut [u8],
) -> Result<usize, PusError> {
    let secondary = secondary_header(header, service, subtype)?;
    let primary = tm_primary(header);
    let data_len = app_len.saturating_add(TM_SECONDARY_HEADER_LEN);
    encoded_len(&primary, data_len, out.len())?;
    if let Some((sec, app)) = out
        .get_mut(PRIMARY_HEADER_LEN..)
        .and_then(|u| u.split_first_chunk_mut::<TM_SECONDARY_HEADER_LEN>())
    {
        *sec = secondary;
        for (o, b) in app.iter_mut().zip(data.iter().take(app_len)) {
            *o = *b;
        }
    }
    Ok(encode_in_place(&primary, data_len, out)?)
}

/// Writes the housekeeping parameter report TM\[3,25\] of structure `structure_id` with the
/// parameter values `parameters` (the structure's bytes, as the packet dictionary lays them
/// out) to the start of `out`; returns its length ([`tm_packet_len`]`(2 + parameters.len())`).
/// Errors as [`encode_tm`].
#[cfg_attr(target_arch = "msp430", optimize(size))]
pub fn housekeeping_report(
    header: &TmHeader,
    structure_id: u16,
    parameters: &[u8],
    out: &mut [u8],
) -> Result<usize, PusError> {
    encode_tm(
        header,
        service::HOUSEKEEPING,
        service::HOUSEKEEPING_REPORT,
        &structure_id.to_be_bytes(),
        parameters,
        out,
    )
}

/// Writes the event report TM\[5,`severity`\] of event `event_id` with auxiliary data `aux` to
/// the start of `out`; returns its length ([`tm_packet_len`]`(2 + aux.len())`). Errors as
/// [`encode_tm`].
#[cfg_attr(target_arch = "msp430", optimize(size))]
pub fn event_report(
    header: &TmHeader,
    severity: Severity,
    event_id: u16,
    aux: &[u8],
    out: &mut [u8],
) -> Result<usize, PusError> {
    encode_tm(
        header,
        service::EVENT,
        severity as u8,
        &event_id.to_be_bytes(),
        aux,
        out,
    )
}

/// Writes the PUS-C telecommand of `header` with application data `app_data` to the start of
/// `out`; returns its length (`app_data.len()` + [`TC_OVERHEAD`]). What the ground sends; on
/// the nodes for tests and the processor-in-the-loop rehearsal, not for flight. Errors:
/// [`space_packet::encode`]'s; on error `out` is unchanged.
pub fn encode_tc(header: &TcHeader, app_data: &[u8], out: &mut [u8]) -> Result<usize, PusError> {
    let primary = PacketHeader {
        packet_type: PacketType::Telecommand,
        secondary_header: true,
        apid: header.apid,
        sequence_count: header.sequence_count,
    };
    let data_len = app_data.len().saturating_add(TC_SECONDARY_HEADER_LEN);
    let len = encoded_len(&primary, data_len, out.len())?;
    let [s0, s1] = header.source_id.to_be_bytes();
    let secondary = [
        (PUS_VERSION << 4) | header.ack.bits(),
        header.service,
        header.subtype,
        s0,
        s1,
    ];
    let user = out
        .get_mut(PRIMARY_HEADER_LEN..len - space_packet::CRC_LEN)
        .unwrap_or_default();
    for (o, b) in user.iter_mut().zip(secondary.iter().chain(app_data)) {
        *o = *b;
    }
    Ok(encode_in_place(&primary, data_len, out)?)
}

/// A TM packet as [`decode_tm`] reads it: the header fields, service, subtype and application
/// data (a slice of the packet).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Telemetry<'a> {
    /// The header (APID, count, time status, counter, destination, time).
    pub header: TmHeader,
    /// The service type ID.
    pub service: u8,
    /// The message subtype ID.
    pub subtype: u8,
    /// The application data.
    pub app_data: &'a [u8],
}

/// The TM packet `packet` of application process `apid`, read back: the inverse of
/// [`encode_tm`], for tests, the PIL and a ground without `spacepackets`. Errors as
/// [`decode_tc`]'s, a telecommand refused as [`PusError::WrongPacketType`].
pub fn decode_tm(packet: &[u8], apid: Apid) -> Result<Telemetry<'_>, PusError> {
    let (primary, data) = space_packet::decode(packet, apid)?;
    if primary.packet_type != PacketType::Telemetry {
        return Err(PusError::WrongPacketType);
    }
    if !primary.secondary_header {
        return Err(PusError::NoSecondaryHeader);
    }
    let (secondary, app_data) = data
        .split_first_chunk::<TM_SECONDARY_HEADER_LEN>()
        .ok_or(PusError::TooShort { len: data.len() })?;
    let [v, service, subtype, c0, c1, d0, d1, t0, t1, t2, t3, f0, f1] = *secondary;
    let version = v >> 4;
    if version != PUS_VERSION {
        return Err(PusError::Version(version));
    }
    Ok(Telemetry {
        header: TmHeader {
            apid: primary.apid,
            sequence_count: primary.sequence_count,
            time_status: v & 0x0F,
            message_counter: u16::from_be_bytes([c0, c1]),
            destination_id: u16::from_be_bytes([d0, d1]),
            time: CucTime {
                seconds: u32::from_be_bytes([t0, t1, t2, t3]),
                fraction: u16::from_be_bytes([f0, f1]),
            },
        },
        service,
        subtype,
        app_data,
    })
}
