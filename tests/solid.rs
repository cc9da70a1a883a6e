//! Elastic solids in 2D and 3D: reduction of Q1 with plane-wave data to the 1D bar (λ = 0, and
//! roller faces with λ > 0), exact L² errors, node-wise complementarity, the energy identities
//! of the hybrid, Crank–Nicolson and backward Euler schemes, total mass, rigid motions, and the
//! `[solid]` keys.

use massredist::driver::{Observer, Sample, integrate};
use massredist::fem::Cell;
use massredist::fem::layers::{cell_weights, layers};
use massredist::linalg::sparse;
use massredist::mass::MassKind;
use massredist::models::{PaperBar, PlaneWaveSolid, RoundOffGrowth};
use massredist::observe::{EnergyRecorder, SummaryObserver};
use massredist::problem::Problem;
use massredist::scene::parse_solid;
use massredist::scene::{Formulation, SchemeSpec};
use massredist::schemes::{Hybrid, Scheme};
use massredist::solid::{Lame, Lateral, SolidSpec, SolidSystem};

const CN: SchemeSpec = SchemeSpec::CrankNicolson { formulation: Formulation::Full };
const SCHEMES: [SchemeSpec; 3] = [CN, SchemeSpec::BackwardEuler, SchemeSpec::Hybrid];

fn spec(text: &str) -> SolidSpec {
    parse_solid(&toml::from_str::<toml::Table>(text).unwrap()).unwrap()
}

/// Steps a solid and a bar side by side; max over steps 0..=steps of |u_x − u_1D(x_i)|,
/// |v_x − v_1D| and of the transverse components (which the plane wave has 0).
fn solid_vs_bar(
    solid: &Problem<SolidSystem>,
    bar: &Problem<massredist::bar::BarSystem>,
    scheme: &SchemeSpec,
    dt: f64,
    steps: usize,
) -> [f64; 3] {
    let g = &solid.system;
    let (d, n1) = (g.mesh.dim, g.mesh.grid.unwrap()[0] + 1);
    let (mut s2, mut s1) = (solid.scheme(scheme, dt).unwrap(), bar.scheme(scheme, dt).unwrap());
    let mut worst = [0.0f64; 3];
    let mut contact_steps = 0;
    for n in 0..=steps {
        let (a, b) = (s2.state(), s1.state());
        for (k, &full) in g.dofs.iter().enumerate() {
            let (node, comp) = (full / d, full % d);
            if comp == 0 {
                worst[0] = worst[0].max((a.u[k] - b.u[node % n1]).abs());
                worst[1] = worst[1].max((a.v[k] - b.v[node % n1]).abs());
            } else {
                worst[2] = worst[2].max(a.u[k].abs());
            }
        }
        contact_steps += usize::from(b.lambda[0] < 0.0);
        if n < steps {
            s2.step().unwrap();
            s1.step().unwrap();
        }
    }
    assert!(contact_steps > 0, "the run must reach the obstacle");
    worst
}

#[test]
fn q1_with_the_paper_data_is_the_1d_solution_extended_in_y_and_z() {
    // The model's reduction (models::PlaneWaveSolid: λ = 0, μ = ½, ρ = 1, the contact LCP has
    // the y-constant solution): each step is the 1D step, to round-off growing at most linearly
    // (its tolerance, models::RoundOffGrowth, says why).
    // Mutation: the cell weight dropped from the vector mass (w_c → 1 in solid::assembly) ->
    // fails at "2D crank-nicolson mod1".
    let (dt, steps) = (0.01, 300);
    let RoundOffGrowth { u: tol_u, v: tol_v } = PlaneWaveSolid::tolerance(steps, dt);
    for (dim, cells) in [(2, [20, 3, 0]), (3, [10, 2, 2])] {
        let solid = PlaneWaveSolid { dim, cells };
        for mass in [MassKind::Mod1, MassKind::Mod2, MassKind::Mod3] {
            let p = solid.problem(&mass, 3.0).unwrap();
            let bar = solid.reference().problem(&mass).unwrap();
            for scheme in &SCHEMES {
                let [du, dv, dt_] = solid_vs_bar(&p, &bar, scheme, dt, steps);
                eprintln!("{dim}D Q1 vs 1D {} {}: |du| {du:e} |dv| {dv:e} |u_t| {dt_:e}", scheme.name(), mass.name());
                assert!(du <= tol_u && dv <= tol_v && dt_ <= tol_u, "{dim}D {} {}", scheme.name(), mass.name());
            }
        }
    }
}

