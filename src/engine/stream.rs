//! The engine's stream: what the FEniCSx process sends for each state it computes, and the
//! observers and divergence rule of a Rust run fed with it (the engine streams, Rust observes).
//!
//! Protocol (python/engine/stream.py is the other end). Rank 0 of the engine writes one record
//! per line to its standard output, each line `@massredist/1 ` followed by a JSON object; every
//! other byte the engine's processes print goes to standard error (the engine points its file
//! descriptor 1 there), and a line without the prefix is passed through to this process's
//! standard error. The records:
//!
//! - `{"kind": "head", h, total_mass, unknowns, load_energy}`: the engine's own problem (its mesh
//!   size, `∫ ρ w_h`, unknowns, `E_F` of [`crate::driver::DivergenceCriterion`]), once, first;
//! - `{"kind": "sample", n, t, energy, u0, u_mean, contact_force, pressure, y_variation,
//!   l2_error, exact_interp_norm, iterations, min_u, max_lambda, max_product, touching}`: state
//!   n, every step from t_0 on, values reduced over the ranks (the fields of
//!   [`crate::driver::Sample`]; `iterations` are the step's solver iterations, reported as its
//!   pivots), after which the engine waits for the reply `go` or `stop` on its standard input;
//! - `{"kind": "non-finite", n, t}`: the step to n gave a non-finite state; the engine stops.
//!
//! Numbers are JSON numbers written by Python's `repr` (shortest round-trip) and read with
//! serde_json's `float_roundtrip`, so no digit is lost; a non-finite number is the string
//! `"nan"`, `"inf"` or `"-inf"`. Standard output and input are what every MPI launcher forwards
//! from rank 0 to the launching process (mpirun, srun), also across the nodes of a cluster.

use crate::column::Column;
use crate::driver::ContactStats;
use crate::driver::{Divergence, DivergenceReason, DivergenceWatch, Observer, Sample, Verdict};
use crate::exact::Exact;
use crate::problem::{GeometryView, OwnSummary};
use crate::schemes::StateView;
use serde::Deserialize;

/// The prefix of a protocol line (its version is the number).
pub const PREFIX: &str = "@massredist/1 ";

/// A JSON number, or one of the strings `"nan"`, `"inf"`, `"-inf"` (JSON has no non-finite
/// numbers).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Num(f64);

impl<'de> Deserialize<'de> for Num {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Either {
            Number(f64),
            Text(String),
        }
        match Either::deserialize(d)? {
            Either::Number(x) => Ok(Num(x)),
            Either::Text(s) => match s.as_str() {
                "nan" => Ok(Num(f64::NAN)),
                "inf" => Ok(Num(f64::INFINITY)),
                "-inf" => Ok(Num(f64::NEG_INFINITY)),
                _ => Err(serde::de::Error::custom(format!("{s:?} is not a number (nan, inf, -inf)"))),
            },
        }
    }
}

/// What the engine computed of its own problem (the `head` record).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Head {
    /// Mesh size along x.
    pub h: f64,
    /// `∫ ρ w_h` (per component).
    pub total_mass: f64,
    /// Unknowns (free components).
    pub unknowns: usize,
    /// `E_F = ½ F_rᵀ S_rr⁻¹ F_r`, 0 without load.
    pub load_energy: f64,
}

/// One state as the engine streams it: the scalar fields of a [`Sample`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Record {
    pub n: usize,
    pub t: f64,
    pub energy: f64,
    pub u0: f64,
    pub u_mean: f64,
    pub contact_force: f64,
    pub pressure: f64,
    pub y_variation: f64,
    pub l2_error: f64,
    pub exact_interp_norm: f64,
    /// The step's solver iterations (SNES), in the place of a Rust run's pivots.
    pub iterations: usize,
    pub contact: ContactStats,
    /// A body's reports (world components; `crate::solid::report::COLUMNS` order), absent
    /// for the other geometries.
    pub body: Option<[f64; 9]>,
}

/// One protocol record.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Message {
    Head(Head),
    Sample(Record),
    /// The step to state n gave a non-finite state (not shown).
    NonFinite {
        n: usize,
        t: f64,
    },
}

