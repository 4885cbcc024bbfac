//! Packet sequence counts: the sender's counter and the receiver's gap count.
//!
//! CCSDS 133.0-B-2 §4.1.3.4.3: each application process numbers the packets it sends, 14 bits,
//! counting modulo 16 384. The sender takes each packet's count from a [`SequenceCounter`]; the
//! receiver gives the count of each packet it accepts to a [`SequenceTracker`], which says how it
//! follows the previous one ([`Continuity`]) and counts the gaps and the packets missed. The
//! tracker never refuses a packet: a gap is a fact to report (telemetry, the fault log), and the
//! packet after a gap is as good as any.
//!
//! The counts are compared modulo 2¹⁴ (so a gap across the wrap 16383 → 0 is counted like any
//! other), with the rule RTP receivers use for their 16-bit counts (RFC 3550, appendix A.1,
//! "MAX_MISORDER"): a count at most [`LATE_WINDOW`] behind the newest one (or equal to it) is a
//! late packet (repeated, or overtaken by a later one), which does not move the newest count;
//! one ahead by less than half the count range is new, and the counts it jumped over are missed;
//! one further behind than the window means the sender started counting again (it was reset),
//! and the tracker follows it.
//!
//! | distance d = (count − newest) mod 16 384 | [`Continuity`] | counters |
//! |---|---|---|
//! | (no packet before) | [`Continuity::First`] | — |
//! | 1 | [`Continuity::Next`] | — |
//! | 2 ≤ d < 8 192 | [`Continuity::Gap`] with `missed` = d − 1 | [`gaps`](SequenceTracker::gaps) + 1, [`missed`](SequenceTracker::missed) + d − 1 |
//! | d = 0 or d ≥ 16 384 − [`LATE_WINDOW`] | [`Continuity::Late`] (newest unchanged) | [`late`](SequenceTracker::late) + 1 |
//! | otherwise | [`Continuity::Restart`] | [`restarts`](SequenceTracker::restarts) + 1 |
//!
//! A packet overtaken by the next one is counted missed when the next arrives, then late when it
//! does: `missed` counts the packets not there when a later one was.
//!
//! ```
//! use acs::link::sequence::{Continuity, SequenceCounter, SequenceTracker};
//! let mut counter = SequenceCounter::new();
//! let mut tracker = SequenceTracker::new();
//! assert_eq!(tracker.accept(counter.next_count()), Continuity::First);
//! let _lost = counter.next_count();
//! assert_eq!(tracker.accept(counter.next_count()), Continuity::Gap { missed: 1 });
//! assert_eq!((tracker.gaps(), tracker.missed()), (1, 1));
//! ```

use super::space_packet::MAX_SEQUENCE_COUNT;

/// How far behind the newest count a count is taken for a late packet rather than a sender
/// that started again.
pub const LATE_WINDOW: u16 = 64;

/// Half the count range: a count this far ahead or more is not taken for a new packet.
const HALF_RANGE: u16 = 1 << 13;

/// The sender's packet sequence count for one application process: 0, 1, …, 16383, 0, …
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SequenceCounter {
    next: u16,
}

impl SequenceCounter {
    /// A counter whose first count is 0.
    pub const fn new() -> Self {
        Self { next: 0 }
    }

    /// The count for the next packet; the one after it is one more, modulo 16 384.
    pub fn next_count(&mut self) -> u16 {
        let count = self.next;
        self.next = count.wrapping_add(1) & MAX_SEQUENCE_COUNT;
        count
    }
}

/// How a received packet's count follows the newest one before it ([module docs](self)).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Continuity {
    /// The first packet since the tracker was made or reset.
    First,
    /// The count after the newest one: nothing missed.
    Next,
    /// Ahead of the newest count by more than one: `missed` packets did not arrive before it.
    Gap {
        /// Counts jumped over, 1–8 190.
        missed: u16,
    },
    /// Equal to the newest count or at most [`LATE_WINDOW`] behind it: a repeated or overtaken
    /// packet. The newest count stays.
    Late,
    /// Far behind the newest count: the sender started counting again. The tracker follows it.
    Restart,
}

/// The receiver's view of one application process's sequence counts ([module docs](self)).
/// The counters saturate at their largest value.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SequenceTracker {
    newest: Option<u16>,
    gaps: u16,
    missed: u32,
    late: u16,
    restarts: u16,
}

impl SequenceTracker {
    /// A tracker that has seen no packet.
    pub const fn new() -> Self {
        Self {
            newest: None,
            gaps: 0,
            missed: 0,
            late: 0,
            restarts: 0,
        }
    }

    /// Back to no packet seen, counters zero.
    pub fn reset(&mut self) {
        *self = Self::new();
    }

    /// Records the count of an accepted packet (its 14 bits; higher bits are ignored) and says
    /// how it follows the newest count before it. Never fails.
    pub fn accept(&mut self, count: u16) -> Continuity {
        let count = count & MAX_SEQUENCE_COUNT;
        let Some(newest) = self.newest else {
            self.newest = Some(count);
            return Continuity::First;
        };
        // d = (count − newest) mod 2¹⁴
        let d = count.wrapping_sub(newest) & MAX_SEQUENCE_COUNT;
        let late_from = MAX_SEQUENCE_COUNT - LATE_WINDOW;
        let continuity = if d == 1 {
            Continuity::Next
        } else if d != 0 && HALF_RANGE > d {
            let missed = d - 1;
            self.gaps = self.gaps.saturating_add(1);
            self.missed = self.missed.saturating_add(u32::from(missed));
            Continuity::Gap { missed }
        } else if d == 0 || d > late_from {
            self.late = self.late.saturating_add(1);
            return Continuity::Late;
        } else {
            self.restarts = self.restarts.saturating_add(1);
            Continuity::Restart
        };
        self.newest = Some(count);
        continuity
    }

    /// The newest count accepted (`None` before the first packet).
    pub fn newest(&self) -> Option<u16> {
        self.newest
    }

    /// Number of gaps: packets that arrived with counts missing before them.
    pub fn gaps(&self) -> u16 {
        self.gaps
    }

    /// Number of counts jumped over by the gaps: packets missed.
    pub fn missed(&self) -> u32 {
        self.missed
    }

    /// Number of late packets (repeated or overtaken).
    pub fn late(&self) -> u16 {
        self.late
    }

    /// Number of times the sender started counting again.
    pub fn restarts(&self) -> u16 {
        self.restarts
    }
}
