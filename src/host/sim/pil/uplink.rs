//! The ground side of the node images' telecommands ([`crate::uplink::telecommand`]): each
//! ground command goes up as a PUS-C TC\[8,1\] to the node that owns it ([`owner`]: track,
//! slew, element set and clock to the reference node, sun-safe and the tiles to the attitude
//! node; [`Uplink::to_telecommand`], built by [`GroundStation`]), and the host composition's
//! node takes the same packet bytes with the function the image runs
//! ([`crate::uplink::telecommand::take`] over [`crate::uplink::apply_reference`] or
//! [`crate::uplink::apply_attitude`], [`HostTelecommands`]), so that both sides decode every
//! command alike and answer it with the same verification reports (TM\[1,1\] and TM\[1,7\],
//! or TM\[1,2\] with a failure code; [`describe_reports`]).
//!
//! A slew's target goes up as a quaternion (`Dcm::to_quaternion`) and the node turns it back
//! into a DCM after normalising it, so the host composition gets the same DCM only through the
//! telecommand; that is why the host is commanded through it too.

use crate::acs_loop::{Command, Mode};
use crate::attitude::Quaternion;
use crate::flight::{FIELD_COEFFS, TILES};
use crate::link::messages::{ATTITUDE_TC_APID, REFERENCE_TC_APID};
use crate::link::pus::{self, decode_tm, encode_tc, AckFlags, TcHeader};
use crate::link::sequence::SequenceCounter;
use crate::link::space_packet::{Apid, PRIMARY_HEADER_LEN};
use crate::orbit::sgp4::ELEMENT_WORDS;
use crate::time::{Epoch, Utc};
use crate::two_node::TwoNodeLoop;
use crate::uplink::telecommand::{self, REPORTS_LEN};
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

    /// The APID of its telecommands and of its reports on them
    /// ([`REFERENCE_TC_APID`], [`ATTITUDE_TC_APID`]).
    pub fn tc_apid(self) -> Apid {
        match self {
            Self::Reference => REFERENCE_TC_APID,
            Self::Attitude => ATTITUDE_TC_APID,
        }
    }

    fn index(self) -> usize {
        match self {
            Self::Reference => 0,
            Self::Attitude => 1,
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

/// The ground's source ID in the TC secondary header (1: the one ground of the rehearsal); the
/// reports carry it back as their destination ID.
pub const GROUND_SOURCE_ID: u16 = 1;

/// The TC\[`service`,`subtype`\] packet on `apid` with sequence count `count`, the
/// acceptance and completion flags, the ground's source ID and `app_data`.
pub fn tc_packet(apid: Apid, count: u16, service: u8, subtype: u8, app_data: &[u8]) -> Vec<u8> {
    let header = TcHeader {
        apid,
        sequence_count: count,
        ack: AckFlags::ACCEPTANCE.with(AckFlags::COMPLETION),
        service,
        subtype,
        source_id: GROUND_SOURCE_ID,
    };
    let mut out = vec![0u8; pus::TC_OVERHEAD + app_data.len()];
    let n = encode_tc(&header, app_data, &mut out).unwrap_or(0);
    out.truncate(n);
    out
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

    /// The command's name in a mismatch.
    pub fn name(&self) -> &'static str {
        match self {
            Self::SunSafe => "sun-safe",
            Self::Track { .. } => "track",
            Self::Slew { .. } => "slew",
            Self::Elements(_) => "element set",
            Self::Clock(_) => "clock",
            Self::MarkFailed(_) => "mark failed",
            Self::Restore(_) => "restore",
        }
    }

    /// The command code: the telecommand's function ID.
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

    /// The argument words ([`crate::uplink`]'s; exactly [`telecommand::arity`] of them).
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
            Self::MarkFailed(tile) | Self::Restore(tile) => vec![*tile, 0],
        }
    }

    /// The TC\[8,1\] application data: the function ID ([`Uplink::kind`]) and the argument
    /// words, big-endian.
    pub fn app_data(&self) -> Vec<u8> {
        let mut data = self.kind().to_be_bytes().to_vec();
        data.extend(self.args().iter().flat_map(|w| w.to_be_bytes()));
        data
    }

    /// The TC\[8,1\] of this command on `apid` with sequence count `count` ([`tc_packet`]).
    pub fn to_telecommand(&self, apid: Apid, count: u16) -> Vec<u8> {
        tc_packet(
            apid,
            count,
            telecommand::SERVICE,
            telecommand::SUBTYPE,
            &self.app_data(),
        )
    }
}