#[derive(Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
enum Wire {
    Head {
        h: Num,
        total_mass: Num,
        unknowns: usize,
        load_energy: Num,
    },
    Sample {
        n: usize,
        t: Num,
        energy: Num,
        u0: Num,
        u_mean: Num,
        contact_force: Num,
        pressure: Num,
        y_variation: Num,
        l2_error: Num,
        exact_interp_norm: Num,
        iterations: usize,
        min_u: Num,
        max_lambda: Num,
        max_product: Num,
        touching: bool,
        #[serde(default)]
        body: Option<WireBody>,
    },
    NonFinite {
        n: usize,
        t: Num,
    },
}

/// A body's reports in a `sample` record: `{contact_force, active, min_distance, momentum,
/// mean_u}` (the last two: 3 world components).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct WireBody {
    contact_force: Num,
    active: usize,
    min_distance: Num,
    momentum: [Num; 3],
    mean_u: [Num; 3],
}

/// Parses one line of the engine's standard output: None if it is not a protocol line (it is
/// then passed through), else the record or why it is malformed.
pub fn parse(line: &str) -> Option<Result<Message, String>> {
    let json = line.strip_prefix(PREFIX)?;
    let wire: Wire = match serde_json::from_str(json.trim_end()) {
        Ok(w) => w,
        Err(e) => return Some(Err(format!("malformed engine record ({e}): {}", line.trim_end()))),
    };
    Some(Ok(match wire {
        Wire::Head { h, total_mass, unknowns, load_energy } => {
            Message::Head(Head { h: h.0, total_mass: total_mass.0, unknowns, load_energy: load_energy.0 })
        }
        Wire::Sample {
            n,
            t,
            energy,
            u0,
            u_mean,
            contact_force,
            pressure,
            y_variation,
            l2_error,
            exact_interp_norm,
            iterations,
            min_u,
            max_lambda,
            max_product,
            touching,
            body,
        } => Message::Sample(Record {
            n,
            t: t.0,
            energy: energy.0,
            u0: u0.0,
            u_mean: u_mean.0,
            contact_force: contact_force.0,
            pressure: pressure.0,
            y_variation: y_variation.0,
            l2_error: l2_error.0,
            exact_interp_norm: exact_interp_norm.0,
            iterations,
            contact: ContactStats { min_u: min_u.0, max_lambda: max_lambda.0, max_product: max_product.0, touching },
            body: body.map(|b| {
                let (momentum, mean_u) = (b.momentum.map(|x| x.0), b.mean_u.map(|x| x.0));
                crate::solid::report::values(b.contact_force.0, b.active, b.min_distance.0, momentum, mean_u)
            }),
        }),
        Wire::NonFinite { n, t } => Message::NonFinite { n, t: t.0 },
    }))
}

/// The geometry of a run whose state lives in the engine: the measures the observers read (from
/// the scene and the engine's head record), and no unknowns on this side (the contact set is
/// empty; the field methods give NaN or nothing: the engine computes u0, the means, the L² error
/// and the y-variation itself and streams them).
#[derive(Debug, Clone, PartialEq)]
pub struct StreamedGeometry {
    pub name: &'static str,
    pub dim: usize,
    pub h: f64,
    pub length: f64,
    /// `|Ω|/L` (= `|Γ_C|` for these prisms).
    pub section: f64,
    /// Whether the engine integrates the exact L² error (structured tensor cells, and plates).
    pub integrates: bool,
    /// Whether the scene is a body against a plane (its summary keys: `crate::solid::report`).
    pub is_body: bool,
    /// A solid: its summary has the friction keys (0 and empty: the engine is frictionless).
    pub tangential: bool,
    /// A body's reports of the state being shown (set by [`Observed::show`] on its copy;
    /// `crate::solid::report::COLUMNS` order).
    pub body: Option<[f64; 9]>,
}

