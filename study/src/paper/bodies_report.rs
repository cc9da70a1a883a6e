//! The bodies section's outputs ([`super::bodies`]): `bodies.csv` (one row per run), the
//! figures `bodies-energy` (energy over time of the disc at rest, one panel per scheme, finest
//! mesh run) and `bodies-drop` (centre-of-mass velocity P_y/(1ᵀM1) of the dropped disc, one
//! panel per mesh), `bodies-sphere` (the dropped sphere: centre-of-mass velocity P_z/(1ᵀM1)
//! and total contact force ΣR over time, one column per mesh), `bodies-impact` (the dropped
//! disc, finest mesh, mod3, at its largest total contact force: the deformed mesh on the plane
//! and the contact pressure), and the report section. Pure: strings and figure data from the results.

use super::band::sig;
use super::bodies::{
    Bench, BodyResult, BodyScheme, COPIES, DROP_GAP, DROP_SPEED, DT, FINE_MASSES, MESHES, Metrics, PERTURBATION,
    SPHERE_DT,
};
use super::experiments::Experiment;
use super::figures::{FigureFile, grid_rows, mass_style, off_scale, points};
use super::methods::SAFETY;
use crate::plot::{self, Curve, Figure, Panel, Style};
use massredist::mass::MassKind;
use massredist::output::fmt_f64;
use std::fmt::Write as _;

/// The section's table file and figure stems.
pub const BODIES_TABLE: &str = "bodies.csv";
pub const BODIES_ENERGY: &str = "bodies-energy";
pub const BODIES_DROP: &str = "bodies-drop";
pub const BODIES_SPHERE: &str = "bodies-sphere";
pub const BODIES_IMPACT: &str = "bodies-impact";

/// Header of `bodies.csv`.
pub const BODIES_COLUMNS: [&str; 21] = [
    "bench",
    "h",
    "scheme",
    "mass",
    "end",
    "dt",
    "stable_step",
    "stable_step_method",
    "unknowns",
    "layer_mass_fraction",
    "energy_drift",
    "max_energy_deviation",
    "max_energy_increase",
    "contact_force_variation",
    "contact_episodes",
    "min_distance",
    "max_contact_force",
    "first_impact_time",
    "first_release_time",
    "contact_duration",
    "rebound_velocity",
];

fn bench_name(b: Bench) -> &'static str {
    match b {
        Bench::Rest => "rest",
        Bench::Drop => "drop",
        Bench::Sphere => "sphere",
    }
}

fn duration(m: &Metrics) -> Option<f64> {
    m.first_impact.zip(m.first_release).map(|(a, b)| b - a)
}

/// The rows of `bodies.csv`, full precision (the unperturbed runs).
pub(super) fn bodies_csv_rows(results: &[BodyResult]) -> Vec<Vec<String>> {
    let o = |x: Option<f64>| x.map_or(String::new(), fmt_f64);
    results
        .iter()
        .map(|r| {
            let m = &r.metrics;
            vec![
                bench_name(r.case.bench).into(),
                fmt_f64(r.case.h()),
                r.case.scheme.slug().into(),
                r.case.mass.name().into(),
                fmt_f64(r.end),
                fmt_f64(r.dt),
                r.stable.map_or(String::new(), |(l, _)| fmt_f64(l)),
                r.stable.map_or(String::new(), |(_, by)| by.to_string()),
                r.unknowns.to_string(),
                fmt_f64(r.layer_fraction),
                fmt_f64(m.drift),
                fmt_f64(m.max_energy_deviation),
                fmt_f64(m.max_energy_increase),
                fmt_f64(m.force_variation),
                m.episodes.to_string(),
                fmt_f64(m.min_distance),
                o(r.summary.own_number("max_contact_force")),
                o(m.first_impact),
                o(m.first_release),
                o(duration(m)),
                fmt_f64(m.rebound_velocity),
            ]
        })
        .collect()
}

/// The drops' scheme (the figures draw its runs; the reference has its own step grid).
const CN: BodyScheme = BodyScheme::Paper(Experiment::CrankNicolson);

