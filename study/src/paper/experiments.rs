//! The registry of the paper's experiments: which schemes, which masses, which horizons, and
//! what each run records. Everything else (runs, figures, tables, claims) iterates over it.

use super::Config;
use massredist::mass::MassKind;
use massredist::scene::{Column, SchemeSpec};
use massredist::schemes::{Beta, Restitution};
use serde::Serialize;

/// The standard mass and the paper's three redistributions (§3).
pub fn masses() -> Vec<MassKind> {
    vec![MassKind::Standard, MassKind::Mod1, MassKind::Mod2, MassKind::Mod3]
}

/// The four time schemes of the paper's experiments: the one list of the paper's schemes, each
/// mapped to its [`SchemeSpec`] (the bench's `scheme_cases` is built from it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum Experiment {
    CrankNicolson,
    BackwardEuler,
    PaoliSchatzman,
    Hybrid,
}

impl Experiment {
    pub const ALL: [Experiment; 4] =
        [Experiment::CrankNicolson, Experiment::BackwardEuler, Experiment::PaoliSchatzman, Experiment::Hybrid];

    /// The scheme as the paper runs it: Crank–Nicolson is Newmark (β, γ) = (¼, ½) on the full
    /// system (§4.2.1); Paoli–Schatzman has (β, e) = (¼, 1) (§4.2.3).
    pub fn spec(self) -> SchemeSpec {
        match self {
            Experiment::CrankNicolson => SchemeSpec::CRANK_NICOLSON,
            Experiment::BackwardEuler => SchemeSpec::BackwardEuler,
            Experiment::PaoliSchatzman => {
                SchemeSpec::PaoliSchatzman { beta: Beta::new(0.25), restitution: Restitution::new(1.0) }
            }
            Experiment::Hybrid => SchemeSpec::Hybrid,
        }
    }

    /// File-name part (the scene's `scheme.kind`).
    pub fn slug(self) -> &'static str {
        self.spec().name()
    }

    /// Name in tables and titles.
    pub fn title(self) -> &'static str {
        match self {
            Experiment::CrankNicolson => "Crank–Nicolson",
            Experiment::BackwardEuler => "backward Euler",
            Experiment::PaoliSchatzman => "Paoli–Schatzman (β=1/4, e=1)",
            Experiment::Hybrid => "hybrid",
        }
    }

    /// The paper's (solution, energy) figure numbers.
    pub fn paper_figures(self) -> (u32, u32) {
        match self {
            Experiment::CrankNicolson => (11, 12),
            Experiment::BackwardEuler => (21, 22),
            Experiment::PaoliSchatzman => (31, 32),
            Experiment::Hybrid => (34, 35),
        }
    }

    /// Whether the scheme is second order in time (the paper's "second order schemes", §5).
    pub fn second_order(self) -> bool {
        matches!(self, Experiment::CrankNicolson | Experiment::PaoliSchatzman)
    }

    /// Whether the scheme is defined only for a massless contact node (w_0 = 0): the hybrid
    /// scheme (§5).
    pub fn needs_massless(self) -> bool {
        self == Experiment::Hybrid
    }

    /// The masses of the paper's figures: all of [`masses`], or only those with w_0 = 0 where the
    /// scheme needs them.
    pub fn masses(self) -> Vec<MassKind> {
        masses().into_iter().filter(|m| !self.needs_massless() || massless_contact(m)).collect()
    }
}

/// Whether the mass has w_0 = 0 (the paper's redistributions), i.e. a massless contact node.
pub(super) fn massless_contact(mass: &MassKind) -> bool {
    !matches!(mass, MassKind::Standard)
}

/// Which output a case feeds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Purpose {
    /// The solution and energy figures (u_0, λ, energy every step) and the horizon's table.
    Figures,
    /// The long energy run (raw energy at [`Config::long_every`], per-period extremes) and its
    /// table.
    LongEnergy,
}

/// One run: a scheme, a mass, a horizon, and what to record.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Case {
    pub experiment: Experiment,
    /// Written by its name in `summaries.json` (`"mass": "mod3"`).
    #[serde(serialize_with = "mass_name")]
    pub mass: MassKind,
    pub end: f64,
    pub purpose: Purpose,
}

fn mass_name<S: serde::Serializer>(mass: &MassKind, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(mass.name())
}

impl Case {
    /// The series columns its figures plot (u_0 and λ for the solution figure, energy for both
    /// energy figures); the exact curves are drawn from [`massredist::exact::ImpactingBar`] directly.
    pub fn columns(&self) -> Vec<Column> {
        match self.purpose {
            Purpose::Figures => vec![Column::U0, Column::Lambda, Column::Energy],
            Purpose::LongEnergy => vec![Column::Energy],
        }
    }

    pub fn name(&self) -> String {
        format!("{} / {} / T = {}", self.experiment.slug(), self.mass.name(), self.end)
    }
}

/// Every run of [`Config`]: for each horizon, each scheme with each of its masses; then
/// Paoli–Schatzman with every mass over each of `long_ends` (the w_0 = 0 masses the paper asks
/// about, and the standard mass for comparison).
pub fn cases(config: &Config) -> Vec<Case> {
    let mut out = Vec::new();
    for &end in &config.horizons {
        for e in Experiment::ALL {
            for mass in e.masses() {
                out.push(Case { experiment: e, mass, end, purpose: Purpose::Figures });
            }
        }
    }
    let e = Experiment::PaoliSchatzman;
    for &end in &config.long_ends {
        for mass in e.masses() {
            out.push(Case { experiment: e, mass, end, purpose: Purpose::LongEnergy });
        }
    }
    out
}