/// A telecommand as the ground sends it: what it is (named in a mismatch) and its bytes.
#[derive(Clone, Debug, PartialEq)]
pub struct Sent {
    /// The command's name, or what is wrong with the packet.
    pub what: String,
    /// The packet.
    pub packet: Vec<u8>,
}

/// The ground: its telecommands' sequence count, per node (its APID).
#[derive(Clone, Debug, Default)]
pub struct GroundStation {
    counts: [SequenceCounter; 2],
}

impl GroundStation {
    /// The telecommand of `uplink` to `node`.
    pub fn send(&mut self, node: Node, uplink: &Uplink) -> Sent {
        let count = self.counts[node.index()].next_count();
        Sent {
            what: format!("{} (function {})", uplink.name(), uplink.kind()),
            packet: uplink.to_telecommand(node.tc_apid(), count),
        }
    }

    /// Two malformed telecommands to `node`, which it must refuse at acceptance: a command of
    /// its own (reference node: track to the identity, attitude node: sun-safe) with its
    /// function ID's low byte flipped (the CRC fails: failure code 2), and a TC\[17,1\] (not
    /// served: code 7).
    pub fn malformed(&mut self, node: Node) -> [Sent; 2] {
        let own = match node {
            Node::Reference => Uplink::Track {
                target: Quaternion::IDENTITY,
            },
            Node::Attitude => Uplink::SunSafe,
        };
        let mut flipped = self.send(node, &own).packet;
        // the function ID's low byte, after the primary and the secondary header
        if let Some(b) = flipped.get_mut(PRIMARY_HEADER_LEN + pus::TC_SECONDARY_HEADER_LEN + 1) {
            *b ^= 0x01;
        }
        let count = self.counts[node.index()].next_count();
        [
            Sent {
                what: format!("{} with a flipped byte", own.name()),
                packet: flipped,
            },
            Sent {
                what: "TC[17,1]".into(),
                packet: tc_packet(node.tc_apid(), count, 17, 1, &[]),
            },
        ]
    }
}

/// The host composition's side of the telecommands: each node's TM sequence counter for its
/// reports, as its image keeps it (from 0 at reset).
#[derive(Clone, Debug, Default)]
pub struct HostTelecommands {
    counts: [SequenceCounter; 2],
}

impl HostTelecommands {
    /// `node`'s counter from 0 again (its image's power-on reset zeroes it).
    pub fn reset(&mut self, node: Node) {
        self.counts[node.index()] = SequenceCounter::new();
    }

    /// `node` of the host composition takes the telecommand `packet` as its image does
    /// ([`telecommand::take`] on the node's APID, stamped with the node's clock before the
    /// command, applied with [`crate::uplink::apply_reference`], a slew planned from
    /// `attitude` (the attitude of the STATUS the reference image holds when it takes the
    /// telecommand), or [`crate::uplink::apply_attitude`]); returns the reports.
    pub fn take(
        &mut self,
        packet: &[u8],
        node: Node,
        acs: &mut HostLoop<'_>,
        attitude: Option<&Quaternion>,
    ) -> Vec<u8> {
        let mut out = [0u8; REPORTS_LEN];
        let count = &mut self.counts[node.index()];
        let apid = node.tc_apid();
        let n = match node {
            Node::Reference => {
                let clock = acs.reference_node_mut().clock();
                telecommand::take(packet, apid, clock, count, &mut out, |k, a| {
                    uplink::apply_reference(k, a, acs.reference_node_mut(), attitude)
                })
            }
            Node::Attitude => {
                let clock = acs.attitude_node_mut().clock();
                telecommand::take(packet, apid, clock, count, &mut out, |k, a| {
                    uplink::apply_attitude(k, a, acs.attitude_node_mut())
                })
            }
        };
        out[..n.min(REPORTS_LEN)].to_vec()
    }
}

