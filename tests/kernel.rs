//! The cell-by-cell stiffness (issue 31, item 2; `solid::kernel`): on every cell kind (P1, P2
//! straight and curved, Q1 of any shape, 2D and 3D) the same operator as the assembled stiffness,
//! product by product, in the world frame and in per-node frames.

mod common;

use massredist::fem::{Cell, Mesh};
use massredist::linalg::sparse;
use massredist::linalg::{Operator, SymMatrix};
use massredist::material::Lame;
use massredist::solid::columns;
use massredist::solid::dof_map::DofMap;
use massredist::solid::kernel::CellKernel;
use std::sync::Arc;

struct Rand(u64);

impl Rand {
    /// Uniform in [−½, ½) (xorshift).
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

const LAME: Lame = Lame { lambda: 0.7, mu: 0.45, density: 1.3 };

/// A structured mesh of `kind` on (1, 0.6[, 0.4]) with every node not on x = 0 or x = 1 moved by
/// up to 0.15 of a cell in each direction (general quadrilaterals and hexahedra, simplices of
/// every orientation).
fn perturbed(kind: Cell, rand: &mut Rand) -> Mesh {
    let mut mesh = match kind.dim() {
        2 => Mesh::structured_2d(1.0, 0.6, 5, 4, kind).unwrap(),
        _ => Mesh::structured_3d([1.0, 0.6, 0.4], [4, 3, 3], kind).unwrap(),
    };
    let h = [0.2, 0.15, 0.13];
    for p in mesh.points.iter_mut() {
        if p[0] > 1e-12 && p[0] < 1.0 - 1e-12 {
            for k in 0..kind.dim() {
                p[k] += 0.3 * h[k] * rand.next();
            }
        }
    }
    mesh
}

/// `mesh`'s P2 mesh with its edge nodes (but those on x = 0) moved off the midpoints by up to
/// 0.05 of a cell (`curved`), or straight.
fn quadratic(mesh: &Mesh, curved: bool, rand: &mut Rand) -> Mesh {
    let mut q = mesh.quadratic().unwrap();
    if curved {
        // The face x = 0 kept (the clamped face of the trajectory check).
        for p in q.points[mesh.n_nodes()..].iter_mut().filter(|p| p[0] > 1e-12) {
            for k in 0..mesh.dim {
                p[k] += 0.1 * 0.13 * rand.next();
            }
        }
    }
    q
}

fn fixture(name: &str, dim: usize) -> Mesh {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/meshes").join(name);
    massredist::mesh_file::read_body("mesh", &path, dim).unwrap()
}

/// The meshes of the checks: each cell kind, general shapes, P2 straight and curved (gmsh's
/// curved disc and sphere among them).
fn meshes() -> Vec<(String, Mesh)> {
    let mut rand = Rand(0x2545F4914F6CDD1D);
    let mut out = Vec::new();
    for kind in [Cell::Triangle, Cell::Quad, Cell::Tet, Cell::Hex] {
        out.push((kind.name().to_string(), perturbed(kind, &mut rand)));
    }
    for kind in [Cell::Quad, Cell::Hex] {
        // Parallelograms and parallelepipeds (the kernel's affine Q1 cells): a sheared box.
        let mut mesh = match kind.dim() {
            2 => Mesh::structured_2d(1.0, 0.6, 5, 4, kind).unwrap(),
            _ => Mesh::structured_3d([1.0, 0.6, 0.4], [4, 3, 3], kind).unwrap(),
        };
        for p in mesh.points.iter_mut() {
            // x kept (the clamped face x = 0 stays one), y and z sheared.
            let z = if kind.dim() == 3 { p[2] + 0.1 * p[0] + 0.25 * p[1] } else { 0.0 };
            *p = [p[0], p[1] + 0.3 * p[0] - 0.2 * p[2], z];
        }
        out.push((format!("sheared {}", kind.name()), mesh));
    }
    for kind in [Cell::Triangle, Cell::Tet] {
        let p1 = perturbed(kind, &mut rand);
        out.push((format!("{} straight P2", kind.name()), quadratic(&p1, false, &mut rand)));
        out.push((format!("{} curved P2", kind.name()), quadratic(&p1, true, &mut rand)));
    }
    out.push(("gmsh disc_p2_h2".into(), fixture("disc_p2_h2.msh", 2)));
    out.push(("gmsh sphere_tet10_h4".into(), fixture("sphere_tet10_h4.msh", 3)));
    out
}

/// The free unknowns: every node but those within 5 % of the mesh's x-extent from its lowest x
/// (clamped: the generated meshes' face x = 0, a cap of gmsh's disc and sphere).
fn clamped_low(mesh: &Mesh) -> DofMap {
    let d = mesh.dim;
    let low = mesh.points.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min);
    let high = mesh.points.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max);
    let band = low + 0.05 * (high - low);
    let dofs: Vec<usize> = (0..mesh.n_nodes() * d).filter(|&g| mesh.points[g / d][0] > band).collect();
    DofMap::new(mesh.n_nodes() * d, &dofs)
}

