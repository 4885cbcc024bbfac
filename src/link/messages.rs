//! The two nodes' messages and their timing contract (issue #29): STATUS from the attitude node,
//! REF from the reference node, plain `Copy` data with a fixed big-endian layout on the wire.
//!
//! # Timing contract
//! The attitude node owns the control period. At step `k` it reads its tiles with the REF that
//! arrived for step `k`, commands its actuators and sends **STATUS(k)**: the step number, mode,
//! attitude and its validity, wheel momentum, the last guidance it accepted, its boot count, its
//! fault word and its copy of the clock. The reference node answers **REF(k+1)**: the step
//! number `k+1`, the UTC of that step, the position, the Sun unit vector, the shadow, the
//! field in TEME at that UTC and the albedo the lit Sun sensors see at STATUS(k)'s attitude
//! (issue #30), the guidance (an id, the target attitude, rate and feed-forward
//! momentum), the flags `clock_valid` and `elements_valid`, and its own faults.
//!
//! - REF(k+1) is used at step `k+1` only if it is complete before that step's sensor reads and
//!   carries that step number: freshness goes by step number, never by UTC (a ground clock
//!   correction must not make every packet stale).
//! - A REF without `clock_valid` is never used: a reference node just reset must not steer the
//!   satellite with a default date ([`Reference::usable_at`]).
//! - A guidance whose id differs from the last one the attitude node accepted is a new ground
//!   command (track, or a slew then track); the same id is the same command, continued.
//!
//! Attitudes are `v_body = A(q) · v_ref` with the reference frame TEME of date, quaternions
//! scalar-first ([`crate::attitude`]).
//!
//! # Layout
//! Every field big-endian, `f32` as its IEEE 754 bits: a message crosses the link bit for bit.
//! An absent optional value is sent as zeros with its validity bit clear and read back as
//! `None`. [`Status::BYTES`] = 56, [`Reference::BYTES`] = 117.
//!
//! # Packets
//! Each message is the user data of one CCSDS space packet with its CRC
//! ([`crate::link::space_packet`]): STATUS telemetry on APID [`STATUS_APID`] (64 B), REF on
//! [`REFERENCE_APID`] (125 B). The ground's telecommands reach each node on its own APID
//! ([`ATTITUDE_TC_APID`], [`REFERENCE_TC_APID`]), from the on-board computer directly: a dead
//! link between the nodes never takes away the attitude node's commands (sun-safe, the tiles).

use core::fmt;

use crate::attitude::Quaternion;
use crate::env::eclipse::{Illumination, Shadow};
use crate::linalg::Vec3;
use crate::link::space_packet::{self, packet_len, Apid, PacketError, PacketHeader, PacketType};
use crate::time::{Epoch, Utc};

/// APID of STATUS, attitude node → reference node.
pub const STATUS_APID: Apid = Apid::masked(0x040);
/// APID of REF, reference node → attitude node.
pub const REFERENCE_APID: Apid = Apid::masked(0x041);
/// APID of the ground's telecommands to the attitude node.
pub const ATTITUDE_TC_APID: Apid = Apid::masked(0x050);
/// APID of the ground's telecommands to the reference node.
pub const REFERENCE_TC_APID: Apid = Apid::masked(0x051);

/// Bytes of a STATUS packet.
pub const STATUS_PACKET_BYTES: usize = packet_len(Status::BYTES);
/// Bytes of a REF packet.
pub const REFERENCE_PACKET_BYTES: usize = packet_len(Reference::BYTES);

/// Why a received packet gave no message.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LinkError {
    /// The packet was refused ([`space_packet::decode`]).
    Packet(PacketError),
    /// Its message was refused.
    Message(MessageError),
}

impl fmt::Display for LinkError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Packet(e) => write!(f, "packet refused: {e}"),
            Self::Message(e) => write!(f, "message refused: {e}"),
        }
    }
}