/// The reports `bytes` (back to back, on `apid`) in words: `TM[1,1] TM[1,7]`, or `TM[1,2]
/// 0x104` with the failure code; `(undecodable)` for what does not decode.
pub fn describe_reports(bytes: &[u8], apid: Apid) -> String {
    let mut words = Vec::new();
    let mut rest = bytes;
    while !rest.is_empty() {
        let len = match rest.get(4..6) {
            Some(&[a, b]) => 7 + usize::from(u16::from_be_bytes([a, b])),
            _ => rest.len(),
        };
        let (packet, tail) = rest.split_at(len.min(rest.len()));
        rest = tail;
        match decode_tm(packet, apid) {
            Ok(tm) => {
                let mut w = format!("TM[{},{}]", tm.service, tm.subtype);
                if let Some(&[c0, c1]) = tm.app_data.get(4..6) {
                    w.push_str(&format!(" 0x{:x}", u16::from_be_bytes([c0, c1])));
                }
                words.push(w);
            }
            Err(_) => words.push("(undecodable)".into()),
        }
    }
    if words.is_empty() {
        "none".into()
    } else {
        words.join(" ")
    }
}

/// The failure code of the TM\[1,2\] among `bytes` (the reports of one telecommand on
/// `apid`), `None` if there is none.
pub fn failure_code(bytes: &[u8], apid: Apid) -> Option<u16> {
    let len = 7 + usize::from(u16::from_be_bytes([*bytes.get(4)?, *bytes.get(5)?]));
    let tm = decode_tm(bytes.get(..len)?, apid).ok()?;
    let code = tm.app_data.get(4..6)?;
    (tm.subtype == 2).then(|| u16::from_be_bytes([code[0], code[1]]))
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
    use crate::link::pus::decode_tc;
    use crate::orbit::sgp4::{Gravity, Sgp4};
    use crate::tle::Tle;

    fn orbit() -> Sgp4 {
        let (l1, l2) = make_tle(90101, (25, 79.5), 97.4, 90.0, 0.0, 0.0, 15.2);
        Sgp4::new(&Tle::parse(&l1, &l2).unwrap(), Gravity::Wgs72).unwrap()
    }

    const ACCEPTED: &str = "TM[1,1] TM[1,7]";

    #[test]
    fn commands_encode_as_the_telecommands_the_nodes_read() {
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
        let elements = Uplink::Elements(Box::new(words));
        assert_eq!(elements.args(), words.to_vec());
        assert_eq!(Uplink::MarkFailed(2).args(), vec![2, 0]);
        assert_eq!(Uplink::Restore(2).args(), vec![2, 0]);
        // every command: exactly its arity's words, in a TC[8,1] the node decodes
        let uplinks = [
            Uplink::SunSafe,
            Uplink::Track { target: q },
            slew,
            elements,
            Uplink::Clock(t),
            Uplink::MarkFailed(1),
            Uplink::Restore(1),
        ];
        for u in &uplinks {
            assert_eq!(Some(u.args().len()), telecommand::arity(u.kind()), "{u:?}");
            let packet = u.to_telecommand(REFERENCE_TC_APID, 77);
            let tc = decode_tc(&packet, REFERENCE_TC_APID).unwrap();
            assert_eq!(
                (tc.service, tc.subtype, tc.source_id),
                (8, 1, GROUND_SOURCE_ID)
            );
            assert_eq!(tc.ack, AckFlags::ACCEPTANCE.with(AckFlags::COMPLETION));
            assert_eq!(tc.request_id.sequence_control & 0x3fff, 77);
            assert_eq!(tc.app_data, &u.app_data()[..]);
            assert_eq!(&tc.app_data[..2], &u.kind().to_be_bytes());
        }
        let packet = uplinks[3].to_telecommand(REFERENCE_TC_APID, 0);
        assert_eq!(packet.len(), telecommand::MAX_TC_LEN);
        assert!(packet.len() <= telecommand::REFERENCE_TC_BYTES);
        for u in &uplinks[..3] {
            assert!(u.to_telecommand(ATTITUDE_TC_APID, 0).len() <= telecommand::ATTITUDE_TC_BYTES);
        }
        assert_eq!(&uplinks[1].app_data()[2..6], &q.q0.to_bits().to_be_bytes());
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
        assert_eq!(Node::Reference.tc_apid(), REFERENCE_TC_APID);
        assert_eq!(Node::Attitude.tc_apid(), ATTITUDE_TC_APID);
    }

    #[test]
    fn the_host_takes_telecommands_as_the_node_images() {
        let mut acs = HostLoop::new(&CONFIG, orbit()).unwrap();
        let mut ground = GroundStation::default();
        let mut host = HostTelecommands::default();
        let r = Node::Reference;
        let a = Node::Attitude;
        let rapid = r.tc_apid();
        let aapid = a.tc_apid();
        let mut send =
            |node: Node, u: &Uplink, acs: &mut HostLoop<'_>, att: Option<&Quaternion>| {
                let sent = ground.send(node, u);
                let reports = host.take(&sent.packet, node, acs, att);
                describe_reports(&reports, node.tc_apid())
            };

        let t = Epoch::<Utc>::from_parts(9_300, 7, 0).unwrap();
        assert_eq!(send(r, &Uplink::Clock(t), &mut acs, None), ACCEPTED);
        assert_eq!(acs.reference_node_mut().clock(), Some(t));
        // the other node's command is refused: 0x100 + 4
        assert_eq!(send(a, &Uplink::Clock(t), &mut acs, None), "TM[1,2] 0x104");

        let q = Quaternion::new_normalize(0.9, 0.1, -0.3, 0.2).unwrap();
        assert_eq!(
            send(r, &Uplink::Track { target: q }, &mut acs, None),
            ACCEPTED
        );
        // the target as the node decodes it: normalised again
        let decoded = Quaternion::new_normalize(q.q0, q.q1, q.q2, q.q3).unwrap();
        assert_eq!(acs.guidance().target, decoded);

        // a slew needs an attitude to plan from
        let slew = Uplink::of_command(&Command::Slew {
            target: Dcm::a1(0.5),
            within_s: 100.0,
        });
        assert_eq!(send(r, &slew, &mut acs, None), "TM[1,2] 0x103");
        assert_eq!(send(r, &slew, &mut acs, Some(&q)), ACCEPTED);

        // a zero quaternion is invalid; a corrupt element set names its word
        let zero = Quaternion {
            q0: 0.0,
            q1: 0.0,
            q2: 0.0,
            q3: 0.0,
        };
        assert_eq!(
            send(r, &Uplink::Track { target: zero }, &mut acs, None),
            "TM[1,2] 0x102"
        );
        let mut words = orbit().to_words();
        assert_eq!(
            send(r, &Uplink::Elements(Box::new(words)), &mut acs, None),
            ACCEPTED
        );
        words[ELEMENT_WORDS - 1] ^= 1;
        assert_eq!(
            send(r, &Uplink::Elements(Box::new(words)), &mut acs, None),
            format!("TM[1,2] 0x{:x}", 0x200 + ELEMENT_WORDS - 1)
        );
        assert_eq!(send(a, &Uplink::MarkFailed(0), &mut acs, None), ACCEPTED);
        assert_eq!(acs.tile_state(0), Some(crate::tiles::TileState::Failed));
        assert_eq!(send(a, &Uplink::Restore(0), &mut acs, None), ACCEPTED);
        assert_eq!(
            send(a, &Uplink::MarkFailed(TILES as u32), &mut acs, None),
            "TM[1,2] 0x102"
        );
        assert_eq!(send(a, &Uplink::SunSafe, &mut acs, None), ACCEPTED);
        assert_eq!(acs.mode(), Mode::SunSafe);

        // an unknown function ID, a wrong number of words
        let mut ground = GroundStation::default();
        let unknown = tc_packet(aapid, 0, 8, 1, &99u16.to_be_bytes());
        let reports = host.take(&unknown, a, &mut acs, None);
        assert_eq!(describe_reports(&reports, aapid), "TM[1,2] 0x101");
        assert_eq!(failure_code(&reports, aapid), Some(0x101));
        let short = tc_packet(rapid, 0, 8, 1, &[0, 2, 0, 0, 0, 0]);
        let reports = host.take(&short, r, &mut acs, None);
        assert_eq!(failure_code(&reports, rapid), Some(0x105));
        // malformed packets: a CRC failure, a service not served
        for node in Node::ALL {
            let [flipped, other] = ground.malformed(node);
            let reports = host.take(&flipped.packet, node, &mut acs, None);
            assert_eq!(
                failure_code(&reports, node.tc_apid()),
                Some(2),
                "{}",
                flipped.what
            );
            let reports = host.take(&other.packet, node, &mut acs, None);
            assert_eq!(
                failure_code(&reports, node.tc_apid()),
                Some(7),
                "{}",
                other.what
            );
        }
        // an accepted command's reports: on the node's APID, counted, to the ground
        let sent = ground.send(a, &Uplink::SunSafe);
        let reports = host.take(&sent.packet, a, &mut acs, None);
        assert_eq!(reports.len(), REPORTS_LEN);
        assert_eq!(failure_code(&reports, aapid), None);
        let half = REPORTS_LEN / 2;
        let first = decode_tm(&reports[..half], aapid).unwrap();
        let second = decode_tm(&reports[half..], aapid).unwrap();
        assert_eq!(
            second.header.sequence_count,
            first.header.sequence_count + 1
        );
        assert_eq!(first.header.destination_id, GROUND_SOURCE_ID);
        host.reset(a);
        let reports = host.take(&sent.packet, a, &mut acs, None);
        assert_eq!(
            decode_tm(&reports[..half], aapid)
                .unwrap()
                .header
                .sequence_count,
            0
        );
        assert_eq!(describe_reports(&[], aapid), "none");
        assert_eq!(describe_reports(&[1, 2, 3], aapid), "(undecodable)");
    }

    /// The PIL run's non-finite uplinks are each refused by the reference node (invalid
    /// argument, or the element set at its first bad word), with or without an attitude to
    /// plan from, and by the attitude node as not its own (but the element set, which does
    /// not fit its mailbox); they change nothing.
    #[test]
    fn non_finite_uplinks_are_refused() {
        let mut acs = HostLoop::new(&CONFIG, orbit()).unwrap();
        let start = Epoch::<Utc>::from_parts(9_210, 43_200, 0).unwrap();
        acs.reference_node_mut().set_clock(start);
        let guidance = *acs.guidance();
        let mut ground = GroundStation::default();
        let mut host = HostTelecommands::default();
        let q = Quaternion::new_normalize(0.9, 0.1, -0.3, 0.2).unwrap();
        let uplinks = crate::host::sim::pil::non_finite_uplinks(&orbit().to_words());
        assert_eq!(uplinks.len(), 7);
        for u in &uplinks {
            for attitude in [None, Some(&q)] {
                let sent = ground.send(Node::Reference, u);
                let reports = host.take(&sent.packet, Node::Reference, &mut acs, attitude);
                let code = failure_code(&reports, REFERENCE_TC_APID).unwrap_or(0);
                assert!(code == 0x102 || code >= 0x200, "{u:?}: code {code:#x}");
                if u.kind() != kind::ELEMENTS {
                    let sent = ground.send(Node::Attitude, u);
                    let reports = host.take(&sent.packet, Node::Attitude, &mut acs, attitude);
                    assert_eq!(failure_code(&reports, ATTITUDE_TC_APID), Some(0x104));
                }
                assert_eq!(acs.mode(), Mode::Detumble, "{u:?}");
                assert_eq!(*acs.guidance(), guidance, "{u:?}");
                assert_eq!(acs.reference_node_mut().clock(), Some(start));
            }
        }
    }
}
