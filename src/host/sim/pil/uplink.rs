//! The ground side of the node images' uplinks ([`crate::uplink`]): ground commands encoded
//! as a command code and argument words, each sent to the node that owns it ([`owner`]: track,
//! slew, element set and clock to the reference node, sun-safe and the tiles to the attitude
//! node), written to the host's copy of that node's mailbox and applied to the host
//! composition's node by the same function the image runs ([`crate::uplink::apply_reference`],
//! [`crate::uplink::apply_attitude`]), so that both sides receive every command exactly as the
//! image decodes it.
//!
//! A slew's target goes up as a quaternion (`Dcm::to_quaternion`) and the image turns it back
//! into a DCM after normalising it, so the host composition gets the same DCM only through the
//! mailbox; that is why the host is commanded through it too.

use crate::acs_loop::{Command, Mode, StepReport};
use crate::attitude::Quaternion;
use crate::flight::{FIELD_COEFFS, TILES};
use crate::link::messages::{ATTITUDE_TC_APID, REFERENCE_TC_APID};
use crate::link::pus::{decode_tm, encode_tc, AckFlags, TcHeader, TC_OVERHEAD};
use crate::link::sequence::SequenceCounter;
use crate::link::space_packet::Apid;
use crate::orbit::sgp4::ELEMENT_WORDS;
use crate::telemetry::Downlink;
use crate::time::{Epoch, Utc};
use crate::two_node::TwoNodeLoop;
use crate::uplink::telecommand::{self, ATTITUDE_TC_BYTES, REFERENCE_TC_BYTES, REPORTS_LEN};
use crate::uplink::{self, kind};

/// The host composition the PIL flies: the two nodes over the flight configuration.
pub type HostLoop<'c> = TwoNodeLoop<'c, TILES, FIELD_COEFFS>;

/// A node of the satellite, with its flight image.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum Node {
    /// The reference node (`acs-reference`): clock, SGP4, Sun, shadow, IGRF, guidance.
    Reference,
    /// The attitude node (`acs-attitude`): tiles, determination, modes, laws, actuators.
    Attitude,
}

impl Node {
    /// Both nodes, in the order of `pil.json`'s `nodes`.
    pub const ALL: [Node; 2] = [Node::Reference, Node::Attitude];

    /// Its name in `pil.json` and in a mismatch.
    pub fn name(self) -> &'static str {
        match self {
            Self::Reference => "reference",
            Self::Attitude => "attitude",
        }
    }
}

/// The node that owns command `kind` ([`crate::two_node`]): track, slew, element set and clock
/// the reference node; sun-safe, mark failed, restore (and any unknown code) the attitude node.
pub fn owner(kind: u16) -> Node {
    match kind {
        kind::TRACK | kind::SLEW | kind::ELEMENTS | kind::CLOCK => Node::Reference,
        _ => Node::Attitude,
    }
}

/// The failure code of a command applied: none (the reports of [`outcome`]).
pub const ACCEPTED: u16 = 0;

/// The source ID the PIL's ground puts in its telecommands (the reports' destination).
pub const GROUND_ID: u16 = 1;

/// The APID of `node`'s telecommands and reports.
pub fn tc_apid(node: Node) -> Apid {
    match node {
        Node::Reference => REFERENCE_TC_APID,
        Node::Attitude => ATTITUDE_TC_APID,
    }
}

/// The mailbox bytes of `node`'s image for a telecommand
/// ([`crate::uplink::telecommand::REFERENCE_TC_BYTES`], [`ATTITUDE_TC_BYTES`]).
pub fn tc_bytes(node: Node) -> usize {
    match node {
        Node::Reference => REFERENCE_TC_BYTES,
        Node::Attitude => ATTITUDE_TC_BYTES,
    }
}

/// What `reports` (the verification reports of one telecommand to `node`, back to back) say:
/// [`ACCEPTED`] if the first is a TM\[1,1\] or TM\[1,7\], the failure code of a TM\[1,2\], and
/// `u16::MAX` if there is no readable report.
pub fn outcome(reports: &[u8], node: Node) -> u16 {
    // the first packet: its data length field + 1, after the 6 B primary header
    let first = reports
        .get(4..6)
        .map(|l| usize::from(u16::from_be_bytes([l[0], l[1]])) + 7)
        .and_then(|n| reports.get(..n));
    match first.map(|p| decode_tm(p, tc_apid(node))) {
        Some(Ok(tm)) if tm.subtype == 2 => tm
            .app_data
            .get(4..6)
            .map_or(u16::MAX, |c| u16::from_be_bytes([c[0], c[1]])),
        Some(Ok(_)) => ACCEPTED,
        _ => u16::MAX,
    }
}