/// `K x` by the kernel against the assembled stiffness (`columns::stiffness`) on random vectors,
/// entry by entry: `|y_kernel − y_assembled|_i ≤ 512 ε (|K| |x|)_i` and the quadratic forms
/// within `1024 ε |x|ᵀ|K||x|`. Derivation: an assembled entry is a sum over ≤ 24 cells (a P1
/// vertex's tetrahedra) of each cell's quadrature sum; the kernel sums the same cell terms
/// per point in another association (H, then σ, then the force: each term a product of ≤ 4
/// rounded factors). Straight P2 cells take a 4-point rule where the assembler takes the
/// 15-point degree-5 rule (both exact for the degree-2 integrand), whose weights have both
/// signs: its sums cancel by up to a factor of a few, which the constant 512 covers (measured:
/// at most 102 ε, on gmsh's disc). (Mutation, as run: σ without its μ Hᵀ term -> fails on every
/// kind; the curved P2 cells taken as straight -> fails on the curved cases only.)
#[test]
fn the_kernel_is_the_assembled_stiffness_to_round_off_on_every_cell_kind() {
    let mut rand = Rand(0x9E3779B97F4A7C15);
    for (name, mesh) in meshes() {
        let dof_of = clamped_low(&mesh);
        let n = dof_of.iter().flatten().count();
        let k = columns::stiffness(&mesh, &LAME, &dof_of, n);
        let op = CellKernel::new(Arc::new(mesh), LAME, &dof_of, None);
        assert_eq!(op.n(), n, "{name}");
        let mut worst = 0.0f64;
        for _ in 0..3 {
            let x: Vec<f64> = (0..n).map(|_| rand.next()).collect();
            let (mut y, mut z) = (vec![0.0; n], vec![0.0; n]);
            op.apply(&x, &mut y);
            k.mul_into(&x, &mut z);
            let mut bound = vec![0.0; n];
            for (i, j, v) in sparse::triplets(&k) {
                bound[i] += v.abs() * x[j].abs();
            }
            for i in 0..n {
                worst = worst.max((y[i] - z[i]).abs() / (f64::EPSILON * bound[i]));
                assert!(
                    (y[i] - z[i]).abs() <= 512.0 * f64::EPSILON * bound[i],
                    "{name}: row {i}: kernel {} vs assembled {} (|K||x| = {})",
                    y[i],
                    z[i],
                    bound[i]
                );
            }
            let scale: f64 = x.iter().zip(&bound).map(|(a, b)| a.abs() * b).sum();
            let (q, qk) = (op.quad_form(&x), k.quad_form(&x));
            assert!((q - qk).abs() <= 1024.0 * f64::EPSILON * scale, "{name}: xᵀKx {q} vs {qk}");
        }
        eprintln!("{name}: {n} unknowns, largest |Δ(Kx)_i| = {worst:.1} ε (|K||x|)_i");
    }
}