/// A panel of one curve per run of `runs`, y from `y`.
fn panel(title: String, y_label: &str, runs: &[&BodyResult], y: impl Fn(&BodyResult) -> Vec<f64>) -> Panel {
    let curves: Vec<Curve> = runs
        .iter()
        .map(|r| Curve {
            label: r.case.mass.name().into(),
            points: points(&r.t, &y(r)),
            style: mass_style(&r.case.mass),
        })
        .collect();
    // The range of the w_0 = 0 masses' curves when there are some (the standard mass with CN
    // chatters to E ~ 1e4, which would flatten them); a curve leaving it is named in the title.
    let massless = curves.iter().filter(|c| c.label != MassKind::Standard.name());
    let values = |c: &Curve| c.points.iter().map(|p| p.1).collect::<Vec<f64>>();
    let range = match massless.clone().count() {
        0 => plot::data_range(curves.iter().flat_map(values), 0.05),
        _ => plot::data_range(massless.flat_map(values), 0.05),
    };
    // The standard mass chatters with Crank–Nicolson: its extremes change with a 1e-13
    // perturbation, and so does whether they leave the range (issue 22: in the drop at h = 4 it
    // did in one run and not in a perturbed one). Such a curve is always named, whatever this
    // run did; other standard curves are named (without digits) when they leave the range.
    let chatters = |c: &Curve| c.label == MassKind::Standard.name() && runs.iter().any(|r| r.case.scheme == CN);
    let has_massless = curves.iter().any(|c| c.label != MassKind::Standard.name());
    let notes: Vec<String> = curves
        .iter()
        .filter_map(|c| match chatters(c) && has_massless {
            true => Some(format!("{} may leave the range (round-off sensitive)", c.label)),
            false => off_scale(&c.label, &values(c), range, c.label == MassKind::Standard.name()),
        })
        .collect();
    let title = if notes.is_empty() { title } else { format!("{title}; off-scale: {}", notes.join("; ")) };
    Panel { title, x_label: "t".into(), y_label: y_label.into(), curves, x_range: None, y_range: Some(range) }
}

/// A figure of `panels` (rows of up to 3) with the CSV of `runs`' `y` columns behind it (one
/// per run and per `(suffix, y)`).
fn figure(stem: &str, title: String, panels: Vec<Panel>, runs: &[&BodyResult], ys: &[(&str, Series)]) -> FigureFile {
    let times = runs.iter().map(|r| r.t.clone()).max_by_key(Vec::len).unwrap_or_default();
    let mut header = vec!["t".to_string()];
    let mut columns: Vec<Vec<f64>> = Vec::new();
    for (suffix, y) in ys {
        header.extend(runs.iter().map(|r| r.case.name().replace(" / ", "_").replace(" = ", "") + suffix));
        columns.extend(runs.iter().map(|r| y(r)));
    }
    let figure = Figure { title, columns: panels.len().min(3), panels, panel_size: (620, 480) };
    FigureFile { stem: stem.into(), figure, header, rows: grid_rows(&times, &columns), periods: None }
}

/// A series of a run, for a figure's panels and CSV.
type Series = fn(&BodyResult) -> Vec<f64>;

/// The centre-of-mass velocity P/(1ᵀM1) along the plane's normal.
fn com_velocity(r: &BodyResult) -> Vec<f64> {
    r.momentum_y.iter().map(|p| p / r.mass_total).collect()
}

/// `bodies-energy` (rest, finest mesh run, a panel per scheme), `bodies-drop` (a panel per
/// mesh) and `bodies-sphere` (velocity and contact force, a column per mesh).
pub(super) fn bodies_figures(results: &[BodyResult]) -> Vec<FigureFile> {
    let finest = |b: Bench| results.iter().filter(|r| r.case.bench == b).map(|r| r.case.mesh).max().unwrap_or(0);
    let rest_mesh = finest(Bench::Rest);
    let rest: Vec<&BodyResult> =
        results.iter().filter(|r| r.case.bench == Bench::Rest && r.case.mesh == rest_mesh).collect();
    let schemes = [Experiment::CrankNicolson, Experiment::BackwardEuler, Experiment::Hybrid];
    let panels = schemes
        .iter()
        .map(|&e| {
            let runs: Vec<&BodyResult> =
                rest.iter().copied().filter(|r| r.case.scheme == BodyScheme::Paper(e)).collect();
            panel(format!("energy Eⁿ, {}", e.title()), "E", &runs, |r| r.energy.clone())
        })
        .collect();
    let title = format!("GetFEM's disc at rest on the plane, P2, h = {}, Δt = {}", MESHES[rest_mesh].0, fmt_f64(DT));
    let energy = figure(BODIES_ENERGY, title, panels, &rest, &[("", |r| r.energy.clone())]);
    let drops: Vec<&BodyResult> =
        results.iter().filter(|r| r.case.bench == Bench::Drop && r.case.scheme == CN).collect();
    let panels = by_mesh(&drops)
        .iter()
        .map(|runs| panel(format!("P_y/(1ᵀM1), h = {}", runs[0].case.h()), "v̄_y", runs, com_velocity))
        .collect();
    let title = format!("Disc dropped at {} from {} above the plane, Crank–Nicolson", DROP_SPEED, DROP_GAP);
    let drop = figure(BODIES_DROP, title, panels, &drops, &[("", com_velocity)]);
    let mut out = vec![energy, drop, sphere_figure(results)];
    out.extend(impact_figure(results));
    out
}

