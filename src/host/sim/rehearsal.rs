//! Rehearsing an operation (issue 31, item 5): `acs sim SCENARIO --tc SCRIPT --tm FILE` flies
//! a time-tagged telecommand script ([`parse_script`]) with the scenario and records every
//! packet the nodes send (the verification reports, the events and the housekeeping), in the
//! simulator ([`fly`]) and in the two-node processor-in-the-loop run ([`super::pil`]) with the
//! same bytes.
//!
//! # The schedule: [`Operations`]
//! Both runs take their telecommands from one schedule, period by period ([`Operations::due`]):
//! 1. at the first period, the scenario's element set ([`Sgp4::to_words`] of its TLE, function
//!    4) and its start as the clock (function 5), both to the reference node;
//! 2. each of the scenario's own commands (`commands` of a scenario file) at the first period
//!    that starts at or after its time, to the node that owns it ([`super::pil::owner`]);
//! 3. each of the script's packets at the first period that starts at or after its time, in the
//!    order of their times (the file's order for equal times), to the node of its APID: 0x051
//!    the reference node, 0x050 the attitude node, and any other APID (or a packet too short
//!    to hold one) the attitude node, which refuses it with failure code 4 (another node's
//!    APID) or the code of what is wrong first (1: too short).
//!
//! The schedule's own telecommands (1 and 2) are TC\[8,1\] with both reports asked for, source
//! ID 1, sequence counts 0, 1, 2, … in the order sent ([`Uplink::telecommand`]); the script's
//! packets go exactly as written.
//!
//! # The host run: [`fly`]
//! The packets are taken on the host composition of the two nodes
//! ([`crate::two_node::TwoNodeLoop`] over the flight configuration, [`super::pil::HostLoop`]) as the
//! node images take them ([`Mirror`]: [`super::pil::uplink::Ground::take`], each node with its own
//! count of reports, a slew planned from the attitude of the STATUS the reference node received
//! the period before), and the composition is stepped as the images step
//! ([`crate::two_node::TwoNodeLoop::step_over_link`], every packet delivered; the reference
//! node's clock the one the ground set), and after each step the nodes' telemetry is made as
//! the images make it ([`Mirror::telemetry`]). So the packets are the ones the images send, and
//! the processor-in-the-loop run of the same scenario and script writes the same bytes. A plain
//! `acs sim` (no script) flies [`super::scenarios::Scenario::run`] instead: commands given to
//! the loop directly, without telecommands.

use super::pil::uplink::{tc_bytes, Ground, Uplink};
use super::pil::{owner, HostLoop, Node};
use super::scenarios::{Satellite, Scenario};
use super::{Sample, SimError};
use crate::acs_loop::StepReport;
use crate::attitude::Quaternion;
use crate::flight::{CONFIG, CONTROL_PERIOD_S, TILES};
use crate::link::messages::REFERENCE_TC_APID;
use crate::link::pus::TC_OVERHEAD;
use crate::orbit::sgp4::{Sgp4, ELEMENT_WORDS};

/// One packet of a telecommand script.
#[derive(Clone, Debug, PartialEq)]
pub struct ScriptPacket {
    /// The script's line (1 first).
    pub line: usize,
    /// When to send it: seconds since the scenario's start.
    pub t_s: f64,
    /// The packet's bytes.
    pub packet: Vec<u8>,
}

/// The node a packet goes to: the reference node for APID 0x051, the attitude node for any
/// other (it refuses a packet that is not its own).
pub fn node_of(packet: &[u8]) -> Node {
    match packet {
        [a, b, ..] if u16::from_be_bytes([*a, *b]) & 0x07FF == REFERENCE_TC_APID.get() => {
            Node::Reference
        }
        _ => Node::Attitude,
    }
}

/// The function ID of a telecommand (its command code), 0 if the packet is too short to hold
/// one; only to name the packet.
pub fn function_id(packet: &[u8]) -> u16 {
    // after the primary (6 B) and TC secondary (5 B) headers
    let at = TC_OVERHEAD - 2;
    packet
        .get(at..at + 2)
        .map_or(0, |f| u16::from_be_bytes([f[0], f[1]]))
}