/// The packet of `message` on `apid` with `sequence_count` (14 bits: wrapped), into `out`.
#[cfg_attr(target_arch = "msp430", optimize(size))]
fn to_packet<const P: usize>(apid: Apid, sequence_count: u16, message: &[u8]) -> [u8; P] {
    let mut out = [0u8; P];
    let header = PacketHeader {
        packet_type: PacketType::Telemetry,
        secondary_header: false,
        apid,
        sequence_count: sequence_count & space_packet::MAX_SEQUENCE_COUNT,
    };
    // the sizes are constants: P is the packet of the message, and the count fits 14 bits
    let _ = space_packet::encode(&header, message, &mut out);
    out
}

/// The message of a packet on `apid` (decoded by `message`) and the packet's sequence count.
fn from_packet<M>(
    bytes: &[u8],
    apid: Apid,
    message: fn(&[u8]) -> Result<M, MessageError>,
) -> Result<(M, u16), LinkError> {
    let (header, data) = space_packet::decode(bytes, apid).map_err(LinkError::Packet)?;
    let m = message(data).map_err(LinkError::Message)?;
    Ok((m, header.sequence_count))
}

/// Why a message's bytes were refused.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum MessageError {
    /// Not the message's length.
    Length,
    /// A field holds a value no sender writes (a mode, shadow or guidance code, an epoch out of
    /// range).
    Field,
}

impl fmt::Display for MessageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Length => write!(f, "message of the wrong length"),
            Self::Field => write!(f, "message field out of range"),
        }
    }
}

/// What the reference node asks the attitude node to do (the ground's track and slew commands,
/// which the reference node owns).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum GuidanceKind {
    /// No command yet.
    None,
    /// Track `target` with the closed-loop law.
    Track,
    /// A slew in progress: the wheels hold the momentum before the slew less `h_ff_body_nms`;
    /// then [`GuidanceKind::Track`] of the same id.
    Slew,
}

/// The guidance of one step.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Guidance {
    /// The command's id (0: none yet); a new id is a new command.
    pub id: u16,
    /// What is asked.
    pub kind: GuidanceKind,
    /// The target attitude (reference TEME → body).
    pub target: Quaternion,
    /// The target's body rate, rad/s.
    pub rate_body_radps: Vec3,
    /// Feed-forward momentum of the body (a slew's plan), kg·m²/s.
    pub h_ff_body_nms: Vec3,
}

impl Guidance {
    /// No guidance: id 0.
    pub const NONE: Self = Self {
        id: 0,
        kind: GuidanceKind::None,
        target: Quaternion {
            q0: 1.0,
            q1: 0.0,
            q2: 0.0,
            q3: 0.0,
        },
        rate_body_radps: Vec3::new(0.0, 0.0, 0.0),
        h_ff_body_nms: Vec3::new(0.0, 0.0, 0.0),
    };
}

/// STATUS(k), attitude node → reference node.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Status {
    /// The step number `k`.
    pub step: u32,
    /// Resets of the attitude node since it was first powered.
    pub boot_count: u16,
    /// The mode after the step ([`crate::acs_loop::Mode::code`]).
    pub mode: u8,
    /// The filtered attitude (reference TEME → body), if valid.
    pub attitude: Option<Quaternion>,
    /// Total wheel momentum commanded (body), kg·m²/s.
    pub h_wheels_body_nms: Vec3,
    /// The id of the last guidance accepted.
    pub guidance_id: u16,
    /// The step's fault word ([`crate::acs_loop::Faults::bits`]).
    pub faults: u16,
    /// The UTC of the step by the attitude node's copy of the clock (the last REF's, advanced
    /// one period a step): what a reference node just reset takes back; `None` before any.
    pub utc: Option<Epoch<Utc>>,
}

