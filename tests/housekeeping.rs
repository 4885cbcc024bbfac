//! The nodes' telemetry as PUS packets (`acs::telemetry`; issue 31 item 3): the housekeeping
//! reports TM\[3,25\] of both nodes written by our code from a flown two-node loop and read
//! back by the `spacepackets` crate (CRC checked), field by field against the nodes' state and
//! against the parameter tables the ground uses; the events TM\[5,x\] of every fault bit raised
//! and cleared and of a mode change; the housekeeping command accepted and refused on both
//! nodes, directly and as a telecommand.

use acs::acs_loop::{Mode, StepReport};
use acs::attitude_node::AttitudeNode;
use acs::flight::{FlightLoop, CONFIG, FIELD_COEFFS, TILES};
use acs::host::sim::faults::Fault;
use acs::host::sim::scenarios;
use acs::link::messages::{Reference, ATTITUDE_TC_APID, REFERENCE_TC_APID};
use acs::link::pus::{encode_tc, tm_packet_len, AckFlags, CucTime, TcHeader, TmHeader, TIME_LEN};
use acs::link::sequence::SequenceCounter;
use acs::link::space_packet::Apid;
use acs::reference_node::ReferenceNode;
use acs::telemetry::{
    attitude_data_len, attitude_report, events, reference_report, write_events, Downlink,
    Housekeeping, LinkCounts, Parameter, ParameterType, State, ATTITUDE_PARAMETERS,
    ATTITUDE_STRUCTURE, DEFAULT_INTERVAL, EVENT_REPORT_LEN, FAULT_EVENT, MAX_EVENTS, MAX_INTERVAL,
    MODE_CHANGED, REFERENCE_DATA_LEN, REFERENCE_PARAMETERS, REFERENCE_REPORT_LEN,
    REFERENCE_STRUCTURE,
};
use acs::uplink::telecommand::{cuc, take, REPORTS_LEN, SERVICE, SUBTYPE};
use acs::uplink::{apply, apply_attitude, apply_reference, kind, UplinkError, ARG_WORDS};
use spacepackets::ecss::tm::{GenericPusTmSecondaryHeader, PusTmReader};
use spacepackets::ecss::PusPacket;
use spacepackets::CcsdsPacket;

fn header(apid: Apid, count: u16) -> TmHeader {
    TmHeader {
        apid,
        sequence_count: count,
        time_status: 1,
        message_counter: 0,
        destination_id: 0,
        time: CucTime {
            seconds: 812_345_678,
            fraction: 0x4000,
        },
    }
}

/// The parameters of `table` read from `data` (after the structure ID): name (`NAME_k` for
/// element k of several) and value as `u64` bits.
fn read(table: &[Parameter], data: &[u8]) -> Vec<(String, u64)> {
    let mut out = vec![];
    let mut at = 0;
    for p in table {
        for k in 0..p.count {
            let n = p.ty.bytes();
            let v = data[at..at + n]
                .iter()
                .fold(0u64, |v, b| (v << 8) | u64::from(*b));
            let name = if p.count == 1 {
                p.name.to_string()
            } else {
                format!("{}_{k}", p.name)
            };
            out.push((name, v));
            at += n;
        }
    }
    assert_eq!(at, data.len(), "the table covers the structure");
    out
}

fn f(x: f32) -> u64 {
    u64::from(x.to_bits())
}

/// A flown two-node loop: the tracking scenario, `TRACK` at 1 s, tile 2 dead from 20 s.
fn flown() -> (FlightLoop, StepReport) {
    let sc = scenarios::tracking(None).expect("scenario");
    let mut sim = sc.simulator().expect("simulator");
    sim.inject(Fault::DeadTile { tile: 2 }, 20.0, 1e9);
    let mut acs = FlightLoop::new(&CONFIG, sc.orbit().expect("orbit")).expect("loop");
    let mut clock = sim.epoch_at(0.0);
    let target = sc.target.expect("target");
    let mut last = StepReport::empty(acs.mode());
    for k in 0..30 {
        if k == 1 {
            let mut w = [0u32; ARG_WORDS];
            for (o, x) in w.iter_mut().zip(target) {
                *o = (x as f32).to_bits();
            }
            assert_eq!(apply(kind::TRACK, &w, &mut acs, &mut clock, None), Ok(()));
        }
        let t = sim.truth().t_s;
        let now = sim.epoch_at(t);
        last = acs.step(&mut sim, now, 1.0);
        sim.advance(1.0).expect("advance");
    }
    (acs, last)
}

