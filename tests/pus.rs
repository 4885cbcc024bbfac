//! The PUS-C packet layer (`acs::link::pus`; issue 31 items 2 and 3): round trips, every
//! refusal, the `spacepackets` crate as the independent reference both ways (its
//! `PusTcCreator` and `PusTmCreator` build, ours decodes; ours builds, its `PusTcReader` and
//! `PusTmReader` read with the CRC checked), its CUC reader on our time field, and random bytes
//! (no panic, and whatever is accepted re-encodes to the same bytes).

use acs::link::pus::{
    decode_tc, decode_tm, encode_tc, encode_tm, event_report, failure, housekeeping_report,
    tm_packet_len, verification_report, AckFlags, CucTime, PusError, RequestId, Severity, TcHeader,
    Telecommand, TmHeader, Verification, CUC_P_FIELD, PUS_VERSION, REQUEST_ID_LEN, TC_OVERHEAD,
    TC_SECONDARY_HEADER_LEN, TIME_LEN, TM_OVERHEAD, TM_SECONDARY_HEADER_LEN,
};
use acs::link::space_packet::{
    encode, packet_len, Apid, PacketError, PacketHeader, PacketType, MAX_DATA_LEN,
};
use arbitrary_int::{u11, u14, u4};
use spacepackets::ecss::tc::{
    AckFlags as SpAckFlags, GenericPusTcSecondaryHeader, PusTcCreator, PusTcReader,
    PusTcSecondaryHeader,
};
use spacepackets::ecss::tm::{
    GenericPusTmSecondaryHeader, PusTmCreator, PusTmReader, PusTmSecondaryHeader,
};
use spacepackets::ecss::{CreatorConfig, MessageTypeId, PusPacket};
use spacepackets::time::cuc::CucTime as SpCucTime;
use spacepackets::time::TimeReader;
use spacepackets::{CcsdsPacket, SpHeader};

/// The reference CRC: the catalogue's CRC-16/IBM-3740 (the `crc` crate).
const REFERENCE_CRC: crc::Crc<u16> = crc::Crc::<u16>::new(&crc::CRC_16_IBM_3740);

fn apid(value: u16) -> Apid {
    Apid::new(value).expect("an 11-bit APID")
}

/// Sets the CRC of a packet altered by hand.
fn fix_crc(p: &mut [u8]) {
    let n = p.len();
    let crc = REFERENCE_CRC.checksum(&p[..n - 2]);
    p[n - 2..].copy_from_slice(&crc.to_be_bytes());
}

fn tc_header() -> TcHeader {
    TcHeader {
        apid: apid(0x123),
        sequence_count: 0x2ABC,
        ack: AckFlags::ACCEPTANCE.with(AckFlags::COMPLETION),
        service: 8,
        subtype: 1,
        source_id: 0xBEEF,
    }
}

fn tc(h: &TcHeader, app_data: &[u8]) -> Vec<u8> {
    let mut out = vec![0; app_data.len() + TC_OVERHEAD];
    let n = encode_tc(h, app_data, &mut out).expect("encodes");
    assert_eq!(n, out.len());
    out
}

fn tm_header() -> TmHeader {
    TmHeader {
        apid: apid(0x45),
        sequence_count: 0x3FFF,
        time_status: 0xA,
        message_counter: 0x1234,
        destination_id: 0xBEEF,
        time: CucTime {
            seconds: 0x3065_A1B2,
            fraction: 0xC3D4,
        },
    }
}

/// One report through `build`, checked for its length.
fn report(build: impl Fn(&mut [u8]) -> Result<usize, PusError>, app_len: usize) -> Vec<u8> {
    let mut out = vec![0; tm_packet_len(app_len)];
    let n = build(&mut out).expect("builds");
    assert_eq!(n, out.len());
    out
}

