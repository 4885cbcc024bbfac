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
//! | host link | two in-memory ends with deterministic faults (drop, corrupt, delay, reorder) for tests and the simulator | — | `crate::host::link` (feature `host`) |
//!
//! A node sends: `sequence::SequenceCounter::next_count`, [`space_packet::encode`] into a
//! buffer of [`space_packet::packet_len`]`(message)` bytes, [`NodeLink::send`]. It receives:
//! [`NodeLink::receive`] into a buffer as long as its longest packet until it returns
//! `Ok(None)`, [`space_packet::decode`] with the APID it expects, then
//! `sequence::SequenceTracker::accept`. Every refusal on the way is a typed error, reported,
//! never a silent default; a lost or damaged packet shows as an error at the receiver or as a
//! gap in the sequence counts.
//!
//! On the wire a packet with `n` bytes of message takes `n` + 8 bytes (header 6, CRC 2) + 2
//! (COBS code byte and delimiter, for `n` + 8 ≤ 253) + 1 (the leading delimiter
//! [`FramedLink`] writes): `n` + 11 bytes, 131 for a 120-byte message (0.14 s at 9 600 baud).
//!
//! # Flash
//! Measured on the MSP430 (nightly-2026-05-20, opt-level "s", LTO, the firmware's link
//! flags; a probe image calling each function, code bytes by function): see the table in
//! [`crc16`] for the CRC variants and the crate's report for the rest.
//!
//! [`FramedLink`]: crate::hal::link::FramedLink
//! [`NodeLink::send`]: crate::hal::link::NodeLink::send
//! [`NodeLink::receive`]: crate::hal::link::NodeLink::receive

pub mod cobs;
pub mod crc16;
pub mod messages;
pub mod sequence;
pub mod space_packet;