#[test]
fn attitude_report_decodes_field_by_field() {
    let (mut acs, report) = flown();
    assert!(report.attitude.is_some() && report.omega_body_radps.is_some());
    let link = LinkCounts {
        received: 28,
        refused: 1,
        missed: 2,
    };
    let node = acs.attitude_node_mut();
    node.housekeeping_mut().set_interval(7);
    let mut out = vec![0u8; 400];
    let n = attitude_report(
        &header(ATTITUDE_TC_APID, 77),
        node,
        &report,
        &link,
        &mut out,
    )
    .expect("written");
    assert_eq!(n, tm_packet_len(attitude_data_len(TILES)));
    assert_eq!(n, 169);
    let r = PusTmReader::new(&out[..n], TIME_LEN).expect("spacepackets reads it, CRC checked");
    assert_eq!(r.apid().value(), ATTITUDE_TC_APID.get());
    assert_eq!(r.seq_count().value(), 77);
    assert_eq!(
        (
            PusPacket::service_type_id(&r),
            PusPacket::message_subtype_id(&r)
        ),
        (3, 25)
    );
    assert_eq!(r.sc_time_ref_status().value(), 1);
    assert_eq!(r.timestamp(), &[0x30, 0x6B, 0x69, 0x4E, 0x40, 0x00]);
    let data = r.source_data();
    assert_eq!(u16::from_be_bytes([data[0], data[1]]), ATTITUDE_STRUCTURE);
    let values = read(ATTITUDE_PARAMETERS, &data[2..]);
    let q = report.attitude.expect("attitude");
    let w = report.omega_body_radps.expect("rate");
    let var = node.filter_variances();
    let mut expected: Vec<(String, u64)> = vec![
        ("STEP".into(), 30),
        ("MODE".into(), u64::from(report.mode.code())),
        ("COILS_FAILED".into(), 0),
        ("FAULTS".into(), u64::from(report.faults.bits())),
        ("HK_INTERVAL".into(), 7),
        ("WITHOUT_REF".into(), 0),
        ("LINK_RECEIVED".into(), 28),
        ("LINK_REFUSED".into(), 1),
        ("LINK_MISSED".into(), 2),
    ];
    for (k, x) in [q.q0, q.q1, q.q2, q.q3].into_iter().enumerate() {
        expected.push((format!("Q_{k}"), f(x)));
    }
    for (k, x) in w.iter().enumerate() {
        expected.push((format!("RATE_{k}"), f(*x)));
    }
    for (k, x) in var.iter().enumerate() {
        expected.push((format!("VARIANCE_{k}"), f(*x)));
    }
    for (k, x) in report.dipole_body_am2.iter().enumerate() {
        expected.push((format!("DIPOLE_{k}"), f(*x)));
    }
    for i in 0..TILES {
        expected.push((format!("TILE_STATE_{i}"), u64::from(node.part_states()[i])));
    }
    for i in 0..TILES {
        expected.push((format!("TILE_ERROR_{i}"), u64::from(node.part_errors()[i])));
    }
    for i in 0..TILES {
        expected.push((format!("WHEEL_CMD_{i}"), f(node.wheels_commanded()[i])));
    }
    for i in 0..TILES {
        expected.push((
            format!("WHEEL_READ_{i}"),
            u64::from(node.health().wheel_reads()[i] as u16),
        ));
    }
    assert_eq!(values, expected);
    // the dead tile: out of service, its error a device absent; the others none
    assert_eq!(node.part_states()[2] & 1, 1);
    assert_eq!(
        node.part_errors()[2] & 0x0F,
        1,
        "{:#x}",
        node.part_errors()[2]
    );
    assert!(node.part_errors()[2] >> 4 != 0);
    for i in [0, 1, 3, 4, 5] {
        assert_eq!(node.part_states()[i] & 1, 0, "tile {i}");
    }
    // the variances are the filter's: finite, the attitude's positive
    assert!(var.iter().all(|v| v.is_finite()) && var[0] > 0.0);
    // too small a buffer: refused, untouched
    let mut small = vec![0u8; n - 1];
    assert!(attitude_report(
        &header(ATTITUDE_TC_APID, 1),
        node,
        &report,
        &link,
        &mut small
    )
    .is_err());
    assert!(small.iter().all(|b| *b == 0));
}

