//! Bodies against a rigid plane (issue 19, `[obstacle]`): a box written as a body gives the
//! box's numbers, a rotated body the rotated physics, and the identities of the definitions
//! (complementarity at every step, momentum balance and ½ g t² in free flight, energy of CN),
//! on meshes built here (structured boxes moved and rotated, a polygonal disc) with the groups
//! filled here.

use massredist::driver::{Observer, Sample};
use massredist::fem::{Cell, Mesh};
use massredist::observe::Column;
use massredist::run::{SceneRun, run_scene};
use massredist::scene::{AnyScene, SolidScene};
use massredist::solid::{ContactSet, MeshSource, SolidSystem, Support};
use std::sync::Arc;

mod body_common;

fn scene(text: &str) -> SolidScene {
    SolidScene::from_toml(text).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// A body scene on a stand-in structured mesh, then given `mesh`, `clamped`, `contact`, the
/// obstacle (normal, point) and the force (expressions).
fn body_scene(
    mesh: Mesh,
    obstacle: ([f64; 3], [f64; 3]),
    contact: ContactSet,
    clamped: Option<&str>,
    rest: &str,
) -> SolidScene {
    let d = mesh.dim;
    let text = format!(
        "[solid]\ndim = {d}\nnx = 2\nny = 1\n{}\n[obstacle]\nnormal = [{}]\n{rest}",
        if d == 3 { "nz = 1" } else { "" },
        if d == 2 { "1, 0" } else { "1, 0, 0" }
    );
    let mut s = scene(&text);
    let Support::Plane(body) = &mut s.geometry.support else { panic!("a body") };
    body.obstacle = massredist::solid::Obstacle::plane(obstacle.0, obstacle.1, contact);
    body.clamped = clamped.map(String::from);
    s.geometry.extent = mesh.extent;
    s.geometry.source = MeshSource::Arrays(Arc::new(mesh));
    s
}

/// Nodes of `mesh` with `pred(point)`.
fn nodes(mesh: &Mesh, pred: impl Fn([f64; 3]) -> bool) -> Vec<usize> {
    (0..mesh.n_nodes()).filter(|&v| pred(mesh.points[v])).collect()
}

/// The L × H box (quads or triangles) with groups "left" (x = 0) and "right" (x = L), its
/// points mapped by `map`.
fn moved_box(l: f64, h: f64, n: [usize; 2], cells: Cell, map: impl Fn([f64; 3]) -> [f64; 3]) -> Mesh {
    let mut m = Mesh::structured_2d(l, h, n[0], n[1], cells).unwrap();
    let left = nodes(&m, |p| p[0] == 0.0);
    let right = nodes(&m, |p| p[0] == l);
    m.groups.insert("left".into(), left);
    m.groups.insert("right".into(), right);
    for p in m.points.iter_mut() {
        *p = map(*p);
    }
    m.grid = None;
    m
}

/// Rotation by θ in the xy-plane.
fn rot(theta: f64) -> impl Fn([f64; 3]) -> [f64; 3] {
    let (s, c) = theta.sin_cos();
    move |p| [c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]]
}

/// A polygonal disc of radius r centred at (cx, cy): a centre node, `rings` rings of `m` nodes
/// each, triangles between them; group "bottom" = the outer nodes with y ≤ cy − 0.9 r.
fn disc(r: f64, centre: [f64; 2], rings: usize, m: usize) -> Mesh {
    let mut pts = vec![centre[0], centre[1]];
    for k in 1..=rings {
        for j in 0..m {
            let (s, c) = (2.0 * std::f64::consts::PI * j as f64 / m as f64).sin_cos();
            let rk = r * k as f64 / rings as f64;
            pts.extend([centre[0] + rk * c, centre[1] + rk * s]);
        }
    }
    let node = |k: usize, j: usize| if k == 0 { 0 } else { 1 + (k - 1) * m + j % m };
    let mut cells = Vec::new();
    for j in 0..m {
        cells.extend([0, node(1, j), node(1, j + 1)]);
    }
    for k in 1..rings {
        for j in 0..m {
            cells.extend([node(k, j), node(k + 1, j), node(k + 1, j + 1)]);
            cells.extend([node(k, j), node(k + 1, j + 1), node(k, j + 1)]);
        }
    }
    let mut mesh = Mesh::from_arrays(Cell::Triangle, &pts, &cells).unwrap();
    let bottom = (0..mesh.n_nodes()).filter(|&v| mesh.points[v][1] <= centre[1] - 0.9 * r).collect();
    mesh.groups.insert("bottom".into(), bottom);
    mesh
}

const SECTIONS: &str = "[mass]\nkind = \"mod3\"\n[time]\ndt = 0.02\nend = 2.0\n";