impl GeometryView for StreamedGeometry {
    fn name(&self) -> &'static str {
        self.name
    }
    fn dim(&self) -> usize {
        self.dim
    }
    fn has_tangential(&self) -> bool {
        self.tangential
    }
    fn h(&self) -> f64 {
        self.h
    }
    fn length(&self) -> f64 {
        self.length
    }
    fn section(&self) -> f64 {
        self.section
    }
    fn contact_measure(&self) -> f64 {
        self.section
    }
    fn contact(&self) -> &[usize] {
        &[]
    }
    fn contact_mean(&self, _u: &[f64]) -> f64 {
        f64::NAN
    }
    fn u0(&self, _u: &[f64]) -> f64 {
        f64::NAN
    }
    fn l2_error(&self, _u: &[f64], _exact: &Exact, _t: f64) -> f64 {
        f64::NAN
    }
    fn integrates(&self, _exact: &Exact) -> bool {
        self.integrates
    }
    fn interp_norm(&self, _exact: &Exact, _t: f64, _scratch: &mut Vec<f64>) -> f64 {
        f64::NAN
    }
    fn n_nodes(&self) -> usize {
        0
    }
    fn nodal_values(&self, _u: &[f64], _out: &mut [f64]) {}
    /// A body's columns, when the engine streamed them for the state being shown.
    fn own_columns(&self) -> &[Column] {
        if self.body.is_some() { &crate::solid::report::COLUMNS } else { &[] }
    }
    fn own_values(&self, _u: &[f64], _v: &[f64], _lambda: &[f64], out: &mut [f64]) {
        if let Some(b) = &self.body {
            out.copy_from_slice(b);
        }
    }
    fn own_summary(&self) -> Option<Box<dyn OwnSummary>> {
        self.is_body.then(|| Box::new(crate::solid::report::BodyKeys::new(self.dim)) as Box<dyn OwnSummary>)
    }
}

/// The reply to a `sample` record (python/engine/stream.py).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reply {
    /// The state was shown; go on.
    Go,
    /// The state was shown and is the last one (a divergence, or an observer halted).
    Last,
    /// The state was not shown (its energy is not finite); stop.
    Hide,
}

impl Reply {
    /// The line sent to the engine.
    pub fn line(self) -> &'static [u8] {
        match self {
            Reply::Go => b"go\n",
            Reply::Last => b"last\n",
            Reply::Hide => b"hide\n",
        }
    }
}

/// The observers of a run fed with streamed records: the same cadence as
/// [`crate::driver::integrate_watched`] (observer k sees the states n with n % every_k == 0,
/// t_0 included) and the same [`DivergenceWatch`].
pub struct Observed<'a> {
    observers: &'a mut [&'a mut dyn Observer],
    cadence: Vec<usize>,
    watch: DivergenceWatch,
    geometry: &'a StreamedGeometry,
    exact: Option<&'a Exact>,
    divergence: Option<Divergence>,
}