#[test]
fn attitude_report_without_a_filter_sends_nan() {
    let node = AttitudeNode::<TILES>::new(&CONFIG).expect("node");
    let report = StepReport::empty(Mode::Detumble);
    let mut out = [0u8; 169];
    let n = attitude_report(
        &header(ATTITUDE_TC_APID, 0),
        &node,
        &report,
        &LinkCounts::default(),
        &mut out,
    )
    .expect("written");
    let r = PusTmReader::new(&out[..n], TIME_LEN).expect("reads");
    let values = read(ATTITUDE_PARAMETERS, &r.source_data()[2..]);
    let get = |name: &str| values.iter().find(|(n, _)| n == name).expect(name).1;
    for name in ["Q_0", "Q_3", "RATE_1", "VARIANCE_0", "VARIANCE_9"] {
        assert_eq!(get(name), 0x7FC0_0000, "{name}");
    }
    assert_eq!(get("HK_INTERVAL"), u64::from(DEFAULT_INTERVAL));
    assert_eq!(get("WHEEL_READ_0"), 0x8000, "no read-back yet");
}

#[test]
fn reference_report_decodes_field_by_field() {
    let (mut acs, _) = flown();
    let (ref_packet, _) = acs.packets();
    let (reference, _) = Reference::from_packet(ref_packet).expect("the last REF");
    assert!(reference.clock_valid && reference.elements_valid);
    let link = LinkCounts {
        received: 29,
        refused: 0,
        missed: 1,
    };
    let node = acs.reference_node_mut();
    let mut out = [0u8; REFERENCE_REPORT_LEN];
    let n = reference_report(
        &header(REFERENCE_TC_APID, 5),
        node,
        &reference,
        &link,
        &mut out,
    )
    .expect("written");
    assert_eq!(n, REFERENCE_REPORT_LEN);
    assert_eq!(n, 66);
    let r = PusTmReader::new(&out[..n], TIME_LEN).expect("spacepackets reads it, CRC checked");
    assert_eq!(r.apid().value(), REFERENCE_TC_APID.get());
    assert_eq!(
        (
            PusPacket::service_type_id(&r),
            PusPacket::message_subtype_id(&r)
        ),
        (3, 25)
    );
    let data = r.source_data();
    assert_eq!(data.len(), REFERENCE_DATA_LEN);
    assert_eq!(u16::from_be_bytes([data[0], data[1]]), REFERENCE_STRUCTURE);
    let values = read(REFERENCE_PARAMETERS, &data[2..]);
    let (clock, _) = cuc(Some(reference.utc));
    let (epoch, _) = cuc(node.elements_epoch());
    assert!(epoch.seconds > 0);
    let shadow = match reference.illumination.map(|i| i.shadow) {
        None => 0,
        Some(acs::env::eclipse::Shadow::Sunlit) => 1,
        Some(acs::env::eclipse::Shadow::Penumbra) => 2,
        Some(acs::env::eclipse::Shadow::Umbra) => 3,
        Some(acs::env::eclipse::Shadow::Antumbra) => 4,
    };
    let g = &reference.guidance;
    assert_eq!(g.kind, acs::link::messages::GuidanceKind::Track);
    let mut expected: Vec<(String, u64)> = vec![
        ("CLOCK_SECONDS".into(), u64::from(clock.seconds)),
        ("CLOCK_FRACTION".into(), u64::from(clock.fraction)),
        ("FLAGS".into(), 3),
        ("SHADOW".into(), shadow),
        ("FAULTS".into(), u64::from(reference.faults)),
        ("HK_INTERVAL".into(), u64::from(DEFAULT_INTERVAL)),
        ("LINK_RECEIVED".into(), 29),
        ("LINK_REFUSED".into(), 0),
        ("LINK_MISSED".into(), 1),
        ("GUIDANCE_ID".into(), u64::from(g.id)),
        ("GUIDANCE_KIND".into(), 1),
    ];
    for (k, x) in [g.target.q0, g.target.q1, g.target.q2, g.target.q3]
        .into_iter()
        .enumerate()
    {
        expected.push((format!("TARGET_{k}"), f(x)));
    }
    expected.push(("EPOCH_SECONDS".into(), u64::from(epoch.seconds)));
    expected.push(("EPOCH_FRACTION".into(), u64::from(epoch.fraction)));
    assert_eq!(values, expected);
    assert_eq!(shadow, 1, "the dawn-dusk orbit is sunlit");
}

