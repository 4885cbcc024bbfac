//! The ground's commands as PUS-C telecommands on the nodes (`acs::uplink::telecommand`; issue
//! 31 item 2): telecommands built by the `spacepackets` crate (the independent reference) are
//! taken and applied, their verification reports read back by `spacepackets` with the CRC
//! checked; every refusal has its failure code and applies nothing; a real attitude node is
//! commanded through a packet; random bytes never panic; the ground tool's `acs tc` packets
//! are taken by the nodes and their reports read back by `acs tm`.

use acs::attitude_node::AttitudeNode;
use acs::flight::{CONFIG, TILES};
use acs::link::messages::{ATTITUDE_TC_APID, REFERENCE_TC_APID};
use acs::link::pus::{decode_tm, TIME_LEN};
use acs::link::sequence::SequenceCounter;
use acs::link::space_packet::Apid;
use acs::tiles::TileState;
use acs::time::{Epoch, Utc};
use acs::uplink::telecommand::{
    arity, cuc, take, ATTITUDE_TC_BYTES, MAX_TC_LEN, REFERENCE_TC_BYTES, REPORTS_LEN, SERVICE,
    SUBTYPE,
};
use acs::uplink::{apply_attitude, kind, UplinkError, ARG_WORDS};
use arbitrary_int::{u11, u14, u4};
use spacepackets::ecss::tc::{AckFlags as SpAckFlags, PusTcCreator, PusTcSecondaryHeader};
use spacepackets::ecss::tm::{GenericPusTmSecondaryHeader, PusTmReader};
use spacepackets::ecss::{CreatorConfig, MessageTypeId, PusPacket};
use spacepackets::{CcsdsPacket, SpHeader};

/// The application data of command `code` with `words`.
fn app_data(code: u16, words: &[u32]) -> Vec<u8> {
    let mut d = code.to_be_bytes().to_vec();
    for w in words {
        d.extend_from_slice(&w.to_be_bytes());
    }
    d
}

/// The telecommand as `spacepackets` builds it (raw ack bits, ECSS order: acceptance last).
fn sp_tc(apid: Apid, count: u16, ack: u8, service: u8, subtype: u8, app: &[u8]) -> Vec<u8> {
    let sp = SpHeader::new_for_unseg_tc(u11::new(apid.get()), u14::new(count), 0);
    let sec = PusTcSecondaryHeader::new(
        MessageTypeId::new(service, subtype),
        SpAckFlags::new_with_raw_value(u4::new(ack)),
        0x0ABC,
    );
    let creator = PusTcCreator::new(sp, sec, app, CreatorConfig::default());
    let mut bytes = vec![0u8; creator.len_written()];
    creator
        .write_to_slice(&mut bytes)
        .expect("spacepackets writes");
    bytes
}

/// The node's clock in these tests: 2026-11-28T06:30:15.25 UTC.
fn clock() -> Option<Epoch<Utc>> {
    Epoch::from_parts(9_828, 23_415, 250_000_000).ok()
}

/// What `take` did: the command it applied (code, words) and its reports.
struct Taken {
    applied: Option<(u16, Vec<u32>)>,
    reports: Vec<u8>,
    counter: SequenceCounter,
}

fn take_with(packet: &[u8], apid: Apid, outcome: Result<(), UplinkError>) -> Taken {
    let mut counter = SequenceCounter::new();
    // the counter is part way: reports continue it
    for _ in 0..5 {
        counter.next_count();
    }
    let mut out = [0u8; REPORTS_LEN];
    let mut applied = None;
    let n = take(
        packet,
        apid,
        clock(),
        &mut counter,
        &mut out,
        |code, args| {
            let n = arity(code).expect("only known codes are applied");
            assert!(
                args[n..].iter().all(|w| *w == 0),
                "the words after the command are 0"
            );
            applied = Some((code, args[..n].to_vec()));
            outcome
        },
    );
    assert!(n <= REPORTS_LEN);
    Taken {
        applied,
        reports: out[..n].to_vec(),
        counter,
    }
}