/// REF(k), reference node → attitude node.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Reference {
    /// The step number it is for.
    pub step: u32,
    /// The UTC of that step.
    pub utc: Epoch<Utc>,
    /// The clock was set (by the ground or the attitude node) since the reference node's reset.
    pub clock_valid: bool,
    /// The reference node holds an element set.
    pub elements_valid: bool,
    /// Position, TEME, km (`None`: no orbit).
    pub r_teme_km: Option<Vec3>,
    /// Unit vector to the Sun, TEME.
    pub sun_teme: Option<Vec3>,
    /// The shadow at the position.
    pub illumination: Option<Illumination>,
    /// Geomagnetic field, TEME, nT.
    pub b_teme_nt: Option<Vec3>,
    /// The Earth's albedo irradiance of a unit albedo, TEME, in units of the solar irradiance,
    /// averaged over the Sun sensors the Sun lights at the last STATUS's attitude
    /// ([`crate::env::albedo::seen_by_lit_sensors`]); `None` without an attitude, a position or
    /// a lit sensor.
    pub albedo_teme: Option<Vec3>,
    /// The guidance.
    pub guidance: Guidance,
    /// The reference node's faults, as [`crate::acs_loop::Faults::bits`] (orbit, model,
    /// extrapolated).
    pub faults: u16,
}

impl Reference {
    /// True if the attitude node may use it at step `step`: made for that step, with a valid
    /// clock.
    pub fn usable_at(&self, step: u32) -> bool {
        self.step == step && self.clock_valid
    }
}

/// Big-endian writer over a fixed buffer (the layouts are constant: every write fits).
pub(crate) struct Writer<'a> {
    pub(crate) out: &'a mut [u8],
    pub(crate) at: usize,
}

impl Writer<'_> {
    pub(crate) fn bytes(&mut self, b: &[u8]) {
        if let Some(slot) = self.out.get_mut(self.at..self.at + b.len()) {
            slot.copy_from_slice(b);
        }
        self.at += b.len();
    }
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub(crate) fn u8(&mut self, v: u8) {
        self.bytes(&[v]);
    }
    // out of line on the MSP430: a field is then a call, not a bounds check and a copy
    // (reference image -478 B, attitude image -276 B)
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub(crate) fn u16(&mut self, v: u16) {
        self.bytes(&v.to_be_bytes());
    }
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub(crate) fn u32(&mut self, v: u32) {
        self.bytes(&v.to_be_bytes());
    }
    pub(crate) fn f32(&mut self, v: f32) {
        self.u32(v.to_bits());
    }
    /// `f32`s, each as its bits (out of line on the MSP430: the housekeeping's arrays).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub(crate) fn f32s(&mut self, v: &[f32]) {
        for x in v {
            self.u32(x.to_bits());
        }
    }

    pub(crate) fn vec3(&mut self, v: Option<&Vec3>) {
        let v = v.copied().unwrap_or_else(Vec3::zeros);
        self.f32(v.x);
        self.f32(v.y);
        self.f32(v.z);
    }
    pub(crate) fn quaternion(&mut self, q: &Quaternion) {
        for x in [q.q0, q.q1, q.q2, q.q3] {
            self.f32(x);
        }
    }
    fn epoch(&mut self, e: Option<&Epoch<Utc>>) {
        let (day, second, nano) = e.map_or((0, 0, 0), |e| (e.day(), e.second_of_day(), e.nano()));
        self.u32(day as u32);
        self.u32(second);
        self.u32(nano);
    }
}

/// Big-endian reader; the caller checked the length.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn array<const K: usize>(&mut self) -> [u8; K] {
        let mut a = [0u8; K];
        if let Some(s) = self.bytes.get(self.at..self.at + K) {
            a.copy_from_slice(s);
        }
        self.at += K;
        a
    }
    fn u8(&mut self) -> u8 {
        self.array::<1>()[0]
    }
    // out of line on the MSP430, as the writer's
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn u16(&mut self) -> u16 {
        u16::from_be_bytes(self.array())
    }
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn u32(&mut self) -> u32 {
        u32::from_be_bytes(self.array())
    }
    fn f32(&mut self) -> f32 {
        f32::from_bits(self.u32())
    }
    fn vec3(&mut self, valid: bool) -> Option<Vec3> {
        let v = Vec3::new(self.f32(), self.f32(), self.f32());
        valid.then_some(v)
    }
    /// Three f32 into `out`.
    fn vec3_into(&mut self, out: &mut Vec3) {
        out.x = self.f32();
        out.y = self.f32();
        out.z = self.f32();
    }
    /// Three f32 into `out`, `None` unless `valid` (read all the same).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn vec3_option(&mut self, out: &mut Option<Vec3>, valid: bool) {
        *out = self.vec3(valid);
    }
    fn quaternion(&mut self) -> Quaternion {
        Quaternion {
            q0: self.f32(),
            q1: self.f32(),
            q2: self.f32(),
            q3: self.f32(),
        }
    }
    fn epoch(&mut self, valid: bool) -> Result<Option<Epoch<Utc>>, MessageError> {
        let (day, second, nano) = (self.u32() as i32, self.u32(), self.u32());
        if !valid {
            return Ok(None);
        }
        Epoch::from_parts(day, second, nano)
            .map(Some)
            .map_err(|_| MessageError::Field)
    }
}

