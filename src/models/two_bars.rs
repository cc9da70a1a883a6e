//! Two bars meeting end to end (issue 30's d'Alembert checks): 2D strips (plane strain, λ = 0,
//! free lateral faces: a 1D wave of speed c = √(2μ/ρ)), the same material and section, so the
//! same impedance Z = ρ c A (A the strip's height, per unit depth). The striker (0 < x + L₁ < L₁)
//! flies at V onto the target (0 < x < L₂), touching it at t = 0. Exact (d'Alembert):
//!
//! - (a) [`Case::Free`], L₁ = L₂ = L: contact lasts 2L/c at the force Z V/2; the velocities swap
//!   (the striker stops, the target leaves at V);
//! - (b) [`Case::Clamped`], L₁ = L₂ = L, the target clamped at x = L (Code_Aster SDNL111):
//!   contact lasts 4L/c at Z V/2; the striker leaves at −V, the target ends at rest;
//! - (c) [`Case::Short`], L₂ = 2 L₁: contact 2L₁/c at Z V/2, the striker stops (the ends then
//!   stay touching with zero force until 2L₂/c: the release is read off the force).
//!
//! A run is measured off its pair's force and its bodies' momenta ([`TwoBarErrors`]): the
//! duration between the crossings of Z V/4 (half the force, linear between samples), the mean
//! force over the middle half of the exact window, the final momenta against the exact ones
//! (relative to the total ρ A L₁ V), and the peak over Z V/2.

use crate::observe::Column;
use crate::run::run_scene;
use crate::scene::SolidScene;

/// Which of the three set-ups (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Case {
    Free,
    Clamped,
    Short,
}

impl Case {
    pub const ALL: [Case; 3] = [Case::Free, Case::Clamped, Case::Short];

    pub fn name(self) -> &'static str {
        match self {
            Case::Free => "(a) onto a free bar",
            Case::Clamped => "(b) onto a clamped bar",
            Case::Short => "(c) shorter striker",
        }
    }
}

/// Two bars of one material (λ = 0, μ, ρ) and height `height`, `n` cells per unit length,
/// one cell across, the striker of length 1 at speed `speed`.
#[derive(Debug, Clone, PartialEq)]
pub struct TwoBars {
    pub case: Case,
    pub n: usize,
    pub height: f64,
    pub mu: f64,
    pub density: f64,
    pub speed: f64,
}

/// The errors of a run against the exact events (module docs), relative.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoBarErrors {
    /// |D − D_exact| / D_exact, D between the half-force crossings.
    pub duration: f64,
    /// |mean force − Z V/2| / (Z V/2) over the middle half of the exact window.
    pub plateau: f64,
    /// max over the two bodies of |P_final − P_exact| / (ρ A L₁ V).
    pub momentum: f64,
    /// max force / (Z V/2).
    pub peak: f64,
    /// The summary's `contact_time` of the pair (read off the force).
    pub contact_time: f64,
}

impl TwoBars {
    /// Case `case` at `n` cells per unit length with the data: height 0.1, μ = ½, ρ = 1
    /// (c = 1, Z = 0.1), V = 1.
    pub fn new(case: Case, n: usize) -> Self {
        TwoBars { case, n, height: 0.1, mu: 0.5, density: 1.0, speed: 1.0 }
    }

    pub fn wave_speed(&self) -> f64 {
        (2.0 * self.mu / self.density).sqrt()
    }

    /// The target's length (the striker's is 1).
    pub fn target_length(&self) -> f64 {
        if self.case == Case::Short { 2.0 } else { 1.0 }
    }

    /// Z V / 2.
    pub fn force(&self) -> f64 {
        self.density * self.wave_speed() * self.height * self.speed / 2.0
    }

    /// The exact contact duration.
    pub fn duration(&self) -> f64 {
        let c = self.wave_speed();
        if self.case == Case::Clamped { 4.0 / c } else { 2.0 / c }
    }

    /// The exact final momenta (striker, target).
    pub fn final_momenta(&self) -> (f64, f64) {
        let p = self.density * self.height * self.speed;
        match self.case {
            Case::Free | Case::Short => (0.0, p),
            Case::Clamped => (-p, 0.0),
        }
    }

    /// The end of a run: one duration after the exact release.
    pub fn end(&self) -> f64 {
        2.0 * self.duration() + 1.0
    }