fn run(s: &SolidScene) -> SceneRun<SolidSystem> {
    run_scene(s, &mut []).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_box_written_as_a_body_gives_the_box_numbers() {
    // normal e_x, point (−gap, 0), contact = the face x = 0, clamped = the face x = L: the same
    // nodes, weights, unknowns and bounds as the box, R = I: every number is bit-identical
    // (the body's contact_force is the reaction Σ R_i = −Σ λ_i).
    // mutation: `0.0 - g` → `-(g + 1e-3)` for the body's bounds in body_system.rs -> fails.
    for (cells, scheme) in [("quad", "crank-nicolson"), ("triangle", "backward-euler"), ("quad", "hybrid")] {
        let (gap, init) = (0.01, "initial = { displacement = [\"(1-x)/2\", \"0.1*x*y\"], velocity = [\"0\", \"0\"] }");
        let mat = "lame_lambda = 0.3\nlame_mu = 0.5\ndensity = 1.5";
        let series = "[output]\nseries = [\"u0\", \"u_mean\", \"lambda\", \"contact_force\", \"energy\"]\n";
        let tail = format!("{SECTIONS}[scheme]\nkind = \"{scheme}\"\n{series}");
        let boxed = scene(&format!(
            "[solid]\nnx = 8\nny = 3\nheight = 0.75\ncells = \"{cells}\"\ngap = {gap}\n{mat}\n{init}\n{tail}"
        ));
        let kind = if cells == "quad" { Cell::Quad } else { Cell::Triangle };
        let mesh = moved_box(1.0, 0.75, [8, 3], kind, |p| p);
        let rest = format!("{mat}\n{init}\n{tail}");
        let mut body =
            body_scene(mesh, ([1.0, 0.0, 0.0], [-gap, 0.0, 0.0]), ContactSet::Group("left".into()), Some("right"), "");
        let text = format!("[solid]\nnx = 2\nny = 1\n{rest}\n[obstacle]\nnormal = [1, 0]\n");
        let parsed = scene(&text);
        body.mass = parsed.mass.clone();
        body.scheme = parsed.scheme;
        body.time = parsed.time.clone();
        body.output = parsed.output.clone();
        body.geometry.lame = parsed.geometry.lame;
        body.geometry.initial = parsed.geometry.initial.clone();
        let (a, b) = (run(&boxed), run(&body));
        let (sa, sb) = (&a.summary, &b.summary);
        assert_eq!(sa.energy_initial, sb.energy_initial, "{cells} {scheme}");
        assert_eq!(sa.energy_final, sb.energy_final, "{cells} {scheme}");
        assert_eq!(sa.first_impact_time, sb.first_impact_time);
        assert_eq!(sa.first_release_time, sb.first_release_time);
        assert!(sa.first_impact_time.is_some(), "the box hits the plane");
        assert_eq!((sa.min_u0, sa.max_lambda, sa.final_u0), (sb.min_u0, sb.max_lambda, sb.final_u0));
        assert_eq!(sa.final_contact_force, -sb.final_contact_force);
        for (ra, rb) in a.series.iter_rows().zip(b.series.iter_rows()) {
            assert_eq!(ra[..2], rb[..2], "t, u0");
            assert_eq!(ra[4], -rb[4], "contact_force is the reaction");
            assert_eq!(ra[5], rb[5], "energy");
            // u_mean and λ divide by |Γ_C|: the body's is the sum of its facet lengths (H up to
            // a few ulps).
            for k in [2, 3] {
                assert!(
                    approx::relative_eq!(ra[k], rb[k], epsilon = 1e-14 * ra[k].abs().max(1.0), max_relative = 0.0),
                    "{} {}",
                    ra[k],
                    rb[k]
                );
            }
        }
        let max_contact_force = sb.own_number("max_contact_force").expect("a body's summary keys");
        assert_eq!(
            max_contact_force,
            a.series
                .column(massredist::observe::Column::ContactForce)
                .unwrap()
                .iter()
                .fold(f64::NEG_INFINITY, |m, &x| m.max(-x))
        );
        assert!(sa.own.is_empty());
        // summary.json: the box keeps its `gap` and `lateral`; a body has neither (its plane is
        // [obstacle]). Mutation: always Some in SolidHead -> fails.
        let ja: serde_json::Value =
            serde_json::from_str(&massredist::run::summary_json(&boxed, &a.problem, sa)).unwrap();
        let jb: serde_json::Value =
            serde_json::from_str(&massredist::run::summary_json(&body, &b.problem, sb)).unwrap();
        assert_eq!((ja["gap"].as_f64(), ja["lateral"].as_str()), (Some(gap), Some("free")));
        assert!(jb.get("gap").is_none() && jb.get("lateral").is_none(), "{jb}");
    }
}

/// A body scene on `mesh` with `solid` keys in `[solid]` and the sections `rest`.
fn body_on(
    mesh: Mesh,
    obstacle: ([f64; 3], [f64; 3]),
    contact: ContactSet,
    clamped: Option<&str>,
    solid: &str,
    rest: &str,
) -> SolidScene {
    let d = mesh.dim;
    let normal = if d == 2 { "1, 0" } else { "1, 0, 0" };
    let text = format!("[solid]\ndim = {d}\nnx = 2\nny = 1\n{solid}\n[obstacle]\nnormal = [{normal}]\n{rest}");
    let mut s = scene(&text);
    let Support::Plane(body) = &mut s.geometry.support else { panic!("a body") };
    body.obstacle = massredist::solid::Obstacle::plane(obstacle.0, obstacle.1, contact);
    body.clamped = clamped.map(String::from);
    s.geometry.extent = mesh.extent;
    s.geometry.source = MeshSource::Arrays(Arc::new(mesh));
    s
}

/// A vector as the text of `[a, b]` expressions (exact: shortest round-trip numbers).
fn vector(v: [f64; 3]) -> String {
    format!("[\"{:e}\", \"{:e}\"]", v[0], v[1])
}

const BODY_SERIES: &str = "[output]\nseries = [\"u0\", \"contact_force\", \"energy\", \"active_nodes\", \"min_distance\", \"momentum_x\", \"momentum_y\", \"mean_u_x\", \"mean_u_y\"]\n";

#[test]
fn axis_and_tilted_normals_give_the_physics_of_the_rotated_body() {
    // The clamped box against the plane x = −gap, and the same box, normal, point, velocity and
    // force rotated by θ (normal e_y for θ = π/2, −e_y for −π/2, a tilted one for 0.3): energy,
    // reaction, active nodes, distance are the same, momentum and mean displacement rotated.
    // Tolerance 1e-11 of each column's scale: the rotated meshes differ from the reference by
    // the round-off of the rotation (≈1e-16), amplified by the condition of the step matrices
    // (≈1e3 here). mutation: `from_frame` returning R x with R transposed -> momentum fails.
    let (gap, v, f) = (0.01, [-1.0, 0.3, 0.0], [-0.5, 0.2, 0.0]);
    let sections = "[mass]\nkind = \"mod2\"\n[scheme]\nkind = \"crank-nicolson\"\n[time]\ndt = 0.02\nend = 1.0\n";
    let rest = format!("{sections}{BODY_SERIES}");
    let make = |theta: f64| {
        let r = rot(theta);
        let mesh = moved_box(1.0, 0.5, [6, 3], Cell::Quad, &r);
        let solid = format!(
            "lame_lambda = 0.5\nlame_mu = 1.0\nforce = {}\ninitial = {{ displacement = [\"0\", \"0\"], velocity = {} }}",
            vector(r(f)),
            vector(r(v))
        );
        let normal = if theta == 0.0 { [1.0, 0.0, 0.0] } else { r([1.0, 0.0, 0.0]) };
        run(&body_on(
            mesh,
            (normal, r([-gap, 0.0, 0.0])),
            ContactSet::Group("left".into()),
            Some("right"),
            &solid,
            &rest,
        ))
    };
    let reference = make(0.0);
    assert!(reference.summary.first_impact_time.is_some(), "the box hits the plane");
    let rows: Vec<Vec<f64>> = reference.series.iter_rows().map(<[f64]>::to_vec).collect();
    let scale: Vec<f64> = (0..rows[0].len()).map(|k| rows.iter().map(|r| r[k].abs()).fold(1e-3, f64::max)).collect();
    for theta in [std::f64::consts::FRAC_PI_2, -std::f64::consts::FRAC_PI_2, 0.3] {
        let turned = make(theta);
        let r = rot(theta);
        for (a, b) in rows.iter().zip(turned.series.iter_rows()) {
            let p = r([a[6], a[7], 0.0]);
            let m = r([a[8], a[9], 0.0]);
            let want = [a[0], a[1], a[2], a[3], a[4], a[5], p[0], p[1], m[0], m[1]];
            assert_eq!(want[4], b[4], "θ = {theta}, t = {}: active nodes", a[0]);
            for k in 1..want.len() {
                let tol =
                    1e-11 * scale[k].max(if k >= 6 { scale[6].max(scale[7]).max(scale[8]).max(scale[9]) } else { 0.0 });
                assert!(
                    approx::relative_eq!(want[k], b[k], epsilon = tol, max_relative = 0.0),
                    "θ = {theta}, t = {}, column {k}: {} vs {}",
                    a[0],
                    want[k],
                    b[k]
                );
            }
        }
    }
}

/// A free disc far above the floor y = 0 (no contact during the run).
fn flying_disc(mass: &str, solid: &str) -> SceneRun<SolidSystem> {
    let mesh = disc(1.0, [1.0, 10.0], 3, 16);
    let rest = format!(
        "[mass]\nkind = \"{mass}\"\n[scheme]\nkind = \"crank-nicolson\"\n[time]\ndt = 0.05\nend = 2.0\n{BODY_SERIES}"
    );
    run(&body_on(mesh, ([0.0, 1.0, 0.0], [0.0; 3]), ContactSet::Auto, None, solid, &rest))
}

#[test]
fn a_free_body_in_free_flight_balances_its_momentum_and_falls_by_half_g_t_squared() {
    // P(t) = P(0) + t ∫ f (1ᵀ S = 0 for a free body, 1ᵀ F = f |Ω|), for every mass; with the
    // standard mass ū(t) = v0 t + ½ (f/ρ) t² exactly for CN under a constant force (the
    // trapezoidal rule integrates the linear momentum exactly). Tolerance 1e-12 of the scale
    // (40 steps of round-off on O(1) sums). mutation: the load doubled in body_system.rs
    // (`m * fb * 2.0`) -> fails.
    let (rho, f, v0) = (2.0, [0.3, -1.0], [0.2, 0.1]);
    let solid = format!(
        "lame_lambda = 3.0\nlame_mu = 2.0\ndensity = {rho}\nforce = [\"{}\", \"{}\"]\ninitial = {{ displacement = [\"0\", \"0\"], velocity = [\"{} - 0.5*(y-10)\", \"{} + 0.5*(x-1)\"] }}",
        f[0], f[1], v0[0], v0[1]
    );
    for mass in ["standard", "mod3"] {
        let run = flying_disc(mass, &solid);
        let area: f64 = run.problem.system.frame.as_ref().unwrap().volume;
        let p = [run.series.column(Column::Momentum(0)).unwrap(), run.series.column(Column::Momentum(1)).unwrap()];
        let t = run.series.times();
        assert_eq!(run.summary.first_impact_time, None, "no contact in flight");
        // With mod3 the massless nodes' rows are quasi-static: the initial data do not satisfy
        // them, the first step moves those nodes, and the balance holds from t_1 on.
        let first = usize::from(mass == "mod3");
        for k in 0..2 {
            for (n, tn) in t.iter().enumerate().skip(first) {
                let want = p[k][first] + (tn - t[first]) * f[k] * area;
                assert!(
                    approx::relative_eq!(p[k][n], want, epsilon = 1e-12 * (1.0 + want.abs()), max_relative = 0.0),
                    "{mass} P_{k}({tn}) = {} vs {want}",
                    p[k][n]
                );
            }
        }
        if mass == "standard" {
            // The rotation part of v0 has zero mean on the symmetric polygon (1e-15).
            let mean = [run.series.column(Column::MeanU(0)).unwrap(), run.series.column(Column::MeanU(1)).unwrap()];
            for k in 0..2 {
                for (n, tn) in t.iter().enumerate() {
                    let want = v0[k] * tn + 0.5 * f[k] / rho * tn * tn;
                    assert!(
                        approx::relative_eq!(mean[k][n], want, epsilon = 1e-12, max_relative = 0.0),
                        "ū_{k}({tn}) = {} vs {want}",
                        mean[k][n]
                    );
                }
            }
        }
    }
}

#[test]
fn crank_nicolson_conserves_the_energy_of_a_free_body_without_contact() {
    // No force, no contact: CN conserves ½VᵀMV + ½UᵀSU exactly up to round-off (1e-12 of E⁰,
    // 40 steps). An identity of the scheme on a body's system (its massless mod3 nodes
    // quasi-static), not of the body code: no mutation of src/solid breaks it alone.
    let solid = "lame_lambda = 1.0\nlame_mu = 1.0\ninitial = { displacement = [\"0.01*x*y\", \"0\"], velocity = [\"-0.5*(y-10)\", \"0.5*(x-1) + 0.2*x*x\"] }";
    for mass in ["standard", "mod3"] {
        let run = flying_disc(mass, solid);
        // mod3: from t_1 on (the first step puts the massless nodes in equilibrium).
        let e = &run.series.column(Column::Energy).unwrap()[usize::from(mass == "mod3")..];
        let drift = e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max);
        assert!(e[0] > 0.0 && drift <= 1e-12 * e[0], "{mass}: drift {drift:e} of {}", e[0]);
    }
}

