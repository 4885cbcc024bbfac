//! The link's packet decoder ([`acs::link::space_packet::decode`]) on arbitrary bytes. The
//! first two bytes choose the expected APID (11 bits) and whether to repair the packet's length
//! field and CRC (so that the fuzzer reaches the checks behind the CRC); the rest is the packet.
//! Never panics; a refusal is the first failed check of the documented order; an accepted
//! packet is of the expected APID and encodes back to the same bytes.
#![no_main]

use acs::link::crc16::crc16;
use acs::link::space_packet::{decode, encode, Apid, PacketError, OVERHEAD};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let [a0, a1, rest @ ..] = data else {
        return;
    };
    let expected = Apid::new(u16::from_le_bytes([*a0, *a1]) & Apid::MAX).expect("11 bits");
    let mut bytes = rest.to_vec();
    let n = bytes.len();
    if a1 & 0x40 != 0 && n >= OVERHEAD && n - 7 <= usize::from(u16::MAX) {
        let field = u16::try_from(n - 7).expect("checked");
        bytes[4..6].copy_from_slice(&field.to_be_bytes());
    }
    if a1 & 0x80 != 0 && n >= 2 {
        let crc = crc16(&bytes[..n - 2]);
        bytes[n - 2..].copy_from_slice(&crc.to_be_bytes());
    }
    match decode(&bytes, expected) {
        Ok((header, user)) => {
            assert_eq!(header.apid, expected);
            assert!(header.sequence_count <= 0x3FFF);
            assert_eq!(user.len() + OVERHEAD, n);
            let mut out = vec![0u8; n];
            assert_eq!(encode(&header, user, &mut out), Ok(n));
            assert_eq!(out, bytes, "re-encoding an accepted packet");
        }
        Err(e) => {
            assert!(!e.to_string().is_empty());
            // the documented order: each refusal means the checks before it passed
            let field = || usize::from(u16::from_be_bytes([bytes[4], bytes[5]]));
            match e {
                PacketError::TooShort { len } => assert!(len < OVERHEAD && len == n),
                PacketError::LengthMismatch { len, .. } => {
                    assert!(n >= OVERHEAD && len == n && field() + 7 != n)
                }
                PacketError::Crc { computed, received } => {
                    assert_eq!(field() + 7, n);
                    assert_eq!(computed, crc16(&bytes[..n - 2]));
                    assert_ne!(computed, received);
                }
                PacketError::Version(v) => assert!(v != 0 && crc16(&bytes) == 0),
                PacketError::SequenceFlags(f) => assert!(bytes[0] >> 5 == 0 && f != 0b11),
                PacketError::WrongApid { expected: x, found } => {
                    assert!(x == expected && found != expected && bytes[2] >> 6 == 0b11)
                }
                other => panic!("an encoding error from decode: {other:?}"),
            }
        }
    }
});
