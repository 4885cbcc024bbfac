//! CCSDS Space Packets with a CRC: what one node sends the other over the link.
//!
//! The packet of CCSDS 133.0-B-2 (Space Packet Protocol, Blue Book issue 2, June 2020), §4.1:
//! a 6-byte primary header (§4.1.3), then the packet data field (§4.1.4): the user data and,
//! as its last two bytes, the packet error control, a CRC-16 ([`crate::link::crc16`],
//! ECSS-E-ST-70-41C annex B.1) over the primary header and the user data. No secondary header is
//! written (the flag is carried, for a message layer that wants one inside its user data).
//! Every field is big-endian, most significant bit first.
//!
//! | bits | field | §133.0-B-2 | here |
//! |---:|---|---|---|
//! | 3 | packet version number | 4.1.3.2 | always `000` (version 1); anything else is refused |
//! | 1 | packet type | 4.1.3.3.2 | [`PacketType`]: 0 telemetry, 1 telecommand |
//! | 1 | secondary header flag | 4.1.3.3.3 | [`PacketHeader::secondary_header`] |
//! | 11 | application process identifier | 4.1.3.3.4 | [`Apid`] (checked); the receiver's expected one, or refused |
//! | 2 | sequence flags | 4.1.3.4.2 | always `11` (unsegmented); anything else is refused |
//! | 14 | packet sequence count | 4.1.3.4.3 | [`PacketHeader::sequence_count`], 0–16383 ([`crate::link::sequence`]) |
//! | 16 | packet data length | 4.1.3.5 | bytes of the data field − 1 = user data + 2 − 1 |
//! | 8·n | user data | 4.1.4.3 | the message, `n` ≥ 0 bytes |
//! | 16 | packet error control | (ECSS-E-ST-70-41C annex B.1) | CRC-16 over everything before it |
//!
//! CCSDS requires at least one byte in the data field (§4.1.4): with the two CRC bytes in
//! it, a packet with no user data is still a valid packet (data length field 1). A packet is
//! [`OVERHEAD`] = 8 bytes longer than its user data ([`packet_len`]).
//!
//! [`decode`] takes exactly one packet (the link's framing delimits it) and refuses, with a
//! [`PacketError`] that carries the offending values, in this order: fewer than 8 bytes; a
//! length field that disagrees with the number of bytes; a CRC that does not match (the packet
//! was damaged); a version other than 0; sequence flags other than "unsegmented"; an APID other
//! than the one expected. What it accepts, [`encode`] gives back byte for byte (tested, and
//! fuzzed by `fuzz/fuzz_targets/link_decode.rs`). Both are checked against the `spacepackets`
//! crate in both directions (`tests/link.rs`).
//!
//! ```
//! use acs::link::space_packet::{decode, encode, packet_len, Apid, PacketHeader, PacketType};
//! let apid = Apid::new(0x123).unwrap();
//! let header = PacketHeader {
//!     packet_type: PacketType::Telemetry,
//!     secondary_header: false,
//!     apid,
//!     sequence_count: 7,
//! };
//! let mut packet = [0u8; packet_len(3)];
//! let n = encode(&header, &[1, 2, 3], &mut packet).unwrap();
//! assert_eq!(n, 11);
//! let (got, data) = decode(&packet, apid).unwrap();
//! assert_eq!((got, data), (header, &[1u8, 2, 3][..]));
//! ```

use core::fmt;

use super::crc16::{crc16, crc16_update};

/// Bytes of the primary header (§4.1.3.1).
pub const PRIMARY_HEADER_LEN: usize = 6;
/// Bytes of the packet error control (the CRC at the end of the data field).
pub const CRC_LEN: usize = 2;
/// Bytes a packet adds to its user data: header and CRC.
pub const OVERHEAD: usize = PRIMARY_HEADER_LEN + CRC_LEN;
/// The longest user data a packet can carry: the data length field's 65 535 is a data field
/// of 65 536 bytes, two of them the CRC.
pub const MAX_DATA_LEN: usize = 65_534;
/// The largest packet sequence count (14 bits).
pub const MAX_SEQUENCE_COUNT: u16 = 0x3FFF;

