//! Flash and cycle probe of the link layer (`acs::link`, `acs::hal::link`) on the MSP430: one
//! image per feature, each calling the code under test between two calls of `mark` (a break
//! point for `measure`, which reads mspdebug's MCLK cycle counter there) through an
//! `#[inline(never)]` wrapper `w_*` whose symbol size is the code's flash. The CRC variants
//! compared in `acs::link::crc16`'s docs are written here. The firmware's runtime and its
//! undefined panic handler: an image in which any panic is reachable does not link.
//! Run `./measure` (needs mspdebug); the figures are in `acs::link`'s and `crc16`'s docs.
#![no_std]
#![no_main]
use acs_firmware as _;
use core::hint::black_box;

static mut ID: u16 = 0;
#[no_mangle]
#[inline(never)]
pub extern "C" fn mark(id: u16) {
    unsafe { core::ptr::write_volatile(&raw mut ID, id) }
}
#[no_mangle]
#[inline(never)]
pub extern "C" fn done() {
    unsafe { core::ptr::write_volatile(&raw mut ID, 0xFFFF) }
}

#[cfg(feature = "crc-bitwise")]
#[inline(never)]
fn crc_bitwise(data: &[u8]) -> u16 {
    let mut crc = 0xFFFFu16;
    for &b in data {
        crc ^= u16::from(b) << 8;
        for _ in 0..8 {
            crc = if crc & 0x8000 != 0 {
                (crc << 1) ^ 0x1021
            } else {
                crc << 1
            };
        }
    }
    crc
}

#[cfg(feature = "crc-nibble")]
const NIBBLE: [u16; 16] = {
    let mut t = [0u16; 16];
    let mut i = 0;
    while i < 16 {
        let mut c = (i as u16) << 12;
        let mut k = 0;
        while k < 4 {
            c = if c & 0x8000 != 0 {
                (c << 1) ^ 0x1021
            } else {
                c << 1
            };
            k += 1;
        }
        t[i] = c;
        i += 1;
    }
    t
};
#[cfg(feature = "crc-nibble")]
#[inline(never)]
fn crc_nibble(data: &[u8]) -> u16 {
    let mut crc = 0xFFFFu16;
    for &b in data {
        let hi = usize::from(((crc >> 12) ^ u16::from(b >> 4)) as u8 & 0x0F);
        crc = (crc << 4) ^ NIBBLE.get(hi).copied().unwrap_or(0);
        let lo = usize::from(((crc >> 12) ^ u16::from(b & 0x0F)) as u8 & 0x0F);
        crc = (crc << 4) ^ NIBBLE.get(lo).copied().unwrap_or(0);
    }
    crc
}

#[cfg(feature = "crc-table")]
static TABLE: [u16; 256] = {
    let mut t = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        let mut c = (i as u16) << 8;
        let mut k = 0;
        while k < 8 {
            c = if c & 0x8000 != 0 {
                (c << 1) ^ 0x1021
            } else {
                c << 1
            };
            k += 1;
        }
        t[i] = c;
        i += 1;
    }
    t
};
#[cfg(feature = "crc-table")]
#[inline(never)]
fn crc_table(data: &[u8]) -> u16 {
    let mut crc = 0xFFFFu16;
    for &b in data {
        let i = usize::from((crc >> 8) as u8 ^ b);
        crc = (crc << 8) ^ TABLE.get(i).copied().unwrap_or(0);
    }
    crc
}

#[cfg(feature = "crc-shift")]
#[inline(never)]
fn crc_shift(data: &[u8]) -> u16 {
    let mut crc = 0xFFFFu16;
    for &b in data {
        let t = (crc >> 8) ^ u16::from(b);
        let t = t ^ (t >> 4);
        crc = (crc << 8) ^ (t << 12) ^ (t << 5) ^ t;
    }
    crc
}

#[cfg(feature = "framed")]
struct Wire {
    buf: [u8; 160],
    w: usize,
    r: usize,
}
#[cfg(feature = "framed")]
impl acs::hal::link::ErrorType for Wire {
    type Error = acs::hal::link::ErrorKind;
}
#[cfg(feature = "framed")]
impl acs::hal::link::ByteStream for Wire {
    fn write(&mut self, bytes: &[u8]) -> Result<(), Self::Error> {
        for &b in bytes {
            *self
                .buf
                .get_mut(self.w)
                .ok_or(acs::hal::link::ErrorKind::Transport)? = b;
            self.w += 1;
        }
        Ok(())
    }
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
        let mut n = 0;
        for o in buf.iter_mut() {
            if self.r >= self.w {
                break;
            }
            *o = self.buf.get(self.r).copied().unwrap_or(0);
            self.r += 1;
            n += 1;
        }
        Ok(n)
    }
}