/// The reports back to back, read by `spacepackets` (CRC checked) and by our reader:
/// (subtype, application data) each, with the header fields checked against the request.
fn read_reports(reports: &[u8], request: &[u8], apid: Apid) -> Vec<(u8, Vec<u8>)> {
    let (stamp, status) = cuc(clock());
    let mut time = [0u8; TIME_LEN];
    time[..4].copy_from_slice(&stamp.seconds.to_be_bytes());
    time[4..].copy_from_slice(&stamp.fraction.to_be_bytes());
    let mut rest = reports;
    let mut out = vec![];
    let mut count = 5;
    while !rest.is_empty() {
        let r = PusTmReader::new(rest, TIME_LEN).expect("spacepackets reads the report");
        let n = r.len_packed();
        assert_eq!(r.apid().value(), apid.get());
        assert_eq!(r.seq_count().value(), count);
        assert_eq!(PusPacket::service_type_id(&r), 1);
        assert_eq!(r.dest_id(), 0x0ABC, "the TC's source ID");
        assert_eq!(r.msg_type_counter(), 0);
        assert_eq!(r.sc_time_ref_status().value(), status);
        assert_eq!(r.timestamp(), time);
        assert_eq!(r.source_data()[..4], request[..4], "the request ID");
        let ours = decode_tm(&rest[..n], apid).expect("ours reads it too");
        assert_eq!(ours.app_data, r.source_data());
        out.push((
            PusPacket::message_subtype_id(&r),
            r.source_data()[4..].to_vec(),
        ));
        rest = &rest[n..];
        count += 1;
    }
    out
}

/// Every command with its words, for the node that owns it.
fn commands() -> Vec<(u16, Vec<u32>)> {
    let q = [1.0f32, 0.0, 0.0, 0.0].map(f32::to_bits).to_vec();
    let mut slew = q.clone();
    slew.push(300.0f32.to_bits());
    vec![
        (kind::SUN_SAFE, vec![]),
        (kind::TRACK, q),
        (kind::SLEW, slew),
        (
            kind::ELEMENTS,
            (0..ARG_WORDS as u32).map(|i| i * 0x0101_0101).collect(),
        ),
        (kind::CLOCK, vec![9_828, 23_415, 250_000_000]),
        (kind::MARK_FAILED, vec![2, 0]),
        (kind::RESTORE, vec![1, 1]),
    ]
}

#[test]
fn sizes() {
    assert_eq!(MAX_TC_LEN, 247);
    assert_eq!(REFERENCE_TC_BYTES % 2, 0);
    assert_eq!(ATTITUDE_TC_BYTES % 2, 0);
    const { assert!(REFERENCE_TC_BYTES >= MAX_TC_LEN) };
    // the attitude node's mailbox holds a slew, its longest foreign command but the elements
    let slew = sp_tc(
        ATTITUDE_TC_APID,
        0,
        0b1001,
        SERVICE,
        SUBTYPE,
        &app_data(3, &[0; 5]),
    );
    assert!(slew.len() <= ATTITUDE_TC_BYTES);
    assert_eq!(REPORTS_LEN, 50);
}

#[test]
fn every_command_is_applied_and_reported() {
    for (code, words) in commands() {
        for ack in 0..16u8 {
            let p = sp_tc(
                REFERENCE_TC_APID,
                77,
                ack,
                SERVICE,
                SUBTYPE,
                &app_data(code, &words),
            );
            let t = take_with(&p, REFERENCE_TC_APID, Ok(()));
            assert_eq!(t.applied, Some((code, words.clone())));
            let reports = read_reports(&t.reports, &p, REFERENCE_TC_APID);
            let mut expected = vec![];
            if ack & 0b0001 != 0 {
                expected.push((1, vec![]));
            }
            if ack & 0b1000 != 0 {
                expected.push((7, vec![]));
            }
            assert_eq!(reports, expected, "code {code}, ack {ack:04b}");
        }
    }
}

#[test]
fn a_refused_command_is_reported_with_its_code() {
    let p = sp_tc(
        ATTITUDE_TC_APID,
        3,
        0,
        SERVICE,
        SUBTYPE,
        &app_data(2, &[0; 4]),
    );
    for (e, code) in [
        (UplinkError::UnknownCommand(9), 0x101u16),
        (UplinkError::InvalidArgument, 0x102),
        (UplinkError::NotThisNode(2), 0x104),
        (UplinkError::ArgumentCount(2), 0x105),
        (UplinkError::BadElementWord(57), 0x100 + 0x100 + 57),
    ] {
        let t = take_with(&p, ATTITUDE_TC_APID, Err(e));
        assert!(t.applied.is_some());
        // a failure is reported whatever the flags ask
        let reports = read_reports(&t.reports, &p, ATTITUDE_TC_APID);
        assert_eq!(reports, vec![(2, code.to_be_bytes().to_vec())], "{e:?}");
    }
}