/// The length of the packet that carries `data_len` bytes of user data: `data_len` + 8. For
/// sizing buffers (`[0u8; packet_len(MESSAGE_LEN)]`).
pub const fn packet_len(data_len: usize) -> usize {
    data_len + OVERHEAD
}

/// An application process identifier: 11 bits (0–2047), checked when made. Which process has
/// which APID is the deployment's choice; 2047 (all ones) is reserved by CCSDS for idle packets
/// (§4.1.3.3.4), which this link never sends.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Apid(u16);

impl Apid {
    /// The largest APID.
    pub const MAX: u16 = 0x07FF;

    /// The APID `value`, or `None` if it does not fit in 11 bits.
    pub const fn new(value: u16) -> Option<Apid> {
        if value > Self::MAX {
            None
        } else {
            Some(Apid(value))
        }
    }

    /// The APID of the low 11 bits of `value` (for constants whose value is known to fit).
    pub const fn masked(value: u16) -> Apid {
        Apid(value & Self::MAX)
    }

    /// Its value, 0–2047.
    pub const fn get(self) -> u16 {
        self.0
    }
}

/// The packet type bit (§4.1.3.3.2).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PacketType {
    /// 0: telemetry (a report).
    Telemetry,
    /// 1: telecommand (a request).
    Telecommand,
}

/// The fields of a primary header that a sender chooses. The version (0), the sequence flags
/// (unsegmented) and the data length are not chosen: [`encode`] writes them.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PacketHeader {
    /// Telemetry or telecommand.
    pub packet_type: PacketType,
    /// The secondary header flag: set when the user data starts with a secondary header (the
    /// message layer's business; this module does not look inside the user data).
    pub secondary_header: bool,
    /// The application process the packet belongs to.
    pub apid: Apid,
    /// The packet sequence count, 0–[`MAX_SEQUENCE_COUNT`] ([`crate::link::sequence`]).
    pub sequence_count: u16,
}

/// Why a packet could not be encoded, or why received bytes are not an acceptable packet.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum PacketError {
    /// Encoding: the output buffer is shorter than the packet.
    OutputTooSmall {
        /// Bytes the packet needs.
        needed: usize,
        /// Bytes of the buffer.
        len: usize,
    },
    /// Encoding: more user data than a packet holds ([`MAX_DATA_LEN`]).
    DataTooLong {
        /// Bytes of user data given.
        len: usize,
    },
    /// Encoding: a sequence count beyond 14 bits.
    SequenceCountTooLarge(u16),
    /// Decoding: fewer bytes than the smallest packet (header and CRC, [`OVERHEAD`]).
    TooShort {
        /// Bytes given.
        len: usize,
    },
    /// Decoding: the data length field says another length than the bytes given.
    LengthMismatch {
        /// The packet data length field (data field bytes − 1).
        field: u16,
        /// Bytes given.
        len: usize,
    },
    /// Decoding: the CRC of the bytes is not the one transmitted (the packet was damaged).
    Crc {
        /// CRC computed over the header and the user data.
        computed: u16,
        /// CRC found in the packet's last two bytes.
        received: u16,
    },
    /// Decoding: a packet version number other than 0 (`000`, version 1).
    Version(u8),
    /// Decoding: sequence flags other than `11` (unsegmented).
    SequenceFlags(u8),
    /// Decoding: an intact packet of another application process.
    WrongApid {
        /// The APID the receiver expects.
        expected: Apid,
        /// The APID of the packet.
        found: Apid,
    },
}

impl fmt::Display for PacketError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::OutputTooSmall { needed, len } => {
                write!(f, "packet of {needed} bytes does not fit {len}")
            }
            Self::DataTooLong { len } => write!(f, "{len} bytes of user data: too long"),
            Self::SequenceCountTooLarge(c) => write!(f, "sequence count {c} beyond 14 bits"),
            Self::TooShort { len } => write!(f, "{len} bytes: shorter than a packet"),
            Self::LengthMismatch { field, len } => {
                write!(f, "data length field {field} for {len} bytes")
            }
            Self::Crc { computed, received } => {
                write!(f, "CRC {received:#06x}, computed {computed:#06x}")
            }
            Self::Version(v) => write!(f, "packet version number {v}"),
            Self::SequenceFlags(s) => write!(f, "sequence flags {s:#04b}, not unsegmented"),
            Self::WrongApid { expected, found } => {
                write!(f, "APID {} where {} expected", found.0, expected.0)
            }
        }
    }
}