/// The reports of every kind, with their service, subtype and application data.
fn every_report(h: &TmHeader, request: RequestId) -> Vec<(Vec<u8>, u8, u8, Vec<u8>)> {
    let id = request.to_bytes().to_vec();
    let with = |a: &[u8], b: &[u8]| [&id[..], a, b].concat();
    let mut all = vec![];
    for (v, sub, app) in [
        (Verification::Accepted, 1, id.clone()),
        (
            Verification::AcceptanceFailed { code: 0x0102 },
            2,
            with(&[1, 2], &[]),
        ),
        (Verification::Completed, 7, id.clone()),
        (
            Verification::CompletionFailed { code: 0xFFEE },
            8,
            with(&[0xFF, 0xEE], &[]),
        ),
    ] {
        let p = report(|o| verification_report(h, request, &v, o), app.len());
        all.push((p, 1, sub, app));
    }
    let params: Vec<u8> = (0..=255).collect();
    let p = report(|o| housekeeping_report(h, 0x0A0B, &params, o), 258);
    all.push((p, 3, 25, [&[0x0A, 0x0B][..], &params].concat()));
    for (s, sub) in [
        (Severity::Informative, 1),
        (Severity::Low, 2),
        (Severity::Medium, 3),
        (Severity::High, 4),
    ] {
        let p = report(|o| event_report(h, s, 0x0C0D, &[5, 6], o), 4);
        all.push((p, 5, sub, vec![0x0C, 0x0D, 5, 6]));
    }
    all
}

// ---- layout and round trips ---------------------------------------------------------------

#[test]
fn lengths_follow_the_headers() {
    assert_eq!(TC_SECONDARY_HEADER_LEN, 5);
    assert_eq!(TM_SECONDARY_HEADER_LEN, 13);
    assert_eq!(TM_OVERHEAD, 21);
    assert_eq!(TC_OVERHEAD, 13);
    assert_eq!(tm_packet_len(REQUEST_ID_LEN), 25);
    // CUC P-field: no extension, time code 010 (agency epoch), 4 − 1 = 3 seconds octets, 2
    // fraction octets
    assert_eq!(CUC_P_FIELD, 0b0010_1110); // 0 | 010 | 11 | 10
    assert_eq!(TIME_LEN, 6);
}

#[test]
fn telecommand_bytes_by_hand() {
    let p = tc(&tc_header(), &[0xAA, 0xBB]);
    assert_eq!(
        p[..11],
        [
            0x19, 0x23, // version 0, TC, secondary header, APID 0x123
            0xEA, 0xBC, // unsegmented, count 0x2ABC
            0x00, 0x08, // data field: 5 + 2 + 2 − 1
            0x29, // PUS 2, acks acceptance (0001) and completion (1000)
            8, 1, 0xBE, 0xEF,
        ]
    );
    let t = decode_tc(&p, apid(0x123)).expect("decodes");
    assert_eq!(
        t,
        Telecommand {
            request_id: RequestId {
                packet_id: 0x1923,
                sequence_control: 0xEABC,
            },
            ack: AckFlags::from_bits(0b1001),
            service: 8,
            subtype: 1,
            source_id: 0xBEEF,
            app_data: &[0xAA, 0xBB],
        }
    );
    assert!(t.ack.contains(AckFlags::ACCEPTANCE) && t.ack.contains(AckFlags::COMPLETION));
    assert!(!t.ack.contains(AckFlags::START) && !t.ack.contains(AckFlags::PROGRESS));
    assert_eq!(RequestId::of_packet(&p), Some(t.request_id));
    assert_eq!(t.request_id.to_bytes(), p[..4]);
}

#[test]
fn telecommand_round_trip() {
    for len in [0usize, 1, 7, 200] {
        for ack in 0..16 {
            let app: Vec<u8> = (0..len).map(|i| (i * 7 + ack) as u8).collect();
            let h = TcHeader {
                ack: AckFlags::from_bits(ack as u8),
                subtype: len as u8,
                ..tc_header()
            };
            let p = tc(&h, &app);
            let t = decode_tc(&p, h.apid).expect("decodes");
            assert_eq!(
                (t.ack, t.service, t.subtype, t.source_id, t.app_data),
                (h.ack, h.service, h.subtype, h.source_id, &app[..])
            );
        }
    }
}