/// Checks d_i ≥ 0, R_i ≥ 0, d_i R_i = 0 at every state, node by node.
struct Complementarity {
    lower: Vec<f64>,
    worst: [f64; 3],
    touched: bool,
}

impl Observer for Complementarity {
    fn observe(&mut self, s: &Sample) {
        let (u, lambda) = (s.state.u, s.state.lambda);
        for (k, &c) in s.geometry.contact().iter().enumerate() {
            let (d, r) = (u[c] - self.lower[k], -lambda[k]);
            self.worst = [self.worst[0].min(d), self.worst[1].min(r), self.worst[2].max((d * r).abs())];
            self.touched |= d <= 0.0;
        }
    }
}

#[test]
fn a_dropped_disc_meets_the_plane_with_exact_complementarity() {
    // A disc 0.02 above y = 0 falls under gravity: at every step and contact node d_i ≥ 0,
    // R_i ≥ 0 and d_i R_i = 0 (the exact solver: u_n = −g exactly where active, λ = 0 where
    // not), min_distance is exactly 0, the reaction positive, for CN, BE and hybrid with mod3.
    // mutation: `stats.contact_force -= l` → `+= l` in solid/geometry.rs -> max_contact_force fails.
    for scheme in ["crank-nicolson", "backward-euler", "hybrid"] {
        let mesh = disc(1.0, [1.0, 1.02], 3, 16);
        let rest = format!("[mass]\nkind = \"mod3\"\n[scheme]\nkind = \"{scheme}\"\n[time]\ndt = 0.01\nend = 1.0\n");
        let solid = "lame_lambda = 20.0\nlame_mu = 20.0\nforce = [\"0\", \"-1\"]";
        let s = body_on(mesh, ([0.0, 1.0, 0.0], [0.0; 3]), ContactSet::Auto, None, solid, &rest);
        let setup = massredist::run::setup(&s).unwrap();
        let lower = setup.problem.system.system.lower.clone();
        assert_eq!(lower.len(), 9, "auto: the outer nodes of the 8 edges facing down");
        let mut check = Complementarity { lower, worst: [f64::INFINITY, f64::INFINITY, 0.0], touched: false };
        let run = run_scene(&s, &mut [&mut check]).unwrap();
        let b = &run.summary;
        assert!(check.touched, "{scheme}: the disc lands");
        assert!(check.worst[0] >= 0.0 && check.worst[1] >= 0.0, "{scheme}: {:?}", check.worst);
        assert_eq!(check.worst[2], 0.0, "{scheme}: d_i R_i");
        assert_eq!(b.own_number("min_distance"), Some(0.0), "{scheme}");
        assert!(b.own_number("max_contact_force").unwrap() > 0.0, "{scheme}");
        let t = run.summary.first_impact_time.unwrap();
        // Free fall from rest: 0.02 = t²/2 at t = 0.2 (the disc deforms: within two steps).
        assert!(approx::relative_eq!(t, 0.2, epsilon = 0.02 + 1e-12, max_relative = 0.0), "{scheme}: first impact {t}");
    }
}