/// In frames (a curved obstacle's per-node frames, a plane's one frame): the kernel's product is
/// `Rᵀ K R x` with K the assembled world stiffness, to the same bound as in the world frame
/// (each rotation adds ≤ 3 ε relative). Every node takes a random frame (its first column a
/// random unit normal, `solid::body::rotation`), or all take one. (Mutation, as run: the
/// product rotated back with R instead of Rᵀ -> fails.)
#[test]
fn in_frames_the_kernel_is_the_rotated_assembled_stiffness() {
    use massredist::solid::Frames;
    use massredist::solid::body::rotation;
    let mut rand = Rand(0xD1B54A32D192ED03);
    for (name, mesh) in meshes() {
        let d = mesh.dim;
        let dof_of = clamped_low(&mesh);
        let n = dof_of.iter().flatten().count();
        let dofs: Vec<usize> = dof_of.iter().enumerate().filter_map(|(g, k)| k.map(|_| g)).collect();
        let k = columns::stiffness(&mesh, &LAME, &DofMap::identity(mesh.n_nodes() * d), mesh.n_nodes() * d);
        let mut normal = || {
            let v = [rand.next(), rand.next(), if d == 3 { rand.next() } else { 0.0 }];
            let l = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            rotation(v.map(|x| x / l), d)
        };
        let one = normal();
        let per_node: Vec<[[f64; 3]; 3]> = (0..mesh.n_nodes()).map(|_| normal()).collect();
        let mesh = Arc::new(mesh);
        for frames in [Frames::Global(one), Frames::Nodes(per_node)] {
            let op = CellKernel::new(Arc::clone(&mesh), LAME, &dof_of, Some(frames.clone()));
            let x: Vec<f64> = (0..n).map(|_| rand.next()).collect();
            // R x on full indices (0 where clamped), K, then Rᵀ.
            let mut xs = vec![0.0; mesh.n_nodes() * d];
            for (&g, &v) in dofs.iter().zip(&x) {
                xs[g] = v;
            }
            let world: Vec<f64> = (0..xs.len())
                .map(|g| {
                    let (node, i) = (g / d, g % d);
                    let r = frames.of(node);
                    (0..d).map(|kk| r[i][kk] * xs[node * d + kk]).sum()
                })
                .collect();
            let (mut kw, mut aw) = (vec![0.0; xs.len()], vec![0.0; xs.len()]);
            k.mul_into(&world, &mut kw);
            let absw: Vec<f64> = world.iter().map(|v| v.abs()).collect();
            for (i, j, v) in sparse::triplets(&k) {
                aw[i] += v.abs() * absw[j];
            }
            let mut y = vec![0.0; n];
            op.apply(&x, &mut y);
            for (kk, &g) in dofs.iter().enumerate() {
                let (node, i) = (g / d, g % d);
                let r = frames.of(node);
                let z: f64 = (0..d).map(|l| r[l][i] * kw[node * d + l]).sum();
                let bound: f64 = (0..d).map(|l| r[l][i].abs() * aw[node * d + l]).sum();
                assert!(
                    (y[kk] - z).abs() <= 512.0 * f64::EPSILON * bound,
                    "{name}: row {kk}: kernel {} vs Rᵀ K R x {z} (bound {bound})",
                    y[kk]
                );
            }
        }
    }
}

/// `mesh` as an MSH 2.2 ASCII file (gmsh's node order: `Cell::gmsh_order`), its cells in
/// physical group 1, and a physical group "fixed" of vertices: the nodes of [`clamped_low`].
fn write_msh(mesh: &Mesh, path: &std::path::Path) {
    use std::fmt::Write;
    let code = match mesh.kind {
        Cell::Triangle => 2,
        Cell::Quad => 3,
        Cell::Tet => 4,
        Cell::Hex => 5,
        Cell::Triangle6 => 9,
        Cell::Tet10 => 11,
    };
    let mut text = format!(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n0 2 \"fixed\"\n$EndPhysicalNames\n$Nodes\n{}\n",
        mesh.n_nodes()
    );
    for (i, p) in mesh.points.iter().enumerate() {
        writeln!(text, "{} {:e} {:e} {:e}", i + 1, p[0], p[1], p[2]).unwrap();
    }
    let dof_of = clamped_low(mesh);
    let fixed: Vec<usize> = (0..mesh.n_nodes()).filter(|&v| !dof_of.is_free(v * mesh.dim)).collect();
    writeln!(text, "$EndNodes\n$Elements\n{}", mesh.n_cells() + fixed.len()).unwrap();
    for (k, &v) in fixed.iter().enumerate() {
        writeln!(text, "{} 15 2 2 2 {}", mesh.n_cells() + k + 1, v + 1).unwrap();
    }
    let order = mesh.kind.gmsh_order();
    for c in 0..mesh.n_cells() {
        let v = mesh.cell(c);
        let mut listed = vec![0; v.len()];
        for (i, &node) in v.iter().enumerate() {
            listed[order[i]] = node + 1;
        }
        let nodes: Vec<String> = listed.iter().map(|n| n.to_string()).collect();
        writeln!(text, "{} {code} 2 1 1 {}", c + 1, nodes.join(" ")).unwrap();
    }
    text.push_str("$EndElements\n");
    std::fs::write(path, text).unwrap();
}

