//! The link between the two nodes, as a node sees it: send one packet, receive one packet.
//!
//! Shaped like embedded-hal's traits (STYLE.md §5): an [`ErrorType`] whose errors say their
//! [`ErrorKind`], a few required methods, forwarding impls for `&mut T`. Two implementations:
//! [`FramedLink`], over any byte stream (a UART driver implements [`ByteStream`] and nothing
//! else: framing, resynchronisation and buffering are here), and the host's in-memory pair with
//! fault injection (`crate::host::link`, feature `host`), which the tests and the simulator use.
//!
//! A [`NodeLink`] moves the bytes of whole packets ([`crate::link::space_packet`]); it does not
//! look inside them. The CRC, the APID and the sequence count are checked by the receiver's
//! [`crate::link::space_packet::decode`] and [`crate::link::sequence::SequenceTracker`].
//!
//! [`FramedLink`] writes each packet as `0x00`, its COBS blocks ([`crate::link::cobs`]), `0x00`:
//! the leading delimiter ends whatever noise the line carried before the frame, so the noise
//! is a damaged frame of its own and the packet arrives intact. It reads the stream one byte at
//! a time, taking no more than it needs: bytes after a frame's delimiter stay in the driver for
//! the next call, so the link keeps no receive buffer besides its deframer's `N` bytes.

use core::fmt;

use crate::link::cobs::{self, Deframer, FrameError, DELIMITER};

/// What went wrong on the link, whatever its implementation.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ErrorKind {
    /// The byte stream failed (a UART overrun, parity or framing error; a write that did not
    /// complete).
    Transport,
    /// Bytes arrived that are not a frame (lost, changed or spurious bytes on the line): the
    /// packet in them is lost.
    Frame,
    /// A packet does not fit the buffer given for it.
    TooLong,
    /// Any other failure.
    Other,
}

impl fmt::Display for ErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = match self {
            Self::Transport => "link transport error",
            Self::Frame => "damaged frame on the link",
            Self::TooLong => "packet longer than its buffer",
            Self::Other => "link failure",
        };
        f.write_str(s)
    }
}

/// A link error: anything that can say which [`ErrorKind`] it is.
pub trait Error: fmt::Debug {
    /// The kind of the error.
    fn kind(&self) -> ErrorKind;
}

impl Error for ErrorKind {
    fn kind(&self) -> ErrorKind {
        *self
    }
}

/// The error type of a link or a byte stream.
pub trait ErrorType {
    /// The implementation's error.
    type Error: Error;
}

impl<T: ErrorType + ?Sized> ErrorType for &mut T {
    type Error = T::Error;
}

/// One node's end of the link: whole packets out and in.
pub trait NodeLink: ErrorType {
    /// Sends the packet `packet` (its bytes, as [`crate::link::space_packet::encode`] wrote
    /// them). Errors: the implementation's (a transport failure, a packet it cannot carry).
    fn send(&mut self, packet: &[u8]) -> Result<(), Self::Error>;

    /// Receives the next packet, if one has arrived whole, into the start of `buf`, and
    /// returns its length; `Ok(None)` when none has (never waits). Each call returns at most
    /// one packet: call until `Ok(None)` to take all that arrived. An error is about one
    /// packet or one stretch of the line (a damaged frame, a packet longer than `buf`, which is
    /// dropped); the next call goes on with what follows.
    fn receive(&mut self, buf: &mut [u8]) -> Result<Option<usize>, Self::Error>;
}

impl<T: NodeLink + ?Sized> NodeLink for &mut T {
    fn send(&mut self, packet: &[u8]) -> Result<(), Self::Error> {
        T::send(self, packet)
    }
    fn receive(&mut self, buf: &mut [u8]) -> Result<Option<usize>, Self::Error> {
        T::receive(self, buf)
    }
}

/// A byte stream: what a UART driver gives the link.
pub trait ByteStream: ErrorType {
    /// Queues all of `bytes` for sending, or fails.
    fn write(&mut self, bytes: &[u8]) -> Result<(), Self::Error>;

    /// Moves bytes that have arrived (at most `buf.len()`) into `buf` and returns how many;
    /// `Ok(0)` when none has (never waits).
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error>;
}

impl<T: ByteStream + ?Sized> ByteStream for &mut T {
    fn write(&mut self, bytes: &[u8]) -> Result<(), Self::Error> {
        T::write(self, bytes)
    }
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
        T::read(self, buf)
    }
}

