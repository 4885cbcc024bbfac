//! An in-memory link between two node ends, with the faults the tests and the simulator inject.
//!
//! [`MemoryLink`] holds one packet queue each way; [`MemoryLink::end`] lends one end as a
//! [`NodeLink`] (the same trait the flight nodes use over a UART with
//! [`crate::hal::link::FramedLink`]), so the deployment that owns the link passes an end to each
//! node's step. Time is counted in steps: [`MemoryLink::advance_step`] is called once per
//! control step; a packet sent is receivable in the same step unless delayed.
//!
//! The faults are deterministic: nothing random inside, the caller sets each one for the next
//! packets sent from an end ([`MemoryLink::faults`]), and each is used up as packets pass. On a
//! send, in this order:
//!
//! | [`Faults`] field | what happens to the next packet(s) sent | counted in [`LinkStats`] |
//! |---|---|---|
//! | `drop: n` | the next `n` packets are lost | `dropped` |
//! | `corrupt: Some(Corruption { byte, xor })` | the next packet's byte `byte` is xored with `xor` (nothing if the packet is shorter) | `corrupted` |
//! | `delay: n` | the next `n` packets become receivable one step late (after the next `advance_step`) | `delayed` |
//! | `reorder: true` | the next packet is delivered after the one sent after it (or at the next `advance_step` if none is) | `reordered` |
//!
//! A receive returns the first packet in the queue that is receivable now, so an undelayed
//! packet overtakes a delayed one. Each queue holds [`MemoryLink::capacity`] packets; a packet
//! sent to a full queue is lost (`lost_full`), as bytes are when a UART driver's buffer
//! overflows: the sender is not told, the receiver sees a gap in the sequence counts.
//!
//! Both ends of a message's way, with a packet lost on the line:
//!
//! ```
//! use acs::hal::link::NodeLink;
//! use acs::host::link::{End, MemoryLink};
//! use acs::link::sequence::{Continuity, SequenceCounter, SequenceTracker};
//! use acs::link::space_packet::{decode, encode, packet_len, Apid, PacketHeader, PacketType};
//!
//! const REF_APID: Apid = match Apid::new(0x10) {
//!     Some(a) => a,
//!     None => panic!(),
//! };
//! let mut link = MemoryLink::new();
//! let (mut counter, mut tracker) = (SequenceCounter::new(), SequenceTracker::new());
//! let mut packet = [0u8; packet_len(4)];
//! let mut received = [0u8; packet_len(4)];
//! for step in 0..3u8 {
//!     if step == 1 {
//!         link.faults(End::A).drop = 1;
//!     }
//!     // the sending node (end A)
//!     let header = PacketHeader {
//!         packet_type: PacketType::Telemetry,
//!         secondary_header: false,
//!         apid: REF_APID,
//!         sequence_count: counter.next_count(),
//!     };
//!     let n = encode(&header, &[step; 4], &mut packet).unwrap();
//!     link.end(End::A).send(&packet[..n]).unwrap();
//!     // the receiving node (end B)
//!     while let Some(n) = link.end(End::B).receive(&mut received).unwrap() {
//!         let (header, message) = decode(&received[..n], REF_APID).unwrap();
//!         let continuity = tracker.accept(header.sequence_count);
//!         match step {
//!             0 => assert_eq!(continuity, Continuity::First),
//!             _ => assert_eq!(continuity, Continuity::Gap { missed: 1 }),
//!         }
//!         assert_eq!(message, &[step; 4]);
//!     }
//!     link.advance_step();
//! }
//! assert_eq!((tracker.gaps(), tracker.missed()), (1, 1));
//! ```

use std::collections::VecDeque;

use crate::hal::link::{ErrorKind, ErrorType, NodeLink};

/// One end of the link (which node is which is the deployment's choice).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum End {
    /// One end (for example the reference node).
    A,
    /// The other end (for example the attitude node).
    B,
}

impl End {
    /// The far end.
    pub fn other(self) -> End {
        match self {
            End::A => End::B,
            End::B => End::A,
        }
    }

    fn index(self) -> usize {
        match self {
            End::A => 0,
            End::B => 1,
        }
    }
}

/// Changes one byte of a packet: `packet[byte] ^= xor`.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Corruption {
    /// Index of the byte in the packet.
    pub byte: usize,
    /// Bits to flip (0 changes nothing).
    pub xor: u8,
}

/// The faults to inject into the next packets sent from one end ([module docs](self)).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct Faults {
    /// Packets to drop.
    pub drop: u32,
    /// A change to the next packet.
    pub corrupt: Option<Corruption>,
    /// Packets to deliver one step late.
    pub delay: u32,
    /// Swap the next packet with the one after it.
    pub reorder: bool,
}

/// What happened to the packets sent from one end.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct LinkStats {
    /// Packets sent.
    pub sent: u64,
    /// Packets received by the far end.
    pub delivered: u64,
    /// Packets dropped by [`Faults::drop`].
    pub dropped: u64,
    /// Packets changed by [`Faults::corrupt`].
    pub corrupted: u64,
    /// Packets delayed by [`Faults::delay`].
    pub delayed: u64,
    /// Packets held back by [`Faults::reorder`].
    pub reordered: u64,
    /// Packets lost because the far end's queue was full.
    pub lost_full: u64,
}