#[test]
fn report_bytes_by_hand() {
    let request = RequestId {
        packet_id: 0x1923,
        sequence_control: 0xEABC,
    };
    let p = report(
        |o| {
            verification_report(
                &tm_header(),
                request,
                &Verification::AcceptanceFailed { code: 7 },
                o,
            )
        },
        6,
    );
    let body = [
        0x08, 0x45, // version 0, TM, secondary header, APID 0x45
        0xFF, 0xFF, // unsegmented, count 0x3FFF
        0x00, 0x14, // data field: 13 + 6 + 2 − 1 = 20
        0x2A, // PUS 2, time status 0xA
        1, 2, // TM[1,2]
        0x12, 0x34, // message type counter
        0xBE, 0xEF, // destination
        0x30, 0x65, 0xA1, 0xB2, 0xC3, 0xD4, // CUC 4 + 2
        0x19, 0x23, 0xEA, 0xBC, // request ID
        0x00, 0x07, // failure notice: the code, no failure data
    ];
    assert_eq!(p[..body.len()], body);
    assert_eq!(
        u16::from_be_bytes([p[25], p[26]]),
        REFERENCE_CRC.checksum(&body)
    );
}

#[test]
fn reports_round_trip() {
    let h = tm_header();
    let request = RequestId::of_packet(&tc(&tc_header(), &[])).expect("four bytes");
    for (p, service, subtype, app) in every_report(&h, request) {
        let t = decode_tm(&p, h.apid).expect("decodes");
        assert_eq!(
            (t.header, t.service, t.subtype, t.app_data),
            (h, service, subtype, &app[..])
        );
    }
    // encode_tm with no application data: the header alone
    let mut out = [0u8; TM_OVERHEAD];
    assert_eq!(encode_tm(&h, 17, 2, &[], &[], &mut out), Ok(TM_OVERHEAD));
    let t = decode_tm(&out, h.apid).expect("decodes");
    assert_eq!((t.service, t.subtype, t.app_data), (17, 2, &[][..]));
}

// ---- against spacepackets -----------------------------------------------------------------

#[test]
fn spacepackets_telecommands_decode() {
    for (service, subtype, source, ack, app, count) in [
        (8u8, 1u8, 0u16, 0u8, vec![], 0u16),
        (17, 1, 0xFFFF, 0b1111, vec![1], 0x3FFF),
        (3, 5, 0x1234, 0b0001, (0..=255).collect::<Vec<u8>>(), 77),
        (255, 255, 42, 0b1000, vec![0; 60], 16_000),
    ] {
        let sp = SpHeader::new_for_unseg_tc(u11::new(0x7FE), u14::new(count), 0);
        let sec = PusTcSecondaryHeader::new(
            MessageTypeId::new(service, subtype),
            SpAckFlags::new_with_raw_value(u4::new(ack)),
            source,
        );
        let creator = PusTcCreator::new(sp, sec, &app, CreatorConfig::default());
        let mut bytes = vec![0u8; creator.len_written()];
        creator
            .write_to_slice(&mut bytes)
            .expect("spacepackets writes");
        let t = decode_tc(&bytes, apid(0x7FE)).expect("ours decodes spacepackets' TC");
        assert_eq!(
            (t.service, t.subtype, t.source_id, t.ack.bits(), t.app_data),
            (service, subtype, source, ack, &app[..])
        );
        assert_eq!(t.request_id.to_bytes(), bytes[..4]);
        assert_eq!(t.request_id.sequence_control & 0x3FFF, count);
        // and ours writes the same bytes for the same fields
        let h = TcHeader {
            apid: apid(0x7FE),
            sequence_count: count,
            ack: AckFlags::from_bits(ack),
            service,
            subtype,
            source_id: source,
        };
        assert_eq!(tc(&h, &app), bytes);
    }
}