/// Reads the event reports in `bytes` with spacepackets: (subtype, event ID, aux).
fn read_events(bytes: &[u8], apid: Apid) -> Vec<(u8, u16, [u8; 2])> {
    let mut out = vec![];
    let mut at = 0;
    while at < bytes.len() {
        let r = PusTmReader::new(&bytes[at..], TIME_LEN).expect("reads, CRC checked");
        assert_eq!(r.apid().value(), apid.get());
        assert_eq!(PusPacket::service_type_id(&r), 5);
        let d = r.source_data();
        assert_eq!(d.len(), 4);
        out.push((
            PusPacket::message_subtype_id(&r),
            u16::from_be_bytes([d[0], d[1]]),
            [d[2], d[3]],
        ));
        at += r.len_packed();
        assert_eq!(r.len_packed(), EVENT_REPORT_LEN);
    }
    out
}

#[test]
fn every_fault_bit_raised_and_cleared_is_an_event() {
    for apid in [ATTITUDE_TC_APID, REFERENCE_TC_APID] {
        for bit in 0..16u16 {
            let clear = State { mode: 3, faults: 0 };
            let raised = State {
                mode: 3,
                faults: 1 << bit,
            };
            let mut count = SequenceCounter::new();
            let mut out = [0u8; 2 * EVENT_REPORT_LEN];
            let (n, left) = write_events(&header(apid, 0), &mut count, clear, raised, &mut out);
            assert_eq!((n, left), (EVENT_REPORT_LEN, 0));
            let (m, _) = write_events(&header(apid, 0), &mut count, raised, clear, &mut out[n..]);
            assert_eq!(m, EVENT_REPORT_LEN);
            let got = read_events(&out[..n + m], apid);
            let w = (1u16 << bit).to_be_bytes();
            assert_eq!(
                got,
                vec![(2, FAULT_EVENT + bit, w), (1, FAULT_EVENT + bit, [0, 0]),],
                "bit {bit}"
            );
        }
    }
}

#[test]
fn a_mode_change_and_several_bits_in_one_step() {
    let prev = State {
        mode: 0,
        faults: 0b0000_0100_0001,
    };
    let new = State {
        mode: 1,
        faults: 0b1000_0000_0011,
    };
    let mut count = SequenceCounter::new();
    let mut out = [0u8; MAX_EVENTS * EVENT_REPORT_LEN];
    let (n, left) = write_events(
        &header(ATTITUDE_TC_APID, 0),
        &mut count,
        prev,
        new,
        &mut out,
    );
    assert_eq!(left, 0);
    let w = new.faults.to_be_bytes();
    assert_eq!(
        read_events(&out[..n], ATTITUDE_TC_APID),
        vec![
            (1, MODE_CHANGED, [0, 1]),
            (2, FAULT_EVENT + 1, w),
            (1, FAULT_EVENT + 6, w),
            (2, FAULT_EVENT + 11, w),
        ]
    );
    // the sequence counts follow on
    assert_eq!(count.next_count(), 4);
    // nothing changed: no event
    assert_eq!(events(new, new).count(), 0);
    // everything changed: MAX_EVENTS, and a short buffer says how many were left out
    let all = State {
        mode: 2,
        faults: u16::MAX,
    };
    assert_eq!(events(State::default(), all).count(), MAX_EVENTS);
    let mut short = [0u8; 3 * EVENT_REPORT_LEN + 5];
    let (n, left) = write_events(
        &header(ATTITUDE_TC_APID, 0),
        &mut SequenceCounter::new(),
        State::default(),
        all,
        &mut short,
    );
    assert_eq!((n, left), (3 * EVENT_REPORT_LEN, MAX_EVENTS - 3));
}

#[test]
fn the_flown_loop_reports_its_mode_changes() {
    let sc = scenarios::tracking(None).expect("scenario");
    let mut sim = sc.simulator().expect("simulator");
    let mut acs = FlightLoop::new(&CONFIG, sc.orbit().expect("orbit")).expect("loop");
    let mut prev = State::of_step(&StepReport::empty(acs.mode()));
    let mut modes = vec![];
    for _ in 0..10 {
        let t = sim.truth().t_s;
        let now = sim.epoch_at(t);
        let r = acs.step(&mut sim, now, 1.0);
        sim.advance(1.0).expect("advance");
        let new = State::of_step(&r);
        for e in events(prev, new) {
            if e.id == MODE_CHANGED {
                modes.push(e.aux);
            }
        }
        prev = new;
    }
    // from rest: detumble, then sun-safe
    assert_eq!(modes.first(), Some(&[0, 1]), "{modes:?}");
}