/// `bodies-impact`: the dropped disc on its finest mesh with mod3 at its largest total contact
/// force, the deformed mesh (true scale) on the plane, and the nodal contact pressure R_i/a_i.
fn impact_figure(results: &[BodyResult]) -> Option<FigureFile> {
    let r = results
        .iter()
        .filter(|r| r.case.bench == Bench::Drop && r.case.scheme == CN && r.case.mass == MassKind::Mod3)
        .max_by_key(|r| r.case.mesh)?;
    let snap = r.snapshot.as_ref()?;
    let mut curves: Vec<Curve> = snap
        .sides
        .iter()
        .map(|side| Curve {
            label: "deformed mesh".into(),
            points: side.iter().map(|&i| (snap.points[i][0], snap.points[i][1])).collect(),
            style: Style::Numeric(1),
        })
        .collect();
    curves.push(Curve {
        label: "plane".into(),
        points: vec![(-24.0, -DROP_GAP), (24.0, -DROP_GAP)],
        style: Style::Exact,
    });
    let mesh = Panel {
        title: format!("t = {}, ΣR = {:.0}", fmt_f64(snap.t), snap.contact_force),
        x_label: "x".into(),
        y_label: "y".into(),
        curves,
        x_range: Some((-24.0, 24.0)),
        y_range: Some((-4.0, 44.0)),
    };
    let pressure = Panel {
        title: "contact pressure R_i/a_i".into(),
        x_label: "x".into(),
        y_label: "p".into(),
        curves: vec![Curve { label: "mod3".into(), points: snap.pressure.clone(), style: mass_style(&MassKind::Mod3) }],
        x_range: None,
        y_range: None,
    };
    let title = format!(
        "Disc dropped at {} from {} above the plane: P2, h = {}, mod3, Crank–Nicolson, at the largest contact force",
        DROP_SPEED,
        DROP_GAP,
        r.case.h()
    );
    let figure = Figure { title, columns: 2, panels: vec![mesh, pressure], panel_size: (620, 620) };
    let header = ["x", "pressure"].map(String::from).to_vec();
    let rows = snap.pressure.iter().map(|&(x, p)| vec![fmt_f64(x), fmt_f64(p)]).collect();
    Some(FigureFile { stem: BODIES_IMPACT.into(), figure, header, rows, periods: None })
}

/// `runs` grouped by mesh, coarsest first (meshes without a run left out).
fn by_mesh<'a>(runs: &[&'a BodyResult]) -> Vec<Vec<&'a BodyResult>> {
    let finest = runs.iter().map(|r| r.case.mesh).max().unwrap_or(0);
    (0..=finest)
        .map(|k| runs.iter().copied().filter(|r| r.case.mesh == k).collect::<Vec<_>>())
        .filter(|v| !v.is_empty())
        .collect()
}

/// `bodies-sphere`: a column per mesh, P_z/(1ᵀM1) above, ΣR below.
fn sphere_figure(results: &[BodyResult]) -> FigureFile {
    let spheres: Vec<&BodyResult> =
        results.iter().filter(|r| r.case.bench == Bench::Sphere && r.case.scheme == CN).collect();
    let groups = by_mesh(&spheres);
    let force = |r: &BodyResult| r.contact_force.clone();
    let velocity =
        groups.iter().map(|runs| panel(format!("P_z/(1ᵀM1), h = {}", runs[0].case.h()), "v̄_z", runs, com_velocity));
    let forces = groups.iter().map(|runs| panel(format!("ΣR, h = {}", runs[0].case.h()), "ΣR", runs, force));
    let mut panels: Vec<Panel> = velocity.collect();
    panels.extend(forces);
    let title =
        format!("Sphere (tetra10) dropped at {} from {}, CN, Δt = {}", DROP_SPEED, DROP_GAP, fmt_f64(SPHERE_DT));
    let mut f = figure(BODIES_SPHERE, title, panels, &spheres, &[("_velocity", com_velocity), ("_force", force)]);
    f.figure.columns = groups.len().max(1);
    f
}

