//! The inter-node link (`acs::link`, `acs::hal::link`, `acs::host::link`; issue 29 item 2),
//! against its standards and independent crates: the CRC against its check value and the `crc`
//! crate; the space packets against hand-assembled CCSDS 133.0-B-2 headers and the
//! `spacepackets` crate, both ways; COBS against the paper's examples and the `cobs` crate, both
//! ways; then every refusal, the sequence gaps across the 14-bit wrap, the deframer's
//! resynchronisation, the framed link over a byte stream and the in-memory link's faults.

use std::collections::VecDeque;

use acs::hal::link::{
    ByteStream, Error as _, ErrorKind, ErrorType, FramedLink, FramedLinkError, NodeLink,
};
use acs::host::link::{Corruption, End, MemoryLink};
use acs::link::cobs::{self, max_encoded_len, Deframer, FrameError};
use acs::link::crc16::{crc16, crc16_update};
use acs::link::sequence::{Continuity, SequenceCounter, SequenceTracker, LATE_WINDOW};
use acs::link::space_packet::{
    decode, encode, packet_len, Apid, PacketError, PacketHeader, PacketType, MAX_DATA_LEN,
    MAX_SEQUENCE_COUNT, OVERHEAD,
};
use arbitrary_int::{u11, u14};
use proptest::prelude::*;
use spacepackets::{CcsdsPacket, CcsdsPacketCreator, CcsdsPacketReader, SequenceFlags, SpHeader};

/// The reference CRC: the catalogue's CRC-16/IBM-3740 (the `crc` crate).
const REFERENCE_CRC: crc::Crc<u16> = crc::Crc::<u16>::new(&crc::CRC_16_IBM_3740);

fn apid(value: u16) -> Apid {
    Apid::new(value).expect("an 11-bit APID")
}

fn header(apid_value: u16, count: u16) -> PacketHeader {
    PacketHeader {
        packet_type: PacketType::Telemetry,
        secondary_header: false,
        apid: apid(apid_value),
        sequence_count: count,
    }
}

fn packet(h: &PacketHeader, data: &[u8]) -> Vec<u8> {
    let mut out = vec![0; packet_len(data.len())];
    let n = encode(h, data, &mut out).expect("encodes");
    assert_eq!(n, out.len());
    out
}

/// Sets the CRC of a packet whose header was altered by hand.
fn fix_crc(p: &mut [u8]) {
    let n = p.len();
    let crc = REFERENCE_CRC.checksum(&p[..n - 2]);
    p[n - 2..].copy_from_slice(&crc.to_be_bytes());
}

/// Feeds a byte stream to a deframer, collecting every result.
fn deframe<const N: usize>(d: &mut Deframer<N>, wire: &[u8]) -> Vec<Result<Vec<u8>, FrameError>> {
    wire.iter()
        .filter_map(|&b| d.push(b).map(|r| r.map(<[u8]>::to_vec)))
        .collect()
}

fn frame(data: &[u8]) -> Vec<u8> {
    let mut out = vec![0; max_encoded_len(data.len())];
    let n = cobs::encode(data, &mut out).expect("fits its maximum");
    out.truncate(n);
    out
}

// ---- CRC-16 -------------------------------------------------------------------------------

#[test]
fn crc_check_value() {
    // ECSS-E-ST-70-41C annex B.1's CRC (CRC-16/IBM-3740): check value of "123456789"
    assert_eq!(crc16(b"123456789"), 0x29B1);
    assert_eq!(crc16(&[]), 0xFFFF);
    // the syndrome of intact data and its big-endian CRC is zero
    let mut d = b"123456789".to_vec();
    d.extend_from_slice(&0x29B1u16.to_be_bytes());
    assert_eq!(crc16(&d), 0);
}

proptest! {
    /// Equal to the `crc` crate's CRC-16/IBM-3740, and continuable across any split.
    #[test]
    fn crc_matches_the_crc_crate(data in proptest::collection::vec(any::<u8>(), 0..600), cut in any::<prop::sample::Index>()) {
        prop_assert_eq!(crc16(&data), REFERENCE_CRC.checksum(&data));
        let k = cut.index(data.len() + 1);
        prop_assert_eq!(crc16_update(crc16(&data[..k]), &data[k..]), crc16(&data));
    }
}

// ---- space packets ------------------------------------------------------------------------

#[test]
fn apid_is_eleven_bits() {
    assert_eq!(Apid::new(0).map(Apid::get), Some(0));
    assert_eq!(Apid::new(2047).map(Apid::get), Some(2047));
    assert_eq!(Apid::new(2048), None);
    assert_eq!(Apid::new(u16::MAX), None);
}

