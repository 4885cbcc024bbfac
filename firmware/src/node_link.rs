//! The link between the two node images, as RAM mailboxes (processor-in-the-loop build): one
//! packet each way per period, the CCSDS space packet of the message with its CRC
//! ([`acs::link::messages`]). The PIL host moves each node's `LINK_TX` packet into the other's
//! `LINK_RX`; on the satellite a UART driver carries the same packets, COBS-framed
//! ([`acs::hal::link::FramedLink`]; the flight build, feature `pil` off: [`crate::periph`]).
//!
//! | symbol | type | meaning |
//! |---|---|---|
//! | `LINK_TX` | `[u8; 128]` | the packet this node sent in its last period |
//! | `LINK_TX_LEN` | `u16` | its length (0: none); the host clears it when it takes the packet |
//! | `LINK_RX` | `[u8; 128]` | a packet for this node |
//! | `LINK_RX_LEN` | `u16` | its length (0: none); the node clears it when it takes the packet |

/// The longest packet of the link (REF: 125 B).
pub const LINK_BYTES: usize = 128;

/// The packet sent (see the [module docs](self)).
#[no_mangle]
pub static mut LINK_TX: [u8; LINK_BYTES] = [0; LINK_BYTES];
/// Its length.
#[no_mangle]
pub static mut LINK_TX_LEN: u16 = 0;
/// A packet received.
#[no_mangle]
pub static mut LINK_RX: [u8; LINK_BYTES] = [0; LINK_BYTES];
/// Its length.
#[no_mangle]
pub static mut LINK_RX_LEN: u16 = 0;

/// Puts `packet` (at most [`LINK_BYTES`]) in `LINK_TX`.
pub fn send(packet: &[u8]) {
    let n = packet.len().min(LINK_BYTES);
    // SAFETY: the mailboxes are this module's statics, never referenced: raw pointers and
    // volatile accesses only (the host writes them between periods, the node within them).
    unsafe {
        let base = &raw mut LINK_TX as *mut u8;
        for (i, b) in packet.iter().take(n).enumerate() {
            core::ptr::write_volatile(base.add(i), *b);
        }
        core::ptr::write_volatile(&raw mut LINK_TX_LEN, n as u16);
    }
}

/// Takes the packet in `LINK_RX` into `buf`: its length, `None` if there is none.
pub fn receive(buf: &mut [u8; LINK_BYTES]) -> Option<usize> {
    // SAFETY: as in `send`.
    unsafe {
        let n = usize::from(core::ptr::read_volatile(&raw const LINK_RX_LEN));
        if n == 0 || n > LINK_BYTES {
            core::ptr::write_volatile(&raw mut LINK_RX_LEN, 0);
            return None;
        }
        let base = &raw const LINK_RX as *const u8;
        for (i, b) in buf.iter_mut().take(n).enumerate() {
            *b = core::ptr::read_volatile(base.add(i));
        }
        core::ptr::write_volatile(&raw mut LINK_RX_LEN, 0);
        Some(n)
    }
}