#[test]
fn roller_faces_with_lambda_give_the_bar_of_modulus_lambda_plus_2mu() {
    // λ = 1, μ = 0.75, ρ = 2.5 with u·n = 0 on the lateral faces: the plane wave of speed
    // sqrt((λ+2μ)/ρ) = 1, and the Q1 solid steps as the bar of modulus 2.5 and density 2.5,
    // with a gap and expression data. Mutation: the λ term dropped from the stiffness
    // (λ ∂_i φa ∂_j φb → 0) -> fails at "2D crank-nicolson".
    let (dt, steps) = (0.01, 200);
    let RoundOffGrowth { u: tol_u, v: tol_v } = RoundOffGrowth::new(steps, dt); // as the plane wave's
    let tail = "[mass]\nkind = \"mod3\"\n[time]\ndt = 0.01\nend = 2.0\n";
    let bar_text = format!(
        "[bar]\nelements = 12\ndensity = 2.5\nmodulus = 2.5\ngap = 0.05\n\
         initial = {{ displacement = \"0.1*(1-x)\", velocity = \"-(1-x)\" }}\n{tail}"
    );
    let bar = Problem::from_scene(&massredist::scene::Scene::from_toml(&bar_text).unwrap()).unwrap();
    for (dim, extra, cells) in [(2, "", "quad"), (3, "nz = 2\ndepth = 0.5\n", "hex")] {
        let s = spec(&format!(
            "dim = {dim}\nnx = 12\nny = 2\nheight = 0.5\n{extra}cells = \"{cells}\"\nlame_lambda = 1.0\nlame_mu = 0.75\n\
             density = 2.5\ngap = 0.05\nlateral = \"roller\"\n\
             initial = {{ displacement = [\"0.1*(1-x)\", \"0\"{z}], velocity = [\"-(1-x)\", \"0\"{z}] }}",
            z = if dim == 3 { ", \"0\"" } else { "" }
        ));
        assert!(s.is_plane_wave());
        let p = s.problem(&MassKind::Mod3, 2.0).unwrap();
        assert_eq!(p.system.system.lower[0], -0.05);
        for scheme in &SCHEMES {
            let [du, dv, dt_] = solid_vs_bar(&p, &bar, scheme, dt, steps);
            eprintln!("{dim}D roller vs bar {}: |du| {du:e} |dv| {dv:e} |u_t| {dt_:e}", scheme.name());
            assert!(du <= tol_u && dv <= tol_v && dt_ <= tol_u, "{dim}D {}", scheme.name());
        }
    }
}

#[test]
fn q1_l2_error_is_the_1d_error_times_the_root_of_the_section() {
    // ‖e‖²_{L²(Ω)^d} = |Γ_C| ‖e_1D‖² for a plane-wave error; both are exact integrals split at
    // the kinks, and the states agree to ~1e-12 (test above). Mutation: the Gauss weight ½ → 1
    // in SolidSystem::x_error_squared -> fails by a factor sqrt(2) (sqrt(4) in 3D).
    let steps = 300;
    let bar = PaperBar::unit(10).problem(&MassKind::Mod3).unwrap();
    let mut s1 = bar.scheme(&CN, 0.01).unwrap();
    let mut sum1 = SummaryObserver::new(&bar, steps, 0.01, true);
    integrate(&bar, s1.as_mut(), steps, &mut [&mut sum1]).unwrap();
    let e1 = sum1.finish().linf_l2_error.unwrap();
    for (dim, text) in
        [(2, "nx = 10\nny = 3\nheight = 0.5"), (3, "dim = 3\nnx = 10\nny = 2\nnz = 3\nheight = 0.5\ndepth = 0.4")]
    {
        let p = spec(text).problem(&MassKind::Mod3, 3.0).unwrap();
        let mut sum = SummaryObserver::new(&p, steps, 0.01, true);
        let mut s = p.scheme(&CN, 0.01).unwrap();
        integrate(&p, s.as_mut(), steps, &mut [&mut sum]).unwrap();
        let summary = sum.finish();
        let area: f64 = if dim == 2 { 0.5 } else { 0.2 };
        let e = summary.linf_l2_error.unwrap();
        assert!(
            approx::relative_eq!(e, area.sqrt() * e1, epsilon = 1e-10, max_relative = 0.0),
            "{dim}D: {e} vs {}",
            area.sqrt() * e1
        );
        // The driver's pressure is the total reaction over |Γ_C|, so λ compares with the bar's.
        assert!(summary.max_y_variation.unwrap() <= 1e-11, "{dim}D: {:?}", summary.max_y_variation);
    }
}