#[test]
fn every_refusal_before_the_command_applies_nothing() {
    let apid = ATTITUDE_TC_APID;
    let good = sp_tc(apid, 1, 0b1001, SERVICE, SUBTYPE, &app_data(6, &[1, 0]));
    let mut crc = good.clone();
    *crc.last_mut().unwrap() ^= 1;
    let mut tm = good.clone();
    tm[0] &= !0x10;
    let tm_fixed = {
        // a TM packet with a valid CRC
        let n = tm.len();
        let c = crc::Crc::<u16>::new(&crc::CRC_16_IBM_3740).checksum(&tm[..n - 2]);
        tm[n - 2..].copy_from_slice(&c.to_be_bytes());
        tm
    };
    let cases: Vec<(&str, Vec<u8>, Apid, u16)> = vec![
        ("empty", vec![], apid, 1),
        ("three bytes", good[..3].to_vec(), apid, 1),
        ("cut short", good[..good.len() - 1].to_vec(), apid, 1),
        ("CRC", crc, apid, 2),
        ("other APID", good.clone(), REFERENCE_TC_APID, 4),
        ("TM", tm_fixed, apid, 5),
        ("TC[17,1]", sp_tc(apid, 1, 0b1001, 17, 1, &[]), apid, 7),
        (
            "TC[8,2]",
            sp_tc(apid, 1, 0b1001, 8, 2, &app_data(6, &[1, 0])),
            apid,
            7,
        ),
        (
            "no function ID",
            sp_tc(apid, 1, 0b1001, 8, 1, &[6]),
            apid,
            0x101,
        ),
        (
            "function 0",
            sp_tc(apid, 1, 0b1001, 8, 1, &app_data(0, &[])),
            apid,
            0x101,
        ),
        (
            "function 9",
            sp_tc(apid, 1, 0b1001, 8, 1, &app_data(9, &[])),
            apid,
            0x101,
        ),
        (
            "one word short",
            sp_tc(apid, 1, 0b1001, 8, 1, &app_data(6, &[1])),
            apid,
            0x105,
        ),
        (
            "one word long",
            sp_tc(apid, 1, 0b1001, 8, 1, &app_data(6, &[1, 0, 0])),
            apid,
            0x105,
        ),
        (
            "half a word",
            sp_tc(apid, 1, 0b1001, 8, 1, &[0, 6, 0, 0, 0, 1, 0, 0]),
            apid,
            0x105,
        ),
        (
            "sun-safe with a word",
            sp_tc(apid, 1, 0b1001, 8, 1, &app_data(1, &[0])),
            apid,
            0x105,
        ),
    ];
    for (what, packet, node_apid, code) in cases {
        let t = take_with(&packet, node_apid, Ok(()));
        assert_eq!(t.applied, None, "{what}");
        // the first four bytes, zeros if there are fewer
        let request = packet.get(..4).unwrap_or(&[0; 4]);
        // a packet refused before its header could be trusted has destination 0: read the
        // failure without the header checks of `read_reports` there
        let r = PusTmReader::new(&t.reports, TIME_LEN).expect("one report");
        assert_eq!(r.len_packed(), t.reports.len(), "{what}: one report");
        assert_eq!(PusPacket::message_subtype_id(&r), 2, "{what}");
        assert_eq!(r.apid().value(), node_apid.get());
        assert_eq!(r.source_data()[..4], request[..4], "{what}: request ID");
        assert_eq!(r.source_data()[4..], code.to_be_bytes(), "{what}");
        let trusted = code >= 7;
        assert_eq!(r.dest_id(), if trusted { 0x0ABC } else { 0 }, "{what}");
        assert_eq!(t.counter, {
            let mut c = SequenceCounter::new();
            for _ in 0..6 {
                c.next_count();
            }
            c
        });
    }
}