#[test]
fn header_bits_as_ccsds_133_lays_them_out() {
    // TC, secondary header, APID 0x5A5, count 0x2AAA, user data AB CD
    let h = PacketHeader {
        packet_type: PacketType::Telecommand,
        secondary_header: true,
        apid: apid(0x5A5),
        sequence_count: 0x2AAA,
    };
    let p = packet(&h, &[0xAB, 0xCD]);
    // 000 1 1 101_1010_0101 | 11 10_1010_1010_1010 | data field 4 bytes → 3
    assert_eq!(&p[..8], &[0x1D, 0xA5, 0xEA, 0xAA, 0x00, 0x03, 0xAB, 0xCD]);
    assert_eq!(
        u16::from_be_bytes([p[8], p[9]]),
        REFERENCE_CRC.checksum(&p[..8])
    );
    // no user data: data field = the CRC, length field 1
    let p = packet(&header(0, 0), &[]);
    assert_eq!(p.len(), OVERHEAD);
    assert_eq!(&p[..6], &[0x00, 0x00, 0xC0, 0x00, 0x00, 0x01]);
    assert_eq!(decode(&p, apid(0)), Ok((header(0, 0), &[][..])));
}

#[test]
fn encode_refusals() {
    let mut out = [0x55u8; 16];
    assert_eq!(
        encode(&header(1, MAX_SEQUENCE_COUNT + 1), &[1], &mut out),
        Err(PacketError::SequenceCountTooLarge(16384))
    );
    assert_eq!(
        encode(&header(1, 0), &[1, 2, 3, 4, 5, 6, 7, 8, 9], &mut out),
        Err(PacketError::OutputTooSmall {
            needed: 17,
            len: 16
        })
    );
    assert_eq!(
        out, [0x55; 16],
        "a refused encode leaves the buffer as it was"
    );
    assert_eq!(encode(&header(1, 0), &[1; 8], &mut out), Ok(16));
    let big = vec![7u8; MAX_DATA_LEN + 1];
    let mut out = vec![0u8; packet_len(MAX_DATA_LEN + 1)];
    assert_eq!(
        encode(&header(1, 0), &big, &mut out),
        Err(PacketError::DataTooLong { len: 65_535 })
    );
    let n = encode(&header(1, 0), &big[..MAX_DATA_LEN], &mut out).expect("the longest packet");
    assert_eq!(&out[4..6], &[0xFF, 0xFF]);
    assert_eq!(
        decode(&out[..n], apid(1)).map(|(_, d)| d.len()),
        Ok(MAX_DATA_LEN)
    );
}

#[test]
fn decode_refusals_each_case() {
    let good = packet(&header(0x123, 42), &[1, 2, 3, 4]);
    let a = apid(0x123);
    assert_eq!(
        decode(&good, a),
        Ok((header(0x123, 42), &[1u8, 2, 3, 4][..]))
    );
    // too short: fewer bytes than header + CRC
    for n in 0..OVERHEAD {
        assert_eq!(decode(&good[..n], a), Err(PacketError::TooShort { len: n }));
    }
    // every longer prefix (a truncated packet) disagrees with its length field
    for n in OVERHEAD..good.len() {
        assert_eq!(
            decode(&good[..n], a),
            Err(PacketError::LengthMismatch { field: 5, len: n })
        );
    }
    let mut long = good.clone();
    long.push(0);
    assert_eq!(
        decode(&long, a),
        Err(PacketError::LengthMismatch { field: 5, len: 13 })
    );
    // a changed byte: the CRC
    let mut bad = good.clone();
    bad[7] ^= 0x10;
    let computed = REFERENCE_CRC.checksum(&bad[..10]);
    let received = u16::from_be_bytes([bad[10], bad[11]]);
    assert_eq!(
        decode(&bad, a),
        Err(PacketError::Crc { computed, received })
    );
    // version 1 (bits 001) with a valid CRC
    let mut v = good.clone();
    v[0] |= 0x20;
    fix_crc(&mut v);
    assert_eq!(decode(&v, a), Err(PacketError::Version(1)));
    // first segment (01) with a valid CRC
    let mut s = good.clone();
    s[2] = (s[2] & 0x3F) | 0x40;
    fix_crc(&mut s);
    assert_eq!(decode(&s, a), Err(PacketError::SequenceFlags(1)));
    // an intact packet of another process
    assert_eq!(
        decode(&good, apid(0x124)),
        Err(PacketError::WrongApid {
            expected: apid(0x124),
            found: a
        })
    );
    // every error says what it is
    for e in [
        decode(&good[..3], a),
        decode(&good[..9], a),
        decode(&bad, a),
        decode(&v, a),
        decode(&s, a),
    ] {
        assert!(!e.expect_err("refused").to_string().is_empty());
    }
}