/// Reads a telecommand script: one packet a line, `SECONDS PACKET_HEX` (the time since the
/// scenario's start, finite and not negative; the packet as `acs tc` prints it, one byte or
/// more, at most as long as the ground mailbox of the node it goes to: 248 B for the reference
/// node, 36 B for the attitude node); blank lines and lines starting with `#` are ignored.
/// The error names the line.
pub fn parse_script(text: &str) -> Result<Vec<ScriptPacket>, String> {
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let l = raw.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = l.split_whitespace().collect();
        let [time, hex] = fields.as_slice() else {
            return Err(format!(
                "line {line}: expected `SECONDS PACKET_HEX`, found {} field(s)",
                fields.len()
            ));
        };
        let t_s: f64 = time
            .parse()
            .map_err(|_| format!("line {line}: time `{time}` is not a number of seconds"))?;
        if !t_s.is_finite() || t_s < 0.0 {
            return Err(format!(
                "line {line}: time `{time}` is not a finite, non-negative number of seconds"
            ));
        }
        let packet = decode_hex(hex).map_err(|m| format!("line {line}: packet: {m}"))?;
        let node = node_of(&packet);
        if packet.len() > tc_bytes(node) {
            return Err(format!(
                "line {line}: a packet of {} B for the {} node does not fit its telecommand \
                 mailbox ({} B)",
                packet.len(),
                node.name(),
                tc_bytes(node)
            ));
        }
        out.push(ScriptPacket { line, t_s, packet });
    }
    Ok(out)
}

fn decode_hex(hex: &str) -> Result<Vec<u8>, String> {
    if let Some((i, c)) = hex
        .chars()
        .enumerate()
        .find(|(_, c)| !c.is_ascii_hexdigit())
    {
        return Err(format!("`{c}` at character {} is not a hex digit", i + 1));
    }
    if !hex.len().is_multiple_of(2) {
        return Err(format!("an odd number of hex digits ({})", hex.len()));
    }
    Ok(hex
        .as_bytes()
        .chunks_exact(2)
        .map(|p| {
            let d = |c: u8| (c as char).to_digit(16).unwrap_or(0) as u8;
            d(p[0]) << 4 | d(p[1])
        })
        .collect())
}

/// A telecommand of the schedule: the node it goes to, its command code (to name it) and the
/// packet.
#[derive(Clone, Debug, PartialEq)]
pub struct Telecommand {
    /// The node whose ground mailbox it goes to.
    pub node: Node,
    /// Its function ID ([`function_id`]).
    pub kind: u16,
    /// The packet.
    pub packet: Vec<u8>,
}

/// The schedule of a run's telecommands (see the [module docs](self)), which the host run
/// ([`fly`]) and the processor-in-the-loop run ([`super::pil::run`]) both follow.
#[derive(Clone, Debug)]
pub struct Operations {
    /// The element set and the clock, for the first period.
    first: Vec<Uplink>,
    /// The scenario's commands not yet sent, with their times.
    commands: Vec<(f64, Uplink)>,
    /// The script's packets not yet sent, in the order of their times.
    script: Vec<ScriptPacket>,
    /// The ground's sequence count of its own telecommands.
    count: u16,
}

impl Operations {
    /// The schedule of `scenario` with the element set `words` (its TLE's) and the packets of
    /// `script`. A script packet after the start of the scenario's last period is refused,
    /// naming its line (it would never be sent).
    pub fn new(
        scenario: &Scenario,
        words: &[u32; ELEMENT_WORDS],
        script: &[ScriptPacket],
    ) -> Result<Self, String> {
        let steps = (scenario.duration_s / scenario.dt_s).round() as usize;
        let last = steps.saturating_sub(1) as f64 * scenario.dt_s;
        if let Some(p) = script.iter().find(|p| p.t_s > last) {
            return Err(format!(
                "line {}: time {} s is after the start of the scenario's last period ({last} s)",
                p.line, p.t_s
            ));
        }
        let mut script = script.to_vec();
        script.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
        Ok(Self {
            first: vec![
                Uplink::Elements(Box::new(*words)),
                Uplink::Clock(scenario.sim.start),
            ],
            commands: scenario
                .commands
                .iter()
                .map(|(t, c)| (*t, Uplink::of_command(c)))
                .collect(),
            script,
            count: 0,
        })
    }