#[test]
fn a_node_is_commanded_through_a_packet() {
    let mut node = AttitudeNode::<TILES>::new(&CONFIG).expect("the flight configuration");
    let mut counter = SequenceCounter::new();
    // sends command `code` with `words` as telecommand `count`: its reports
    let mut send = |count: u16, code: u16, words: &[u32], node: &mut AttitudeNode<TILES>| {
        let p = sp_tc(
            ATTITUDE_TC_APID,
            count,
            0b1001,
            SERVICE,
            SUBTYPE,
            &app_data(code, words),
        );
        let mut out = [0u8; REPORTS_LEN];
        let clock = node.clock();
        let n = take(
            &p,
            ATTITUDE_TC_APID,
            clock,
            &mut counter,
            &mut out,
            |k, a| apply_attitude(k, a, node),
        );
        out[..n].to_vec()
    };
    let reports = send(0, 6, &[2, 0], &mut node);
    assert_eq!(node.tile_state(2), Some(TileState::Failed));
    // no clock before the first REF: time status 0, time 0
    let r = PusTmReader::new(&reports, TIME_LEN).expect("TM[1,1]");
    assert_eq!(
        (
            PusPacket::message_subtype_id(&r),
            r.sc_time_ref_status().value()
        ),
        (1, 0)
    );
    assert_eq!(r.timestamp(), [0; TIME_LEN]);
    // a tile that does not exist: refused, nothing changed
    let reports = send(1, 7, &[TILES as u32, 0], &mut node);
    let r = PusTmReader::new(&reports, TIME_LEN).expect("TM[1,2]");
    assert_eq!(PusPacket::message_subtype_id(&r), 2);
    assert_eq!(r.source_data()[4..], [0x01, 0x02]);
    assert_eq!(node.tile_state(2), Some(TileState::Failed));
    // the reference node's command: not this node's
    let reports = send(2, 5, &[1, 2, 3], &mut node);
    let r = PusTmReader::new(&reports, TIME_LEN).expect("TM[1,2]");
    assert_eq!(r.source_data()[4..], [0x01, 0x04]);
    // TM[1,1] and TM[1,7] took counts 0 and 1, the first refusal 2
    assert_eq!(r.seq_count().value(), 3, "one count per report");
}

/// xorshift64*: reproducible random bytes.
fn next(state: &mut u64) -> u64 {
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    state.wrapping_mul(0x2545_F491_4F6C_DD1D)
}

#[test]
fn random_packets_never_panic() {
    let mut s = 0x9E37_79B9_7F4A_7C15u64;
    let good = sp_tc(
        REFERENCE_TC_APID,
        1,
        0b1001,
        SERVICE,
        SUBTYPE,
        &app_data(2, &[0; 4]),
    );
    for i in 0..200_000 {
        // random lengths and bytes, and a valid packet with bytes changed
        let mut p = if i % 2 == 0 {
            let n = (next(&mut s) % (MAX_TC_LEN as u64 + 8)) as usize;
            (0..n).map(|_| next(&mut s) as u8).collect::<Vec<u8>>()
        } else {
            let mut p = good.clone();
            let at = (next(&mut s) as usize) % p.len();
            p[at] = next(&mut s) as u8;
            p
        };
        if i % 3 == 0 && p.len() > 6 {
            // a length field that agrees, so the CRC is what refuses
            let l = (p.len() - 7) as u16;
            p[4..6].copy_from_slice(&l.to_be_bytes());
        }
        let t = take_with(&p, REFERENCE_TC_APID, Ok(()));
        let mut rest = &t.reports[..];
        assert!(!rest.is_empty(), "every packet is answered");
        while !rest.is_empty() {
            let r = PusTmReader::new(rest, TIME_LEN).expect("a valid report");
            rest = &rest[r.len_packed()..];
        }
    }
}

#[test]
fn the_time_field() {
    let (t, status) = cuc(clock());
    assert_eq!(status, 1);
    assert_eq!(t.seconds, 9_828 * 86_400 + 23_415);
    // 0.25 s = 16 384 / 65 536, to one unit below
    assert!((16_383..=16_384).contains(&t.fraction));
    let (t, status) = cuc(Epoch::from_parts(49_710, 0, 0).ok());
    assert_eq!(
        (t.seconds, t.fraction, status),
        (0, 0, 0),
        "past the 32-bit count"
    );
    let (t, _) = cuc(Epoch::from_parts(49_709, 86_399, 999_999_999).ok());
    assert_eq!(t.seconds, 49_709 * 86_400 + 86_399);
}