/// One ground command as the uplink carries it.
#[derive(Clone, Debug, PartialEq)]
pub enum Uplink {
    /// Kind 1.
    SunSafe,
    /// Kind 2.
    Track {
        /// Commanded attitude (reference TEME → body).
        target: Quaternion,
    },
    /// Kind 3.
    Slew {
        /// Commanded attitude, as a quaternion.
        target: Quaternion,
        /// Time allowed, s.
        within_s: f32,
    },
    /// Kind 4 (boxed: 232 B).
    Elements(Box<[u32; ELEMENT_WORDS]>),
    /// Kind 5.
    Clock(Epoch<Utc>),
    /// Kind 6.
    MarkFailed(u32),
    /// Kind 7.
    Restore(u32),
}

fn quaternion_words(q: &Quaternion) -> [u32; 4] {
    [
        q.q0.to_bits(),
        q.q1.to_bits(),
        q.q2.to_bits(),
        q.q3.to_bits(),
    ]
}

impl Uplink {
    /// The uplink of a loop command.
    pub fn of_command(command: &Command) -> Self {
        match command {
            Command::SunSafe => Self::SunSafe,
            Command::Track { target } => Self::Track { target: *target },
            Command::Slew { target, within_s } => Self::Slew {
                target: target.to_quaternion(),
                within_s: *within_s,
            },
        }
    }

    /// The command code (the telecommand's function ID).
    pub fn kind(&self) -> u16 {
        match self {
            Self::SunSafe => kind::SUN_SAFE,
            Self::Track { .. } => kind::TRACK,
            Self::Slew { .. } => kind::SLEW,
            Self::Elements(_) => kind::ELEMENTS,
            Self::Clock(_) => kind::CLOCK,
            Self::MarkFailed(_) => kind::MARK_FAILED,
            Self::Restore(_) => kind::RESTORE,
        }
    }

    /// The telecommand TC\[8,1\] of this command to `node` (its APID: the other node refuses
    /// it), with sequence count `count`, both reports asked for: the function ID, then the
    /// argument words ([`Uplink::args`]) big-endian ([`crate::uplink::telecommand`]).
    pub fn telecommand(&self, node: Node, count: u16) -> Vec<u8> {
        let mut data = self.kind().to_be_bytes().to_vec();
        data.extend(self.args().iter().flat_map(|w| w.to_be_bytes()));
        let header = TcHeader {
            apid: tc_apid(node),
            sequence_count: count & 0x3FFF,
            ack: AckFlags::ACCEPTANCE.with(AckFlags::COMPLETION),
            service: telecommand::SERVICE,
            subtype: telecommand::SUBTYPE,
            source_id: GROUND_ID,
        };
        let mut out = vec![0u8; data.len() + TC_OVERHEAD];
        let n = encode_tc(&header, &data, &mut out).unwrap_or(0);
        out.truncate(n);
        out
    }

    /// The command's argument words, exactly as many as it takes
    /// ([`crate::uplink::telecommand::arity`]).
    pub fn args(&self) -> Vec<u32> {
        match self {
            Self::SunSafe => vec![],
            Self::Track { target } => quaternion_words(target).to_vec(),
            Self::Slew { target, within_s } => {
                let mut w = quaternion_words(target).to_vec();
                w.push(within_s.to_bits());
                w
            }
            Self::Elements(words) => words.to_vec(),
            Self::Clock(t) => vec![t.day() as u32, t.second_of_day(), t.nano()],
            // a tile (word 1 = 0), not a coil
            Self::MarkFailed(tile) | Self::Restore(tile) => vec![*tile, 0],
        }
    }
}

/// The host's copy of a node's ground mailbox: the node's count of verification reports, and
/// the image's taking of a telecommand ([`crate::uplink::telecommand::take`], what
/// `acs_firmware::flight::take_telecommand` runs).
#[derive(Clone, Debug, Default)]
pub struct Ground {
    count: SequenceCounter,
    /// The node's telemetry, as its image keeps it.
    downlink: Downlink,
}

impl Ground {
    /// The telemetry `node`'s image sends after the step of `report` on the host composition
    /// `acs` ([`Downlink::attitude`], [`Downlink::reference`]), its packets in order:
    /// `received` what its link layer made of the packet of the period (the attitude node: the
    /// REF of the step; the reference node: the STATUS of the step before), `took` whether it
    /// took a telecommand in the period (the reference node then sends none).
    pub fn telemetry(
        &mut self,
        node: Node,
        acs: &mut HostLoop<'_>,
        report: &StepReport,
        received: Option<bool>,
        took: bool,
    ) -> Vec<Vec<u8>> {
        let mut out = Vec::new();
        let send = |p: &[u8]| out.push(p.to_vec());
        self.downlink.link.count(received);
        match node {
            Node::Reference => {
                if let Some(r) = acs.reference_made().copied() {
                    if !took {
                        let n = acs.reference_node_mut();
                        self.downlink.reference(n, &r, &mut self.count, send);
                    }
                }
            }
            Node::Attitude => {
                let n = acs.attitude_node_mut();
                self.downlink.attitude(n, report, &mut self.count, send);
            }
        }
        out
    }