#[test]
fn every_single_bit_flip_is_refused() {
    let good = packet(&header(0x0F0, 1000), b"attitude reference");
    for i in 0..good.len() * 8 {
        let mut p = good.clone();
        p[i / 8] ^= 1 << (i % 8);
        assert!(
            decode(&p, apid(0x0F0)).is_err(),
            "bit {i} flipped was accepted"
        );
    }
}

fn any_header() -> impl Strategy<Value = PacketHeader> {
    (
        any::<bool>(),
        any::<bool>(),
        0u16..=2047,
        0u16..=MAX_SEQUENCE_COUNT,
    )
        .prop_map(|(tc, sec, a, count)| PacketHeader {
            packet_type: if tc {
                PacketType::Telecommand
            } else {
                PacketType::Telemetry
            },
            secondary_header: sec,
            apid: apid(a),
            sequence_count: count,
        })
}

/// Counts near the wrap drawn often, the rest anywhere.
fn any_count() -> impl Strategy<Value = u16> {
    prop_oneof![0u16..4, 16380u16..=16383, 0u16..=16383]
}

proptest! {
    /// Encoding then decoding gives back header and data; the packet is 8 bytes longer.
    #[test]
    fn packet_round_trip(h in any_header(), data in proptest::collection::vec(any::<u8>(), 0..300)) {
        let p = packet(&h, &data);
        prop_assert_eq!(p.len(), data.len() + 8);
        prop_assert_eq!(decode(&p, h.apid), Ok((h, &data[..])));
    }

    /// Ours → spacepackets: its reader accepts the CRC and reads the same fields and data.
    #[test]
    fn spacepackets_reads_ours(h in any_header(), count in any_count(), data in proptest::collection::vec(any::<u8>(), 0..200)) {
        let h = PacketHeader { sequence_count: count, ..h };
        let p = packet(&h, &data);
        let r = CcsdsPacketReader::new_with_checksum(&p).expect("spacepackets accepts the packet and its CRC");
        prop_assert_eq!(r.ccsds_version().value(), 0);
        prop_assert_eq!(r.apid().value(), h.apid.get());
        prop_assert_eq!(r.seq_count().value(), count);
        prop_assert_eq!(r.sequence_flags(), SequenceFlags::Unsegmented);
        prop_assert_eq!(r.sec_header_flag(), h.secondary_header);
        prop_assert_eq!(r.packet_type() == spacepackets::PacketType::Tc, h.packet_type == PacketType::Telecommand);
        prop_assert_eq!(usize::from(r.data_len()), data.len() + 1);
        prop_assert_eq!(r.packet_len(), p.len());
        prop_assert_eq!(r.user_data(), &data[..]);
    }

    /// spacepackets → ours: we read its packets, and encode them back byte for byte (with at
    /// least one byte of user data: [`spacepackets_empty_user_data`]).
    #[test]
    fn we_read_spacepackets(h in any_header(), count in any_count(), data in proptest::collection::vec(any::<u8>(), 1..200)) {
        let ptype = match h.packet_type {
            PacketType::Telemetry => spacepackets::PacketType::Tm,
            PacketType::Telecommand => spacepackets::PacketType::Tc,
        };
        let sp = SpHeader::new_from_fields(
            ptype, h.secondary_header, u11::new(h.apid.get()), SequenceFlags::Unsegmented, u14::new(count), 0,
        );
        let creator = CcsdsPacketCreator::new_with_checksum(sp, ptype, &data).expect("a valid packet");
        let mut theirs = vec![0u8; creator.len_written()];
        creator.write_to_slice(&mut theirs).expect("fits");
        let expected = PacketHeader { sequence_count: count, ..h };
        let (got, user) = decode(&theirs, h.apid).expect("we accept spacepackets' packet");
        prop_assert_eq!(got, expected);
        prop_assert_eq!(user, &data[..]);
        prop_assert_eq!(packet(&got, user), theirs);
    }
}