#[no_mangle]
pub extern "C" fn main() -> ! {
    let mut data = [0u8; 128];
    for (i, b) in data.iter_mut().enumerate() {
        *b = (i as u8).wrapping_mul(37).wrapping_add(11);
    }
    #[allow(unused_variables)]
    let data = black_box(data);
    mark(0);
    mark(1);
    #[cfg(feature = "crc-bitwise")]
    {
        mark(2);
        let c = crc_bitwise(black_box(&data));
        mark(3);
        black_box(c);
    }
    #[cfg(feature = "crc-nibble")]
    {
        mark(2);
        let c = crc_nibble(black_box(&data));
        mark(3);
        black_box(c);
    }
    #[cfg(feature = "crc-table")]
    {
        mark(2);
        let c = crc_table(black_box(&data));
        mark(3);
        black_box(c);
    }
    #[cfg(feature = "crc-shift")]
    {
        mark(2);
        let c = crc_shift(black_box(&data));
        mark(3);
        black_box(c);
    }
    #[cfg(feature = "crc-acs")]
    {
        mark(2);
        let c = acs::link::crc16::crc16(black_box(&data));
        mark(3);
        black_box(c);
    }
    #[cfg(feature = "packet")]
    {
        use acs::link::space_packet::*;
        let apid = Apid::new(black_box(0x123)).unwrap_or(Apid::new(0).unwrap_or_else(|| loop {}));
        let header = PacketHeader {
            packet_type: PacketType::Telemetry,
            secondary_header: false,
            apid,
            sequence_count: black_box(5),
        };
        let mut out = [0u8; 136];
        mark(2);
        let r = w_encode(&header, black_box(&data[..120]), &mut out);
        mark(3);
        black_box(r.is_ok());
        let out = black_box(out);
        mark(4);
        let r = w_decode(black_box(&out[..128]), apid);
        mark(5);
        black_box(r.map(|(h, d)| (h.sequence_count, d.len())).ok());
    }
    #[cfg(feature = "cobs")]
    {
        use acs::link::cobs::*;
        let mut out = [0u8; 140];
        mark(2);
        let r = w_cobs_encode(black_box(&data), &mut out);
        mark(3);
        let n = black_box(r.unwrap_or(0));
        let mut d = Deframer::<136>::new();
        let mut got = 0;
        mark(4);
        for &b in out.get(..n).unwrap_or(&[]) {
            if let Some(Ok(f)) = w_push(&mut d, b) {
                got = f;
            }
        }
        mark(5);
        black_box(got);
    }
    #[cfg(feature = "framed")]
    {
        use acs::hal::link::*;
        let mut link = FramedLink::<Wire, 136>::new(Wire {
            buf: [0; 160],
            w: 0,
            r: 0,
        });
        mark(2);
        let r = w_send(&mut link, black_box(&data));
        mark(3);
        black_box(r.is_ok());
        let mut buf = [0u8; 136];
        mark(4);
        let mut got = None;
        for _ in 0..4 {
            if let Ok(Some(n)) = w_receive(&mut link, &mut buf) {
                got = Some(n);
                break;
            }
        }
        mark(5);
        black_box((got, buf));
    }
    #[cfg(feature = "sequence")]
    {
        use acs::link::sequence::*;
        let mut c = SequenceCounter::new();
        let mut t = SequenceTracker::new();
        mark(2);
        let n = w_next(&mut c);
        mark(3);
        let k = w_accept(&mut t, black_box(n));
        mark(4);
        black_box((k, t.gaps(), t.missed(), t.late(), t.restarts()));
    }
    done();
    acs_firmware::fw_halt()
}

#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    extern "C" {
        fn probe_has_a_reachable_panic() -> !;
    }
    unsafe { probe_has_a_reachable_panic() }
}

#[cfg(feature = "packet")]
#[inline(never)]
fn w_encode(
    h: &acs::link::space_packet::PacketHeader,
    d: &[u8],
    o: &mut [u8],
) -> Result<usize, acs::link::space_packet::PacketError> {
    acs::link::space_packet::encode(h, d, o)
}
#[cfg(feature = "packet")]
#[inline(never)]
fn w_decode(
    b: &[u8],
    a: acs::link::space_packet::Apid,
) -> Result<(acs::link::space_packet::PacketHeader, &[u8]), acs::link::space_packet::PacketError> {
    acs::link::space_packet::decode(b, a)
}
#[cfg(feature = "cobs")]
#[inline(never)]
fn w_cobs_encode(d: &[u8], o: &mut [u8]) -> Result<usize, acs::link::cobs::FrameError> {
    acs::link::cobs::encode(d, o)
}
#[cfg(feature = "cobs")]
#[inline(never)]
fn w_push(
    d: &mut acs::link::cobs::Deframer<136>,
    b: u8,
) -> Option<Result<usize, acs::link::cobs::FrameError>> {
    d.push(b).map(|r| r.map(|f| f.len()))
}
#[cfg(feature = "framed")]
#[inline(never)]
fn w_send(
    l: &mut acs::hal::link::FramedLink<Wire, 136>,
    d: &[u8],
) -> Result<(), acs::hal::link::FramedLinkError<acs::hal::link::ErrorKind>> {
    use acs::hal::link::NodeLink;
    l.send(d)
}
#[cfg(feature = "framed")]
#[inline(never)]
fn w_receive(
    l: &mut acs::hal::link::FramedLink<Wire, 136>,
    b: &mut [u8],
) -> Result<Option<usize>, acs::hal::link::FramedLinkError<acs::hal::link::ErrorKind>> {
    use acs::hal::link::NodeLink;
    l.receive(b)
}
#[cfg(feature = "sequence")]
#[inline(never)]
fn w_next(c: &mut acs::link::sequence::SequenceCounter) -> u16 {
    c.next_count()
}
#[cfg(feature = "sequence")]
#[inline(never)]
fn w_accept(
    t: &mut acs::link::sequence::SequenceTracker,
    n: u16,
) -> acs::link::sequence::Continuity {
    t.accept(n)
}
