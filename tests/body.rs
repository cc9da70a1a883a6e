//! Bodies against a rigid plane (issue 19, `[obstacle]`): a box written as a body gives the
//! box's numbers, a rotated body the rotated physics, and the identities of the definitions
//! (complementarity at every step, momentum balance and ½ g t² in free flight, energy of CN),
//! on meshes built here (structured boxes moved and rotated, a polygonal disc) with the groups
//! filled here.

use massredist::driver::{Observer, Sample};
use massredist::fem::{Cell, Mesh};
use massredist::mass::MassKind;
use massredist::run::{SceneRun, run_scene};
use massredist::scene::{SchemeSpec, SolidScene};
use massredist::solid::{ContactSet, SolidSystem};
use std::sync::Arc;

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
    let body = s.geometry.body.as_mut().unwrap();
    body.obstacle.normal = obstacle.0;
    body.obstacle.point = obstacle.1;
    body.obstacle.contact = contact;
    body.clamped = clamped.map(String::from);
    s.geometry.extent = mesh.extent;
    s.geometry.mesh = Some(Arc::new(mesh));
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
                assert!((ra[k] - rb[k]).abs() <= 1e-14 * ra[k].abs().max(1.0), "{} {}", ra[k], rb[k]);
            }
        }
        let body_keys = sb.body.as_ref().expect("a body's summary keys");
        assert_eq!(
            body_keys.max_contact_force,
            a.series
                .column(massredist::observe::Column::ContactForce)
                .unwrap()
                .iter()
                .fold(f64::NEG_INFINITY, |m, &x| m.max(-x))
        );
        assert!(sa.body.is_none());
    }
}