/// The report section: the rest table, the drop table, the figures.
pub(super) fn bodies_section(results: &[BodyResult]) -> String {
    let mut s = format!(
        "\n## Bodies against a rigid plane: GetFEM's disc (beyond the paper)\n\n\
         Disc of radius 20 centred at (0, 20), λ = μ = 20, ρ = 1, P2 triangles (gmsh, nominal size h), free body, contact nodes by GetFEM's rule \
         on y = 0, Δt = {}. Each run is repeated {COPIES} times from an initial velocity perturbed by at most {PERTURBATION:e} (four patterns); \
         numbers keep only the digits all five runs share (a band min–max if they share fewer than two), counts are one value or the band min–max. E⁰ = 0 (U⁰ = V⁰ = 0); drift = Eᴺ − E⁰; TV(ΣR) = Σ_n |ΣR^{{n+1}} − ΣR^n|; episodes = maximal runs of steps \
         with a node in contact; contact is read off the force (R_i > 0), never off d_i ≤ 0, as are the first impact and release. The hybrid scheme is defined for w_0 = 0 masses only (no standard mass). (`{BODIES_TABLE}`)\n\n\
         ### At rest under f = (0, −0.1)\n\n\
         | h | T | scheme | mass | drift Eᴺ − E⁰ | max \\|Eⁿ − E⁰\\| | max ΔE | TV(ΣR) | episodes | min_distance |\n|---|---|---|---|---|---|---|---|---|---|\n",
        fmt_f64(DT)
    );
    for r in results.iter().filter(|r| r.case.bench == Bench::Rest) {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            fmt_f64(r.case.h()),
            fmt_f64(r.end),
            r.case.scheme.title(),
            r.case.mass.name(),
            r.stable(|m| Some(m.drift)),
            r.stable(|m| Some(m.max_energy_deviation)),
            r.stable(|m| Some(m.max_energy_increase)),
            r.stable(|m| Some(m.force_variation)),
            r.count(|m| m.episodes),
            r.stable(|m| Some(m.min_distance)),
        );
    }
    let _ = write!(
        s,
        "\n![{BODIES_ENERGY}]({BODIES_ENERGY}.png)\n\n### Dropped at {DROP_SPEED} from {DROP_GAP} above the plane (no force), Crank–Nicolson and the reference\n\n\
         Rebound velocity = P_y(T)/(1ᵀM1), the velocity of the centre of the redistributed mass after release (constant in free flight; \
         +{DROP_SPEED} for an elastic rebound that keeps no vibration energy; 1ᵀM1 = ρ|Ω| but for mod1, which drops layer 0's mass).\n\n\
         {}\n\n{DROP_HEADER}",
        reference(),
    );
    drop_rows(&mut s, results, Bench::Drop);
    let _ = writeln!(s, "\n![{BODIES_DROP}]({BODIES_DROP}.png)\n\n![{BODIES_IMPACT}]({BODIES_IMPACT}.png)");
    s.push_str(&sphere_section(results));
    s
}

/// The rows of a drop table (`bench`: the disc's or the sphere's).
fn drop_rows(s: &mut String, results: &[BodyResult], bench: Bench) {
    for r in results.iter().filter(|r| r.case.bench == bench) {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {:.0} % | {} | {} | {} | {} | {} | {} |",
            fmt_f64(r.case.h()),
            r.unknowns,
            r.case.scheme.title(),
            r.case.mass.name(),
            sig(r.dt, 4),
            100.0 * r.layer_fraction,
            r.stable(|m| m.first_impact),
            r.stable(|m| m.first_release),
            r.stable(duration),
            r.stable(|m| Some(m.rebound_velocity)),
            r.count(|m| m.episodes),
            r.stable(|m| Some(m.min_distance)),
        );
    }
}

/// The sphere's table and figure.
fn sphere_section(results: &[BodyResult]) -> String {
    let mut s = format!(
        "\n### A sphere dropped at {DROP_SPEED} from {DROP_GAP} above the plane (no force), Crank–Nicolson and the reference\n\n\
         Sphere of radius 20 centred at (0, 0, 20), the disc's material, tetra10 (gmsh, nominal size h), free body, contact nodes by GetFEM's rule \
         on z = 0, Δt = {} (twice the disc's, to keep the set's cost down; the contact lasts 890–960 steps). \
         Rebound velocity = P_z(T)/(1ᵀM1); the same five runs, stable digits and reference as above. The three coarse meshes put over \
         half the sphere's mass in the redistributed layer (the column \"layer mass\"); the two finer ones (h = 5 and 4) run mod1, mod3 \
         and the reference only ({}: the standard mass chatters with Crank–Nicolson and costs all five runs; mod2 follows mod3). \
         The reference is the same discrete model without redistribution, not a closed form.\n\n{DROP_HEADER}",
        fmt_f64(SPHERE_DT),
        FINE_MASSES.map(|m| m.name()).join(", "),
    );
    drop_rows(&mut s, results, Bench::Sphere);
    let _ = writeln!(s, "\n![{BODIES_SPHERE}]({BODIES_SPHERE}.png)");
    s.push_str(&convergence_table(results));
    s
}