/// A body on `mesh` clamped on its group "fixed" (no rigid motion: a round-off force on one
/// would grow quadratically in time) with a smooth initial displacement and velocity in every component
/// (every coupling of K acts), the obstacle (`obstacle`: a plane or a circle/sphere) far below
/// it (never reached), mod3 (a massless layer on the facets that face it: the layer's
/// quasi-static rows are solved at every step), central differences with `operator` at dt.
fn free_body(path: &std::path::Path, dim: usize, obstacle: &str, operator: &str, dt: f64) -> String {
    let (fields, plane, sphere) = if dim == 2 {
        (
            "displacement = [\"0.01*y\", \"0.02*x*y\"], velocity = [\"0.05*x\", \"-0.03*y\"]",
            "normal = [0.0, 1.0]\npoint = [0.0, -100.0]",
            "shape = \"sphere\"\ncenter = [0.0, -130.0]\nradius = 30.0",
        )
    } else {
        (
            "displacement = [\"0.01*y*z\", \"0.02*x\", \"0.01*(y-z)\"], velocity = [\"0.05*x\", \"-0.03*y\", \"0.04*z\"]",
            "normal = [0.0, 1.0, 0.0]\npoint = [0.0, -100.0, 0.0]",
            "shape = \"sphere\"\ncenter = [0.0, -130.0, 0.0]\nradius = 30.0",
        )
    };
    let obstacle = if obstacle == "plane" { plane } else { sphere };
    format!(
        "[solid]\ndim = {dim}\nmesh = \"{}\"\nclamped = \"fixed\"\nlame_lambda = 0.7\nlame_mu = 0.45\ndensity = 1.3\ninitial = {{ {fields} }}\n[obstacle]\n{obstacle}\n[mass]\nkind = \"mod3\"\n[scheme]\nkind = \"central-difference\"\noperator = \"{operator}\"\n[time]\ndt = {dt}\nend = {}\n",
        path.display(),
        1000.0 * dt
    )
}

/// Without contact (the obstacle 100 below, λ = 0 at every step), central differences with the
/// kernel (`auto`) and with the assembled matrix follow the same trajectory on every cell kind
/// (the meshes of the product check, written as gmsh files and run as clamped bodies, against a
/// plane and, in per-node frames, a sphere): 1000 steps at 0.9 Δt_c agree to 1e-12 relative to
/// the largest |u| and |v| (the bound; gmsh's meshes 1e-11, on its line: the products differ at round-off, ≤ 512 ε of
/// `|K||x|` above, and a linear, stable recurrence carries such differences with growth at most
/// linear in the steps). The notes say which product each run uses. (Mutation, as run: the
/// kernel's λ scaled by 1 + 1e-9 -> fails on the first mesh.)
#[test]
fn without_contact_the_kernel_and_assembled_trajectories_agree_over_1000_steps() {
    let dir = tempfile::tempdir().unwrap();
    for (name, mesh) in meshes() {
        let path = dir.path().join(format!("{}.msh", name.replace(' ', "_")));
        write_msh(&mesh, &path);
        let dim = mesh.dim;
        for obstacle in ["plane", "sphere"] {
            let what = format!("{name} against a {obstacle}");
            let parse = |op: &str, dt: f64| {
                let text = free_body(&path, dim, obstacle, op, dt);
                massredist::scene::SolidScene::from_toml(&text).unwrap_or_else(|e| panic!("{what}: {e}\n{text}"))
            };
            let probe = massredist::run::setup(&parse("assembled", 1e-6)).unwrap();
            let (limit, _) = probe.scheme.stable_limit().unwrap();
            let dt = 0.9 * limit;
            let mut runs = ["assembled", "auto"].map(|op| massredist::run::setup(&parse(op, dt)).unwrap());
            let notes: Vec<String> = runs.iter().map(|r| r.scheme.note().unwrap()).collect();
            assert!(
                !notes[0].contains("matrix-free") && notes[1].contains("K u matrix-free (the cell-by-cell kernel)"),
                "{what}: {notes:?}"
            );
            let [du, dv, su, sv] = common::contact_free_lockstep(&mut runs, 1000, &what);
            eprintln!("{what}: |Δu| {du:.1e} of {su:.1e}, |Δv| {dv:.1e} of {sv:.1e}");
            // The 1e-12 on the generated meshes (every cell kind); gmsh's disc and
            // sphere (P2, mostly straight cells) 1e-11: their products differ by up to 102 ε of
            // |K||x| (the assembler's 15-point rule, whose weights have both signs, against the
            // kernel's 4 points), three times the generated meshes' 34 ε (measured at most
            // 2.4e-12 relative, in v, the sphere against the plane).
            let tol = if name.starts_with("gmsh") { 1e-11 } else { 1e-12 };
            assert!(du <= tol * su && dv <= tol * sv, "{what}: |Δu| {du:e} of {su:e}, |Δv| {dv:e} of {sv:e}");
        }
    }
}