#[test]
fn ack_flags_bit_order_against_spacepackets() {
    // The acknowledgement field's raw 4 bits agree (above). Its flag names do not:
    // spacepackets 0.19 puts `acceptance` on the field's most significant bit (its bit 3,
    // counted from the least significant), where ECSS numbering (bit 0 first transmitted) and
    // PUS-A's table put completion. This test pins both readings, so a change in either shows.
    let sp_acceptance = SpAckFlags::builder()
        .with_acceptance(true)
        .with_start(false)
        .with_progress(false)
        .with_completion(false)
        .build();
    assert_eq!(sp_acceptance.raw_value().value(), 0b1000);
    assert_eq!(AckFlags::COMPLETION.bits(), 0b1000);
    assert_eq!(AckFlags::ACCEPTANCE.bits(), 0b0001);
}

#[test]
fn our_telecommands_read_by_spacepackets() {
    let h = tc_header();
    let app = [1u8, 2, 3, 4, 5];
    let bytes = tc(&h, &app);
    let r = PusTcReader::new(&bytes).expect("spacepackets reads ours, CRC checked");
    assert_eq!(r.apid().value(), h.apid.get());
    assert_eq!(r.seq_count().value(), h.sequence_count);
    assert_eq!(
        (
            PusPacket::service_type_id(&r),
            PusPacket::message_subtype_id(&r)
        ),
        (h.service, h.subtype)
    );
    assert_eq!(r.source_id(), h.source_id);
    assert_eq!(r.ack_flags().raw_value().value(), h.ack.bits());
    assert_eq!(r.app_data(), app);
}

#[test]
fn our_reports_read_by_spacepackets() {
    let h = tm_header();
    let request = RequestId::of_packet(&tc(&tc_header(), &[])).expect("four bytes");
    let stamp = {
        let mut t = [0u8; TIME_LEN];
        t[..4].copy_from_slice(&h.time.seconds.to_be_bytes());
        t[4..].copy_from_slice(&h.time.fraction.to_be_bytes());
        t
    };
    for (p, service, subtype, app) in every_report(&h, request) {
        let r = PusTmReader::new(&p, TIME_LEN).expect("spacepackets reads ours, CRC checked");
        assert_eq!(r.apid().value(), h.apid.get());
        assert_eq!(r.seq_count().value(), h.sequence_count);
        assert_eq!(
            (
                PusPacket::service_type_id(&r),
                PusPacket::message_subtype_id(&r)
            ),
            (service, subtype)
        );
        assert_eq!(r.msg_type_counter(), h.message_counter);
        assert_eq!(r.dest_id(), h.destination_id);
        assert_eq!(r.sc_time_ref_status().value(), h.time_status);
        assert_eq!(PusPacket::pus_version(&r).map(|v| v as u8), Ok(PUS_VERSION));
        assert_eq!(r.timestamp(), stamp);
        assert_eq!(r.source_data(), app);
        assert_eq!(r.len_packed(), p.len());
        assert_eq!(
            r.checksum(),
            Some(REFERENCE_CRC.checksum(&p[..p.len() - 2]))
        );
    }
}