/// The drops' table head.
const DROP_HEADER: &str = "| h | unknowns | scheme | mass | Δt | layer mass | first impact | first release | contact duration | rebound velocity | episodes | min_distance |\n\
     |---|---|---|---|---|---|---|---|---|---|---|---|\n";

/// What the reference rows are.
fn reference() -> String {
    format!(
        "The reference (scheme \"central differences\") is free of redistribution: the standard lumped mass, whose contact \
     nodes keep their mass, exact contact (the forward-increment multiplier), at the largest Δt dividing T that is at most {SAFETY} Δt_c \
     (Δt_c and its estimator: `stable_step`, `stable_step_method` in the CSV). Its force acts from the step before the body would \
     reach the plane, so its first impact can be read up to one of its steps early. \"layer mass\" = Σ ρ|c| over the cells whose \
     weight is not 1, over ρ|Ω|: mod1's layer 0 (the mass it drops), mod3's layers 0 and 1; mod2 rescales every cell (100 %)."
    )
}

/// The contact duration against the mesh: mod1, mod3 and the reference per mesh, with the
/// relative change from the previous mesh (the convergence the section's meshes show).
fn convergence_table(results: &[BodyResult]) -> String {
    let mut s = String::from(
        "\n### The contact duration against the mesh\n\n\
         From the two tables above (the same runs): the contact duration of mod1 and mod3 (Crank–Nicolson) and of the reference, and \
         each one's relative change from the previous mesh (run k against run k, two digits or the band).\n\n\
         | body | h | unknowns | layer mass mod1 | layer mass mod3 | mod1 | mod3 | reference | mod1 change | mod3 change | reference change |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for bench in [Bench::Drop, Bench::Sphere] {
        let of = |mesh: usize, scheme: BodyScheme, mass: &MassKind| {
            results.iter().find(|r| {
                r.case.bench == bench && r.case.mesh == mesh && r.case.scheme == scheme && r.case.mass == *mass
            })
        };
        let columns = [(CN, MassKind::Mod1), (CN, MassKind::Mod3), (BodyScheme::Reference, MassKind::Standard)];
        let meshes = results.iter().filter(|r| r.case.bench == bench).map(|r| r.case.mesh).max().map_or(0, |m| m + 1);
        for mesh in 0..meshes {
            let (Some(mod1), Some(mod3)) = (of(mesh, CN, &MassKind::Mod1), of(mesh, CN, &MassKind::Mod3)) else {
                continue;
            };
            let cells: Vec<String> = columns
                .iter()
                .map(|(sch, mass)| of(mesh, *sch, mass).map_or("—".into(), |r| r.stable(duration)))
                .collect();
            let changes: Vec<String> = columns
                .iter()
                .map(|(sch, mass)| {
                    let now = of(mesh, *sch, mass);
                    let before = mesh.checked_sub(1).and_then(|k| of(k, *sch, mass));
                    let Some((now, before)) = now.zip(before) else { return "—".into() };
                    // Run k against run k of the previous mesh (the copies are perturbed alike).
                    let change =
                        |(a, b): (&Metrics, &Metrics)| duration(a).zip(duration(b)).map(|(a, b)| 100.0 * (a - b) / b);
                    let v: Vec<Option<f64>> = now.runs().zip(before.runs()).map(change).collect();
                    let printed = super::band::stable_digits(&v, 2);
                    if printed.starts_with('-') || printed == "—" {
                        format!("{printed} %")
                    } else {
                        format!("+{printed} %")
                    }
                })
                .collect();
            let _ = writeln!(
                s,
                "| {} | {} | {} | {:.0} % | {:.0} % | {} | {} | {} | {} | {} | {} |",
                if bench == Bench::Sphere { "sphere" } else { "disc" },
                fmt_f64(mod3.case.h()),
                mod3.unknowns,
                100.0 * mod1.layer_fraction,
                100.0 * mod3.layer_fraction,
                cells[0],
                cells[1],
                cells[2],
                changes[0],
                changes[1],
                changes[2],
            );
        }
    }
    s
}