    /// Takes the telecommand `packet` on `node` of the host composition, as that node's image
    /// does: stamped with the node's clock now, applied with
    /// [`crate::uplink::apply_reference`] (a slew planned from `attitude`, the attitude of the
    /// STATUS the reference image holds when it takes the telecommand) or
    /// [`crate::uplink::apply_attitude`]; returns the verification reports the image writes to
    /// its mailbox.
    pub fn take(
        &mut self,
        packet: &[u8],
        node: Node,
        acs: &mut HostLoop<'_>,
        attitude: Option<&Quaternion>,
    ) -> Vec<u8> {
        let mut out = [0u8; REPORTS_LEN];
        let apid = tc_apid(node);
        let n = match node {
            Node::Reference => {
                let r = acs.reference_node_mut();
                let clock = r.clock();
                telecommand::take(
                    packet,
                    apid,
                    clock,
                    &mut self.count,
                    &mut out,
                    |code, args| uplink::apply_reference(code, args, r, attitude),
                )
            }
            Node::Attitude => {
                let a = acs.attitude_node_mut();
                let clock = a.clock();
                telecommand::take(
                    packet,
                    apid,
                    clock,
                    &mut self.count,
                    &mut out,
                    |code, args| uplink::apply_attitude(code, args, a),
                )
            }
        };
        out.get(..n).unwrap_or_default().to_vec()
    }
}

/// The image's `STEP_MODE` code of a mode ([`Mode::code`]).
pub fn mode_code(mode: Mode) -> u16 {
    mode.code()
}