/// spacepackets 0.19.0 writes 7 bytes for a packet with a CRC and no user data
/// (`ccsds_packet_len_for_user_data_len(0, Some(WithCrc16))` is 7: its special case for an
/// empty data field ignores the CRC), its CRC over the header's first 5 bytes and on top of the
/// header's last: a packet that its own reader refuses too. We refuse it (too short) and write
/// the 8-byte packet, which its reader accepts.
#[test]
fn spacepackets_empty_user_data() {
    let sp = SpHeader::new_for_unseg_tm(u11::new(0x42), u14::new(3), 0);
    let creator = CcsdsPacketCreator::new_with_checksum(sp, spacepackets::PacketType::Tm, &[])
        .expect("a packet");
    assert_eq!(creator.len_written(), 7);
    let mut theirs = vec![0u8; 7];
    creator.write_to_slice(&mut theirs).expect("fits");
    assert!(CcsdsPacketReader::new_with_checksum(&theirs).is_err());
    assert_eq!(
        decode(&theirs, apid(0x42)),
        Err(PacketError::TooShort { len: 7 })
    );
    let ours = packet(&header(0x42, 3), &[]);
    assert_eq!(ours.len(), 8);
    let r = CcsdsPacketReader::new_with_checksum(&ours).expect("accepted");
    assert_eq!((r.seq_count().value(), r.user_data()), (3, &[][..]));
}

// ---- sequence counts ----------------------------------------------------------------------

#[test]
fn counter_wraps_after_16383() {
    let mut c = SequenceCounter::new();
    for expected in 0..=MAX_SEQUENCE_COUNT {
        assert_eq!(c.next_count(), expected);
    }
    assert_eq!(c.next_count(), 0);
    assert_eq!(c.next_count(), 1);
}

#[test]
fn gaps_are_counted_across_the_wrap() {
    let mut t = SequenceTracker::new();
    assert_eq!(t.accept(16381), Continuity::First);
    assert_eq!(t.accept(16382), Continuity::Next);
    assert_eq!(t.accept(16383), Continuity::Next);
    assert_eq!(t.accept(0), Continuity::Next);
    // 1, 2, 3 lost
    assert_eq!(t.accept(4), Continuity::Gap { missed: 3 });
    assert_eq!((t.gaps(), t.missed()), (1, 3));
    // a gap across the wrap: 16383, 0 missed between 16382 and 1
    let mut t = SequenceTracker::new();
    t.accept(16382);
    assert_eq!(t.accept(1), Continuity::Gap { missed: 2 });
    // the furthest jump taken for a gap: 8 190 missed
    let mut t = SequenceTracker::new();
    t.accept(100);
    assert_eq!(t.accept(100 + 8191), Continuity::Gap { missed: 8190 });
    assert_eq!((t.gaps(), t.missed(), t.newest()), (1, 8190, Some(8291)));
}

#[test]
fn late_packets_and_restarts() {
    let mut t = SequenceTracker::new();
    t.accept(10);
    // a repeat and an overtaken packet: late, the newest count stays
    assert_eq!(t.accept(10), Continuity::Late);
    assert_eq!(t.accept(9), Continuity::Late);
    assert_eq!(t.accept(11), Continuity::Next);
    // LATE_WINDOW behind, across the wrap: late
    let mut t = SequenceTracker::new();
    t.accept(3);
    assert_eq!(
        t.accept(3u16.wrapping_sub(LATE_WINDOW) & 0x3FFF),
        Continuity::Late
    );
    // one further: the sender started again, and the tracker follows it
    let restart = 3u16.wrapping_sub(LATE_WINDOW + 1) & 0x3FFF;
    assert_eq!(t.accept(restart), Continuity::Restart);
    assert_eq!(t.accept(restart + 1), Continuity::Next);
    // a sender reset from 5 000 to 0: followed
    t.accept(5000);
    assert_eq!(t.accept(0), Continuity::Restart);
    assert_eq!(t.accept(1), Continuity::Next);
    assert_eq!((t.late(), t.restarts(), t.gaps()), (1, 2, 1));
    // higher bits than 14 are ignored
    assert_eq!(t.accept(0x8002), Continuity::Next);
    t.reset();
    assert_eq!((t.newest(), t.late(), t.restarts()), (None, 0, 0));
    assert_eq!(t.accept(5), Continuity::First);
}

#[test]
fn tracker_counters_saturate() {
    let mut t = SequenceTracker::new();
    let mut count = 0u16;
    t.accept(count);
    for _ in 0..70_000 {
        count = (count + 8191) & 0x3FFF; // a gap of 8 190 each time
        assert_eq!(t.accept(count), Continuity::Gap { missed: 8190 });
    }
    assert_eq!(t.gaps(), u16::MAX);
    assert_eq!(t.missed(), 70_000 * 8190);
}

