//! Framing packets on a byte stream: Consistent Overhead Byte Stuffing, 0x00 between frames.
//!
//! S. Cheshire and M. Baker, "Consistent Overhead Byte Stuffing", IEEE/ACM Transactions on
//! Networking 7(2), 159–172, April 1999 (§III, and its `StuffData` / `UnStuffData` code). The
//! frame's bytes are rewritten so that none is 0x00, and 0x00 then marks the end of a frame: a
//! receiver that lost or misread bytes finds the next frame at the next 0x00, whatever came
//! before. The data is cut at each zero byte (and after each 254 non-zero bytes) into blocks;
//! each block is sent as a code byte, its length + 1 (1–255), then its non-zero bytes; the zero
//! that ended the block is implied by a code below 255 (a code of 255 is a full block of 254
//! with no zero after it). The zero implied after the last block is not data.
//!
//! | data | frame on the wire |
//! |---|---|
//! | (none) | `01 00` |
//! | `00` | `01 01 00` |
//! | `11 22 00 33` | `03 11 22 02 33 00` |
//! | `11 00 00 00` | `02 11 01 01 01 00` |
//! | 254 bytes `01..=FE` | `FF 01 … FE 01 00` |
//!
//! **Overhead**: a frame is at most ⌊n/254⌋ + 1 bytes longer than its `n` data bytes, plus the
//! delimiter ([`max_encoded_len`] = n + ⌊n/254⌋ + 2): 2 bytes for any packet up to 253 bytes,
//! whatever its content (the link's packets are under 130 B). The encoder is the paper's: after
//! a full block that ends the data it writes a last, empty block (`01`); encoders that omit it
//! (the `cobs` crate) are read the same way by the [`Deframer`] (tests: both directions against
//! the `cobs` crate).
//!
//! [`encode`] writes a frame into a buffer; [`blocks`] gives the same frame as slices of the
//! data, for a sender that writes straight to a stream
//! ([`crate::hal::link::FramedLink`]). The [`Deframer`] is fed the received bytes one at a time
//! and decodes in place into its own buffer of `N` bytes (no copy of the encoded frame). A
//! damaged frame is refused ([`FrameError`]) and costs only itself: a lost byte, a changed byte or
//! a spurious 0x00 touches at most the frames it falls in (a spurious 0x00 splits one frame into
//! two damaged ones); a frame that decodes to more than `N` bytes is dropped with
//! [`FrameError::Overlong`] as soon as it outgrows the buffer, and the deframer starts afresh at
//! the next 0x00. A changed byte that leaves the frame well formed is caught by the packet's
//! CRC. Several 0x00 in a
//! row are idle line, not frames: a sender may write a 0x00 before each frame too, so that noise
//! before it is ended there and cannot run into it (what `FramedLink` does).

use core::fmt;

/// The frame delimiter.
pub const DELIMITER: u8 = 0x00;

/// The longest run of non-zero bytes a block carries (its code is 255).
const MAX_RUN: usize = 254;

/// The longest frame, delimiter included, of `data_len` bytes of data: `data_len` +
/// ⌊`data_len`/254⌋ + 2. For sizing buffers.
pub const fn max_encoded_len(data_len: usize) -> usize {
    data_len + data_len / MAX_RUN + 2
}

/// Why data could not be framed, or why a received frame was dropped.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum FrameError {
    /// Encoding: the output buffer is too short for the frame ([`max_encoded_len`] is always
    /// enough).
    OutputTooSmall {
        /// Bytes of the buffer.
        len: usize,
    },
    /// Receiving: the frame decodes to more bytes than the deframer holds: reported at the
    /// byte that does not fit, and the rest of the frame, up to its delimiter, is dropped.
    Overlong {
        /// The deframer's capacity, bytes.
        capacity: usize,
    },
    /// Receiving: the delimiter came inside a block (a code byte promised more bytes than
    /// arrived): bytes were lost or changed.
    Truncated,
}

impl fmt::Display for FrameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::OutputTooSmall { len } => write!(f, "frame does not fit {len} bytes"),
            Self::Overlong { capacity } => write!(f, "frame longer than {capacity} bytes"),
            Self::Truncated => f.write_str("frame ends inside a block"),
        }
    }
}