    /// `u` as the ground's telecommand to `node`, with the ground's next sequence count.
    pub fn telecommand(&mut self, u: &Uplink, node: Node) -> Telecommand {
        let packet = u.telecommand(node, self.count);
        self.count = self.count.wrapping_add(1);
        Telecommand {
            node,
            kind: u.kind(),
            packet,
        }
    }

    /// The telecommands of period `k`, which starts `t_s` after the scenario's start, in the
    /// order they are sent: the element set and the clock at period 0, then the scenario's
    /// commands due (time ≤ `t_s`), then the script's packets due.
    pub fn due(&mut self, k: usize, t_s: f64) -> Vec<Telecommand> {
        let mut out = Vec::new();
        let mut uplinks = if k == 0 {
            std::mem::take(&mut self.first)
        } else {
            Vec::new()
        };
        let mut i = 0;
        while i < self.commands.len() {
            if self.commands[i].0 <= t_s {
                uplinks.push(self.commands.remove(i).1);
            } else {
                i += 1;
            }
        }
        for u in &uplinks {
            out.push(self.telecommand(u, owner(u.kind())));
        }
        let n = self.script.iter().take_while(|p| p.t_s <= t_s).count();
        out.extend(self.script.drain(..n).map(|p| Telecommand {
            node: node_of(&p.packet),
            kind: function_id(&p.packet),
            packet: p.packet,
        }));
        out
    }
}

/// The host's copies of the two nodes' ground mailboxes ([`Ground`]), taking a period's
/// telecommands on the host composition as the images take them.
#[derive(Clone, Debug, Default)]
pub struct Mirror {
    grounds: [Ground; 2],
    /// The attitude of the STATUS the reference node received the period before: what the
    /// reference image plans a slew from ([`super::pil`]).
    held_attitude: Option<Quaternion>,
}

impl Mirror {
    /// Takes the telecommands `tcs` of a period, before the period's step, on `acs`; the
    /// reports of each, in order.
    pub fn period(&mut self, acs: &mut HostLoop<'_>, tcs: &[Telecommand]) -> Vec<Vec<u8>> {
        let slew_from = self.held_attitude;
        self.held_attitude = acs.last_status().and_then(|s| s.attitude);
        tcs.iter()
            .map(|tc| {
                let (ground, attitude) = match tc.node {
                    Node::Reference => (&mut self.grounds[0], slew_from.as_ref()),
                    Node::Attitude => (&mut self.grounds[1], None),
                };
                ground.take(&tc.packet, tc.node, acs, attitude)
            })
            .collect()
    }

    /// The two nodes' telemetry after the period's step on `acs` (its report `report`), as
    /// the images send it ([`Ground::telemetry`]): the reference node's packets, then the
    /// attitude node's. `status_received` is what the reference node made of the STATUS of
    /// the step before ([`crate::two_node::TwoNodeLoop::received`] before the step), `tcs` the
    /// period's telecommands.
    pub fn telemetry(
        &mut self,
        acs: &mut HostLoop<'_>,
        report: &StepReport,
        status_received: Option<bool>,
        tcs: &[Telecommand],
    ) -> [Vec<Vec<u8>>; 2] {
        let took = tcs.iter().any(|tc| tc.node == Node::Reference);
        let [reference, attitude] = &mut self.grounds;
        let ref_received = acs.received()[0];
        [
            reference.telemetry(Node::Reference, acs, report, status_received, took),
            attitude.telemetry(Node::Attitude, acs, report, ref_received, false),
        ]
    }

    /// A power-on reset of the reference node: its count of reports starts again.
    pub fn reset_reference(&mut self) {
        self.grounds[0] = Ground::default();
    }
}