proptest! {
    /// Whatever is lost from a counted stream, the tracker's gap and missed counts say it.
    #[test]
    fn tracker_counts_what_was_lost(start in 0u16..=16383, lost in proptest::collection::vec(0u16..40, 1..60)) {
        let mut c = SequenceCounter::new();
        for _ in 0..start { c.next_count(); }
        let mut t = SequenceTracker::new();
        t.accept(c.next_count());
        let (mut gaps, mut missed) = (0, 0);
        for n in lost {
            for _ in 0..n { c.next_count(); }
            let expected = if n == 0 { Continuity::Next } else { Continuity::Gap { missed: n } };
            prop_assert_eq!(t.accept(c.next_count()), expected);
            gaps += u16::from(n > 0);
            missed += u32::from(n);
        }
        prop_assert_eq!((t.gaps(), t.missed()), (gaps, missed));
    }
}

// ---- COBS framing -------------------------------------------------------------------------

#[test]
fn cobs_examples() {
    // Cheshire & Baker 1999's encoding (the paper's StuffData), each with its delimiter
    let run: Vec<u8> = (1..=254).collect();
    let mut run_framed = vec![0xFF];
    run_framed.extend(1..=254u8);
    run_framed.extend([0x01, 0x00]);
    let cases: Vec<(Vec<u8>, Vec<u8>)> = vec![
        (vec![], vec![0x01, 0x00]),
        (vec![0x00], vec![0x01, 0x01, 0x00]),
        (vec![0x00, 0x00], vec![0x01, 0x01, 0x01, 0x00]),
        (
            vec![0x11, 0x22, 0x00, 0x33],
            vec![0x03, 0x11, 0x22, 0x02, 0x33, 0x00],
        ),
        (
            vec![0x11, 0x22, 0x33, 0x44],
            vec![0x05, 0x11, 0x22, 0x33, 0x44, 0x00],
        ),
        (
            vec![0x11, 0x00, 0x00, 0x00],
            vec![0x02, 0x11, 0x01, 0x01, 0x01, 0x00],
        ),
        (run.clone(), run_framed),
    ];
    for (data, wire) in cases {
        assert_eq!(frame(&data), wire, "frame of {data:02x?}");
        let mut d = Deframer::<300>::new();
        assert_eq!(deframe(&mut d, &wire), vec![Ok(data.clone())]);
        // the blocks are the frame without its delimiter
        let from_blocks: Vec<u8> = cobs::blocks(&data)
            .flat_map(|(code, block)| std::iter::once(code).chain(block.iter().copied()))
            .collect();
        assert_eq!(from_blocks, wire[..wire.len() - 1]);
    }
    // the form without the final empty block (the `cobs` crate's) reads the same
    let mut short = vec![0xFF];
    short.extend(1..=254u8);
    short.push(0x00);
    assert_eq!(deframe(&mut Deframer::<300>::new(), &short), vec![Ok(run)]);
    // an output buffer one byte short is refused
    assert_eq!(
        cobs::encode(&[1, 2, 3], &mut [0u8; 4]),
        Err(FrameError::OutputTooSmall { len: 4 })
    );
    assert_eq!(cobs::encode(&[1, 2, 3], &mut [0u8; 5]), Ok(5));
}

/// Data that is mostly zeros, mostly 0xFF, long runs without zeros, or anything.
fn any_frame_data() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        proptest::collection::vec(any::<u8>(), 0..700),
        (0usize..700).prop_map(|n| vec![0x00; n]),
        (0usize..700).prop_map(|n| vec![0xFF; n]),
        proptest::collection::vec(prop_oneof![Just(0u8), Just(0xFFu8), 1u8..=0xFE], 0..700),
        (250usize..=260, 1u8..=255).prop_map(|(n, b)| vec![b; n]),
    ]
}

proptest! {
    /// Round trip through our encoder and deframer; no 0x00 inside a frame; the length within
    /// its bound; and both ways against the `cobs` crate.
    #[test]
    fn cobs_round_trip_and_the_cobs_crate(data in any_frame_data()) {
        let wire = frame(&data);
        prop_assert!(wire.len() <= max_encoded_len(data.len()));
        prop_assert!(wire.len() >= data.len() + 2);
        prop_assert_eq!(wire.iter().position(|&b| b == 0), Some(wire.len() - 1));
        let mut d = Deframer::<700>::new();
        prop_assert_eq!(deframe(&mut d, &wire), vec![Ok(data.clone())]);
        // the cobs crate decodes ours
        let mut out = vec![0u8; data.len() + 1];
        let report = ::cobs::decode(&wire, &mut out).expect("the cobs crate reads our frame");
        prop_assert_eq!(&out[..report.frame_size()], &data[..]);
        // we decode the cobs crate's
        let mut theirs = vec![0u8; ::cobs::max_encoding_length(data.len())];
        let n = ::cobs::encode(&data, &mut theirs);
        theirs.truncate(n);
        theirs.push(0);
        prop_assert_eq!(deframe(&mut d, &theirs), vec![Ok(data)]);
    }

    /// A frame longer than the deframer is dropped with an error, and the next frame arrives.
    #[test]
    fn overlong_frames_are_dropped(data in proptest::collection::vec(any::<u8>(), 33..200), next in proptest::collection::vec(any::<u8>(), 0..32)) {
        let mut wire = frame(&data);
        wire.extend(frame(&next));
        let mut d = Deframer::<32>::new();
        prop_assert_eq!(deframe(&mut d, &wire), vec![Err(FrameError::Overlong { capacity: 32 }), Ok(next)]);
    }
}