fn refused(text: &str, needles: &[&str]) {
    let err = AnyScene::from_toml(text).map(|_| ()).unwrap_err().to_string();
    for n in needles {
        assert!(err.contains(n), "{n:?} not in: {err}\n{text}");
    }
}

const BLOCK: &str = "[solid]\ndim = 2\nnx = 4\nny = 2\n";

#[test]
fn bad_bodies_are_refused_naming_the_key_or_node() {
    // mutation: the inside test `gap(v) < 0.0` → `gap(v) < -1.0` in solid/body.rs -> the
    // "starts inside" case is accepted and this fails.
    let ok = format!("{BLOCK}[obstacle]\nnormal = [0, 1]\n");
    assert!(AnyScene::from_toml(&ok).is_ok());
    refused(
        &format!("{BLOCK}clamped = \"nope\"\n[obstacle]\nnormal = [0, 1]\n"),
        &["solid.clamped = \"nope\"", "xmin"],
    );
    refused(&format!("{BLOCK}[obstacle]\nnormal = [0, 1]\ncontact = \"nope\"\n"), &["obstacle.contact = \"nope\""]);
    refused(&format!("{BLOCK}[obstacle]\nnormal = [0, 0]\n"), &["obstacle.normal = [0, 0]", "not zero"]);
    refused(&format!("{BLOCK}[obstacle]\nnormal = [nan, 1]\n"), &["obstacle.normal"]);
    refused(&format!("{BLOCK}[obstacle]\nnormal = [0, 1, 0]\n"), &["obstacle.normal"]);
    refused(&format!("{BLOCK}[obstacle]\n"), &["obstacle.normal is required"]);
    refused(
        &format!("{BLOCK}[obstacle]\nnormal = [0, 1]\npoint = [0, 0.1]\n"),
        &["node 0 at (0, 0) starts inside the obstacle"],
    );
    refused(
        &format!("{BLOCK}clamped = \"ymin\"\n[obstacle]\nnormal = [0, 1]\ncontact = \"ymin\"\n"),
        &["every node of the group is clamped"],
    );
    refused(&format!("{BLOCK}gap = 0.1\n[obstacle]\nnormal = [0, 1]\n"), &["solid.gap"]);
    refused(&format!("{BLOCK}clamped = \"xmax\"\n"), &["solid.clamped does not apply"]);
    refused("[plate]\n[obstacle]\nnormal = [0, 1]\n", &["[obstacle] does not apply"]);
    refused(&format!("{BLOCK}[obstacle]\nnormal = [0, 1]\n[output]\nseries = [\"momentum_z\"]\n"), &["momentum_z"]);
    refused(&format!("{BLOCK}force = [\"0\", \"1/(y-0)\"]\n[obstacle]\nnormal = [0, 1]\n"), &["solid.force"]);
    refused(&format!("{BLOCK}force = [\"0\", \"y\"]\n"), &["solid.force", "expressions: bodies"]);
    // An empty group (a mesh file may have one): refused when the problem is set up.
    let mut mesh = moved_box(1.0, 0.5, [4, 2], Cell::Quad, |p| p);
    mesh.groups.insert("none".into(), vec![]);
    let s = body_on(mesh, ([1.0, 0.0, 0.0], [0.0; 3]), ContactSet::Group("none".into()), None, "", "");
    let err = massredist::run::setup(&s).map(|_| ()).unwrap_err().to_string();
    assert!(err.contains("obstacle.contact = \"none\": the physical group has no node"), "{err}");
}

