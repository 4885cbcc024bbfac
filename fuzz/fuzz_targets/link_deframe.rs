//! The link's receiving side on an arbitrary byte stream: the COBS [`Deframer`] fed byte by
//! byte, and [`FramedLink::receive`] over the same bytes. The stream is fuzz noise interleaved
//! with frames of real packets as [`FramedLink`] sends them (0x00, blocks, 0x00), some of those
//! frames with a byte changed. Never panics; the framed link reports exactly what the deframer
//! does; every frame that comes out is decoded or refused cleanly (an accepted one re-encodes
//! to its bytes); and every packet whose frame the fuzzer did not touch is recovered, in order,
//! whatever noise surrounds it.
#![no_main]

use std::collections::VecDeque;

use acs::hal::link::{ByteStream, ErrorKind, ErrorType, FramedLink, FramedLinkError, NodeLink};
use acs::link::cobs::{self, Deframer, FrameError};
use acs::link::space_packet::{decode, encode, packet_len, Apid, PacketHeader, PacketType};
use arbitrary::{Arbitrary, Unstructured};
use libfuzzer_sys::fuzz_target;

/// The longest message the link carries here, and its packet.
const MESSAGE_MAX: usize = 120;
const N: usize = packet_len(MESSAGE_MAX);

#[derive(Arbitrary, Debug)]
enum Chunk {
    Noise(Vec<u8>),
    Packet {
        telecommand: bool,
        secondary_header: bool,
        apid: u16,
        count: u16,
        data: Vec<u8>,
        /// A byte of the frame changed: (index, xor).
        touch: Option<(u16, u8)>,
    },
}

/// The stream a UART driver would give: what arrived, read on request.
struct Wire(VecDeque<u8>);

impl ErrorType for Wire {
    type Error = ErrorKind;
}

impl ByteStream for Wire {
    fn write(&mut self, bytes: &[u8]) -> Result<(), ErrorKind> {
        self.0.extend(bytes);
        Ok(())
    }
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, ErrorKind> {
        let mut n = 0;
        for b in buf.iter_mut() {
            let Some(x) = self.0.pop_front() else { break };
            *b = x;
            n += 1;
        }
        Ok(n)
    }
}

fuzz_target!(|data: &[u8]| {
    let mut u = Unstructured::new(data);
    let mut stream = Vec::new();
    // the packets whose frames are untouched, in order
    let mut intact: Vec<Vec<u8>> = Vec::new();
    for _ in 0..12 {
        let Ok(chunk) = Chunk::arbitrary(&mut u) else {
            break;
        };
        match chunk {
            Chunk::Noise(bytes) => stream.extend(bytes),
            Chunk::Packet {
                telecommand,
                secondary_header,
                apid,
                count,
                mut data,
                touch,
            } => {
                data.truncate(MESSAGE_MAX);
                let header = PacketHeader {
                    packet_type: if telecommand {
                        PacketType::Telecommand
                    } else {
                        PacketType::Telemetry
                    },
                    secondary_header,
                    apid: Apid::new(apid & Apid::MAX).expect("11 bits"),
                    sequence_count: count & 0x3FFF,
                };
                let mut packet = vec![0u8; packet_len(data.len())];
                encode(&header, &data, &mut packet).expect("fits");
                // as FramedLink::send writes it
                let mut sender = FramedLink::<Wire, N>::new(Wire(VecDeque::new()));
                sender.send(&packet).expect("an in-memory stream");
                let mut frame: Vec<u8> = sender.release().0.into();
                let mut frame_check = vec![0u8; cobs::max_encoded_len(packet.len())];
                let k = cobs::encode(&packet, &mut frame_check).expect("fits");
                assert_eq!(
                    frame[1..],
                    frame_check[..k],
                    "send writes 0x00 and the frame"
                );
                match touch {
                    Some((i, x)) if x != 0 => {
                        let i = usize::from(i) % frame.len();
                        frame[i] ^= x;
                    }
                    _ => intact.push(packet),
                }
                stream.extend(frame);
            }
        }
    }
    // the deframer, byte by byte
    let mut deframer = Deframer::<N>::new();
    let mut direct: Vec<Result<Vec<u8>, FrameError>> = Vec::new();
    for &b in &stream {
        if let Some(r) = deframer.push(b) {
            direct.push(r.map(<[u8]>::to_vec));
        }
    }
    // the framed link over the same bytes: the same results
    let mut link = FramedLink::<Wire, N>::new(Wire(stream.iter().copied().collect()));
    let mut via_link: Vec<Result<Vec<u8>, FrameError>> = Vec::new();
    let mut buf = [0u8; N];
    let mut calls = 0;
    while !link.stream_mut().0.is_empty() || calls == 0 {
        calls += 1;
        assert!(calls <= stream.len() + 1, "receive makes progress");
        match link.receive(&mut buf) {
            Ok(Some(n)) => via_link.push(Ok(buf[..n].to_vec())),
            Ok(None) => {}
            Err(FramedLinkError::Frame(e)) => via_link.push(Err(e)),
            Err(e) => panic!("unexpected link error {e:?}"),
        }
    }
    assert_eq!(via_link, direct);
    // every frame decodes or is refused cleanly
    for frame in direct.iter().flatten() {
        assert!(frame.len() <= N);
        let apid = frame.first().map_or(0, |&b| u16::from(b & 0x07) << 8)
            | u16::from(frame.get(1).copied().unwrap_or(0));
        match decode(frame, Apid::new(apid).expect("11 bits")) {
            Ok((h, user)) => {
                let mut out = vec![0u8; frame.len()];
                assert_eq!(encode(&h, user, &mut out), Ok(frame.len()));
                assert_eq!(&out, frame);
            }
            Err(e) => assert!(!e.to_string().is_empty()),
        }
    }
    // the intact packets come out, in order
    let mut outputs = direct.iter().flatten();
    for p in &intact {
        assert!(
            outputs.any(|f| f == p),
            "an untouched packet was lost: {p:02x?}"
        );
    }
});