fn acs(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_acs"))
        .args(args)
        .output()
        .expect("the acs binary runs")
}

/// The ground tool end to end: `acs tc` packets (built by `spacepackets`) taken by the nodes'
/// handling, with the real commands applied to an attitude and a reference node; the reports,
/// written to a file, read back by `acs tm` as CSV.
#[test]
fn acs_tc_to_the_nodes_and_acs_tm_back() {
    use acs::orbit::sgp4::{Gravity, Sgp4};
    use acs::reference_node::ReferenceNode;
    use acs::tle::Tle;
    use acs::uplink::apply_reference;

    let tle_path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/sgp4/dtusat.tle");
    let tle = Tle::parse_text(&std::fs::read_to_string(tle_path).expect("TLE")).expect("TLE");
    let orbit = Sgp4::new(&tle, Gravity::Wgs72).expect("SGP4");
    let mut reference =
        ReferenceNode::<TILES, { acs::flight::FIELD_COEFFS }>::new(&CONFIG, None).expect("node");
    let mut attitude = AttitudeNode::<TILES>::new(&CONFIG).expect("node");
    let mut counts = [SequenceCounter::new(), SequenceCounter::new()];
    let mut telemetry = Vec::new();
    let sent: [&[&str]; 6] = [
        &["clock", "2026-11-28T06:30:15.25Z", "--count", "0"],
        &["elements", "--tle", tle_path, "--count", "1"],
        &["mark-failed", "tile", "2", "--count", "0"],
        &["restore", "coil", "9", "--count", "1"],
        &["track", "0", "0", "0", "0", "--count", "2"],
        &["sun-safe", "--ack", "none", "--count", "3"],
    ];
    for args in sent {
        let mut a = vec!["tc"];
        a.extend_from_slice(args);
        a.extend_from_slice(&["--format", "bin"]);
        let out = acs(&a);
        if args[0] == "track" {
            // the tool refuses what the node would: exit 2, nothing sent
            assert_eq!(out.status.code(), Some(2), "{args:?}");
            continue;
        }
        assert_eq!(
            out.status.code(),
            Some(0),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let p = out.stdout;
        let mut reports = [0u8; REPORTS_LEN];
        let n = if u16::from_be_bytes([p[0], p[1]]) & 0x7FF == REFERENCE_TC_APID.get() {
            let clock = reference.clock();
            take(
                &p,
                REFERENCE_TC_APID,
                clock,
                &mut counts[0],
                &mut reports,
                |k, w| apply_reference(k, w, &mut reference, None),
            )
        } else {
            let clock = attitude.clock();
            take(
                &p,
                ATTITUDE_TC_APID,
                clock,
                &mut counts[1],
                &mut reports,
                |k, w| apply_attitude(k, w, &mut attitude),
            )
        };
        telemetry.extend_from_slice(&reports[..n]);
    }
    // the commands took effect
    assert_eq!(
        reference.clock(),
        Epoch::from_parts(9_828, 23_415, 250_000_000).ok()
    );
    assert_eq!(attitude.tile_state(2), Some(TileState::Failed));
    // the element set is the TLE's, bit for bit: the same REF as a node built with it
    let mut expected =
        ReferenceNode::<TILES, { acs::flight::FIELD_COEFFS }>::new(&CONFIG, orbit).expect("node");
    expected.set_clock(reference.clock().expect("set"));
    assert_eq!(
        reference.reference(0, None).to_bytes(),
        expected.reference(0, None).to_bytes()
    );
    let file = std::env::temp_dir().join(format!("acs-tm-{}.bin", std::process::id()));
    std::fs::write(&file, &telemetry).expect("write");
    let out = acs(&["tm", file.to_str().expect("UTF-8 path")]);
    let _ = std::fs::remove_file(&file);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = String::from_utf8(out.stdout).expect("UTF-8");
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], acs::host::cli::tm::HEADER);
    let rows: Vec<Vec<&str>> = lines[1..].iter().map(|l| l.split(',').collect()).collect();
    // clock: accepted, completed (stamped before the clock was set: no time); elements: both,
    // stamped with the new clock; mark failed: both; restore coil 9: refused
    let summary: Vec<(&str, &str, &str, &str)> =
        rows.iter().map(|r| (r[0], r[7], r[11], r[4])).collect();
    assert_eq!(
        summary,
        [
            ("reference", "accepted", "", ""),
            ("reference", "completed", "", ""),
            (
                "reference",
                "accepted",
                "",
                "2026-11-28T06:30:15.249984741Z"
            ),
            (
                "reference",
                "completed",
                "",
                "2026-11-28T06:30:15.249984741Z"
            ),
            ("attitude", "accepted", "", ""),
            ("attitude", "completed", "", ""),
            ("attitude", "acceptance failed", "0x102", ""),
        ]
    );
    assert_eq!(rows[6][12], "invalid argument");
    // sequence counts per node, request IDs of each telecommand, destination the source ID 1
    let counts: Vec<(&str, &str, &str)> = rows.iter().map(|r| (r[2], r[9], r[10])).collect();
    assert_eq!(
        counts,
        [
            ("0", "81", "0"),
            ("1", "81", "0"),
            ("2", "81", "1"),
            ("3", "81", "1"),
            ("0", "80", "0"),
            ("1", "80", "0"),
            ("2", "80", "1"),
        ]
    );
    assert!(rows.iter().all(|r| r[8] == "1"));
}

