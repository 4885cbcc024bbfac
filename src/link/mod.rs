//! The inter-node link: packets between the ACS's two processors over one serial line
//! (issue 29, item 2).
//!
//! The ACS runs on two MSP430 nodes: a *reference* node (orbit, Sun, field, guidance) and an
//! *attitude* node (sensors, estimation, control), joined by one UART. What one node's
//! component sends the other's is a message (its bytes are the message layer's business); this
//! module carries it, checked, across the line:
//!
//! | layer | what it does | standard | module |
//! |---|---|---|---|
//! | packet | primary header (APID, sequence count, length) and CRC around the message; refuses a damaged, foreign or malformed packet | CCSDS 133.0-B-2 §4.1 | [`space_packet`] |
//! | packet error control | CRC-16/CCITT over header and message | ECSS-E-ST-70-41C annex B.1 | [`crc16`] |
//! | sequence | the sender's count, the receiver's gap count | CCSDS 133.0-B-2 §4.1.3.4.3 | [`sequence`] |
//! | framing | the packet as a COBS frame ended by 0x00 on the byte stream; resynchronises at the next 0x00 | Cheshire & Baker 1999 | [`cobs`] |
//! | node link | send one packet, receive one packet (non-blocking); over any byte stream with [`FramedLink`] | — | [`crate::hal::link`] |
//! | messages | STATUS and REF: their layout, their APIDs and the two nodes' timing contract | — | [`messages`] |
//! | PUS | the ground's telecommands in (TC secondary header), the nodes' reports out: request verification, housekeeping, events | ECSS-E-ST-70-41C §7.4, services 1, 3, 5 | [`pus`] |
//! | host link | two in-memory ends with deterministic faults (drop, corrupt, delay, reorder) for tests and the simulator | — | `crate::host::link` (feature `host`) |
//!
//! A node sends: [`sequence::SequenceCounter::next_count`], [`space_packet::encode`] into a
//! buffer of [`space_packet::packet_len`]`(message)` bytes, [`NodeLink::send`]. It receives:
//! [`NodeLink::receive`] into a buffer as long as its longest packet until it returns
//! `Ok(None)`, [`space_packet::decode`] with the APID it expects, then
//! [`sequence::SequenceTracker::accept`]. Every refusal on the way is a typed error, reported,
//! never a silent default; a lost or damaged packet shows as an error at the receiver or as a
//! gap in the sequence counts. (An example of both ends: `crate::host::link`'s docs.)
//!
//! On the wire a packet with `n` bytes of message takes `n` + 8 bytes (header 6, CRC 2) + 2
//! (COBS code byte and delimiter, for `n` + 8 ≤ 253) + 1 (the leading delimiter
//! [`FramedLink`] writes): `n` + 11 bytes, 131 for a 120-byte message (0.14 s at 9 600 baud).
//!
//! # Flash and cycles
//! Measured on the MSP430 (nightly-2026-05-20, opt-level "s", LTO, the firmware's link flags
//! and memory map) with `firmware/tools/link-probe/measure`: a probe image, linked with the
//! firmware's runtime and its undefined panic handler (so it also proves that no panic is
//! reachable in any of this code), calls each function once through an `#[inline(never)]`
//! wrapper; bytes are the wrappers' and the shared functions' symbol sizes, cycles MCLK cycles
//! in mspdebug's simulator, for a 120-byte message (a 128-byte packet, a 131-byte frame).
//!
//! | function | code, B | cycles |
//! |---|---:|---:|
//! | [`crc16::crc16_update`] (shared by encode and decode) | 82 | 42 a byte |
//! | [`space_packet::encode`] (CRC aside) | 210 | 7 160 |
//! | [`space_packet::decode`] (CRC aside) | 342 | 5 540 |
//! | [`cobs::Blocks`]`::next` (shared by both encoders) | 122 | — |
//! | [`cobs::encode`] into a buffer | 168 | 3 750 |
//! | [`cobs::Deframer`]`::push` (one copy for each `N` used) | 212 | 96 a byte |
//! | [`FramedLink`] `send` (over a RAM stream) | 162 | 5 370 |
//! | [`FramedLink`] `receive` (over a RAM stream, deframer aside) | 190 | 11 700 for the packet |
//! | [`sequence::SequenceTracker::accept`] | 228 | 67 |
//! | [`sequence::SequenceCounter::next_count`] | 20 | 25 |
//!
//! All of it is 1 736 B; a node that sends with [`FramedLink`] does not need [`cobs::encode`]:
//! 1 568 B, no constant tables, and RAM for the deframer's `N` bytes, 6 of state, and the
//! caller's packet buffers.
//!
//! The PUS layer above the packets ([`pus`]) has its own table in its module docs: 1.5–1.9 KB
//! on a node with its calls.
//!
//! [`FramedLink`]: crate::hal::link::FramedLink
//! [`NodeLink::send`]: crate::hal::link::NodeLink::send
//! [`NodeLink::receive`]: crate::hal::link::NodeLink::receive

pub mod cobs;
pub mod crc16;
pub mod messages;
pub mod pus;
pub mod sequence;
pub mod space_packet;
