//! Test models, one file each: a problem, its exact or reference solution, and the tolerance a
//! run of it is held to, with the reason beside the number. Tests, `benches/`, `bench` and
//! `reproduce` take their problems from here (the model of *diffsol*'s
//! `ode_equations/test_models/`, whose problems come with their solutions).
//!
//! - [`PaperBar`]: the paper's benchmark (§6), exact solution in closed form.
//! - [`ReboundBar`]: a free bar thrown at the obstacle; exact impact, contact time, force and
//!   departure velocity from the wave equation.
//! - [`PaperPlate`], [`PlaneWaveSolid`]: the paper's data on a Q1 plate or solid, which steps as
//!   the paper's bar to round-off ([`RoundOffGrowth`]).
//! - [`TwoBars`]: two bars meeting end to end (issue 30), exact by d'Alembert: contact
//!   duration, force and final momenta, for a free, a clamped and a longer target.
//! - [`PlateBump`]: y-dependent data on a plate (the contact state varies along Γ_C); no exact
//!   solution, its reference is the schemes' energy identities ([`PlateBump::ENERGY_ROUND_OFF`]).

mod paper_bar;
mod plane_wave_solid;
mod plate_bump;
mod rebound_bar;
mod two_bars;

pub use paper_bar::{PaperBar, PaperPlate, RoundOffGrowth};
pub use plane_wave_solid::PlaneWaveSolid;
pub use plate_bump::PlateBump;
pub use rebound_bar::{ReboundBar, ReboundExact};
pub use two_bars::{Case as TwoBarCase, TwoBarErrors, TwoBarSeries, TwoBars};