#[test]
fn acs_tm_refuses_a_damaged_packet() {
    let mut counter = SequenceCounter::new();
    let mut out = [0u8; REPORTS_LEN];
    let p = sp_tc(
        ATTITUDE_TC_APID,
        0,
        0b1001,
        SERVICE,
        SUBTYPE,
        &app_data(1, &[]),
    );
    let n = take(
        &p,
        ATTITUDE_TC_APID,
        clock(),
        &mut counter,
        &mut out,
        |_, _| Ok(()),
    );
    let mut hex: String = out[..n].iter().map(|b| format!("{b:02x}")).collect();
    let file = std::env::temp_dir().join(format!("acs-tm-hex-{}.txt", std::process::id()));
    std::fs::write(
        &file,
        format!("# two reports\n{}\n\n{}\n", &hex[..50], &hex[50..]),
    )
    .expect("write");
    let good = acs(&["tm", file.to_str().expect("UTF-8 path")]);
    assert_eq!(good.status.code(), Some(0));
    assert_eq!(String::from_utf8_lossy(&good.stdout).lines().count(), 3);
    // the second report's CRC damaged
    hex.replace_range(hex.len() - 2.., "00");
    std::fs::write(&file, &hex).expect("write");
    let bad = acs(&["tm", file.to_str().expect("UTF-8 path")]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("packet 2 at byte 25"));
    // a telecommand is not telemetry
    let hex: String = p.iter().map(|b| format!("{b:02x}")).collect();
    std::fs::write(&file, &hex).expect("write");
    let tc = acs(&["tm", file.to_str().expect("UTF-8 path")]);
    let _ = std::fs::remove_file(&file);
    assert_eq!(tc.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&tc.stderr).contains("a telecommand"));
}

/// Each command of the dictionary is applied by the node of its APID and refused by the other
/// as not its own (0x104), on the real nodes' functions; the housekeeping interval, which both
/// own, is applied by both.
#[test]
fn each_command_belongs_to_the_node_of_its_apid() {
    use acs::reference_node::ReferenceNode;
    use acs::uplink::telecommand::COMMANDS;
    use acs::uplink::{apply_reference, UplinkError};
    let mut reference =
        ReferenceNode::<TILES, { acs::flight::FIELD_COEFFS }>::new(&CONFIG, None).expect("node");
    let mut attitude = AttitudeNode::<TILES>::new(&CONFIG).expect("node");
    for d in COMMANDS {
        let words = [0u32; ARG_WORDS];
        let on_reference = apply_reference(d.code, &words, &mut reference, None);
        let on_attitude = apply_attitude(d.code, &words, &mut attitude);
        let (own, other) = if d.apid == REFERENCE_TC_APID {
            (on_reference, on_attitude)
        } else {
            assert_eq!(d.apid, ATTITUDE_TC_APID);
            (on_attitude, on_reference)
        };
        assert_ne!(own, Err(UplinkError::NotThisNode(d.code)), "{}", d.name);
        if d.code == acs::uplink::kind::HOUSEKEEPING {
            // both nodes own it, each for itself
            assert_eq!(other, Ok(()), "{}", d.name);
        } else {
            assert_eq!(other, Err(UplinkError::NotThisNode(d.code)), "{}", d.name);
        }
    }
}