#[test]
fn spacepackets_reports_decode() {
    let stamp = [0x30, 0x65, 0xA1, 0xB2, 0xC3, 0xD4];
    let app = [0x19, 0x23, 0xEA, 0xBC, 0, 9];
    let sp = SpHeader::new_for_unseg_tm(u11::new(0x45), u14::new(99), 0);
    let mut sec = PusTmSecondaryHeader::new(MessageTypeId::new(1, 8), 0x55AA, 0x0102, &stamp);
    sec.sc_time_ref_status = u4::new(3);
    let creator = PusTmCreator::new(sp, sec, &app, CreatorConfig::default());
    let mut bytes = vec![0u8; creator.len_written()];
    creator
        .write_to_slice(&mut bytes)
        .expect("spacepackets writes");
    let t = decode_tm(&bytes, apid(0x45)).expect("ours decodes spacepackets' TM");
    assert_eq!(
        t.header,
        TmHeader {
            apid: apid(0x45),
            sequence_count: 99,
            time_status: 3,
            message_counter: 0x55AA,
            destination_id: 0x0102,
            time: CucTime {
                seconds: 0x3065_A1B2,
                fraction: 0xC3D4,
            },
        }
    );
    assert_eq!((t.service, t.subtype, t.app_data), (1, 8, &app[..]));
}

#[test]
fn time_field_read_by_spacepackets_cuc() {
    // spacepackets' CUC reader takes only the CCSDS epoch's P-field (0x1E); the field after
    // the P-field, 4 octets of seconds and 2 of fraction, is ours whatever the epoch.
    for (seconds, fraction) in [
        (0u32, 0u16),
        (1, 0x8000),
        (0x3065_A1B2, 0xC3D4),
        (u32::MAX, u16::MAX),
    ] {
        let mut out = [0u8; TM_OVERHEAD];
        let h = TmHeader {
            time: CucTime { seconds, fraction },
            ..tm_header()
        };
        encode_tm(&h, 9, 2, &[], &[], &mut out).expect("encodes");
        let field = &out[6 + 7..6 + 13];
        let with_p = [&[(CUC_P_FIELD & 0x8F) | 0x10][..], field].concat();
        let cuc = SpCucTime::from_bytes(&with_p).expect("a CUC 4+2 time");
        assert_eq!(cuc.counter(), seconds);
        assert_eq!(cuc.fractions().counter, u32::from(fraction));
    }
}

// ---- refusals -----------------------------------------------------------------------------