/// The sequence flags of an unsegmented packet (§4.1.3.4.2).
const UNSEGMENTED: u16 = 0b11;

/// Writes the packet of `header` and user data `data` to the start of `out` and returns its
/// length ([`packet_len`]`(data.len())`). Errors: [`PacketError::SequenceCountTooLarge`] (the
/// header's count beyond 14 bits), [`PacketError::DataTooLong`] (more than [`MAX_DATA_LEN`]
/// bytes), [`PacketError::OutputTooSmall`] (`out` shorter than the packet). On error `out` is
/// unchanged.
pub fn encode(header: &PacketHeader, data: &[u8], out: &mut [u8]) -> Result<usize, PacketError> {
    let (len, length_field, head, body, crc) = split_packet(header, data.len(), out)?;
    *head = primary_header(header, length_field);
    for (o, d) in body.iter_mut().zip(data) {
        *o = *d;
    }
    *crc = crc16_update(crc16(head), body).to_be_bytes();
    Ok(len)
}

/// [`encode`] for user data already in place: `out[6..6 + data_len]` holds the `data_len`
/// bytes of user data (a message layer wrote them there, as [`crate::link::pus`] does with its
/// secondary header and application data, so no second buffer is needed); this writes the
/// primary header before them and the CRC after them, and returns the packet's length. Errors
/// as [`encode`] ([`encoded_len`]); on error `out` is unchanged.
pub fn encode_in_place(
    header: &PacketHeader,
    data_len: usize,
    out: &mut [u8],
) -> Result<usize, PacketError> {
    let (len, length_field, head, body, crc) = split_packet(header, data_len, out)?;
    *head = primary_header(header, length_field);
    *crc = crc16_update(crc16(head), body).to_be_bytes();
    Ok(len)
}

/// The length of the packet of `header` with `data_len` bytes of user data
/// ([`packet_len`]`(data_len)`), if [`encode`] can write it into a buffer of `out_len` bytes;
/// else [`encode`]'s error, checked in the same order. For a message layer that writes its user
/// data into the packet buffer itself ([`encode_in_place`]) and wants to know first.
pub fn encoded_len(
    header: &PacketHeader,
    data_len: usize,
    out_len: usize,
) -> Result<usize, PacketError> {
    if header.sequence_count > MAX_SEQUENCE_COUNT {
        return Err(PacketError::SequenceCountTooLarge(header.sequence_count));
    }
    if data_len > MAX_DATA_LEN {
        return Err(PacketError::DataTooLong { len: data_len });
    }
    let len = data_len + OVERHEAD;
    if len > out_len {
        return Err(PacketError::OutputTooSmall {
            needed: len,
            len: out_len,
        });
    }
    Ok(len)
}

/// The packet of `data_len` bytes of user data in `out`: its length, its data length field and
/// its primary header, user data and CRC as parts of `out`; or [`encode`]'s error, checked in
/// its order (as [`encoded_len`]).
type Parts<'a> = (
    usize,
    u16,
    &'a mut [u8; PRIMARY_HEADER_LEN],
    &'a mut [u8],
    &'a mut [u8; CRC_LEN],
);

/// Splits `out` into the parts of the packet of `header` with `data_len` bytes of user data
/// ([`Parts`]), the checks of [`encode`] on the way. Inlined: each encoder keeps its one body.
#[inline(always)]
fn split_packet<'a>(
    header: &PacketHeader,
    data_len: usize,
    out: &'a mut [u8],
) -> Result<Parts<'a>, PacketError> {
    if header.sequence_count > MAX_SEQUENCE_COUNT {
        return Err(PacketError::SequenceCountTooLarge(header.sequence_count));
    }
    // data field bytes − 1 = user data + CRC − 1
    let length_field =
        u16::try_from(data_len + 1).map_err(|_| PacketError::DataTooLong { len: data_len })?;
    let len = data_len + OVERHEAD;
    let too_small = PacketError::OutputTooSmall {
        needed: len,
        len: out.len(),
    };
    let (head, rest) = out
        .get_mut(..len)
        .and_then(|p| p.split_first_chunk_mut::<PRIMARY_HEADER_LEN>())
        .ok_or(too_small)?;
    let (body, crc) = rest.split_last_chunk_mut::<CRC_LEN>().ok_or(too_small)?;
    Ok((len, length_field, head, body, crc))
}