/// The element words of `scenario`'s TLE (SGP4 initialised on the ground) and the orbit the
/// nodes propagate from them; an error if the scenario does not fly the flight configuration
/// (its period, its tiles), which the node images fly.
pub fn flight_orbit(scenario: &Scenario) -> Result<([u32; ELEMENT_WORDS], Sgp4), String> {
    if scenario.dt_s != f64::from(CONTROL_PERIOD_S) || !matches!(scenario.flight, Satellite::Flight)
    {
        return Err(format!(
            "scenario `{}`: not the flight configuration (control period {} s; the nodes fly \
             {CONTROL_PERIOD_S} s)",
            scenario.name, scenario.dt_s
        ));
    }
    if scenario.sim.tiles.len() != TILES {
        return Err(format!(
            "scenario `{}`: {} tiles, the nodes fly {TILES}",
            scenario.name,
            scenario.sim.tiles.len()
        ));
    }
    let tle = crate::tle::Tle::parse(&scenario.sim.tle.0, &scenario.sim.tle.1)
        .map_err(|e| format!("TLE: {e}"))?;
    let words = Sgp4::new(&tle, scenario.gravity)
        .map_err(|e| format!("TLE: {e:?}"))?
        .to_words();
    let orbit = Sgp4::from_words(&words).map_err(|e| format!("element words: {e:?}"))?;
    Ok((words, orbit))
}

/// Why a rehearsal could not be flown.
#[derive(Debug)]
pub enum RehearsalError {
    /// The scenario or the script cannot be flown (the message names the line).
    Input(String),
    /// The simulator failed.
    Sim(SimError),
}

impl std::fmt::Display for RehearsalError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Input(m) => f.write_str(m),
            Self::Sim(e) => write!(f, "simulator: {e}"),
        }
    }
}

/// A rehearsal flown on the host.
#[derive(Clone, Debug)]
pub struct Rehearsal {
    /// The truth and the composition's report of every step.
    pub samples: Vec<Sample>,
    /// Every telecommand sent, in order, with its period.
    pub sent: Vec<(usize, Telecommand)>,
    /// The verification reports of each telecommand of `sent`.
    pub reports: Vec<Vec<u8>>,
    /// Each period's telemetry packets after its step: the reference node's, then the
    /// attitude node's ([`Mirror::telemetry`]).
    pub downlinked: Vec<Vec<Vec<u8>>>,
}

impl Rehearsal {
    /// Every packet, back to back (`acs tm` reads it): period by period, the verification
    /// reports of its telecommands in the order sent, then its telemetry.
    pub fn telemetry(&self) -> Vec<u8> {
        let mut out = Vec::new();
        let mut reports = self.sent.iter().zip(&self.reports).peekable();
        for (k, packets) in self.downlinked.iter().enumerate() {
            while let Some((_, r)) = reports.next_if(|((at, _), _)| *at == k) {
                out.extend_from_slice(r);
            }
            for p in packets {
                out.extend_from_slice(p);
            }
        }
        out
    }
}