/// Why a [`FramedLink`] could not send or receive.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FramedLinkError<E> {
    /// The byte stream's error (its kind is the stream's).
    Transport(E),
    /// A frame was dropped ([`FrameError`]): kind [`ErrorKind::Frame`].
    Frame(FrameError),
    /// A received packet is longer than the caller's buffer and was dropped: kind
    /// [`ErrorKind::TooLong`].
    TooLong {
        /// Bytes of the packet.
        len: usize,
        /// Bytes of the buffer.
        capacity: usize,
    },
}

impl<E: Error> Error for FramedLinkError<E> {
    fn kind(&self) -> ErrorKind {
        match self {
            Self::Transport(e) => e.kind(),
            Self::Frame(_) => ErrorKind::Frame,
            Self::TooLong { .. } => ErrorKind::TooLong,
        }
    }
}

impl<E: fmt::Debug> fmt::Display for FramedLinkError<E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Transport(e) => write!(f, "link transport: {e:?}"),
            Self::Frame(e) => write!(f, "link frame dropped: {e}"),
            Self::TooLong { len, capacity } => {
                write!(f, "packet of {len} bytes dropped: buffer of {capacity}")
            }
        }
    }
}

/// A [`NodeLink`] over a [`ByteStream`]: COBS frames between 0x00 delimiters
/// ([module docs](self)). `N` is the longest packet it receives; longer frames are dropped
/// ([`FrameError::Overlong`]). Its RAM is `N` bytes and a few of state, besides the stream.
#[derive(Clone, Debug)]
pub struct FramedLink<T, const N: usize> {
    stream: T,
    deframer: Deframer<N>,
}

impl<T: ByteStream, const N: usize> FramedLink<T, N> {
    /// Bytes one [`NodeLink::receive`] call reads at most: twice a whole frame of `N` bytes
    /// with its delimiter, enough for the end of a frame begun in an earlier call, a leading
    /// delimiter and the next whole frame. A call that reaches it returns `Ok(None)` and the
    /// next goes on from there: a stream that never runs dry (noise) cannot hold a call for
    /// longer.
    pub const MAX_READ_PER_RECEIVE: usize = 2 * cobs::max_encoded_len(N);

    /// The link over `stream`, between frames.
    pub const fn new(stream: T) -> Self {
        Self {
            stream,
            deframer: Deframer::new(),
        }
    }

    /// The byte stream (for its own status, or to reconfigure it).
    pub fn stream_mut(&mut self) -> &mut T {
        &mut self.stream
    }

    /// The byte stream back; a frame being received is lost.
    pub fn release(self) -> T {
        self.stream
    }
}

impl<T: ByteStream, const N: usize> ErrorType for FramedLink<T, N> {
    type Error = FramedLinkError<T::Error>;
}

impl<T: ByteStream, const N: usize> NodeLink for FramedLink<T, N> {
    /// Writes `0x00`, the frame's blocks, `0x00` to the stream. Error: the stream's
    /// ([`FramedLinkError::Transport`]); the far end then receives a damaged frame or nothing.
    fn send(&mut self, packet: &[u8]) -> Result<(), Self::Error> {
        let stream = &mut self.stream;
        stream
            .write(&[DELIMITER])
            .map_err(FramedLinkError::Transport)?;
        for (code, block) in cobs::blocks(packet) {
            stream.write(&[code]).map_err(FramedLinkError::Transport)?;
            stream.write(block).map_err(FramedLinkError::Transport)?;
        }
        stream
            .write(&[DELIMITER])
            .map_err(FramedLinkError::Transport)
    }

    /// Reads the stream byte by byte (at most [`Self::MAX_READ_PER_RECEIVE`] bytes) until a
    /// frame ends or no byte is left. Errors: [`FramedLinkError::Transport`] (the stream's),
    /// [`FramedLinkError::Frame`] (a damaged frame ended), [`FramedLinkError::TooLong`] (a frame
    /// longer than `buf`).
    fn receive(&mut self, buf: &mut [u8]) -> Result<Option<usize>, Self::Error> {
        for _ in 0..Self::MAX_READ_PER_RECEIVE {
            let mut byte = [0u8];
            let n = self
                .stream
                .read(&mut byte)
                .map_err(FramedLinkError::Transport)?;
            if n == 0 {
                return Ok(None);
            }
            let [byte] = byte;
            if let Some(frame) = self.deframer.push(byte) {
                let frame = frame.map_err(FramedLinkError::Frame)?;
                let (len, capacity) = (frame.len(), buf.len());
                let dst = buf
                    .get_mut(..len)
                    .ok_or(FramedLinkError::TooLong { len, capacity })?;
                for (d, s) in dst.iter_mut().zip(frame) {
                    *d = *s;
                }
                return Ok(Some(len));
            }
        }
        Ok(None)
    }
}