#[test]
fn every_telecommand_refusal() {
    let a = apid(0x123);
    let good = tc(&tc_header(), &[1, 2, 3]);
    assert!(decode_tc(&good, a).is_ok());

    // the space packet layer's, passed on
    let short = decode_tc(&good[..7], a);
    assert_eq!(
        short,
        Err(PusError::Packet(PacketError::TooShort { len: 7 }))
    );
    let e = decode_tc(&good[..good.len() - 1], a).expect_err("length");
    assert!(matches!(
        e,
        PusError::Packet(PacketError::LengthMismatch { .. })
    ));
    assert_eq!(e.failure_code(), failure::LENGTH);
    let mut damaged = good.clone();
    damaged[8] ^= 0x10;
    let e = decode_tc(&damaged, a).expect_err("crc");
    assert!(matches!(e, PusError::Packet(PacketError::Crc { .. })));
    assert_eq!(e.failure_code(), failure::CRC);
    // the request ID of a damaged packet is still there for its TM[1,2]
    assert_eq!(RequestId::of_packet(&damaged), RequestId::of_packet(&good));
    assert_eq!(RequestId::of_packet(&good[..3]), None);
    let mut v = good.clone();
    v[0] |= 0x20;
    fix_crc(&mut v);
    let e = decode_tc(&v, a).expect_err("version");
    assert_eq!(e, PusError::Packet(PacketError::Version(1)));
    assert_eq!(e.failure_code(), failure::PACKET_FORMAT);
    let mut seg = good.clone();
    seg[2] &= 0x7F;
    fix_crc(&mut seg);
    let e = decode_tc(&seg, a).expect_err("segmented");
    assert_eq!(e, PusError::Packet(PacketError::SequenceFlags(1)));
    assert_eq!(e.failure_code(), failure::PACKET_FORMAT);
    let e = decode_tc(&good, apid(0x124)).expect_err("apid");
    assert!(matches!(e, PusError::Packet(PacketError::WrongApid { .. })));
    assert_eq!(e.failure_code(), failure::APID);

    // this layer's
    let mut tm = good.clone();
    tm[0] &= !0x10;
    fix_crc(&mut tm);
    assert_eq!(decode_tc(&tm, a), Err(PusError::WrongPacketType));
    let mut plain = good.clone();
    plain[0] &= !0x08;
    fix_crc(&mut plain);
    assert_eq!(decode_tc(&plain, a), Err(PusError::NoSecondaryHeader));
    assert_eq!(
        PusError::NoSecondaryHeader.failure_code(),
        failure::PACKET_TYPE
    );
    assert_eq!(
        PusError::WrongPacketType.failure_code(),
        failure::PACKET_TYPE
    );
    for n in 0..TC_SECONDARY_HEADER_LEN {
        let h = PacketHeader {
            packet_type: PacketType::Telecommand,
            secondary_header: true,
            apid: a,
            sequence_count: 1,
        };
        let mut p = vec![0; packet_len(n)];
        encode(&h, &good[6..6 + n], &mut p).expect("encodes");
        let e = decode_tc(&p, a).expect_err("short");
        assert_eq!(e, PusError::TooShort { len: n });
        assert_eq!(e.failure_code(), failure::LENGTH);
    }
    for version in [0u8, 1, 3, 15] {
        let mut p = good.clone();
        p[6] = (version << 4) | (p[6] & 0x0F);
        fix_crc(&mut p);
        let e = decode_tc(&p, a).expect_err("PUS version");
        assert_eq!(e, PusError::Version(version));
        assert_eq!(e.failure_code(), failure::PUS_VERSION);
    }
    let unknown = decode_tc(
        &tc(
            &TcHeader {
                service: 200,
                subtype: 1,
                ..tc_header()
            },
            &[],
        ),
        a,
    )
    .expect("decodes")
    .not_served();
    assert_eq!(
        unknown,
        PusError::UnknownMessageType {
            service: 200,
            subtype: 1
        }
    );
    assert_eq!(unknown.failure_code(), failure::MESSAGE_TYPE);
    assert_eq!(unknown.to_string(), "TC[200,1] not served");
}

#[test]
fn every_telemetry_refusal() {
    let h = tm_header();
    let a = h.apid;
    let good = report(|o| event_report(&h, Severity::High, 1, &[], o), 2);
    assert_eq!(
        decode_tm(&tc(&tc_header(), &[]), apid(0x123)),
        Err(PusError::WrongPacketType)
    );
    let mut plain = good.clone();
    plain[0] &= !0x08;
    fix_crc(&mut plain);
    assert_eq!(decode_tm(&plain, a), Err(PusError::NoSecondaryHeader));
    let mut v = good.clone();
    v[6] = 0x1A;
    fix_crc(&mut v);
    assert_eq!(decode_tm(&v, a), Err(PusError::Version(1)));
    let ph = PacketHeader {
        packet_type: PacketType::Telemetry,
        secondary_header: true,
        apid: a,
        sequence_count: 0,
    };
    let mut p = vec![0; packet_len(12)];
    encode(&ph, &good[6..18], &mut p).expect("encodes");
    assert_eq!(decode_tm(&p, a), Err(PusError::TooShort { len: 12 }));
}