/// The blocks of `data`'s frame, in order: each a code byte and the data bytes that follow it
/// on the wire. Written one after the other, then [`DELIMITER`], they are the frame
/// [`encode`] writes.
pub fn blocks(data: &[u8]) -> Blocks<'_> {
    Blocks { rest: Some(data) }
}

/// The iterator of [`blocks`].
#[derive(Clone, Debug)]
pub struct Blocks<'a> {
    /// The data not yet in a block (`None`: done).
    rest: Option<&'a [u8]>,
}

impl<'a> Iterator for Blocks<'a> {
    type Item = (u8, &'a [u8]);

    fn next(&mut self) -> Option<(u8, &'a [u8])> {
        let rest = self.rest?;
        let window = rest.get(..MAX_RUN).unwrap_or(rest);
        let run = window.iter().position(|&b| b == 0).unwrap_or(window.len());
        let (block, after) = rest.split_at_checked(run)?;
        self.rest = if run == MAX_RUN {
            // a full block: no zero to skip; an empty last block follows at the end of the data
            Some(after)
        } else {
            // skip the zero that ended the block; none left: this was the last block
            after.get(1..)
        };
        // run ≤ 254, so the code fits
        Some((run as u8 + 1, block))
    }
}

/// Writes the frame of `data` (blocks and the trailing [`DELIMITER`]) to the start of `out`
/// and returns its length, at most [`max_encoded_len`]`(data.len())`. Error:
/// [`FrameError::OutputTooSmall`] if `out` is too short (then what `out` holds is unspecified).
pub fn encode(data: &[u8], out: &mut [u8]) -> Result<usize, FrameError> {
    let too_small = FrameError::OutputTooSmall { len: out.len() };
    let mut len = 0;
    for (code, block) in blocks(data) {
        let end = len + 1 + block.len();
        let (c, d) = out
            .get_mut(len..end)
            .and_then(|o| o.split_first_mut())
            .ok_or(too_small)?;
        *c = code;
        for (o, b) in d.iter_mut().zip(block) {
            *o = *b;
        }
        len = end;
    }
    *out.get_mut(len).ok_or(too_small)? = DELIMITER;
    Ok(len + 1)
}

/// The deframer's state, apart from its buffer.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
struct DeframeState {
    /// Bytes decoded into the buffer.
    len: usize,
    /// Data bytes still to come in the current block (0: the next byte is a code byte).
    block_left: u8,
    /// The current block ends in an implied zero (its code was below 255).
    zero_pending: bool,
    /// A byte other than the delimiter arrived since the last delimiter.
    in_frame: bool,
    /// The frame outgrew the buffer (reported): the rest of it is dropped.
    overlong: bool,
}

impl DeframeState {
    /// Feeds one received byte: at a delimiter, the frame's length in `buf` or why it was
    /// dropped (nothing for idle line); at the first byte that does not fit, the overlong error.
    /// (Left to the inliner: a node has one link, one `N`, and inlined it is 212 B against
    /// 170 + 114 B out of line; measured as in the [`crate::link`] docs.)
    fn push(&mut self, buf: &mut [u8], byte: u8) -> Option<Result<usize, FrameError>> {
        if byte == DELIMITER {
            let frame = core::mem::take(self);
            return if !frame.in_frame || frame.overlong {
                // idle line, or the end of a frame already reported overlong
                None
            } else if frame.block_left != 0 {
                Some(Err(FrameError::Truncated))
            } else {
                Some(Ok(frame.len))
            };
        }
        if self.overlong {
            return None;
        }
        self.in_frame = true;
        let stored = if self.block_left == 0 {
            // a code byte: the previous block's implied zero is data now that a block follows
            let zero_pending = self.zero_pending;
            self.block_left = byte - 1;
            self.zero_pending = byte != 0xFF;
            !zero_pending || self.store(buf, 0)
        } else {
            self.block_left -= 1;
            self.store(buf, byte)
        };
        if stored {
            None
        } else {
            self.overlong = true;
            Some(Err(FrameError::Overlong {
                capacity: buf.len(),
            }))
        }
    }