#[test]
fn deframer_resynchronises() {
    let a = frame(&[0x10, 0x00, 0x20, 0x30]); // 02 10 03 20 30 00
    let b = frame(&[0x40, 0x50]);
    let c = frame(&[0x60]);
    let mut d = Deframer::<16>::new();
    // idle delimiters are no frames
    assert_eq!(deframe(&mut d, &[0, 0, 0]), vec![]);
    // a code byte that promises more than comes: truncated, then the next frame is whole
    let mut wire = vec![0x07, 0x10, 0x00];
    wire.extend(&b);
    assert_eq!(
        deframe(&mut d, &wire),
        vec![Err(FrameError::Truncated), Ok(vec![0x40, 0x50])]
    );
    // a lost byte inside a frame: that frame only
    let mut wire = a.clone();
    wire.remove(2);
    wire.extend(&b);
    let got = deframe(&mut d, &wire);
    assert_eq!(got.len(), 2);
    assert_ne!(got[0], Ok(vec![0x10, 0x00, 0x20, 0x30]));
    assert_eq!(got[1], Ok(vec![0x40, 0x50]));
    // a spurious 0x00 splits one frame; the frames after it are whole
    let mut wire = a.clone();
    wire.insert(3, 0x00);
    wire.extend(&b);
    wire.extend(&c);
    let got = deframe(&mut d, &wire);
    assert_eq!(
        &got[got.len() - 2..],
        &[Ok(vec![0x40, 0x50]), Ok(vec![0x60])]
    );
    // a lost delimiter: the two frames run together (one damaged), the third is whole
    let mut wire = a[..a.len() - 1].to_vec();
    wire.extend(&b);
    wire.extend(&c);
    let got = deframe(&mut d, &wire);
    assert_eq!(got.len(), 2);
    assert_eq!(got[1], Ok(vec![0x60]));
    // noise before a frame that starts with a delimiter cannot run into it
    let mut wire = vec![0x33, 0x44, 0x05];
    wire.push(0);
    wire.extend(&b);
    assert_eq!(deframe(&mut d, &wire).last(), Some(&Ok(vec![0x40, 0x50])));
    // reset drops a frame half received
    deframe(&mut d, &a[..3]);
    d.reset();
    assert_eq!(deframe(&mut d, &b), vec![Ok(vec![0x40, 0x50])]);
}

#[test]
fn corrupted_packet_in_a_frame_is_caught_by_the_crc() {
    // a changed byte that keeps the frame well formed reaches the packet layer, which refuses it
    let p = packet(&header(3, 9), &[0x01, 0x02, 0x03]);
    let good = frame(&p);
    for i in 0..good.len() - 1 {
        for xor in [0x01, 0x5A, 0xFF] {
            let mut wire = good.clone();
            wire[i] ^= xor;
            if wire[i] == 0 {
                continue; // a spurious delimiter: `deframer_resynchronises`
            }
            let frames = deframe(&mut Deframer::<64>::new(), &wire);
            for bytes in frames.into_iter().flatten() {
                let r = decode(&bytes, apid(3));
                assert!(r.is_err(), "byte {i} ^ {xor:#x} accepted");
            }
        }
    }
}

// ---- the framed link over a byte stream ---------------------------------------------------

/// A UART stand-in: bytes written go to `sent`, bytes read come from `incoming`; `fail` makes
/// the next call fail.
#[derive(Default)]
struct Uart {
    sent: Vec<u8>,
    incoming: VecDeque<u8>,
    fail: bool,
}

#[derive(Debug, PartialEq)]
struct UartError;

impl acs::hal::link::Error for UartError {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Transport
    }
}

impl ErrorType for Uart {
    type Error = UartError;
}

impl ByteStream for Uart {
    fn write(&mut self, bytes: &[u8]) -> Result<(), UartError> {
        if std::mem::take(&mut self.fail) {
            return Err(UartError);
        }
        self.sent.extend_from_slice(bytes);
        Ok(())
    }
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, UartError> {
        if std::mem::take(&mut self.fail) {
            return Err(UartError);
        }
        let n = buf.len().min(self.incoming.len());
        for b in &mut buf[..n] {
            *b = self.incoming.pop_front().expect("counted");
        }
        Ok(n)
    }
}