#[test]
fn the_schedule() {
    let mut h = Housekeeping::new();
    assert_eq!(h.interval(), DEFAULT_INTERVAL);
    let at: Vec<usize> = (0..25usize).filter(|_| h.due()).collect();
    assert_eq!(at, [0, 10, 20]);
    assert!(h.set_interval(1));
    assert!((0..5).all(|_| h.due()));
    assert!(h.set_interval(0));
    assert!((0..100).all(|_| !h.due()));
    assert!(!h.set_interval(u32::from(MAX_INTERVAL) + 1));
    assert_eq!(h.interval(), 0, "a refused interval changes nothing");
    assert!(h.set_interval(u32::from(MAX_INTERVAL)));
    let at: Vec<usize> = (0..8000usize).filter(|_| h.due()).collect();
    assert_eq!(at, [0, 3600, 7200]);
}

fn words(w: u32) -> [u32; ARG_WORDS] {
    let mut a = [0u32; ARG_WORDS];
    a[0] = w;
    a
}

#[test]
fn the_command_on_both_nodes() {
    let mut reference = ReferenceNode::<TILES, FIELD_COEFFS>::new(&CONFIG, None).expect("node");
    let mut attitude = AttitudeNode::<TILES>::new(&CONFIG).expect("node");
    for (periods, ok) in [
        (0, true),
        (1, true),
        (60, true),
        (3600, true),
        (3601, false),
        (65_536 + 10, false),
        (u32::MAX, false),
    ] {
        let before = (
            reference.housekeeping().interval(),
            attitude.housekeeping().interval(),
        );
        let r = apply_reference(kind::HOUSEKEEPING, &words(periods), &mut reference, None);
        let a = apply_attitude(kind::HOUSEKEEPING, &words(periods), &mut attitude);
        if ok {
            assert_eq!((r, a), (Ok(()), Ok(())), "{periods}");
            assert_eq!(u32::from(reference.housekeeping().interval()), periods);
            assert_eq!(u32::from(attitude.housekeeping().interval()), periods);
        } else {
            let e = Err(UplinkError::InvalidArgument);
            assert_eq!((r, a), (e, e), "{periods}");
            let after = (
                reference.housekeeping().interval(),
                attitude.housekeeping().interval(),
            );
            assert_eq!(after, before, "refused: unchanged");
        }
    }
    // each node keeps its own
    apply_attitude(kind::HOUSEKEEPING, &words(5), &mut attitude).expect("5");
    apply_reference(kind::HOUSEKEEPING, &words(0), &mut reference, None).expect("0");
    assert_eq!(
        (
            reference.housekeeping().interval(),
            attitude.housekeeping().interval()
        ),
        (0, 5)
    );
}

#[test]
fn the_command_as_a_telecommand() {
    for apid in [REFERENCE_TC_APID, ATTITUDE_TC_APID] {
        let mut reference = ReferenceNode::<TILES, FIELD_COEFFS>::new(&CONFIG, None).expect("node");
        let mut attitude = AttitudeNode::<TILES>::new(&CONFIG).expect("node");
        for (app, code) in [
            (vec![0, 8, 0, 0, 0, 30], None),
            (vec![0, 8, 0, 0, 0x0E, 0x11], Some(0x102u16)),
            (vec![0, 8], Some(0x105)),
            (vec![0, 8, 0, 0, 0, 1, 0, 0, 0, 1], Some(0x105)),
        ] {
            let h = TcHeader {
                apid,
                sequence_count: 3,
                ack: AckFlags::ACCEPTANCE.with(AckFlags::COMPLETION),
                service: SERVICE,
                subtype: SUBTYPE,
                source_id: 9,
            };
            let mut p = [0u8; 40];
            let len = encode_tc(&h, &app, &mut p).expect("encoded");
            let mut out = [0u8; REPORTS_LEN];
            let n = take(
                &p[..len],
                apid,
                None,
                &mut SequenceCounter::new(),
                &mut out,
                |k, a| {
                    if apid == REFERENCE_TC_APID {
                        apply_reference(k, a, &mut reference, None)
                    } else {
                        apply_attitude(k, a, &mut attitude)
                    }
                },
            );
            let r = PusTmReader::new(&out[..n], TIME_LEN).expect("reads");
            match code {
                None => {
                    assert_eq!(n, 50);
                    assert_eq!(PusPacket::message_subtype_id(&r), 1);
                }
                Some(c) => {
                    assert_eq!(PusPacket::message_subtype_id(&r), 2);
                    let d = r.source_data();
                    assert_eq!(u16::from_be_bytes([d[4], d[5]]), c);
                }
            }
        }
        let interval = if apid == REFERENCE_TC_APID {
            (
                reference.housekeeping().interval(),
                attitude.housekeeping().interval(),
            )
        } else {
            (
                attitude.housekeeping().interval(),
                reference.housekeeping().interval(),
            )
        };
        assert_eq!(interval, (30, DEFAULT_INTERVAL), "the node's own only");
    }
}