#[test]
fn every_encoding_refusal_leaves_out_unchanged() {
    let h = tm_header();
    let request = RequestId {
        packet_id: 1,
        sequence_control: 2,
    };
    let mut out = [0x5Au8; 40];
    let bad_status = TmHeader {
        time_status: 16,
        ..h
    };
    let r = verification_report(&bad_status, request, &Verification::Accepted, &mut out);
    assert_eq!(r, Err(PusError::TimeStatus(16)));
    let bad_count = TmHeader {
        sequence_count: 0x4000,
        ..h
    };
    let r = housekeeping_report(&bad_count, 1, &[], &mut out);
    assert_eq!(
        r,
        Err(PusError::Packet(PacketError::SequenceCountTooLarge(0x4000)))
    );
    let r = event_report(&h, Severity::Low, 1, &[0; 18], &mut out);
    assert_eq!(
        r,
        Err(PusError::Packet(PacketError::OutputTooSmall {
            needed: 41,
            len: 40
        }))
    );
    let huge = vec![0u8; MAX_DATA_LEN];
    let r = housekeeping_report(&h, 1, &huge, &mut out);
    assert_eq!(
        r,
        Err(PusError::Packet(PacketError::DataTooLong {
            len: MAX_DATA_LEN + 2 + TM_SECONDARY_HEADER_LEN
        }))
    );
    let r = encode_tc(&tc_header(), &huge, &mut out);
    assert!(matches!(
        r,
        Err(PusError::Packet(PacketError::DataTooLong { .. }))
    ));
    let r = encode_tc(&tc_header(), &[0; 28], &mut out);
    assert!(matches!(
        r,
        Err(PusError::Packet(PacketError::OutputTooSmall { .. }))
    ));
    assert_eq!(out, [0x5A; 40]);
    // exactly long enough: fits; the bytes after the packet are not touched
    let r = event_report(&h, Severity::Low, 1, &[0; 17], &mut out);
    assert_eq!(r, Ok(40));
    let mut longer = [0x5Au8; 50];
    assert_eq!(
        event_report(&h, Severity::Low, 1, &[0; 17], &mut longer),
        Ok(40)
    );
    assert_eq!(longer[..40], out);
    assert_eq!(longer[40..], [0x5A; 10]);
}

// ---- random bytes -------------------------------------------------------------------------

/// xorshift64*: a deterministic generator (no seed from the environment: a failure reproduces).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
}

/// 1 000 000 inputs in a release build (100 000 in debug): random bytes, and valid packets
/// with random bytes changed and the CRC made right again half the time (so that the checks
/// past the CRC see them). Nothing panics; what decodes re-encodes to the same bytes.
#[test]
fn random_bytes_never_panic_and_accepted_ones_round_trip() {
    let n: u32 = if cfg!(debug_assertions) {
        100_000
    } else {
        1_000_000
    };
    let a = apid(0x123);
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut accepted = 0u32;
    let base = tc(&tc_header(), &[1, 2, 3, 4, 5, 6, 7, 8]);
    let mut out = vec![0u8; 64];
    for i in 0..n {
        let bytes: Vec<u8> = if i.is_multiple_of(2) {
            let len = (rng.next() % 40) as usize;
            (0..len).map(|_| rng.next() as u8).collect()
        } else {
            let mut p = base.clone();
            let len = 6 + (rng.next() % 10) as usize;
            p.truncate(len.max(8).min(base.len()));
            for _ in 0..1 + rng.next() % 3 {
                let at = (rng.next() % p.len() as u64) as usize;
                p[at] ^= 1 << (rng.next() % 8);
            }
            let l = p.len();
            if rng.next().is_multiple_of(2) && l >= 8 {
                // a length field that agrees, and the CRC made right
                let field = (l - 7) as u16;
                p[4..6].copy_from_slice(&field.to_be_bytes());
                fix_crc(&mut p);
            }
            p
        };
        let Ok(t) = decode_tc(&bytes, a) else {
            continue;
        };
        accepted += 1;
        let h = TcHeader {
            apid: a,
            sequence_count: t.request_id.sequence_control & 0x3FFF,
            ack: t.ack,
            service: t.service,
            subtype: t.subtype,
            source_id: t.source_id,
        };
        let m = encode_tc(&h, t.app_data, &mut out).expect("re-encodes");
        assert_eq!(out[..m], bytes[..], "input {i}");
    }
    // the mutated valid packets reach acceptance often enough to exercise the round trip
    assert!(accepted > n / 50, "{accepted} accepted");
}