/// The name of a `STEP_MODE` code.
pub fn mode_name(code: u16) -> &'static str {
    match code {
        0 => "Detumble",
        1 => "SunSafe",
        2 => "Slew",
        3 => "Tracking",
        _ => "(invalid mode code)",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attitude::Dcm;
    use crate::flight::CONFIG;
    use crate::host::sim::scenarios::make_tle;
    use crate::orbit::sgp4::{Gravity, Sgp4};
    use crate::tle::Tle;

    fn orbit() -> Sgp4 {
        let (l1, l2) = make_tle(90101, (25, 79.5), 97.4, 90.0, 0.0, 0.0, 15.2);
        Sgp4::new(&Tle::parse(&l1, &l2).unwrap(), Gravity::Wgs72).unwrap()
    }

    #[test]
    fn commands_encode_as_the_image_reads_them() {
        let q = Quaternion::new_normalize(0.9, 0.1, -0.3, 0.2).unwrap();
        let slew = Uplink::of_command(&Command::Slew {
            target: q.to_dcm(),
            within_s: 120.0,
        });
        assert_eq!(slew.kind(), 3);
        let args = slew.args();
        assert_eq!(args.len(), 5);
        assert_eq!(args[4], 120.0f32.to_bits());
        let t = Epoch::<Utc>::from_parts(9_210, 43_201, 5).unwrap();
        assert_eq!(Uplink::Clock(t).args(), vec![9_210, 43_201, 5]);
        assert_eq!(Uplink::Clock(t).kind(), 5);
        assert_eq!(Uplink::SunSafe.args(), Vec::<u32>::new());
        let words = orbit().to_words();
        assert_eq!(Uplink::Elements(Box::new(words)).args(), words.to_vec());
        assert_eq!(Uplink::MarkFailed(2).args(), vec![2, 0]);
    }

    #[test]
    fn commands_go_to_the_node_that_owns_them() {
        for k in [kind::TRACK, kind::SLEW, kind::ELEMENTS, kind::CLOCK] {
            assert_eq!(owner(k), Node::Reference);
        }
        for k in [kind::SUN_SAFE, kind::MARK_FAILED, kind::RESTORE, 99] {
            assert_eq!(owner(k), Node::Attitude);
        }
        assert_eq!(Node::ALL.map(Node::name), ["reference", "attitude"]);
    }

    /// Sends `u` to `node` as its telecommand and returns the outcome of its reports.
    fn send(
        ground: &mut Ground,
        u: &Uplink,
        node: Node,
        acs: &mut HostLoop<'_>,
        attitude: Option<&Quaternion>,
    ) -> u16 {
        let reports = ground.take(&u.telecommand(node, 7), node, acs, attitude);
        // both reports asked for: 25 + 25 B, or a failure's 27 B alone
        let code = outcome(&reports, node);
        assert_eq!(reports.len(), if code == ACCEPTED { 50 } else { 27 });
        code
    }

    #[test]
    fn the_mirror_applies_commands_as_the_node_images() {
        let mut acs = HostLoop::new(&CONFIG, orbit()).unwrap();
        let mut reference = Ground::default();
        let mut attitude = Ground::default();
        let r = Node::Reference;
        let a = Node::Attitude;

        let t = Epoch::<Utc>::from_parts(9_300, 7, 0).unwrap();
        assert_eq!(
            send(&mut reference, &Uplink::Clock(t), r, &mut acs, None),
            ACCEPTED
        );
        assert_eq!(acs.reference_node_mut().clock(), Some(t));
        // the other node's command is refused as such
        assert_eq!(
            send(&mut attitude, &Uplink::Clock(t), a, &mut acs, None),
            0x104
        );

        let q = Quaternion::new_normalize(0.9, 0.1, -0.3, 0.2).unwrap();
        let track = Uplink::Track { target: q };
        assert_eq!(send(&mut reference, &track, r, &mut acs, None), ACCEPTED);
        // the target as the image decodes it: normalised again
        let decoded = Quaternion::new_normalize(q.q0, q.q1, q.q2, q.q3).unwrap();
        assert_eq!(acs.guidance().target, decoded);

        // a slew needs an attitude to plan from
        let slew = Uplink::of_command(&Command::Slew {
            target: Dcm::a1(0.5),
            within_s: 100.0,
        });
        assert_eq!(send(&mut reference, &slew, r, &mut acs, None), 0x103);
        assert_eq!(send(&mut reference, &slew, r, &mut acs, Some(&q)), ACCEPTED);

        // a zero quaternion is invalid; a corrupt element set names its word
        let zero = Uplink::Track {
            target: Quaternion {
                q0: 0.0,
                q1: 0.0,
                q2: 0.0,
                q3: 0.0,
            },
        };
        assert_eq!(send(&mut reference, &zero, r, &mut acs, None), 0x102);
        let mut words = orbit().to_words();
        let set = Uplink::Elements(Box::new(words));
        assert_eq!(send(&mut reference, &set, r, &mut acs, None), ACCEPTED);
        words[ELEMENT_WORDS - 1] ^= 1;
        let set = Uplink::Elements(Box::new(words));
        assert_eq!(
            send(&mut reference, &set, r, &mut acs, None),
            0x200 + (ELEMENT_WORDS as u16 - 1)
        );
        let failed = Uplink::MarkFailed(0);
        assert_eq!(send(&mut attitude, &failed, a, &mut acs, None), ACCEPTED);
        assert_eq!(acs.tile_state(0), Some(crate::tiles::TileState::Failed));
        assert_eq!(
            send(&mut attitude, &Uplink::Restore(0), a, &mut acs, None),
            ACCEPTED
        );
        let beyond = Uplink::MarkFailed(TILES as u32);
        assert_eq!(send(&mut attitude, &beyond, a, &mut acs, None), 0x102);
        assert_eq!(
            send(&mut attitude, &Uplink::SunSafe, a, &mut acs, None),
            ACCEPTED
        );
        assert_eq!(acs.mode(), Mode::SunSafe);
        // a telecommand for the other node's APID is refused by the packet layer
        let packet = Uplink::SunSafe.telecommand(r, 0);
        let reports = attitude.take(&packet, a, &mut acs, None);
        assert_eq!(outcome(&reports, a), crate::link::pus::failure::APID);
    }

    /// The PIL run's non-finite uplinks are each refused by the reference node (invalid
    /// argument, or the element set at its first bad word), with or without an attitude to
    /// plan from, and by the attitude node as not its own; they change nothing.
    #[test]
    fn non_finite_uplinks_are_refused() {
        let mut acs = HostLoop::new(&CONFIG, orbit()).unwrap();
        let start = Epoch::<Utc>::from_parts(9_210, 43_200, 0).unwrap();
        acs.reference_node_mut().set_clock(start);
        let guidance = *acs.guidance();
        let mut ground = Ground::default();
        let q = Quaternion::new_normalize(0.9, 0.1, -0.3, 0.2).unwrap();
        let uplinks = crate::host::sim::pil::non_finite_uplinks(&orbit().to_words());
        assert_eq!(uplinks.len(), 7);
        for u in &uplinks {
            for attitude in [None, Some(&q)] {
                let code = send(&mut ground, u, Node::Reference, &mut acs, attitude);
                assert!(code == 0x102 || code >= 0x200, "{u:?}: code {code:#x}");
                let code = send(&mut ground, u, Node::Attitude, &mut acs, attitude);
                assert_eq!(code, 0x104);
                assert_eq!(acs.mode(), Mode::Detumble, "{u:?}");
                assert_eq!(*acs.guidance(), guidance, "{u:?}");
                assert_eq!(acs.reference_node_mut().clock(), Some(start));
            }
        }
    }
}