#[test]
fn the_composed_loop_sets_both_and_the_one_image_loop_refuses() {
    let sc = scenarios::tracking(None).expect("scenario");
    let mut acs = FlightLoop::new(&CONFIG, sc.orbit().expect("orbit")).expect("loop");
    let mut clock = acs::time::Epoch::DAY0;
    assert_eq!(
        apply(kind::HOUSEKEEPING, &words(42), &mut acs, &mut clock, None),
        Ok(())
    );
    assert_eq!(acs.reference_node_mut().housekeeping().interval(), 42);
    assert_eq!(acs.attitude_node_mut().housekeeping().interval(), 42);
    assert_eq!(
        apply(kind::HOUSEKEEPING, &words(3601), &mut acs, &mut clock, None),
        Err(UplinkError::InvalidArgument)
    );
    let mut one =
        acs::flight::OneImageLoop::new(&CONFIG, sc.orbit().expect("orbit")).expect("loop");
    assert_eq!(
        apply(kind::HOUSEKEEPING, &words(42), &mut one, &mut clock, None),
        Err(UplinkError::UnknownCommand(kind::HOUSEKEEPING))
    );
}

#[test]
fn the_tables_are_the_lengths() {
    let len = |t: &[Parameter]| t.iter().map(|p| p.ty.bytes() * p.count).sum::<usize>();
    assert_eq!(2 + len(ATTITUDE_PARAMETERS), attitude_data_len(TILES));
    assert_eq!(2 + len(REFERENCE_PARAMETERS), REFERENCE_DATA_LEN);
    assert!(ATTITUDE_PARAMETERS
        .iter()
        .chain(REFERENCE_PARAMETERS)
        .all(|p| p.count > 0 && !p.name.is_empty()));
    let _ = ParameterType::U8;
}

fn acs_tool(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_acs"))
        .args(args)
        .output()
        .expect("the acs binary runs")
}