impl<'a> Observed<'a> {
    pub fn new(
        observers: &'a mut [&'a mut dyn Observer],
        watch: DivergenceWatch,
        geometry: &'a StreamedGeometry,
        exact: Option<&'a Exact>,
    ) -> Self {
        let cadence = observers.iter().map(|o| o.every().max(1)).collect();
        Self { observers, cadence, watch, geometry, exact, divergence: None }
    }

    /// Shows a record to the observers due at its step, as the driver shows a state; returns
    /// the reply to the engine.
    pub fn show(&mut self, r: &Record) -> Reply {
        let verdict = self.watch.judge(r.n, r.t, r.energy);
        if let Verdict::Hidden(d) = verdict {
            self.divergence = Some(d);
            return Reply::Hide;
        }
        let geometry = StreamedGeometry { body: r.body, ..self.geometry.clone() };
        let state = StateView { n: r.n, t: r.t, u: &[], v: &[], lambda: &[] };
        let sample = Sample {
            state,
            geometry: &geometry,
            exact: self.exact,
            energy: r.energy,
            l2_error: r.l2_error,
            exact_interp_norm: r.exact_interp_norm,
            u0: r.u0,
            u_mean: r.u_mean,
            contact_force: r.contact_force,
            pressure: r.pressure,
            y_variation: r.y_variation,
            pivots: r.iterations,
            contact: r.contact,
            friction: None,
        };
        for (o, &every) in self.observers.iter_mut().zip(&self.cadence) {
            if r.n.is_multiple_of(every) {
                o.observe(&sample);
            }
        }
        if let Verdict::Last(d) = verdict {
            self.divergence = Some(d);
            return Reply::Last;
        }
        // A halted observer (a full disk) reports its own error; no step more is computed.
        if self.observers.iter().any(|o| o.halted()) { Reply::Last } else { Reply::Go }
    }

    /// The engine's step to state n gave a non-finite state.
    pub fn non_finite(&mut self, n: usize, t: f64) {
        self.divergence = Some(Divergence { step: n, time: t, reason: DivergenceReason::NonFiniteState });
    }

    /// Ends the run: tells the observers of a divergence; returns it.
    pub fn finish(self) -> Option<Divergence> {
        if let Some(d) = &self.divergence {
            for o in self.observers.iter_mut() {
                o.diverged(d);
            }
        }
        self.divergence
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_round_trip_every_digit_and_non_finite_numbers() {
        // Python's repr of these floats (shortest round-trip), as the engine writes them.
        let line = format!(
            "{PREFIX}{{\"kind\": \"sample\", \"n\": 3, \"t\": 0.15000000000000002, \"energy\": \"inf\", \
             \"u0\": -1.2345678901234567e-17, \"u_mean\": 0.1, \"contact_force\": -0.0, \"pressure\": \"nan\", \
             \"y_variation\": 5e-324, \"l2_error\": 1.7976931348623157e+308, \"exact_interp_norm\": \"-inf\", \
             \"iterations\": 2, \"min_u\": 0.30000000000000004, \"max_lambda\": -2.5, \"max_product\": 0.0, \
             \"touching\": true}}\n"
        );
        let Some(Ok(Message::Sample(r))) = parse(&line) else { panic!("{:?}", parse(&line)) };
        assert_eq!(r.t, 0.15000000000000002);
        assert_eq!(r.t, 3.0 * 0.05);
        assert_eq!(r.energy, f64::INFINITY);
        assert_eq!(r.u0, -1.2345678901234567e-17);
        assert!(r.contact_force == 0.0 && r.contact_force.is_sign_negative());
        assert!(r.pressure.is_nan());
        assert_eq!(r.y_variation, f64::from_bits(1));
        assert_eq!(r.l2_error, f64::MAX);
        assert_eq!(r.exact_interp_norm, f64::NEG_INFINITY);
        assert_eq!(r.contact.min_u, 0.1 + 0.2);
        assert!(r.contact.touching && r.iterations == 2 && r.n == 3);
    }

    #[test]
    fn other_lines_pass_through_and_bad_records_are_named() {
        assert!(parse("a line the engine printed\n").is_none());
        let bad = format!("{PREFIX}{{\"kind\": \"sample\", \"n\": 1}}");
        let e = parse(&bad).unwrap().unwrap_err();
        assert!(e.contains("missing field") && e.contains("malformed engine record"), "{e}");
        let word = format!("{PREFIX}{{\"kind\": \"non-finite\", \"n\": 1, \"t\": \"big\"}}");
        assert!(parse(&word).unwrap().unwrap_err().contains("is not a number"));
    }

    /// 10⁴ bit patterns (xorshift, seed 1), written as shortest round-trip decimals: each reads
    /// back to the same bits (serde_json's `float_roundtrip`, through the untagged [`Num`]).
    // mutation: `serde_json = { version = ... }` without `features = ["float_roundtrip"]` in
    //   Cargo.toml -> fails: 1.3086802819600499e-231 reads back 1 ulp off (and 0.15000000000000002
    //   in the test above).
    #[test]
    fn ten_thousand_random_numbers_round_trip() {
        let mut x: u64 = 1;
        for _ in 0..10_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let v = f64::from_bits(x);
            if !v.is_finite() {
                continue;
            }
            let line = format!("{PREFIX}{{\"kind\": \"non-finite\", \"n\": 0, \"t\": {v:?}}}");
            let Some(Ok(Message::NonFinite { t, .. })) = parse(&line) else { panic!("{line}") };
            assert_eq!(t.to_bits(), v.to_bits(), "{line}");
        }
    }
}