#[test]
fn the_command_line_refuses_a_bad_body_with_exit_2_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("bad.toml");
    std::fs::write(&scene, format!("{BLOCK}[obstacle]\nnormal = [0, 1]\npoint = [0, 0.1]\n")).unwrap();
    let out = tmp.path().join("out");
    let o = body_common::run_cli(&scene, &out);
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("starts inside the obstacle"));
    assert!(!out.exists());
    // A shipped body scene runs and reports the body keys.
    let out = tmp.path().join("drop");
    let summary = body_common::shipped_summary("scenes/body-block-drop-mod3.toml", &out);
    for key in ["max_contact_force", "min_distance", "final_active_nodes", "final_momentum", "final_mean_displacement"]
    {
        assert!(!summary[key].is_null(), "{key}: {summary}");
    }
    assert_eq!(summary["final_momentum"].as_array().unwrap().len(), 2);
    let series = std::fs::read_to_string(out.join("series.csv")).unwrap();
    assert!(series.lines().next().unwrap().contains("momentum_y"), "{series:.200}");
}

#[test]
fn a_body_frame_holds_its_reaction_pressure_and_contact_state() {
    // The dropped disc with a frame every step: contact_pressure · a_i = R_i = −λ_i ≥ 0 on
    // the contact nodes, contact_state 1 exactly where R_i > 0 (read off the force), the displacement
    // in world components (the free body's mean ū from the frame's nodes), some frame in contact.
    // mutation: `sign = -1.0` → `1.0` in solid/vtu.rs -> the pressure check fails.
    let mesh = disc(1.0, [1.0, 1.02], 3, 16);
    let rest = "[mass]\nkind = \"mod3\"\n[scheme]\nkind = \"crank-nicolson\"\n[time]\ndt = 0.01\nend = 0.6\n[output]\nvtu = true\nvtu_every = 1\n";
    let s = body_on(mesh, ([0.0, 1.0, 0.0], [0.0; 3]), ContactSet::Auto, None, "force = [\"0\", \"-1\"]", rest);
    let run = run(&s);
    let g = &run.problem.system;
    let mut touching = 0;
    for frame in &run.frames.as_ref().unwrap().frames {
        let data = massredist::fem::vtu::read_vtu(massredist::solid::vtu::vtu_bytes(
            g,
            &frame.u,
            &frame.v,
            &frame.lambda,
            None,
        ))
        .unwrap();
        let pressure = &data.point_array("contact_pressure").unwrap().values;
        let state = &data.point_array("contact_state").unwrap().values;
        for (c, &node) in g.contact_nodes.iter().enumerate() {
            let r = -frame.lambda[c];
            approx::assert_relative_eq!(
                pressure[node] * g.contact_areas[c],
                r,
                epsilon = 4.0 * f64::EPSILON * r.abs(),
                max_relative = 0.0
            );
            assert!(pressure[node] >= 0.0);
            assert_eq!(state[node], if r > 0.0 { 1.0 } else { 0.0 }, "node {node}");
            touching += usize::from(state[node] == 1.0);
        }
        let disp = &data.point_array("displacement").unwrap().values;
        assert_eq!(disp[1], frame.u[1], "world components (normal e_y: the frame swaps axes)");
    }
    assert!(touching > 0, "some frame in contact");
}