/// Node-wise Signorini complementarity at every step.
#[derive(Default)]
struct Complementarity {
    worst_product: f64,
    below: f64,
    max_lambda: f64,
    mixed_steps: usize,
}

impl Observer for Complementarity {
    fn observe(&mut self, s: &Sample) {
        let lower = -0.02;
        let mut active = 0;
        for (c, &i) in s.geometry.contact().iter().enumerate() {
            let (u, l) = (s.state.u[i], s.state.lambda[c]);
            self.worst_product = self.worst_product.max(((u - lower) * l).abs());
            self.below = self.below.max(lower - u);
            self.max_lambda = self.max_lambda.max(l);
            active += usize::from(l < 0.0);
        }
        if active > 0 && active < s.state.lambda.len() {
            self.mixed_steps += 1;
        }
    }
}

/// A y-dependent solid (the contact state varies along Γ_C) with λ > 0 and free lateral faces.
fn bumpy(cells: &str) -> SolidSpec {
    let dim = if cells == "quad" || cells == "triangle" { 2 } else { 3 };
    let (n, z) = if dim == 2 { ("nx = 8\nny = 6", "") } else { ("dim = 3\nnx = 6\nny = 4\nnz = 3", ", \"0\"") };
    spec(&format!(
        "{n}\ncells = \"{cells}\"\nlame_lambda = 0.6\nlame_mu = 0.5\ngap = 0.02\n\
         initial = {{ displacement = [\"(1-x)/2*(1+0.5*cos(pi*y/H))\", \"0.05*x*y\"{z}], velocity = [\"0\", \"0\"{z}] }}"
    ))
}

#[test]
fn contact_is_solved_exactly_node_by_node_on_every_cell_type() {
    // Active nodes get u_x = −gap exactly, inactive ones λ = 0 exactly (the LCP sets them), so
    // the product is 0 bit for bit. Mutation: Schur::solve without `rhs[i] = lower[c]` -> fails
    // with a product of ~1e-17.
    for cells in ["quad", "triangle", "hex", "tet"] {
        let p = bumpy(cells).problem(&MassKind::Mod3, 3.0).unwrap();
        for scheme in &SCHEMES {
            let mut s = p.scheme(scheme, 0.02).unwrap();
            let mut c = Complementarity::default();
            integrate(&p, s.as_mut(), 150, &mut [&mut c]).unwrap();
            let label = format!("{cells} {}", scheme.name());
            assert_eq!(c.worst_product, 0.0, "{label}");
            assert!(c.below <= 0.0 && c.max_lambda <= 0.0, "{label}: {} {}", c.below, c.max_lambda);
            assert!(c.mixed_steps > 0, "{label}: the contact state never varied along Γ_C");
        }
    }
}

#[test]
fn hybrid_energy_never_increases_and_its_identity_holds() {
    // ΔE = (λ^{n+1})ᵀ(ũ − lb) + (u_Cⁿ − lb)ᵀλ̄ − ½ d_Cᵀ D d_C ≤ 0 with D the Schur complement
    // of the free massless (tangential) unknowns (schemes::hybrid module docs). E = O(0.1) is a
    // sum of O(n) products: its evaluation error is ~ n ε · 0.1 ≤ 1e4 ε for these sizes.
    // Mutation: D = S_CC without the Schur correction of the free massless unknowns (in
    // QuasiStatic::with_free) -> fails: quad mod1 ΔE 1.0e-4, identity off by 2.5e-2. (Φ
    // without the free unknowns keeps this identity, with them extrapolated like interior
    // unknowns; the quasi-static test below catches that.)
    let tol = 1e4 * f64::EPSILON;
    for cells in ["quad", "triangle", "hex", "tet"] {
        for mass in [MassKind::Mod1, MassKind::Mod3] {
            let p = bumpy(cells).problem(&mass, 3.0).unwrap();
            let sys = &p.system.system;
            let mut h = Hybrid::new(sys, 0.02, p.u0.clone(), p.v0.clone()).unwrap();
            let mut e = sys.energy(h.state().u, h.state().v);
            let (mut worst, mut off, mut contact) = (f64::NEG_INFINITY, 0.0f64, 0);
            for _ in 0..150 {
                h.step().unwrap();
                let e_new = sys.energy(h.state().u, h.state().v);
                let terms = h.energy_terms();
                worst = worst.max(e_new - e);
                off = off.max((e_new - e - terms.iter().sum::<f64>()).abs());
                assert!(terms.iter().all(|&t| t <= tol), "{cells} {}: {terms:?}", mass.name());
                contact += usize::from(h.state().lambda.iter().any(|&l| l < 0.0));
                e = e_new;
            }
            eprintln!("hybrid {cells} {}: largest ΔE {worst:e}, identity off by {off:e}", mass.name());
            assert!(contact > 0, "{cells}: no contact");
            assert!(worst <= tol && off <= tol, "{cells} {}: ΔE {worst:e}, identity {off:e}", mass.name());
        }
    }
}