/// Bit `i` of `flags`.
fn flag(flags: u8, i: u8) -> bool {
    flags & (1 << i) != 0
}

impl Status {
    /// Bytes on the wire.
    pub const BYTES: usize = 56;

    /// Its packet (APID [`STATUS_APID`]) with sequence count `sequence_count`.
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    pub fn to_packet(&self, sequence_count: u16) -> [u8; STATUS_PACKET_BYTES] {
        to_packet(STATUS_APID, sequence_count, &self.to_bytes())
    }

    /// The message of a STATUS packet and the packet's sequence count.
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    pub fn from_packet(bytes: &[u8]) -> Result<(Self, u16), LinkError> {
        from_packet(bytes, STATUS_APID, Self::from_bytes)
    }

    /// The message's bytes.
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    pub fn to_bytes(&self) -> [u8; Self::BYTES] {
        let mut out = [0u8; Self::BYTES];
        let mut w = Writer {
            out: &mut out,
            at: 0,
        };
        w.u32(self.step);
        w.u16(self.boot_count);
        w.u8(self.mode);
        w.u8(u8::from(self.attitude.is_some()) | u8::from(self.utc.is_some()) << 1);
        w.quaternion(&self.attitude.unwrap_or(Guidance::NONE.target));
        w.vec3(Some(&self.h_wheels_body_nms));
        w.u16(self.guidance_id);
        w.u16(self.faults);
        w.epoch(self.utc.as_ref());
        out
    }

    /// The message from its bytes.
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, MessageError> {
        if bytes.len() != Self::BYTES {
            return Err(MessageError::Length);
        }
        // read in place, as [`Reference::from_bytes`] (the fields are then not held and
        // copied field by field)
        let mut m = Self {
            step: 0,
            boot_count: 0,
            mode: 0,
            attitude: None,
            h_wheels_body_nms: Vec3::new(0.0, 0.0, 0.0),
            guidance_id: 0,
            faults: 0,
            utc: None,
        };
        m.read(&mut Reader { bytes, at: 0 })?;
        Ok(m)
    }

    /// The fields of [`Status::from_bytes`], in place.
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    fn read(&mut self, r: &mut Reader) -> Result<(), MessageError> {
        self.step = r.u32();
        self.boot_count = r.u16();
        self.mode = r.u8();
        let flags = r.u8();
        let q = r.quaternion();
        self.attitude = flag(flags, 0).then_some(q);
        r.vec3_into(&mut self.h_wheels_body_nms);
        self.guidance_id = r.u16();
        self.faults = r.u16();
        self.utc = r.epoch(flag(flags, 1))?;
        if self.mode > 3 || flags > 3 {
            return Err(MessageError::Field);
        }
        Ok(())
    }
}

/// The wire code of a shadow region.
fn shadow_code(s: Shadow) -> u8 {
    match s {
        Shadow::Sunlit => 0,
        Shadow::Penumbra => 1,
        Shadow::Umbra => 2,
        Shadow::Antumbra => 3,
    }
}

impl Reference {
    /// Bytes on the wire.
    pub const BYTES: usize = 117;

    /// Its packet (APID [`REFERENCE_APID`]) with sequence count `sequence_count`.
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    pub fn to_packet(&self, sequence_count: u16) -> [u8; REFERENCE_PACKET_BYTES] {
        to_packet(REFERENCE_APID, sequence_count, &self.to_bytes())
    }