    /// Appends a decoded byte; false when the buffer is full.
    fn store(&mut self, buf: &mut [u8], byte: u8) -> bool {
        match buf.get_mut(self.len) {
            Some(slot) => {
                *slot = byte;
                self.len += 1;
                true
            }
            None => false,
        }
    }
}

/// Receives frames from a byte stream, one byte at a time, each decoded in place into a buffer
/// of `N` bytes (the longest frame it accepts, decoded: the longest packet). See the
/// [module docs](self) for what happens to damaged frames.
///
/// ```
/// use acs::link::cobs::{encode, Deframer};
/// let mut wire = [0u8; 16];
/// let n = encode(&[0x11, 0x00, 0x22], &mut wire).unwrap();
/// let mut deframer = Deframer::<8>::new();
/// let mut got = None;
/// for &b in &wire[..n] {
///     if let Some(frame) = deframer.push(b) {
///         got = Some(frame.unwrap().to_vec());
///     }
/// }
/// assert_eq!(got.unwrap(), [0x11, 0x00, 0x22]);
/// ```
#[derive(Clone, Debug)]
pub struct Deframer<const N: usize> {
    buf: [u8; N],
    state: DeframeState,
}

impl<const N: usize> Default for Deframer<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Deframer<N> {
    /// A deframer between frames.
    pub const fn new() -> Self {
        Self {
            buf: [0; N],
            state: DeframeState {
                len: 0,
                block_left: 0,
                zero_pending: false,
                in_frame: false,
                overlong: false,
            },
        }
    }

    /// Feeds one received byte. At a delimiter that ends a frame: `Some(Ok(data))`, the decoded
    /// frame (valid until the next call), or `Some(Err(FrameError::Truncated))` if it ends
    /// inside a block. At the byte that makes a frame longer than `N` bytes:
    /// `Some(Err(FrameError::Overlong))`, and the rest of that frame is dropped silently up to
    /// its delimiter. `None` otherwise (inside a frame, or a delimiter with no frame before
    /// it). So every damaged frame gives one error, and a call never holds more than one.
    pub fn push(&mut self, byte: u8) -> Option<Result<&[u8], FrameError>> {
        match self.state.push(&mut self.buf, byte)? {
            Ok(len) => Some(Ok(self.buf.get(..len).unwrap_or_default())),
            Err(e) => Some(Err(e)),
        }
    }

    /// Drops the frame being received: the next byte starts a new one.
    pub fn reset(&mut self) {
        self.state = DeframeState::default();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_error_per_damaged_frame_then_resynchronised() {
        let mut d = Deframer::<2>::new();
        // 5 data bytes into 2: one error at the third, silence to the delimiter
        let results: Vec<_> = [0x06, 1, 2, 3, 4, 5, 0x00]
            .iter()
            .map(|&b| d.push(b).map(|r| r.map(<[u8]>::to_vec)))
            .collect();
        assert_eq!(
            results,
            [
                None,
                None,
                None,
                Some(Err(FrameError::Overlong { capacity: 2 })),
                None,
                None,
                None
            ]
        );
        assert_eq!(d.state, DeframeState::default());
        // an implied zero that does not fit is overlong too
        let mut d = Deframer::<1>::new();
        assert_eq!(d.push(0x02), None);
        assert_eq!(d.push(0x07), None);
        assert_eq!(
            d.push(0x01),
            Some(Err(FrameError::Overlong { capacity: 1 }))
        );
        assert_eq!(d.push(0x00), None);
        // a frame exactly as long as the buffer is whole
        assert_eq!(d.push(0x02), None);
        assert_eq!(d.push(0x07), None);
        assert_eq!(d.push(0x00), Some(Ok(&[0x07][..])));
    }

    #[test]
    fn empty_data_is_a_frame_and_idle_line_is_not() {
        let mut d = Deframer::<0>::new();
        assert_eq!(d.push(0x00), None);
        assert_eq!(d.push(0x01), None);
        assert_eq!(d.push(0x00), Some(Ok(&[][..])));
        assert_eq!(max_encoded_len(0), 2);
        assert_eq!(max_encoded_len(253), 255);
        assert_eq!(max_encoded_len(254), 257);
    }
}