/// The kernel's element eigenvalue bound (issue 31, item 3: Δt_c without a matrix where Lanczos
/// does not converge) bounds `λ_max(M_L,II⁻¹ K_II)`, computed densely from the assembled
/// stiffness, on every mesh of the checks (the lumped mass of `solid::lumped`, and again with
/// the nodes of the lowest fifth in y massless, as a contact layer is, which leaves them out of
/// I), from above: `bound ≥ λ_max (1 − 1e-12)` (the dense solver's own error, relative). Its
/// ratio to λ_max and the Gershgorin bound's are printed (`--nocapture`); measured: the element
/// bound 1.20–2.29 λ_max, Gershgorin's 1.35–2.21, the element bound the smaller on every Q1 mesh
/// and Gershgorin's on P1 simplices (a run takes the smaller). (Mutation, as run: each node's
/// whole lumped mass in every cell instead of its share -> below λ_max on the first mesh, fails.)
#[test]
fn the_kernels_element_bound_bounds_the_largest_eigenvalue() {
    for (name, mesh) in meshes() {
        let d = mesh.dim;
        let dof_of = clamped_low(&mesh);
        let n = dof_of.iter().flatten().count();
        if n > 1500 {
            continue; // the dense eigenvalues of larger meshes take too long in the test profile
        }
        let dofs: Vec<usize> = dof_of.iter().enumerate().filter_map(|(g, k)| k.map(|_| g)).collect();
        let k = columns::stiffness(&mesh, &LAME, &dof_of, n);
        let weights = vec![1.0; mesh.n_cells()];
        let directions = massredist::mass::ContactDirections::All;
        let lumped = massredist::solid::lumped::lumped_on(&mesh, &weights, directions, LAME.density, &dofs);
        let low = mesh.points.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
        let high = mesh.points.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max);
        let layer: Vec<f64> = dofs
            .iter()
            .zip(&lumped)
            .map(|(&g, &m)| if mesh.points[g / d][1] < low + 0.2 * (high - low) { 0.0 } else { m })
            .collect();
        let op = CellKernel::new(Arc::new(mesh), LAME, &dof_of, None);
        for (what, m) in [("lumped", &lumped), ("with a massless layer", &layer)] {
            let kept: Vec<usize> = (0..n).filter(|&i| m[i] > 0.0).collect();
            let dense = sparse::to_dense(&k);
            let a = faer::Mat::<f64>::from_fn(kept.len(), kept.len(), |i, j| {
                dense[kept[i]][kept[j]] / (m[kept[i]] * m[kept[j]]).sqrt()
            });
            let lam = *a.self_adjoint_eigenvalues(faer::Side::Lower).unwrap().last().unwrap();
            let bound = op.element_bound(m).expect("the kernel has an element bound");
            let inv: Vec<f64> = m.iter().map(|&x| if x > 0.0 { 1.0 / x.sqrt() } else { 0.0 }).collect();
            let ones: Vec<f64> = inv.iter().map(|&s| if s > 0.0 { 1.0 } else { 0.0 }).collect();
            let mut rows = vec![0.0; n];
            op.apply_abs(&ones.iter().zip(&inv).map(|(o, s)| o * s).collect::<Vec<_>>(), &mut rows);
            let gershgorin = rows.iter().zip(&inv).map(|(r, s)| r * s).fold(0.0f64, f64::max);
            eprintln!("{name} ({what}): element bound {:.3} λ_max, Gershgorin {:.3}", bound / lam, gershgorin / lam);
            assert!(bound >= lam * (1.0 - 1e-12), "{name} ({what}): element bound {bound:e} below λ_max {lam:e}");
        }
    }
}