/// The six bytes of the primary header of `header` with data length field `length_field`:
/// version 000, the type, the secondary header flag, the APID; unsegmented, the count; the
/// length.
#[inline(always)]
fn primary_header(header: &PacketHeader, length_field: u16) -> [u8; PRIMARY_HEADER_LEN] {
    // version 000 | type | secondary header flag | APID
    let type_bit = match header.packet_type {
        PacketType::Telemetry => 0,
        PacketType::Telecommand => 1 << 12,
    };
    let identification = type_bit | (u16::from(header.secondary_header) << 11) | header.apid.0;
    let sequence = (UNSEGMENTED << 14) | header.sequence_count;
    let [i0, i1] = identification.to_be_bytes();
    let [s0, s1] = sequence.to_be_bytes();
    let [l0, l1] = length_field.to_be_bytes();
    [i0, i1, s0, s1, l0, l1]
}

/// The header and the user data of the packet `bytes` (exactly one packet, as the framing
/// delivers it), if it is intact and belongs to `expected_apid`. The user data excludes the CRC.
///
/// Errors, checked in this order: [`PacketError::TooShort`] (fewer than [`OVERHEAD`] bytes),
/// [`PacketError::LengthMismatch`] (the length field disagrees with `bytes.len()`),
/// [`PacketError::Crc`] (damaged), [`PacketError::Version`] (not version 1),
/// [`PacketError::SequenceFlags`] (not unsegmented), [`PacketError::WrongApid`] (another
/// process's packet). An intact packet is never refused for its sequence count: gaps are the
/// receiver's [`crate::link::sequence::SequenceTracker`]'s business.
pub fn decode(bytes: &[u8], expected_apid: Apid) -> Result<(PacketHeader, &[u8]), PacketError> {
    let too_short = PacketError::TooShort { len: bytes.len() };
    let (head, rest) = bytes
        .split_first_chunk::<PRIMARY_HEADER_LEN>()
        .ok_or(too_short)?;
    let (data, crc) = rest.split_last_chunk::<CRC_LEN>().ok_or(too_short)?;
    let [i0, i1, s0, s1, l0, l1] = *head;
    let identification = u16::from_be_bytes([i0, i1]);
    let sequence = u16::from_be_bytes([s0, s1]);
    let length_field = u16::from_be_bytes([l0, l1]);
    // the data field is length_field + 1 bytes: CRC included
    if usize::from(length_field) != data.len() + 1 {
        return Err(PacketError::LengthMismatch {
            field: length_field,
            len: bytes.len(),
        });
    }
    // the CRC covers everything before it: header and user data
    let computed = crc16(bytes.get(..bytes.len() - CRC_LEN).unwrap_or_default());
    let received = u16::from_be_bytes(*crc);
    if computed != received {
        return Err(PacketError::Crc { computed, received });
    }
    let version = i0 >> 5;
    if version != 0 {
        return Err(PacketError::Version(version));
    }
    let flags = s0 >> 6;
    if u16::from(flags) != UNSEGMENTED {
        return Err(PacketError::SequenceFlags(flags));
    }
    let apid = Apid(identification & Apid::MAX);
    if apid != expected_apid {
        return Err(PacketError::WrongApid {
            expected: expected_apid,
            found: apid,
        });
    }
    let packet_type = if identification & (1 << 12) == 0 {
        PacketType::Telemetry
    } else {
        PacketType::Telecommand
    };
    let header = PacketHeader {
        packet_type,
        secondary_header: identification & (1 << 11) != 0,
        apid,
        sequence_count: sequence & MAX_SEQUENCE_COUNT,
    };
    Ok((header, data))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_follow_the_fields() {
        // the data length field's largest value is a data field of 65 536 bytes, CRC included
        assert_eq!(MAX_DATA_LEN + CRC_LEN, usize::from(u16::MAX) + 1);
        assert_eq!(MAX_SEQUENCE_COUNT, (1 << 14) - 1);
        assert_eq!(Apid::MAX, (1 << 11) - 1);
        assert_eq!(packet_len(0), 8);
    }
}
