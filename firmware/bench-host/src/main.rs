//! Prints the benchmark cases' names and host results as JSON (see `Cargo.toml`).

#[path = "../../src/elements.rs"]
mod elements;
#[cfg(feature = "group-step")]
#[path = "../../src/flight.rs"]
mod flight;
#[cfg(feature = "group-step")]
#[path = "../../src/tiles.rs"]
#[allow(dead_code)]
mod tiles;

#[path = "../../src/cases.rs"]
#[allow(dead_code)]
mod cases;

#[derive(Default)]
struct Host {
    names: Vec<&'static str>,
    results: Vec<u32>,
}

impl cases::Sink for Host {
    fn input(&mut self, x: f32) -> f32 {
        std::hint::black_box(x)
    }
    fn keep(&mut self, x: f32) -> f32 {
        x
    }
    fn begin(&mut self, name: &'static str) {
        self.names.push(name);
    }
    fn end(&mut self) {}
    fn out(&mut self, x: f32) {
        self.results.push(x.to_bits());
    }
}

fn main() {
    #[cfg(feature = "group-step")]
    {
        // the flight configuration's principal axes are those the eigen-decomposition gives
        let d = flight::INERTIA_DIAGONAL;
        let inertia = acs::linalg::Mat3::from_diagonal(&acs::linalg::Vec3::new(d[0], d[1], d[2]));
        let computed = acs::control::principal_axes::principal_axes(&inertia);
        assert_eq!(computed.ok(), Some(flight::principal_axes_of_diagonal(&d)));
        // the flight element set is the text it documents, and the ticks start at its epoch
        let parsed = acs::tle::Tle::parse(
            "1 90101U 25001A   25079.50000000  .00000000  00000-0  00000-0 0  9997",
            "2 90101  97.4000  90.0000 0001000   0.0000   0.0000 15.21936487    10",
        );
        let built = elements::flight_tle();
        let orbit = |t: &acs::tle::Tle| {
            (
                t.epoch,
                t.catalog_number,
                t.mean_motion_dot.to_bits(),
                t.bstar.to_bits(),
                t.inclination_deg.to_bits(),
                t.raan_deg.to_bits(),
                t.eccentricity.to_bits(),
                t.arg_perigee_deg.to_bits(),
                t.mean_anomaly_deg.to_bits(),
                t.mean_motion_rev_per_day.to_bits(),
            )
        };
        assert_eq!(parsed.as_ref().ok().map(orbit), built.as_ref().map(orbit));
        assert_eq!(built.map(|t| t.epoch), flight::tick_epoch(0));
    }
    let mut h = Host::default();
    cases::run(&mut h);
    let names: Vec<String> = h.names.iter().map(|n| format!("{n:?}")).collect();
    let results: Vec<String> = h.results.iter().map(|r| r.to_string()).collect();
    println!(
        "{{\"cases\": [{}], \"results\": [{}]}}",
        names.join(", "),
        results.join(", ")
    );
}