/// The ground tool end to end: a flown two-node loop's housekeeping (every period) and events
/// of 60 s written as the nodes would, read by `acs tm` (its CSV, one line a packet, the report
/// column naming them) and `acs tm --out DIR` (the decoded structures, the events, the plots);
/// `acs tc housekeeping` builds the command the nodes take.
#[test]
fn acs_tm_decodes_the_housekeeping_and_plots_it() {
    let sc = scenarios::tracking(None).expect("scenario");
    let mut sim = sc.simulator().expect("simulator");
    let mut acs = FlightLoop::new(&CONFIG, sc.orbit().expect("orbit")).expect("loop");
    let mut bytes = vec![];
    let mut count = [SequenceCounter::new(), SequenceCounter::new()];
    let mut prev = [State::default(), State::default()];
    let mut packets = 0;
    for k in 0..60 {
        let t = sim.truth().t_s;
        let now = sim.epoch_at(t);
        let report = acs.step(&mut sim, now, 1.0);
        sim.advance(1.0).expect("advance");
        let (time, status) = cuc(Some(now));
        let h = |apid, n: u16| TmHeader {
            sequence_count: n,
            time_status: status,
            time,
            ..header(apid, 0)
        };
        let mut out = [0u8; 512];
        let node = acs.attitude_node_mut();
        let n = attitude_report(
            &h(ATTITUDE_TC_APID, count[0].next_count()),
            node,
            &report,
            &LinkCounts::default(),
            &mut out,
        )
        .expect("written");
        bytes.extend_from_slice(&out[..n]);
        let new = State::of_step(&report);
        let (n, _) = write_events(
            &h(ATTITUDE_TC_APID, 0),
            &mut count[0],
            prev[0],
            new,
            &mut out,
        );
        packets += 1 + n / EVENT_REPORT_LEN;
        bytes.extend_from_slice(&out[..n]);
        prev[0] = new;
        if k % 10 == 0 {
            let (ref_packet, _) = acs.packets();
            let (reference, _) = Reference::from_packet(ref_packet).expect("REF");
            let node = acs.reference_node_mut();
            let n = reference_report(
                &h(REFERENCE_TC_APID, count[1].next_count()),
                node,
                &reference,
                &LinkCounts::default(),
                &mut out,
            )
            .expect("written");
            let new = State::of_reference(&reference);
            let (head, tail) = out.split_at_mut(n);
            let (m, _) = write_events(&h(REFERENCE_TC_APID, 0), &mut count[1], prev[1], new, tail);
            bytes.extend_from_slice(head);
            bytes.extend_from_slice(&tail[..m]);
            packets += m / EVENT_REPORT_LEN;
            prev[1] = new;
            packets += 1;
        }
    }
    let dir = std::env::temp_dir().join(format!("acs-hk-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let file = dir.join("tm.bin");
    std::fs::write(&file, &bytes).expect("write");
    let out_dir = dir.join("out");
    let run = acs_tool(&[
        "tm",
        file.to_str().expect("UTF-8"),
        "--out",
        out_dir.to_str().expect("UTF-8"),
    ]);
    assert_eq!(
        run.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let csv = String::from_utf8_lossy(&run.stdout).to_string();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some(acs::host::cli::tm::HEADER));
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), packets);
    assert_eq!(
        rows.iter()
            .filter(|r| r.contains(",housekeeping attitude,"))
            .count(),
        60
    );
    assert_eq!(
        rows.iter()
            .filter(|r| r.contains(",housekeeping reference,"))
            .count(),
        6
    );
    assert!(rows.iter().any(|r| r.contains(",mode changed,")), "{csv}");
    // the decoded files
    let att = std::fs::read_to_string(out_dir.join("attitude_hk.csv")).expect("attitude_hk.csv");
    let mut att_lines = att.lines();
    let head = att_lines.next().expect("header");
    assert!(
        head.starts_with("node,apid,sequence_count,time_utc,time_s,STEP,MODE,COILS_FAILED,FAULTS,")
    );
    assert!(head.ends_with(",WHEEL_READ_5"));
    let last: Vec<&str> = att_lines.last().expect("a row").split(',').collect();
    assert_eq!(last.len(), head.split(',').count());
    assert_eq!(last[5], "60", "STEP of the last report");
    let reference = std::fs::read_to_string(out_dir.join("reference_hk.csv")).expect("ref");
    assert_eq!(reference.lines().count(), 7);
    let events = std::fs::read_to_string(out_dir.join("events.csv")).expect("events");
    assert!(
        events.lines().any(|l| l.contains("mode changed,0,1,")),
        "{events}"
    );
    for svg in ["hk_rates.svg", "hk_wheels.svg", "hk_attitude_sigma.svg"] {
        let text = std::fs::read_to_string(out_dir.join(svg)).expect(svg);
        assert!(text.starts_with("<svg") || text.contains("<svg"), "{svg}");
    }
    let _ = std::fs::remove_dir_all(&dir);
    // the command
    let tc = acs_tool(&["tc", "housekeeping", "30", "--node", "reference"]);
    assert_eq!(tc.status.code(), Some(0));
    let hex = String::from_utf8_lossy(&tc.stdout).trim().to_string();
    let p: Vec<u8> = (0..hex.len() / 2)
        .map(|i| u8::from_str_radix(&hex[2 * i..2 * i + 2], 16).expect("hex"))
        .collect();
    let mut reference = ReferenceNode::<TILES, FIELD_COEFFS>::new(&CONFIG, None).expect("node");
    let mut out = [0u8; REPORTS_LEN];
    let n = take(
        &p,
        REFERENCE_TC_APID,
        None,
        &mut SequenceCounter::new(),
        &mut out,
        |k, a| apply_reference(k, a, &mut reference, None),
    );
    assert_eq!(n, 50);
    assert_eq!(reference.housekeeping().interval(), 30);
    let refused = acs_tool(&["tc", "housekeeping", "3601", "--node", "attitude"]);
    assert_eq!(refused.status.code(), Some(2));
    let no_node = acs_tool(&["tc", "housekeeping", "30"]);
    assert_ne!(no_node.status.code(), Some(0));
}