#[test]
fn framed_link_carries_packets() {
    let mut tx = FramedLink::<Uart, 64>::new(Uart::default());
    let p1 = packet(&header(5, 1), &[0x00, 0x11, 0x00]);
    let p2 = packet(&header(5, 2), &[0xFF; 40]);
    tx.send(&p1).expect("sent");
    tx.send(&p2).expect("sent");
    let wire = tx.release().sent;
    // each frame between delimiters: 0x00, blocks, 0x00
    assert_eq!(wire[0], 0);
    assert_eq!(wire.len(), 2 * 3 + p1.len() + p2.len());
    // noise before, and the bytes arriving one call at a time
    let mut rx = FramedLink::<Uart, 64>::new(Uart::default());
    rx.stream_mut().incoming.extend([0x42, 0x17]);
    let mut buf = [0u8; 64];
    assert_eq!(rx.receive(&mut buf), Ok(None));
    rx.stream_mut().incoming.extend(&wire);
    // the noise is a damaged frame of its own, reported, then both packets
    let e = rx.receive(&mut buf).expect_err("noise");
    assert_eq!(e, FramedLinkError::Frame(FrameError::Truncated));
    assert_eq!(e.kind(), ErrorKind::Frame);
    let n = rx.receive(&mut buf).expect("ok").expect("a packet");
    assert_eq!(
        decode(&buf[..n], apid(5)),
        Ok((header(5, 1), &[0x00, 0x11, 0x00][..]))
    );
    let n = rx.receive(&mut buf).expect("ok").expect("a packet");
    assert_eq!(decode(&buf[..n], apid(5)).map(|(h, _)| h), Ok(header(5, 2)));
    assert_eq!(rx.receive(&mut buf), Ok(None));
}

#[test]
fn framed_link_errors() {
    // a packet longer than the caller's buffer
    let mut link = FramedLink::<Uart, 64>::new(Uart::default());
    link.send(&[1; 20]).expect("sent");
    let wire = std::mem::take(&mut link.stream_mut().sent);
    link.stream_mut().incoming.extend(&wire);
    let e = link.receive(&mut [0u8; 10]).expect_err("too long");
    assert_eq!(
        e,
        FramedLinkError::TooLong {
            len: 20,
            capacity: 10
        }
    );
    assert_eq!(e.kind(), ErrorKind::TooLong);
    // longer than the deframer: refused as soon as it outgrows it, then the next packet
    let mut small = FramedLink::<Uart, 8>::new(Uart::default());
    small.stream_mut().incoming.extend(&wire);
    small.stream_mut().incoming.extend(&frame(&[9, 8, 7]));
    assert_eq!(
        small.receive(&mut [0u8; 64]),
        Err(FramedLinkError::Frame(FrameError::Overlong { capacity: 8 }))
    );
    let mut buf = [0u8; 8];
    assert_eq!(small.receive(&mut buf), Ok(Some(3)));
    assert_eq!(&buf[..3], &[9, 8, 7]);
    // transport errors, with the stream's kind
    link.stream_mut().fail = true;
    let e = link.send(&[1]).expect_err("fails");
    assert_eq!(
        (e.kind(), e.to_string().is_empty()),
        (ErrorKind::Transport, false)
    );
    link.stream_mut().fail = true;
    assert_eq!(
        link.receive(&mut [0u8; 64]),
        Err(FramedLinkError::Transport(UartError))
    );
    // a line that never runs dry holds one call for a bounded number of bytes
    let mut noisy = FramedLink::<Uart, 8>::new(Uart::default());
    noisy.stream_mut().incoming.extend([0x00; 100]);
    assert_eq!(noisy.receive(&mut [0u8; 8]), Ok(None));
    let read = 100 - noisy.stream_mut().incoming.len();
    assert_eq!(read, FramedLink::<Uart, 8>::MAX_READ_PER_RECEIVE);
    // noise without delimiters: an overlong error within that bound
    let mut noisy = FramedLink::<Uart, 8>::new(Uart::default());
    noisy.stream_mut().incoming.extend([0x11; 100]);
    assert!(matches!(
        noisy.receive(&mut [0u8; 8]),
        Err(FramedLinkError::Frame(FrameError::Overlong { .. }))
    ));
    assert!(100 - noisy.stream_mut().incoming.len() <= FramedLink::<Uart, 8>::MAX_READ_PER_RECEIVE);
}