/// The largest residual of the massless rows: `|(S U − F)_i|` on the free massless unknowns
/// and `|(S U − F)_c + λ_c|` on the contact ones.
struct QuasiStaticRows<'a> {
    system: &'a massredist::system::ContactSystem<sparse::SpMat>,
    residual: Vec<f64>,
    worst_free: f64,
    worst_contact: f64,
}

impl Observer for QuasiStaticRows<'_> {
    fn observe(&mut self, s: &Sample) {
        if s.state.n == 0 {
            return; // the interpolated initial data need not be quasi-static (CN and BE report them)
        }
        sparse::sym_mul_into(&self.system.stiffness, s.state.u, &mut self.residual);
        let contact = &self.system.contact;
        for (i, r) in self.residual.iter().enumerate() {
            if !self.system.massless[i] {
                continue;
            }
            let r = r - self.system.load[i];
            match contact.iter().position(|&c| c == i) {
                Some(c) => self.worst_contact = self.worst_contact.max((r + s.state.lambda[c]).abs()),
                None => self.worst_free = self.worst_free.max(r.abs()),
            }
        }
    }
}

#[test]
fn massless_components_are_quasi_static_at_every_step() {
    // Every component of a contact-face node is massless; the tangential ones carry no contact
    // condition, so their rows read (S U − F)_i = 0 at every t_n (n ≥ 1), and the normal ones
    // (S U − F)_c = −λ_c. Newmark and backward Euler solve these rows with the step; the hybrid
    // scheme sets them with its quasi-static map Φ (schemes::hybrid, "free massless unknowns").
    // Residual: ≤ 81 entries of size ≤ 2(λ + 2μ) times |u| ≤ 1, plus the backward error of the
    // solves (condition numbers ≤ 1e3 at these sizes): 1e-12.
    // Mutation: Φ without the free massless unknowns (QuasiStatic::new in Hybrid::new) -> fails
    // for the hybrid scheme (quad: tangential residual 5.3e-2, the extrapolation 2ū − uⁿ).
    for cells in ["quad", "triangle", "hex", "tet"] {
        let p = bumpy(cells).problem(&MassKind::Mod3, 3.0).unwrap();
        let sys = &p.system.system;
        assert!(sys.massless.iter().filter(|&&m| m).count() > sys.contact.len(), "{cells}: free massless unknowns");
        for scheme in &SCHEMES {
            let mut s = p.scheme(scheme, 0.02).unwrap();
            let mut q =
                QuasiStaticRows { system: sys, residual: vec![0.0; sys.n()], worst_free: 0.0, worst_contact: 0.0 };
            integrate(&p, s.as_mut(), 100, &mut [&mut q]).unwrap();
            eprintln!("{cells} {}: free rows {:e}, contact rows {:e}", scheme.name(), q.worst_free, q.worst_contact);
            assert!(
                q.worst_free <= 1e-12 && q.worst_contact <= 1e-12,
                "{cells} {}: {} {}",
                scheme.name(),
                q.worst_free,
                q.worst_contact
            );
        }
    }
}