/// Flies `scenario` with the telecommands of `script` on the host composition of the two
/// nodes (see the [module docs](self)).
pub fn fly(scenario: &Scenario, script: &[ScriptPacket]) -> Result<Rehearsal, RehearsalError> {
    let (words, orbit) = flight_orbit(scenario).map_err(RehearsalError::Input)?;
    let mut ops = Operations::new(scenario, &words, script).map_err(RehearsalError::Input)?;
    let mut acs = HostLoop::new(&CONFIG, orbit)
        .map_err(|e| RehearsalError::Input(format!("flight configuration: {e}")))?;
    let mut sim = scenario.simulator().map_err(RehearsalError::Sim)?;
    let steps = (scenario.duration_s / scenario.dt_s).round() as usize;
    let mut mirror = Mirror::default();
    let mut report = StepReport::empty(acs.mode());
    let mut out = Rehearsal {
        samples: Vec::with_capacity(steps),
        sent: Vec::new(),
        reports: Vec::new(),
        downlinked: Vec::with_capacity(steps),
    };
    for k in 0..steps {
        let t = sim.truth().t_s;
        let tcs = ops.due(k, t);
        out.reports.extend(mirror.period(&mut acs, &tcs));
        let status_received = acs.received()[1];
        acs.step_over_link(&mut sim, CONTROL_PERIOD_S, &mut report, |_, _| true);
        let [r, a] = mirror.telemetry(&mut acs, &report, status_received, &tcs);
        out.downlinked.push(r.into_iter().chain(a).collect());
        out.sent.extend(tcs.into_iter().map(|tc| (k, tc)));
        out.samples
            .push(Sample::of_step(&sim, t, report, scenario.target));
        sim.advance(scenario.dt_s).map_err(RehearsalError::Sim)?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::uplink::kind;

    /// The schedule of `slew` (its track at 1 s, its slew at 120 s) with a script: the element
    /// set and the clock first, then the scenario's commands, then the script's packets, in
    /// the order of their times; the ground's own counted 0, 1, 2, …
    #[test]
    fn the_schedule_sends_the_scenarios_then_the_scripts() {
        let scenario = crate::host::sim::scenarios::slew().unwrap();
        let (words, _) = flight_orbit(&scenario).unwrap();
        let sun_safe = Uplink::SunSafe.telecommand(Node::Attitude, 40);
        let track = Uplink::Track {
            target: Quaternion::IDENTITY,
        }
        .telecommand(Node::Reference, 41);
        let script = parse_script(&format!(
            "120 {}\n0.5 {}\n1 0852\n",
            hex(&sun_safe),
            hex(&track)
        ))
        .unwrap();
        let mut ops = Operations::new(&scenario, &words, &script).unwrap();
        let seen = |tcs: Vec<Telecommand>| -> Vec<(Node, u16, u16)> {
            tcs.iter()
                .map(|tc| {
                    // a packet too short for a count: 0
                    let count = tc
                        .packet
                        .get(2..4)
                        .map_or(0, |c| u16::from_be_bytes([c[0], c[1]]) & 0x3FFF);
                    (tc.node, tc.kind, count)
                })
                .collect()
        };
        let (r, a) = (Node::Reference, Node::Attitude);
        assert_eq!(
            seen(ops.due(0, 0.0)),
            [(r, kind::ELEMENTS, 0), (r, kind::CLOCK, 1)]
        );
        assert_eq!(
            seen(ops.due(1, 1.0)),
            [(r, kind::TRACK, 2), (r, 2, 41), (a, 0, 0)]
        );
        assert!(ops.due(2, 2.0).is_empty());
        assert_eq!(
            seen(ops.due(120, 120.0)),
            [(r, kind::SLEW, 3), (a, kind::SUN_SAFE, 40)]
        );
        assert!(ops.due(121, 121.0).is_empty());
        // a packet after the start of the last period (1 199 s) is refused, naming its line
        let late = parse_script(&format!("1199 {}\n1199.5 {}", hex(&track), hex(&track))).unwrap();
        let e = Operations::new(&scenario, &words, &late).unwrap_err();
        assert!(e.starts_with("line 2: time 1199.5 s is after"), "{e}");
    }

    fn hex(bytes: &[u8]) -> String {
        bytes.iter().map(|b| format!("{b:02x}")).collect()
    }

    #[test]
    fn a_script_is_read_line_by_line() {
        let s = parse_script("# clock\n\n  5 0851c000000d2\n").unwrap_err();
        assert!(s.starts_with("line 3: packet: an odd number"), "{s}");
        let s = parse_script("# x\n1.5 1851C0 \n 0 0850\n").unwrap();
        assert_eq!(
            s,
            vec![
                ScriptPacket {
                    line: 2,
                    t_s: 1.5,
                    packet: vec![0x18, 0x51, 0xc0]
                },
                ScriptPacket {
                    line: 3,
                    t_s: 0.0,
                    packet: vec![0x08, 0x50]
                }
            ]
        );
        assert_eq!(node_of(&s[0].packet), Node::Reference);
        assert_eq!(node_of(&s[1].packet), Node::Attitude);
        assert_eq!(node_of(&[0x18, 0x52]), Node::Attitude);
        assert_eq!(node_of(&[0x08]), Node::Attitude);
        for (text, want) in [
            ("1", "line 1: expected"),
            ("1 00 00", "line 1: expected `SECONDS PACKET_HEX`, found 3"),
            ("x 00", "line 1: time `x`"),
            ("-1 00", "line 1: time `-1` is not a finite"),
            ("NaN 00", "line 1: time `NaN` is not a finite"),
            ("inf 00", "line 1: time `inf` is not a finite"),
            ("1 0g", "line 1: packet: `g` at character 2"),
            ("1 é0", "line 1: packet: `é` at character 1"),
        ] {
            let e = parse_script(text).unwrap_err();
            assert!(e.starts_with(want), "{text}: {e}");
        }
        let long = format!("0 0850{}", "00".repeat(35));
        let e = parse_script(&long).unwrap_err();
        assert!(
            e.contains("37 B for the attitude node does not fit its telecommand mailbox (36 B)"),
            "{e}"
        );
    }
}