// ---- the in-memory link -------------------------------------------------------------------

/// Sends packets counted 0, 1, … from `from` and returns what the other end decodes.
fn receive_all(link: &mut MemoryLink, to: End) -> Vec<Result<u16, PacketError>> {
    let mut buf = [0u8; 64];
    let mut got = vec![];
    while let Some(n) = link.end(to).receive(&mut buf).expect("fits") {
        got.push(decode(&buf[..n], apid(7)).map(|(h, _)| h.sequence_count));
    }
    got
}

fn send_counts(link: &mut MemoryLink, from: End, counts: std::ops::Range<u16>) {
    for c in counts {
        link.end(from)
            .send(&packet(&header(7, c), &[c as u8; 4]))
            .expect("sent");
    }
}

#[test]
fn memory_link_without_faults_delivers_in_order_both_ways() {
    let mut link = MemoryLink::new();
    send_counts(&mut link, End::A, 0..3);
    send_counts(&mut link, End::B, 10..12);
    assert_eq!((link.in_flight(End::B), link.in_flight(End::A)), (3, 2));
    assert_eq!(receive_all(&mut link, End::B), vec![Ok(0), Ok(1), Ok(2)]);
    assert_eq!(receive_all(&mut link, End::A), vec![Ok(10), Ok(11)]);
    assert_eq!(link.stats(End::A).sent, 3);
    assert_eq!(link.stats(End::A).delivered, 3);
    // a packet longer than the buffer
    link.end(End::A).send(&[0; 100]).expect("sent");
    assert_eq!(
        link.end(End::B).receive(&mut [0u8; 50]),
        Err(ErrorKind::TooLong)
    );
}

#[test]
fn memory_link_faults() {
    let mut link = MemoryLink::new();
    let mut tracker = SequenceTracker::new();
    // drop two: the tracker sees the gap
    send_counts(&mut link, End::A, 0..1);
    link.faults(End::A).drop = 2;
    send_counts(&mut link, End::A, 1..5);
    let got = receive_all(&mut link, End::B);
    assert_eq!(got, vec![Ok(0), Ok(3), Ok(4)]);
    let continuity: Vec<_> = got
        .iter()
        .map(|c| tracker.accept(*c.as_ref().expect("ok")))
        .collect();
    assert_eq!(
        continuity,
        [
            Continuity::First,
            Continuity::Gap { missed: 2 },
            Continuity::Next
        ]
    );
    assert_eq!(link.stats(End::A).dropped, 2);
    // corrupt a byte: the CRC refuses the packet
    link.faults(End::A).corrupt = Some(Corruption { byte: 7, xor: 0x01 });
    send_counts(&mut link, End::A, 5..7);
    let got = receive_all(&mut link, End::B);
    assert!(matches!(got[0], Err(PacketError::Crc { .. })));
    assert_eq!(got[1], Ok(6));
    assert_eq!(link.stats(End::A).corrupted, 1);
    // delay one: it arrives after the next step, overtaken by the next packet
    link.faults(End::A).delay = 1;
    send_counts(&mut link, End::A, 7..9);
    assert_eq!(receive_all(&mut link, End::B), vec![Ok(8)]);
    link.advance_step();
    assert_eq!(receive_all(&mut link, End::B), vec![Ok(7)]);
    // reorder: the next packet comes after the one sent after it
    link.faults(End::A).reorder = true;
    send_counts(&mut link, End::A, 9..12);
    assert_eq!(receive_all(&mut link, End::B), vec![Ok(10), Ok(9), Ok(11)]);
    // reorder with nothing after it: released at the next step
    link.faults(End::A).reorder = true;
    send_counts(&mut link, End::A, 12..13);
    assert_eq!(receive_all(&mut link, End::B), vec![]);
    assert_eq!(link.in_flight(End::B), 1);
    link.advance_step();
    assert_eq!(receive_all(&mut link, End::B), vec![Ok(12)]);
    let s = link.stats(End::A);
    assert_eq!(
        (s.delayed, s.reordered, s.sent, s.delivered),
        (1, 2, 13, 11)
    );
    // the other direction was never touched
    assert_eq!(link.stats(End::B), Default::default());
    assert_eq!(link.step(), 2);
}

#[test]
fn memory_link_full_queue_loses_packets() {
    let mut link = MemoryLink::with_capacity(2);
    send_counts(&mut link, End::B, 0..4);
    assert_eq!(receive_all(&mut link, End::A), vec![Ok(0), Ok(1)]);
    assert_eq!(link.stats(End::B).lost_full, 2);
    assert_eq!(link.capacity(), 2);
}