#[test]
fn crank_nicolson_without_contact_conserves_energy_and_backward_euler_dissipates() {
    // u⁰ = 0 satisfies the massless (quasi-static) rows, and the gap keeps the solid off the
    // obstacle: CN conserves ½VᵀMV + ½UᵀSU exactly (schemes::newmark), up to round-off: a few
    // ε E per step of the solve (16 ε E per step, accumulated over the steps) plus the
    // evaluation of the quadratic forms (one ε E per stored entry of S, a worst case).
    // BE: ΔE ≤ 0 at every step, to the same evaluation round-off.
    // Mutation: Newmark::crank_nicolson with β = 0.3 -> fails (quad: drift 2.8e-7).
    for cells in ["quad", "triangle", "hex", "tet"] {
        let dim = if cells == "quad" || cells == "triangle" { 2 } else { 3 };
        let z = if dim == 3 { ", \"0\"" } else { "" };
        let n = if dim == 2 { "nx = 8\nny = 5" } else { "dim = 3\nnx = 5\nny = 3\nnz = 3" };
        let s = spec(&format!(
            "{n}\ncells = \"{cells}\"\nlame_lambda = 0.6\ngap = 1.0\n\
             initial = {{ displacement = [\"0\", \"0\"{z}], velocity = [\"0.1*sin(pi*x)*(1+y)\", \"0.05*x*(1-x)\"{z}] }}"
        ));
        let p = s.problem(&MassKind::Mod2, 1.0).unwrap();
        for (scheme, conserves) in [(CN, true), (SchemeSpec::BackwardEuler, false)] {
            let mut sch = p.scheme(&scheme, 0.01).unwrap();
            let mut e = EnergyRecorder::default();
            integrate(&p, sch.as_mut(), 200, &mut [&mut e]).unwrap();
            let nnz = sparse::triplets(&p.system.system.stiffness).count();
            let tol = (200.0 * 16.0 + nnz as f64) * f64::EPSILON * e.energy[0];
            let worst = if conserves {
                e.energy.iter().map(|x| (x - e.energy[0]).abs()).fold(0.0, f64::max)
            } else {
                e.energy.windows(2).map(|w| w[1] - w[0]).fold(f64::NEG_INFINITY, f64::max)
            };
            eprintln!("{cells} {}: E0 {} worst {worst:e}", scheme.name(), e.energy[0]);
            assert!(worst <= tol, "{cells} {}: {worst:e}", scheme.name());
        }
    }
}

#[test]
fn total_mass_and_massless_contact_faces_for_every_redistribution() {
    // 1ᵀM1 = d ρ Σ_c w_c |c| (the basis sums to 1, d components): |Ω| − A_0 (mod1), |Ω| (mod2,
    // mod3, standard), and every row of a node on x = 0 vanishes (all components massless).
    // Mutation: ρ dropped from the vector mass in solid::assembly -> fails (quad standard: 2.0
    // vs 3.4).
    let rho = 1.7;
    let lame = Lame { lambda: 0.3, mu: 0.4, density: rho };
    for cells in ["quad", "triangle", "hex", "tet"] {
        let mesh = bumpy(cells).mesh().unwrap();
        let d = mesh.dim as f64;
        let vol: f64 = (0..mesh.n_cells()).map(|c| mesh.measure(c)).sum();
        let a0: f64 = layers(&mesh).iter().enumerate().filter(|(_, l)| **l == 0).map(|(c, _)| mesh.measure(c)).sum();
        for (kind, expected) in
            [(MassKind::Standard, vol), (MassKind::Mod1, vol - a0), (MassKind::Mod2, vol), (MassKind::Mod3, vol)]
        {
            let w = cell_weights(&mesh, &kind).unwrap();
            let (m, _) = massredist::solid::assembly::assemble(&mesh, &w, &lame).unwrap();
            let tol = 16.0 * mesh.n_cells() as f64 * f64::EPSILON * d * rho;
            let total = sparse::total(&m);
            assert!(
                approx::relative_eq!(total, d * rho * expected, epsilon = tol, max_relative = 0.0),
                "{cells} {kind:?}: {total} vs {}",
                d * rho * expected
            );
            if kind != MassKind::Standard {
                for v in (0..mesh.n_nodes()).filter(|&v| mesh.on_contact(v)) {
                    for i in 0..mesh.dim {
                        assert_eq!(sparse::get(&m, v * mesh.dim + i, v * mesh.dim + i), 0.0, "{cells} node {v}");
                    }
                }
            }
        }
    }
}

