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

use crate::acs_loop::{Command, Mode};
use crate::attitude::Quaternion;
use crate::flight::{FIELD_COEFFS, TILES};
use crate::orbit::sgp4::ELEMENT_WORDS;
use crate::time::{Epoch, Utc};
use crate::two_node::TwoNodeLoop;
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

/// Uplink status: accepted.
pub const ACCEPTED: u16 = 0;

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

    /// The `UPLINK_KIND` code.
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

    /// The argument words written to the start of `UPLINK_ARGS` (the rest is left as it was).
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
            Self::MarkFailed(tile) | Self::Restore(tile) => vec![*tile],
        }
    }
}

/// The host's copy of the uplink mailbox and the image's decoding of it.
#[derive(Clone, Debug)]
pub struct UplinkMailbox {
    args: [u32; ELEMENT_WORDS],
}

impl Default for UplinkMailbox {
    fn default() -> Self {
        Self {
            args: [0; ELEMENT_WORDS],
        }
    }
}

impl UplinkMailbox {
    /// Writes `uplink`'s arguments as the ground does; returns its kind.
    pub fn write(&mut self, uplink: &Uplink) -> u16 {
        for (slot, w) in self.args.iter_mut().zip(uplink.args()) {
            *slot = w;
        }
        uplink.kind()
    }

    /// Applies command `kind` with the mailbox's arguments to `node` of the host composition,
    /// as that node's image does: [`crate::uplink::apply_reference`] (a slew planned from
    /// `attitude`, the attitude of the STATUS the reference image holds when it takes the
    /// uplink) or [`crate::uplink::apply_attitude`]; returns the status the image writes to
    /// `UPLINK_STATUS`.
    pub fn take(
        &self,
        kind: u16,
        node: Node,
        acs: &mut HostLoop<'_>,
        attitude: Option<&Quaternion>,
    ) -> u16 {
        match node {
            Node::Reference => uplink::status(&uplink::apply_reference(
                kind,
                &self.args,
                acs.reference_node_mut(),
                attitude,
            )),
            Node::Attitude => uplink::status(&uplink::apply_attitude(
                kind,
                &self.args,
                acs.attitude_node_mut(),
            )),
        }
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
        assert_eq!(Uplink::MarkFailed(2).args(), vec![2]);
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

    #[test]
    fn the_mirror_applies_commands_as_the_node_images() {
        let mut acs = HostLoop::new(&CONFIG, orbit()).unwrap();
        let mut reference = UplinkMailbox::default();
        let mut attitude = UplinkMailbox::default();
        let r = Node::Reference;
        let a = Node::Attitude;

        let t = Epoch::<Utc>::from_parts(9_300, 7, 0).unwrap();
        let kind = reference.write(&Uplink::Clock(t));
        assert_eq!(reference.take(kind, r, &mut acs, None), ACCEPTED);
        assert_eq!(acs.reference_node_mut().clock(), Some(t));
        // the other node's command is refused with status 4
        assert_eq!(attitude.take(kind, a, &mut acs, None), 4);

        let q = Quaternion::new_normalize(0.9, 0.1, -0.3, 0.2).unwrap();
        let kind = reference.write(&Uplink::Track { target: q });
        assert_eq!(reference.take(kind, r, &mut acs, None), ACCEPTED);
        // the target as the image decodes it: normalised again
        let decoded = Quaternion::new_normalize(q.q0, q.q1, q.q2, q.q3).unwrap();
        assert_eq!(acs.guidance().target, decoded);

        // a slew needs an attitude to plan from
        let kind = reference.write(&Uplink::of_command(&Command::Slew {
            target: Dcm::a1(0.5),
            within_s: 100.0,
        }));
        assert_eq!(reference.take(kind, r, &mut acs, None), 3);
        assert_eq!(reference.take(kind, r, &mut acs, Some(&q)), ACCEPTED);

        // a zero quaternion is invalid; a corrupt element set names its word
        let kind = reference.write(&Uplink::Track {
            target: Quaternion {
                q0: 0.0,
                q1: 0.0,
                q2: 0.0,
                q3: 0.0,
            },
        });
        assert_eq!(reference.take(kind, r, &mut acs, None), 2);
        let mut words = orbit().to_words();
        let kind = reference.write(&Uplink::Elements(Box::new(words)));
        assert_eq!(reference.take(kind, r, &mut acs, None), ACCEPTED);
        words[ELEMENT_WORDS - 1] ^= 1;
        let kind = reference.write(&Uplink::Elements(Box::new(words)));
        assert_eq!(
            reference.take(kind, r, &mut acs, None),
            0x100 + (ELEMENT_WORDS as u16 - 1)
        );
        // the attitude node's mailbox has its own argument words: word 0 is still 0 there
        assert_eq!(
            attitude.take(kind::MARK_FAILED, a, &mut acs, None),
            ACCEPTED
        );
        assert_eq!(acs.tile_state(0), Some(crate::tiles::TileState::Failed));
        let kind = attitude.write(&Uplink::Restore(0));
        assert_eq!(attitude.take(kind, a, &mut acs, None), ACCEPTED);
        let kind = attitude.write(&Uplink::MarkFailed(TILES as u32));
        assert_eq!(attitude.take(kind, a, &mut acs, None), 2);
        assert_eq!(attitude.take(99, a, &mut acs, None), 1);
        assert_eq!(reference.take(99, r, &mut acs, None), 1);
        let kind = attitude.write(&Uplink::SunSafe);
        assert_eq!(attitude.take(kind, a, &mut acs, None), ACCEPTED);
        assert_eq!(acs.mode(), Mode::SunSafe);
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
        let mut mailbox = UplinkMailbox::default();
        let q = Quaternion::new_normalize(0.9, 0.1, -0.3, 0.2).unwrap();
        let uplinks = crate::host::sim::pil::non_finite_uplinks(&orbit().to_words());
        assert_eq!(uplinks.len(), 7);
        for u in &uplinks {
            for attitude in [None, Some(&q)] {
                let kind = mailbox.write(u);
                let status = mailbox.take(kind, Node::Reference, &mut acs, attitude);
                assert!(status == 2 || status >= 0x100, "{u:?}: status {status}");
                assert_eq!(mailbox.take(kind, Node::Attitude, &mut acs, attitude), 4);
                assert_eq!(acs.mode(), Mode::Detumble, "{u:?}");
                assert_eq!(*acs.guidance(), guidance, "{u:?}");
                assert_eq!(acs.reference_node_mut().clock(), Some(start));
            }
        }
    }
}