#[test]
fn the_frame_is_a_rotation_whose_first_axis_is_the_normal() {
    // RᵀR = I, R e_x = n, det R = 1 (to round-off), R = I exactly for n = e_x, in 2D and 3D.
    use massredist::solid::body::{rotation, unit_normal};
    for (raw, dim) in [([1.0, 0.0, 0.0], 2), ([0.0, -3.0, 0.0], 2), ([0.3, 1.0, 0.0], 2), ([1.0, 0.0, 0.0], 3)]
        .into_iter()
        .chain([([0.0, 0.0, 1.0], 3), ([-1.0, 0.0, 0.0], 3), ([0.2, -0.5, 0.7], 3), ([-0.9, 1e-9, 0.0], 3)])
    {
        let n = unit_normal(&raw[..dim], dim).unwrap();
        let r = rotation(n, dim);
        for i in 0..3 {
            assert!(approx::relative_eq!(r[i][0], n[i], epsilon = 1e-15, max_relative = 0.0), "{raw:?}");
            for j in 0..3 {
                let dot: f64 = (0..3).map(|k| r[k][i] * r[k][j]).sum();
                assert!(
                    approx::relative_eq!(dot, f64::from(u8::from(i == j)), epsilon = 4e-16, max_relative = 0.0),
                    "{raw:?} {i} {j}: {dot}"
                );
            }
        }
        let det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0])
            + r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
        assert!(approx::relative_eq!(det, 1.0, epsilon = 1e-15, max_relative = 0.0), "{raw:?}: det {det}");
    }
    assert_eq!(rotation([1.0, 0.0, 0.0], 3), [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
}

#[test]
fn three_dimensional_bodies_keep_the_box_numbers_and_balance_their_momentum() {
    // A hex box written as a body (normal e_x, contact xmin, clamped xmax: the face groups of a
    // structured body) gives the box's energies and contact history bit for bit; a free tet
    // block against a tilted plane far below balances P(t) = P(0) + t f |Ω| (standard mass).
    let table = "dim = 3\nnx = 4\nny = 2\nnz = 2\ncells = \"hex\"\nlame_lambda = 0.4\ninitial = { displacement = [\"(1-x)/2\", \"0\", \"0.1*x*z\"], velocity = [\"0\", \"0\", \"0\"] }";
    let tail = "[mass]\nkind = \"mod2\"\n[scheme]\nkind = \"backward-euler\"\n[time]\ndt = 0.05\nend = 2.0\n";
    let boxed = run(&scene(&format!("[solid]\n{table}\ngap = 0.02\n{tail}")));
    let body = run(&scene(&format!(
        "[solid]\n{table}\nclamped = \"xmax\"\n[obstacle]\nnormal = [1, 0, 0]\npoint = [-0.02, 0, 0]\ncontact = \"xmin\"\n{tail}"
    )));
    let (a, b) = (&boxed.summary, &body.summary);
    assert!(a.first_impact_time.is_some());
    assert_eq!((a.energy_initial, a.energy_final, a.energy_max), (b.energy_initial, b.energy_final, b.energy_max));
    assert_eq!(
        (a.first_impact_time, a.first_release_time, a.min_u0),
        (b.first_impact_time, b.first_release_time, b.min_u0)
    );
    let f = [0.1, -0.2, -1.0];
    let free = format!(
        "[solid]\ndim = 3\nnx = 3\nny = 2\nnz = 2\ncells = \"tet\"\nforce = [\"{}\", \"{}\", \"{}\"]\ninitial = {{ displacement = [\"0\", \"0\", \"0\"], velocity = [\"0.1*y\", \"-0.1*x\", \"0.3\"] }}\n[obstacle]\nnormal = [0.2, -0.5, 0.7]\npoint = [0, 0, -10]\n[mass]\nkind = \"standard\"\n[scheme]\nkind = \"crank-nicolson\"\n[time]\ndt = 0.05\nend = 1.0\n",
        f[0], f[1], f[2]
    );
    let run3 = run(&scene(&free));
    assert_eq!(run3.summary.first_impact_time, None);
    let t = run3.series.times();
    for k in 0..3 {
        let p = run3.series.column(Column::Momentum(k as u8)).unwrap();
        for (n, tn) in t.iter().enumerate() {
            let want = p[0] + tn * f[k];
            assert!(
                approx::relative_eq!(p[n], want, epsilon = 1e-12, max_relative = 0.0),
                "P_{k}({tn}) = {} vs {want}",
                p[n]
            );
        }
    }
}

#[test]
fn a_body_starting_on_the_plane_meets_it_at_the_first_step_with_force() {
    // g_i = 0 on the face y = 0: the face touches at t_0 but carries no force there (λ⁰ = 0: a
    // run starts without contact force), so the first impact, read off the force (issue 32,
    // item 1), is t_1 = Δt = 0.05; the clamped top keeps the face on the plane under gravity.
    // mutation: contact read off the position (`u[i] <= lower[c]` in ContactStats::of) -> 0.
    let text = format!(
        "{BLOCK}force = [\"0\", \"-1\"]\nclamped = \"ymax\"\n[obstacle]\nnormal = [0, 1]\n[scheme]\nkind = \"backward-euler\"\n[time]\ndt = 0.05\nend = 0.5\n"
    );
    let r = run(&scene(&text));
    assert_eq!(r.summary.first_impact_time, Some(0.05));
    assert_eq!(r.summary.first_release_time, None, "the face stays pressed");
    assert_eq!(r.summary.own_number("min_distance"), Some(0.0));
}

#[test]
fn resolved_body_scenes_read_back_to_themselves() {
    // The shipped body scenes and a 3D one with a transient force: every key written back
    // (obstacle, clamped, expressions), the same scene read again.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut texts: Vec<String> = ["body-block-drop-mod3.toml", "body-clamped-block.toml"]
        .iter()
        .map(|f| std::fs::read_to_string(dir.join(f)).unwrap())
        .collect();
    texts.push("[solid]\ndim = 3\nnx = 2\nny = 1\nnz = 3\nforce = [\"sin(t)*x\", \"0\", \"-1\"]\nclamped = \"zmax\"\n[obstacle]\nnormal = [0, 0, 2]\npoint = [0, 0, -1]\ncontact = \"zmin\"\n".into());
    for text in texts {
        let s = scene(&text);
        let again = scene(&s.resolved_toml());
        assert_eq!(s, again, "{}", s.resolved_toml());
        assert!(s.resolved_toml().contains("[obstacle]"));
    }
}

#[test]
fn a_bodys_matrices_are_the_triplet_assembly_on_its_frame_bit_for_bit() {
    // The body's mass, stiffness and unit mass, assembled straight into compressed columns
    // (`solid::columns`), equal the principal parts of the triplet assembly (`assembly::
    // assemble_directed`, the matrices dolfinx and scikit-fem assemble) on the mesh in the
    // plane's frame, bit for bit and pattern included: P2 triangles and tetrahedra from the
    // fixtures against tilted and axis planes, mod3 (a massless layer) with both contact
    // directions.
    // (Mutation, as run: `columns::mass` with `entry(c, &e, a, b, i, j)` transposed in
    // `assemble_on` -> the stiffness differs in the last bits, fails.)
    use massredist::fem::Mesh;
    use massredist::solid::assembly::{Lame, assemble, assemble_directed};
    use massredist::solid::body::{rotation, to_frame, unit_normal};
    let fixtures = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/meshes");
    let cases = [
        ("disc_p2_h4.msh", 2, "[0.3, 1]", "normal"),
        ("disc_p2_h4.msh", 2, "[0, 1]", "all"),
        ("sphere_tet10_h14.msh", 3, "[0.2, -0.5, 0.7]", "normal"),
    ];
    let bits = |m: &massredist::linalg::sparse::SpMat| {
        massredist::linalg::sparse::triplets(m).map(|(i, j, v)| (i, j, v.to_bits())).collect::<Vec<_>>()
    };
    for (file, dim, normal, directions) in cases {
        let zeros = vec!["\"0\""; dim].join(", ");
        // The plane 100 below the origin along −normal: below both meshes (radius ≤ 40).
        let raw: Vec<f64> = normal.trim_matches(['[', ']']).split(',').map(|x| x.trim().parse().unwrap()).collect();
        let norm = raw.iter().map(|x| x * x).sum::<f64>().sqrt();
        let point = raw.iter().map(|x| format!("{}", -100.0 * x / norm)).collect::<Vec<_>>().join(", ");
        let text = format!(
            "[solid]\ndim = {dim}\nmesh = \"{}\"\nlame_lambda = 0.7\nlame_mu = 1.3\ndensity = 2.5\nforce = [{zeros}]\ninitial = {{ displacement = [{zeros}], velocity = [{zeros}] }}\n[obstacle]\nnormal = {normal}\npoint = [{point}]\ncontact = \"auto\"\n[mass]\nkind = \"mod3\"\ncontact_directions = \"{directions}\"\n[scheme]\nkind = \"crank-nicolson\"\n[time]\ndt = 0.01\nend = 0.1\n",
            fixtures.join(file).display()
        );
        let s = scene(&text);
        let problem = s.geometry.problem_directed(&s.mass, s.contact_directions, s.time.exact_end()).unwrap();
        let solid = &problem.system;
        let Support::Plane(body) = &s.geometry.support else { panic!("a body") };
        let n = unit_normal(&raw, dim).unwrap();
        assert_eq!(body.obstacle.plane_normal(), Some(n), "the normal the body assembles with");
        let r = rotation(n, dim);
        let mut frame: Mesh = Mesh::clone(&solid.mesh);
        frame.points.iter_mut().for_each(|p| *p = to_frame(&r, *p));
        let directions = s.contact_directions;
        assert!(solid.weights.contains(&0.0), "{file}: a massless layer");
        let (mass_all, stiff_all) = assemble_directed(&frame, &solid.weights, directions, &s.geometry.lame).unwrap();
        let unit = Lame { density: 1.0, ..s.geometry.lame };
        let (unit_all, _) = assemble(&frame, &vec![1.0; frame.n_cells()], &unit).unwrap();
        let free = |m| massredist::linalg::sparse::principal(m, &solid.dofs, "m").unwrap();
        let what = format!("{file} {normal} {directions:?}");
        for (name, got, want) in [
            ("mass", &solid.system.mass, free(&mass_all)),
            ("stiffness", &solid.system.stiffness, free(&stiff_all)),
            ("unit mass", solid.mass_unit(), free(&unit_all)),
        ] {
            let (got, want) = (bits(got), bits(&want));
            let differ = got.iter().zip(&want).filter(|(a, b)| a != b).count();
            assert!(got == want, "{what}: {name}: {} against {} entries, {differ} differ", got.len(), want.len());
        }
    }
}