/// `mass.contact_directions = "normal"`: component 0 (the normal, the box's x) of the directed
/// mass is the weighted mass's, every other component the standard mass's, entry by entry and
/// bit for bit (the same sums); the stiffness is untouched.
/// mutation: `ContactDirections::weight` returning `w` for every component -> the tangential
/// rows differ (the contact nodes' vanish).
#[test]
fn the_normal_directions_mass_weights_only_the_normal_component() {
    use massredist::mass::ContactDirections;
    use massredist::solid::assembly::{assemble, assemble_directed};
    let lame = Lame { lambda: 0.3, mu: 0.4, density: 1.7 };
    for cells in ["quad", "triangle", "hex", "tet"] {
        let mesh = bumpy(cells).mesh().unwrap();
        let d = mesh.dim;
        let w = cell_weights(&mesh, &MassKind::Mod3).unwrap();
        let (weighted, stiff) = assemble(&mesh, &w, &lame).unwrap();
        let (standard, _) = assemble(&mesh, &vec![1.0; mesh.n_cells()], &lame).unwrap();
        let (normal, stiff_n) = assemble_directed(&mesh, &w, ContactDirections::Normal, &lame).unwrap();
        let entries = |m: &sparse::SpMat| sparse::triplets(m).collect::<Vec<_>>();
        assert_eq!(entries(&stiff), entries(&stiff_n), "{cells}: the stiffness");
        let n = mesh.n_nodes() * d;
        let mut tangential_rows_differ = false;
        for i in 0..n {
            for j in (i % d..n).step_by(d) {
                let want = if i % d == 0 { sparse::get(&weighted, i, j) } else { sparse::get(&standard, i, j) };
                assert_eq!(sparse::get(&normal, i, j), want, "{cells}: entry ({i}, {j})");
                tangential_rows_differ |= i % d > 0 && want != sparse::get(&weighted, i, j);
            }
        }
        assert!(tangential_rows_differ, "{cells}: mod3 changes the tangential rows under \"all\"");
    }
}

#[test]
fn rigid_motions_are_in_the_kernel_of_the_free_stiffness() {
    // Before boundary conditions S r = 0 for the translations and the infinitesimal rotations
    // (ε(r) = 0), and S is symmetric. Entries O(λ + μ) ≤ 2: sums of ≤ 30 element terms.
    // Mutation: the μ term ∂_j φa ∂_i φb → ∂_i φa ∂_j φb -> the rotation fails (quad: 0.1).
    let lame = Lame { lambda: 0.8, mu: 0.6, density: 1.0 };
    for cells in ["quad", "triangle", "hex", "tet"] {
        let mesh = bumpy(cells).mesh().unwrap();
        let d = mesh.dim;
        let (_, s) = massredist::solid::assembly::assemble(&mesh, &vec![1.0; mesh.n_cells()], &lame).unwrap();
        let mut motions: Vec<Box<dyn Fn([f64; 3]) -> [f64; 3]>> =
            vec![Box::new(|_| [1.0, 0.0, 0.0]), Box::new(|_| [0.0, 1.0, 0.0]), Box::new(|p| [-p[1], p[0], 0.0])];
        if d == 3 {
            motions.push(Box::new(|_| [0.0, 0.0, 1.0]));
            motions.push(Box::new(|p| [0.0, -p[2], p[1]]));
            motions.push(Box::new(|p| [p[2], 0.0, -p[0]]));
        }
        for (k, r) in motions.iter().enumerate() {
            let x: Vec<f64> = (0..mesh.n_nodes() * d).map(|g| r(mesh.points[g / d])[g % d]).collect();
            let mut y = vec![0.0; x.len()];
            sparse::sym_mul_into(&s, &x, &mut y);
            let worst = y.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            assert!(worst <= 30.0 * 4.0 * f64::EPSILON * 10.0, "{cells} motion {k}: {worst:e}");
        }
        for (i, j, v) in sparse::triplets(&s) {
            assert!(
                approx::relative_eq!(
                    v,
                    sparse::get(&s, j, i),
                    epsilon = 4.0 * f64::EPSILON * v.abs().max(1.0),
                    max_relative = 0.0
                ),
                "{cells} S[{i},{j}]"
            );
        }
    }
}