    /// The scene's text with `mass` (a `mass.kind`), `scheme` (a `scheme.kind`), the
    /// `[contact]` table `contact` (its header and lines, or empty), Δt = `dt`, and `tail`
    /// appended to the striker's velocity expression (a perturbation, or empty).
    pub fn text(&self, mass: &str, scheme: &str, contact: &str, dt: f64, tail: &str) -> String {
        let (n, h, l2) = (self.n, self.height, self.target_length());
        let clamped = if self.case == Case::Clamped { "clamped = \"xmax\"\n" } else { "" };
        let material = format!("lame_lambda = 0.0\nlame_mu = {}\ndensity = {}", self.mu, self.density);
        format!(
            "[[solid]]\nname = \"striker\"\nlength = 1.0\nheight = {h}\nnx = {n}\nny = 1\n{material}\n\
             offset = [-1.0, 0.0]\ninitial = {{ velocity = [\"{}{tail}\", \"0\"] }}\n\
             [[solid]]\nname = \"target\"\nlength = {l2}\nheight = {h}\nnx = {}\nny = 1\n{material}\n{clamped}\
             [[pair]]\nname = \"impact\"\nbodies = [\"striker\", \"target\"]\ngroups = [\"xmax\", \"xmin\"]\n\
             [mass]\nkind = \"{mass}\"\n[scheme]\nkind = \"{scheme}\"\n{contact}\
             [time]\ndt = {dt}\nend = {}\n\
             [output]\nseries = [\"impact.contact_force\", \"striker.momentum_x\", \"target.momentum_x\", \"momentum_x\", \"energy\"]\ndivergence_factor = 1e300\n",
            crate::spec::short(self.speed),
            (n as f64 * l2).round() as usize,
            self.end()
        )
    }

    /// The scene (module docs) with Δt = h/c (cΔt/h = 1).
    pub fn scene(&self, mass: &str, scheme: &str) -> SolidScene {
        let dt = 1.0 / (self.n as f64 * self.wave_speed());
        SolidScene::from_toml(&self.text(mass, scheme, "", dt, "")).expect("the two-bar scene is valid")
    }

    /// Runs `scene` and measures it (module docs); also the series (t, force, total momentum).
    pub fn measure(&self, scene: &SolidScene) -> (TwoBarErrors, TwoBarSeries) {
        let run = run_scene(scene, &mut []).expect("the two-bar run");
        let s = &run.series;
        let named = |name: &str| {
            let c = *s.columns.iter().find(|c| c.name() == name).expect("a recorded column");
            s.column(c).expect("recorded")
        };
        let (t, force) = (s.times(), named("impact.contact_force"));
        let (striker, target) = (named("striker.momentum_x"), named("target.momentum_x"));
        let total = s.column(Column::Momentum(0)).expect("recorded");
        let energy = s.column(Column::Energy).expect("recorded");
        let f = self.force();
        let half = 0.5 * f;
        let crossing = |from: usize, up: bool| -> Option<(usize, f64)> {
            let k = (from.max(1)..force.len()).find(|&k| if up { force[k] >= half } else { force[k] < half })?;
            let (f0, f1) = (force[k - 1], force[k]);
            Some((k, t[k - 1] + (half - f0) / (f1 - f0) * (t[k] - t[k - 1])))
        };
        let duration = match crossing(1, true).and_then(|(k, rise)| crossing(k + 1, false).map(|(_, fall)| fall - rise))
        {
            Some(d) => (d - self.duration()).abs() / self.duration(),
            None => f64::INFINITY,
        };
        let window = self.duration();
        let middle: Vec<f64> = t
            .iter()
            .zip(&force)
            .filter(|(t, _)| (0.25 * window..=0.75 * window).contains(*t))
            .map(|(_, f)| *f)
            .collect();
        let plateau = (middle.iter().sum::<f64>() / middle.len() as f64 - f).abs() / f;
        let p = self.density * self.height * self.speed;
        let (ps, pt) = self.final_momenta();
        let momentum = ((striker[striker.len() - 1] - ps).abs()).max((target[target.len() - 1] - pt).abs()) / p;
        let peak = force.iter().fold(0.0f64, |m, &x| m.max(x)) / f;
        let summary = &run.summary;
        let contact_time = summary
            .own
            .get("pairs")
            .and_then(|p| p.get("impact"))
            .and_then(|p| p.get("contact_time"))
            .and_then(serde_json::Value::as_f64)
            .unwrap_or(f64::NAN);
        let errors = TwoBarErrors { duration, plateau, momentum, peak, contact_time };
        (errors, TwoBarSeries { t, force, total, energy })
    }
}

/// A run's series: t, the pair's force, the total momentum, the energy.
#[derive(Debug, Clone, PartialEq)]
pub struct TwoBarSeries {
    pub t: Vec<f64>,
    pub force: Vec<f64>,
    pub total: Vec<f64>,
    pub energy: Vec<f64>,
}
