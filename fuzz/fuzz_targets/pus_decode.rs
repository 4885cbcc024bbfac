//! The PUS-C telecommand decoder ([`acs::link::pus::decode_tc`]) and the TM reader
//! ([`acs::link::pus::decode_tm`]) on arbitrary bytes. The first two bytes choose the expected
//! APID (11 bits) and whether to repair the packet's length field and CRC (so that the fuzzer
//! reaches the checks behind the CRC); the rest is the packet. Never panics; every refusal has
//! a failure code and a message; an accepted telecommand encodes back to the same bytes, and so
//! does an accepted report; the verification reports of an accepted telecommand are read back
//! with its request ID. The node's handling of the same bytes as a telecommand
//! ([`acs::uplink::telecommand::take`]) answers every packet with valid reports.
#![no_main]

use acs::link::crc16::crc16;
use acs::link::pus::{
    decode_tc, decode_tm, encode_tc, encode_tm, tm_packet_len, verification_report, CucTime,
    RequestId, TcHeader, TmHeader, Verification,
};
use acs::link::sequence::SequenceCounter;
use acs::link::space_packet::{Apid, OVERHEAD};
use acs::time::Epoch;
use acs::uplink::telecommand::{arity, take, REPORTS_LEN};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let [a0, a1, rest @ ..] = data else {
        return;
    };
    let apid = Apid::new(u16::from_le_bytes([*a0, *a1]) & Apid::MAX).expect("11 bits");
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
    match decode_tc(&bytes, apid) {
        Ok(tc) => {
            assert_eq!(Some(tc.request_id), RequestId::of_packet(&bytes));
            let h = TcHeader {
                apid,
                sequence_count: tc.request_id.sequence_control & 0x3FFF,
                ack: tc.ack,
                service: tc.service,
                subtype: tc.subtype,
                source_id: tc.source_id,
            };
            let mut out = vec![0u8; n];
            assert_eq!(encode_tc(&h, tc.app_data, &mut out), Ok(n));
            assert_eq!(out, bytes, "re-encoding an accepted telecommand");
            // its failed-acceptance report, with the application data as failure data
            let tm = TmHeader {
                apid,
                sequence_count: h.sequence_count,
                time_status: tc.ack.bits(),
                message_counter: tc.source_id,
                destination_id: tc.source_id,
                time: CucTime {
                    seconds: u32::from(tc.service) << 8 | u32::from(tc.subtype),
                    fraction: 1,
                },
            };
            let v = Verification::AcceptanceFailed { code: 0x100 };
            let mut report = vec![0u8; tm_packet_len(6)];
            let m = verification_report(&tm, tc.request_id, &v, &mut report).expect("fits");
            let read = decode_tm(&report[..m], apid).expect("reads back");
            assert_eq!((read.header, read.service, read.subtype), (tm, 1, 2));
            assert_eq!(read.app_data[..4], tc.request_id.to_bytes());
            assert_eq!(read.app_data.len(), 6);
        }
        Err(e) => {
            assert!(!e.to_string().is_empty());
            assert!(e.failure_code() > 0);
        }
    }
    if let Ok(tm) = decode_tm(&bytes, apid) {
        let mut out = vec![0u8; n];
        let r = encode_tm(&tm.header, tm.service, tm.subtype, &[], tm.app_data, &mut out);
        assert_eq!(r, Ok(n));
        assert_eq!(out, bytes, "re-encoding an accepted report");
    }
    // the node's handling of the packet (`acs::uplink::telecommand::take`): at most two
    // reports, each a valid TM packet; a command is applied only with its words
    let mut count = SequenceCounter::new();
    let mut reports = [0u8; REPORTS_LEN];
    let clock = Epoch::from_parts(i32::from(a0 & 0x7F) * 400, 0, 0).ok();
    let mut applied = false;
    let written = take(&bytes, apid, clock, &mut count, &mut reports, |code, args| {
        let words = arity(code).expect("a known command");
        assert!(args[words..].iter().all(|w| *w == 0));
        applied = true;
        Ok(())
    });
    let mut left = reports.get(..written).expect("within the buffer");
    // silence only for an applied command whose flags ask for no report
    assert!(applied || !left.is_empty(), "every refused packet is answered");
    while !left.is_empty() {
        // one report: its length field's bytes and the primary header
        let n = usize::from(u16::from_be_bytes([left[4], left[5]])) + 7;
        let tm = decode_tm(&left[..n], apid).expect("a valid report");
        assert_eq!((tm.service, tm_packet_len(tm.app_data.len())), (1, n));
        left = &left[n..];
    }
});