#[test]
fn solid_keys_are_validated_with_their_ranges() {
    let err = |t: &str| parse_solid(&toml::from_str::<toml::Table>(t).unwrap()).unwrap_err().to_string();
    assert!(err("dim = 4").contains("solid.dim") && err("dim = 4").contains("2 | 3"));
    assert!(err("cells = \"hex\"").contains("solid.cells"));
    assert!(err("dim = 3\ncells = \"quad\"").contains("hex | tet"));
    assert!(err("lame_lambda = -1").contains("solid.lame_lambda"));
    assert!(err("lame_mu = 0").contains("solid.lame_mu"));
    assert!(err("density = -2").contains("solid.density"));
    // A subnormal density made masses of 0 and ran (kinetic energy 0 throughout): refused.
    let e = err("density = 1e-320");
    assert!(e.contains("solid.density") && e.contains("a normal double"), "{e}");
    assert!(err("gap = -0.1").contains("solid.gap"));
    assert!(err("lateral = \"glued\"").contains("solid.lateral"));
    assert!(err("nx = 1").contains("solid.nx"));
    assert!(err("nz = 3").contains("solid.nz"));
    assert!(err("force = [1.0]").contains("solid.force"));
    assert!(err("initial = { displacement = [\"x\"] }").contains("solid.initial"));
    assert!(err("initial = { displacement = [\"x+\", \"0\"] }").starts_with("solid.initial.displacement"));
    assert!(err("heigth = 2").contains("[solid]: unknown field `heigth`"));
    let s = spec("dim = 3\ncells = \"tet\"\nlateral = \"roller\"\nlame_lambda = 2\nforce = [0, 0, -1]");
    let support = massredist::solid::Support::Face { gap: 0.0, lateral: Lateral::Roller, force: [0.0, 0.0, -1.0] };
    assert_eq!((s.dim, s.cells, s.support.clone()), (3, Cell::Tet, support));
    assert!(!s.is_plane_wave());
}

#[test]
fn vtu_frames_carry_vectors_and_pressure_and_read_back() {
    // A 3D hexahedral and a 2D triangular run with VTU frames: the files read back (our reader)
    // to the recorded vectors bit for bit (shortest round-trip formatting), the cells are VTK
    // hexahedra (12) / triangles (5), and the pressure times the nodal face areas gives back λ
    // (Σ_c ∫φ_c = |Γ_C| checks the areas). Mutation: to_3d writing (x, y, 0) in 3D -> fails on
    // "displacement".
    use massredist::fem::vtu::{read_pvd, read_vtu};
    use massredist::observe::FrameRecorder;
    for (cells, vtk) in [("hex", 12u8), ("triangle", 5u8)] {
        let p = bumpy(cells).problem(&MassKind::Mod3, 3.0).unwrap();
        let g = &p.system;
        let area: f64 = g.contact_areas.iter().sum();
        assert!(
            approx::relative_eq!(area, g.mesh.face_area(), epsilon = 16.0 * f64::EPSILON, max_relative = 0.0),
            "{cells}: {area}"
        );
        let mut s = p.scheme(&SchemeSpec::Hybrid, 0.02).unwrap();
        let mut frames = FrameRecorder::new(25);
        integrate(&p, s.as_mut(), 100, &mut [&mut frames]).unwrap();
        let dir = tempfile::tempdir().unwrap();
        massredist::solid::vtu::write_frames(dir.path(), g, &frames.frames).unwrap();
        let pvd = read_pvd(&std::fs::read_to_string(dir.path().join("solid.pvd")).unwrap());
        assert_eq!(pvd.len(), 5);
        let d = g.mesh.dim;
        let mut pressed = 0;
        for ((t, file), frame) in pvd.iter().zip(&frames.frames) {
            assert_eq!(*t, frame.t);
            let data = read_vtu(std::fs::read(dir.path().join(file)).unwrap()).unwrap();
            assert_eq!((data.n_points, data.n_cells), (g.mesh.n_nodes(), g.mesh.n_cells()));
            assert_eq!(data.connectivity, g.mesh.cells);
            assert!(data.types.iter().all(|&t| t == vtk));
            let disp = &data.point_array("displacement").unwrap().values;
            for (node, chunk) in disp.chunks(3).enumerate() {
                for i in 0..3 {
                    let want = if i < d { frame.u[node * d + i] } else { 0.0 };
                    assert_eq!(chunk[i], want, "{cells} displacement node {node}");
                }
            }
            let pressure = &data.point_array("contact_pressure").unwrap().values;
            for (c, &node) in g.contact_nodes.iter().enumerate() {
                let back = pressure[node] * g.contact_areas[c];
                approx::assert_relative_eq!(
                    back,
                    frame.lambda[c],
                    epsilon = 4.0 * f64::EPSILON * frame.lambda[c].abs(),
                    max_relative = 0.0
                );
                pressed += usize::from(frame.lambda[c] < 0.0);
            }
            assert_eq!(data.cell_array("weight").unwrap().values, g.weights);
        }
        assert!(pressed > 0, "{cells}: no frame in contact");
    }
}