/// The packets of a node's downlink call as (service, subtype, sequence count) with
/// spacepackets, CRC checked, and their time, the node's clock.
fn read_downlink(packets: &[Vec<u8>], apid: Apid, clock: CucTime) -> Vec<(u8, u8, u16)> {
    packets
        .iter()
        .map(|p| {
            let r = PusTmReader::new(p, TIME_LEN).expect("spacepackets reads it, CRC checked");
            assert_eq!(r.apid().value(), apid.get());
            let t = r.timestamp();
            let seconds = u32::from_be_bytes([t[0], t[1], t[2], t[3]]);
            assert_eq!(
                (seconds, u16::from_be_bytes([t[4], t[5]])),
                (clock.seconds, clock.fraction),
                "stamped with the node's clock"
            );
            (
                PusPacket::service_type_id(&r),
                PusPacket::message_subtype_id(&r),
                r.seq_count().value(),
            )
        })
        .collect()
}

#[test]
fn the_downlink_sends_the_events_then_the_housekeeping_when_due() {
    let (mut acs, report) = flown();
    assert_eq!(report.mode, Mode::Tracking);
    let reference = *acs.reference_made().expect("a REF was made");
    let received = acs.received();
    assert_eq!(received, [Some(true), Some(true)], "every packet delivered");
    // the attitude node: from reset (mode 0, no fault) to the flown step's state
    let mut downlink = Downlink::new();
    downlink.link.count(received[0]);
    let mut count = SequenceCounter::new();
    let mut sent: Vec<Vec<u8>> = Vec::new();
    let node = acs.attitude_node_mut();
    let clock = cuc(node.clock()).0;
    downlink.attitude(node, &report, &mut count, |p| sent.push(p.to_vec()));
    let new = State::of_step(&report);
    let events_expected = events(State::default(), new).count();
    assert!(events_expected >= 2, "the mode and a fault bit at least");
    let got = read_downlink(&sent, ATTITUDE_TC_APID, clock);
    assert_eq!(got.len(), events_expected + 1);
    for (i, (service, _, count)) in got.iter().enumerate() {
        let service_expected = if i < events_expected { 5 } else { 3 };
        assert_eq!((*service, *count), (service_expected, i as u16));
    }
    // the same bytes as the library's writers: the events, then the report
    let h = |n: u16| TmHeader {
        time_status: 1,
        time: clock,
        ..header(ATTITUDE_TC_APID, n)
    };
    let mut events_bytes = [0u8; MAX_EVENTS * EVENT_REPORT_LEN];
    let mut c = SequenceCounter::new();
    let (n, _) = write_events(&h(0), &mut c, State::default(), new, &mut events_bytes);
    assert_eq!(sent[..events_expected].concat(), events_bytes[..n]);
    let link = LinkCounts {
        received: 1,
        ..LinkCounts::default()
    };
    let mut out = [0u8; tm_packet_len(attitude_data_len(TILES))];
    let m = attitude_report(
        &h(events_expected as u16),
        acs.attitude_node_mut(),
        &report,
        &link,
        &mut out,
    )
    .expect("written");
    assert_eq!(sent[events_expected], out[..m]);
    // the same state again: no event, and no report before the interval is over
    for k in 1..DEFAULT_INTERVAL {
        sent.clear();
        let node = acs.attitude_node_mut();
        downlink.attitude(node, &report, &mut count, |p| sent.push(p.to_vec()));
        assert!(sent.is_empty(), "period {k}");
    }
    sent.clear();
    let node = acs.attitude_node_mut();
    downlink.attitude(node, &report, &mut count, |p| sent.push(p.to_vec()));
    assert_eq!(
        read_downlink(&sent, ATTITUDE_TC_APID, clock),
        [(3, 25, events_expected as u16 + 1)]
    );

    // the reference node: its guidance (track) a mode change, then its report
    let mut downlink = Downlink::new();
    let mut count = SequenceCounter::new();
    sent.clear();
    let node = acs.reference_node_mut();
    let clock = cuc(node.clock()).0;
    downlink.reference(node, &reference, &mut count, |p| sent.push(p.to_vec()));
    let got = read_downlink(&sent, REFERENCE_TC_APID, clock);
    let events_expected = events(State::default(), State::of_reference(&reference)).count();
    assert_eq!(got.len(), events_expected + 1);
    assert_eq!(got[0], (5, 1, 0), "the guidance kind changed: 0 → 1");
    assert_eq!(got[events_expected], (3, 25, events_expected as u16));
    assert_eq!(sent[events_expected].len(), REFERENCE_REPORT_LEN);
}