    /// The message of a REF packet and the packet's sequence count.
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    pub fn from_packet(bytes: &[u8]) -> Result<(Self, u16), LinkError> {
        from_packet(bytes, REFERENCE_APID, Self::from_bytes)
    }

    /// The message's bytes.
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    pub fn to_bytes(&self) -> [u8; Self::BYTES] {
        let mut out = [0u8; Self::BYTES];
        let mut w = Writer {
            out: &mut out,
            at: 0,
        };
        w.u32(self.step);
        w.epoch(Some(&self.utc));
        let flags = [
            self.clock_valid,
            self.elements_valid,
            self.r_teme_km.is_some(),
            self.sun_teme.is_some(),
            self.illumination.is_some(),
            self.b_teme_nt.is_some(),
            self.albedo_teme.is_some(),
        ]
        .iter()
        .rev()
        .fold(0u8, |m, f| (m << 1) | u8::from(*f));
        w.u8(flags);
        w.vec3(self.r_teme_km.as_ref());
        w.vec3(self.sun_teme.as_ref());
        let (fraction, shadow) = self
            .illumination
            .map_or((0.0, 0), |i| (i.fraction, shadow_code(i.shadow)));
        w.f32(fraction);
        w.u8(shadow);
        w.vec3(self.b_teme_nt.as_ref());
        w.vec3(self.albedo_teme.as_ref());
        let g = &self.guidance;
        w.u16(g.id);
        w.u8(match g.kind {
            GuidanceKind::None => 0,
            GuidanceKind::Track => 1,
            GuidanceKind::Slew => 2,
        });
        w.quaternion(&g.target);
        w.vec3(Some(&g.rate_body_radps));
        w.vec3(Some(&g.h_ff_body_nms));
        w.u16(self.faults);
        out
    }

    /// The message from its bytes.
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, MessageError> {
        if bytes.len() != Self::BYTES {
            return Err(MessageError::Length);
        }
        let mut m = Self {
            step: 0,
            utc: Epoch::DAY0,
            clock_valid: false,
            elements_valid: false,
            r_teme_km: None,
            sun_teme: None,
            illumination: None,
            b_teme_nt: None,
            albedo_teme: None,
            guidance: Guidance::NONE,
            faults: 0,
        };
        m.read(&mut Reader { bytes, at: 0 })?;
        Ok(m)
    }

    /// [`Reference::from_bytes`]'s fields, read in order into `self` (out of line, through
    /// `&mut self`: each field is stored as it is read, not held and copied).
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    fn read(&mut self, r: &mut Reader) -> Result<(), MessageError> {
        self.step = r.u32();
        self.utc = r.epoch(true)?.ok_or(MessageError::Field)?;
        let flags = r.u8();
        self.clock_valid = flag(flags, 0);
        self.elements_valid = flag(flags, 1);
        r.vec3_option(&mut self.r_teme_km, flag(flags, 2));
        r.vec3_option(&mut self.sun_teme, flag(flags, 3));
        let fraction = r.f32();
        let shadow = match r.u8() {
            0 => Shadow::Sunlit,
            1 => Shadow::Penumbra,
            2 => Shadow::Umbra,
            3 => Shadow::Antumbra,
            _ => return Err(MessageError::Field),
        };
        self.illumination = flag(flags, 4).then_some(Illumination { fraction, shadow });
        r.vec3_option(&mut self.b_teme_nt, flag(flags, 5));
        r.vec3_option(&mut self.albedo_teme, flag(flags, 6));
        let g = &mut self.guidance;
        g.id = r.u16();
        g.kind = match r.u8() {
            0 => GuidanceKind::None,
            1 => GuidanceKind::Track,
            2 => GuidanceKind::Slew,
            _ => return Err(MessageError::Field),
        };
        g.target = r.quaternion();
        r.vec3_into(&mut g.rate_body_radps);
        r.vec3_into(&mut g.h_ff_body_nms);
        self.faults = r.u16();
        if flags > 0x7F {
            return Err(MessageError::Field);
        }
        Ok(())
    }
}