/// `max_n ‖u_h(t_n) − I_h u(t_n)‖_{L²(Ω)^d}` against the plane wave (I_h the nodal
/// interpolant), for any cell type.
fn max_discrete_error(p: &Problem<SolidSystem>, scheme: &SchemeSpec, dt: f64, steps: usize) -> f64 {
    let g = &p.system;
    let exact = p.exact.as_ref().unwrap();
    let d = g.mesh.dim;
    let mut s = p.scheme(scheme, dt).unwrap();
    let mut worst = 0.0f64;
    let mut e = vec![0.0; g.dofs.len()];
    for n in 0..=steps {
        let st = s.state();
        for (k, &full) in g.dofs.iter().enumerate() {
            let x = g.mesh.points[full / d][0];
            e[k] = st.u[k] - if full % d == 0 { exact.u(x, st.t) } else { 0.0 };
        }
        worst = worst.max(sparse::quad_form(g.mass_unit(), &e).sqrt());
        if n < steps {
            s.step().unwrap();
        }
    }
    worst
}

#[test]
fn simplices_converge_towards_the_plane_wave() {
    // P1 triangles and tetrahedra are not tensor products, so their solutions depart from the
    // plane wave; they converge to it as h → 0 (Δt = h/2, T = 2: through impact and contact,
    // hybrid scheme, mod3), in the discrete norm ‖u_h − I_h u‖. Every refinement must reduce the
    // error and the fitted slope of log error against log h must be ≥ 1 (measured: 1.31 for
    // triangles 8..32, 1.39 for tetrahedra 4..12; errors printed).
    // Mutation: the P1 mass denominator (d+1)(d+2) → (d+1)(d+1) in fem::element (a wrong wave
    // speed) -> fails.
    for (cells, sizes) in [("triangle", [8usize, 16, 32]), ("tet", [4, 8, 12])] {
        let mut pts = Vec::new();
        for &n in &sizes {
            let text = if cells == "triangle" {
                format!("nx = {n}\nny = {}\ncells = \"triangle\"", (n / 4).max(1))
            } else {
                format!("dim = 3\nnx = {n}\nny = {}\nnz = {}\ncells = \"tet\"", (n / 4).max(1), (n / 4).max(1))
            };
            let p = spec(&text).problem(&MassKind::Mod3, 2.0).unwrap();
            let h = 1.0 / n as f64;
            let steps = (2.0 / (h / 2.0)).round() as usize;
            let e = max_discrete_error(&p, &SchemeSpec::Hybrid, h / 2.0, steps);
            eprintln!("{cells} n = {n}: max error {e:e}");
            pts.push((h.ln(), e.ln()));
        }
        assert!(pts.windows(2).all(|w| w[1].1 < w[0].1), "{cells}: {pts:?}");
        let (mx, my) = (pts.iter().map(|p| p.0).sum::<f64>() / 3.0, pts.iter().map(|p| p.1).sum::<f64>() / 3.0);
        let slope = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>()
            / pts.iter().map(|p| (p.0 - mx).powi(2)).sum::<f64>();
        eprintln!("{cells}: fitted rate {slope:.3}");
        assert!(slope >= 1.0, "{cells}: rate {slope}");
    }
}

#[test]
fn numeric_initial_values_are_kept_exactly() {
    // Issue 22 D7: numbers in solid.initial were turned into 5-digit text (-0.123456789 became
    // -1.2346e-1). They are kept as their shortest round-trip text, so the values are exact, in
    // the spec and after the resolved scene is read back. Mutation: `crate::expr::sci` instead of
    // `short` in solid/table/mod.rs -> fails (-0.12346 != -0.123456789).
    let s = spec("initial = { displacement = [-0.123456789, 0.987654321], velocity = [1e-7, 3] }");
    let massredist::solid::SolidInitial::Fields { displacement, velocity } = &s.initial else { panic!("fields") };
    let at = [0.3, 0.7];
    let values: Vec<f64> = displacement.iter().chain(velocity).map(|e| e.eval(&at)).collect();
    assert_eq!(values, [-0.123456789, 0.987654321, 1e-7, 3.0]);
}