/// A packet on its way.
#[derive(Clone, Debug)]
struct InFlight {
    /// The first step at which it can be received.
    ready_step: u64,
    bytes: Vec<u8>,
}

/// One direction: the packets sent from one end to the other.
#[derive(Clone, Debug, Default)]
struct Direction {
    queue: VecDeque<InFlight>,
    /// A packet held back by `reorder`, until the next one is sent.
    held: Option<InFlight>,
    faults: Faults,
    stats: LinkStats,
}

impl Direction {
    fn enqueue(&mut self, packet: InFlight, capacity: usize) {
        if self.queue.len() >= capacity {
            self.stats.lost_full += 1;
        } else {
            self.queue.push_back(packet);
        }
    }
}

/// Two node ends joined by in-memory queues, with fault injection ([module docs](self)).
#[derive(Clone, Debug)]
pub struct MemoryLink {
    /// Index 0: sent from [`End::A`]; 1: from [`End::B`].
    directions: [Direction; 2],
    step: u64,
    capacity: usize,
}

impl Default for MemoryLink {
    fn default() -> Self {
        Self::new()
    }
}

impl MemoryLink {
    /// Packets each queue holds by default.
    pub const DEFAULT_CAPACITY: usize = 16;

    /// A link with no packet on its way and no fault set, queues of
    /// [`Self::DEFAULT_CAPACITY`] packets.
    pub fn new() -> Self {
        Self::with_capacity(Self::DEFAULT_CAPACITY)
    }

    /// A link whose queues hold `capacity` packets each.
    pub fn with_capacity(capacity: usize) -> Self {
        Self {
            directions: Default::default(),
            step: 0,
            capacity,
        }
    }

    /// Packets each queue holds.
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// End `end`, lent as a [`NodeLink`].
    pub fn end(&mut self, end: End) -> MemoryEnd<'_> {
        MemoryEnd { link: self, end }
    }

    /// The faults still to inject into the packets sent from `from`; set them here.
    pub fn faults(&mut self, from: End) -> &mut Faults {
        &mut self.directions[from.index()].faults
    }

    /// What happened to the packets sent from `from`.
    pub fn stats(&self, from: End) -> LinkStats {
        self.directions[from.index()].stats
    }

    /// Packets on their way to `toward` (held back ones included).
    pub fn in_flight(&self, toward: End) -> usize {
        let d = &self.directions[toward.other().index()];
        d.queue.len() + usize::from(d.held.is_some())
    }

    /// The current step (0 at the start).
    pub fn step(&self) -> u64 {
        self.step
    }

    /// Moves to the next step: delayed packets become receivable, a packet held back for a
    /// reorder with nothing sent after it is released.
    pub fn advance_step(&mut self) {
        self.step += 1;
        for d in &mut self.directions {
            if let Some(held) = d.held.take() {
                d.enqueue(held, self.capacity);
            }
        }
    }

    fn send(&mut self, from: End, packet: &[u8]) {
        let (step, capacity) = (self.step, self.capacity);
        let d = &mut self.directions[from.index()];
        d.stats.sent += 1;
        if d.faults.drop > 0 {
            d.faults.drop -= 1;
            d.stats.dropped += 1;
            return;
        }
        let mut bytes = packet.to_vec();
        if let Some(c) = d.faults.corrupt.take() {
            if let Some(b) = bytes.get_mut(c.byte) {
                *b ^= c.xor;
                d.stats.corrupted += 1;
            }
        }
        let mut ready_step = step;
        if d.faults.delay > 0 {
            d.faults.delay -= 1;
            d.stats.delayed += 1;
            ready_step += 1;
        }
        let packet = InFlight { ready_step, bytes };
        if d.faults.reorder && d.held.is_none() {
            d.faults.reorder = false;
            d.stats.reordered += 1;
            d.held = Some(packet);
            return;
        }
        d.enqueue(packet, capacity);
        if let Some(held) = d.held.take() {
            d.enqueue(held, capacity);
        }
    }

    fn receive(&mut self, to: End, buf: &mut [u8]) -> Result<Option<usize>, ErrorKind> {
        let step = self.step;
        let d = &mut self.directions[to.other().index()];
        let Some(i) = d.queue.iter().position(|p| p.ready_step <= step) else {
            return Ok(None);
        };
        let Some(packet) = d.queue.remove(i) else {
            return Ok(None);
        };
        let len = packet.bytes.len();
        let dst = buf.get_mut(..len).ok_or(ErrorKind::TooLong)?;
        dst.copy_from_slice(&packet.bytes);
        d.stats.delivered += 1;
        Ok(Some(len))
    }
}

/// One end of a [`MemoryLink`], lent by [`MemoryLink::end`]: sends toward the other end,
/// receives what the other end sent. Its errors are [`ErrorKind`]s: only
/// [`ErrorKind::TooLong`], for a packet longer than the receive buffer (dropped).
#[derive(Debug)]
pub struct MemoryEnd<'a> {
    link: &'a mut MemoryLink,
    end: End,
}

impl ErrorType for MemoryEnd<'_> {
    type Error = ErrorKind;
}

impl NodeLink for MemoryEnd<'_> {
    fn send(&mut self, packet: &[u8]) -> Result<(), ErrorKind> {
        self.link.send(self.end, packet);
        Ok(())
    }

    fn receive(&mut self, buf: &mut [u8]) -> Result<Option<usize>, ErrorKind> {
        self.link.receive(self.end, buf)
    }
}
