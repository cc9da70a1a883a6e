//! `massredist bench --explicit-scaling CSV`: time per step and peak memory against unknowns on
//! 3D hex solids, implicit (Crank–Nicolson: one sparse Cholesky factor, the solid scaling of
//! [`super::baseline`]) against explicit central differences (issue 20, item 3).
//!
//! Cases (the plane-wave solid's paper data, `SolidSpec::paper`, h = 1/N):
//! - `implicit cube`: N × N × N, mod3, Crank–Nicolson;
//! - `explicit cube`: N × N × N, the standard mass (every node massive: the contact nodes take the
//!   forward-increment multipliers, no quasi-static problem), central differences;
//! - `explicit rod`: N × 10 × 10 (length N/10), mod1 (the contact layer massless: its 121 nodes'
//!   quasi-static problem, exact Signorini, is the only solve), central differences.
//!
//! Per case: the set-up split into assembly (mesh, matrices, initial data), the lumped mass
//! and the scheme's construction (Δt_c by Lanczos / Gershgorin for the explicit one; the factor
//! for the implicit one); the median of `steps` steps each timed alone, on rayon pools of 1 and
//! 2 threads (explicit; the implicit step is sequential), at Δt = 0.9 Δt_c (explicit) or 0.01
//! (implicit); and the process's peak resident memory (VmHWM, reset before each case through
//! `/proc/self/clear_refs`). Per explicit case also the floor (issue 31, item 1): STREAM's triad
//! on 1 and 2 threads in the case's process ([`triad_gbs`]), the bytes a step streams per unknown
//! ([`CentralDifference::streamed_bytes`]) and the step over bytes ÷ bandwidth
//! ([`Row::floor_ratio`]). An edge: it times and writes.

use massredist::linalg::SymMatrix;
use massredist::mass::MassKind;
use massredist::problem::{Geometry, Problem};
use massredist::schemes::central_difference::{stable_limit_of, stable_limit_of_operator};
use massredist::schemes::{CentralDifference, Scheme};
use massredist::solid::{SolidSpec, SolidSystem};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// One measured case.
#[derive(Debug, Clone)]
pub struct Row {
    pub method: &'static str,
    pub shape: &'static str,
    pub cells: [usize; 3],
    pub unknowns: usize,
    pub assembly_s: f64,
    pub lumped_s: f64,
    pub scheme_s: f64,
    pub dt: f64,
    /// Median step, one thread (ms).
    pub step_ms_1: f64,
    /// Median step, two threads (ms; the implicit step: same as one).
    pub step_ms_2: f64,
    /// Median on-CPU time of a step, one thread (ms).
    pub cpu_ms_1: f64,
    pub peak_mib: f64,
    /// Bytes a step streams per unknown ([`CentralDifference::streamed_bytes`]; NaN: implicit).
    pub bytes_per_unknown: f64,
    /// The triad's bandwidth in this case's process, GB/s, on 1 and 2 threads ([`triad_gbs`]).
    pub triad_gbs_1: f64,
    pub triad_gbs_2: f64,
}

impl Row {
    /// The step's floor on `threads` (1 or 2): the bytes it streams over the triad's bandwidth,
    /// ms.
    pub fn floor_ms(&self, threads: usize) -> f64 {
        let gbs = if threads == 1 { self.triad_gbs_1 } else { self.triad_gbs_2 };
        self.bytes_per_unknown * self.unknowns as f64 / (gbs * 1e9) * 1e3
    }

    /// The median wall step over its floor, on `threads`.
    pub fn floor_ratio(&self, threads: usize) -> f64 {
        let step = if threads == 1 { self.step_ms_1 } else { self.step_ms_2 };
        step / self.floor_ms(threads)
    }
}

/// The triad's arrays: 2²⁴ values each (3 × 128 MiB, each 4× the 32 MiB L3 cache: STREAM's rule).
pub const TRIAD_LEN: usize = 1 << 24;
/// Passes of the triad; the best counts (STREAM's rule).
pub const TRIAD_PASSES: usize = 10;

/// STREAM's triad `a = b + s c` on three arrays of [`TRIAD_LEN`] values on a rayon pool of
/// `threads` (chunks of [`massredist::linalg::sparse::PAR_ROWS`] at least, as the scheme's
/// loops): the best of [`TRIAD_PASSES`] passes, in GB/s counting 24 bytes per element
/// (STREAM's convention: no write-allocate). The arrays are first written on the same pool.
pub fn triad_gbs(threads: usize) -> Result<f64, String> {
    use rayon::prelude::*;
    let rows = massredist::linalg::sparse::PAR_ROWS;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().map_err(|e| e.to_string())?;
    Ok(pool.install(|| {
        let fill = |x: f64| {
            let mut v = vec![0.0; TRIAD_LEN];
            v.par_iter_mut().with_min_len(rows).for_each(|e| *e = x);
            v
        };
        let (mut a, b, c) = (fill(0.0), fill(1.0), fill(2.0));
        let mut best = f64::INFINITY;
        for pass in 0..TRIAD_PASSES {
            let s = 3.0 + pass as f64;
            let t = Instant::now();
            (&mut a[..], &b[..], &c[..]).into_par_iter().with_min_len(rows).for_each(|(a, b, c)| *a = b + s * c);
            best = best.min(t.elapsed().as_secs_f64());
            std::hint::black_box(&a);
        }
        24.0 * TRIAD_LEN as f64 / best / 1e9
    }))
}

/// Resets the peak resident memory (VmHWM) of this process (Linux ≥ 4.0).
fn reset_peak() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

fn peak_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kb = status
        .lines()
        .find(|l| l.starts_with("VmHWM:"))
        .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        .unwrap_or(f64::NAN);
    kb / 1024.0
}

/// The CPU time (user + system) of the calling thread, ms: `/proc/thread-self/stat` fields 14
/// and 15, in clock ticks of 10 ms (USER_HZ = 100 on Linux).
fn thread_cpu_ms() -> f64 {
    let text = std::fs::read_to_string("/proc/thread-self/stat").unwrap_or_default();
    // The fields after the command name in parentheses (which may hold spaces).
    let rest = text.rsplit_once(')').map_or("", |r| r.1);
    let f: Vec<f64> = rest.split_whitespace().map(|x| x.parse().unwrap_or(f64::NAN)).collect();
    // rest starts at field 3 (state): utime is field 14, stime 15.
    f.get(11).zip(f.get(12)).map_or(f64::NAN, |(u, s)| (u + s) * 10.0)
}

/// The median (the upper one of an even count); NaN for no values.
pub(super) fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// `steps` steps of `scheme` on a pool of `threads`, each timed alone: their median wall time,
/// ms; with one thread also the CPU time per step of the pool's thread (other processes sharing
/// the core do not count): the mean over as many more steps as take about 2 s (at least
/// `steps`), since the clock ticks are 10 ms.
fn median_step(scheme: &mut dyn Scheme, steps: usize, threads: usize) -> Result<(f64, f64), String> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().map_err(|e| e.to_string())?;
    let mut wall = Vec::with_capacity(steps);
    for _ in 0..steps {
        let t = Instant::now();
        pool.install(|| scheme.step()).map_err(|e| e.to_string())?;
        wall.push(t.elapsed().as_secs_f64() * 1e3);
    }
    let wall = median(wall);
    if threads != 1 {
        return Ok((wall, f64::NAN));
    }
    let more = ((2000.0 / wall.max(1e-3)) as usize).clamp(steps, 20_000);
    let cpu = pool.install(|| {
        let c0 = thread_cpu_ms();
        (0..more).try_for_each(|_| scheme.step()).map(|_| (thread_cpu_ms() - c0) / more as f64)
    });
    Ok((wall, cpu.map_err(|e| e.to_string())?))
}

fn spec(cells: [usize; 3]) -> SolidSpec {
    // A rod N × 10 × 10 is (0, N/10) × (0, 1)²: cubic cells of side 1/10 like a cube's 1/N.
    let mut s = SolidSpec::paper(3, cells);
    s.extent[0] = cells[0] as f64 / cells[1] as f64;
    s
}

fn assemble(cells: [usize; 3], mass: &MassKind) -> Result<(Problem<SolidSystem>, f64), String> {
    let t = Instant::now();
    let p = spec(cells).problem(mass, 1.0).map_err(|e| e.to_string())?;
    Ok((p, t.elapsed().as_secs_f64()))
}

/// One explicit case: central differences at 0.9 Δt_c on the lean box system
/// ([`massredist::solid::lean`]: no consistent mass), the stiffness moved into the scheme
/// (`method` "explicit") or applied matrix-free ("matrix-free": the box's stencil,
/// [`massredist::solid::stencil`]; the assembled stiffness kept for Δt_c, as in a scene).
fn explicit(
    method: &'static str,
    shape: &'static str,
    cells: [usize; 3],
    mass: MassKind,
    steps: usize,
) -> Result<Row, String> {
    // The triad first, its arrays freed before the peak is reset.
    let (triad_gbs_1, triad_gbs_2) = (triad_gbs(1)?, triad_gbs(2)?);
    reset_peak();
    let t = Instant::now();
    let (b, stencil) = if method == "matrix-free" {
        let (b, op) = spec(cells).explicit_box_matrix_free(&mass).map_err(|e| e.to_string())?;
        (b, Some(op))
    } else {
        (spec(cells).explicit_box(&mass).map_err(|e| e.to_string())?, None)
    };
    let assembly_s = t.elapsed().as_secs_f64();
    // The lumped mass alone, timed again (explicit_box computed it with the system).
    let t = Instant::now();
    let m = spec(cells).mesh().map_err(|e| e.to_string())?;
    let w = massredist::fem::layers::cell_weights(&m, &mass).map_err(|e| e.to_string())?;
    std::hint::black_box(massredist::solid::lumped::node_masses(&m, &w, 1.0));
    drop((m, w));
    let lumped_s = t.elapsed().as_secs_f64();
    let law = massredist::contact::law::ContactLaw::Exact;
    let (limit, _, _) = match &stencil {
        Some(op) => stable_limit_of_operator(op, &b.lumped, None),
        None => stable_limit_of(&b.system, &b.lumped, None),
    };
    let (dt, unknowns) = (crate::paper::methods::SAFETY * limit, b.lumped.len());
    let t = Instant::now();
    let mut kept = None;
    let mut cd = match stencil {
        Some(op) => {
            let system = kept.insert(b.system);
            CentralDifference::with_operator(system, Some(Box::new(op)), b.lumped, &law, dt, || (b.u0, b.v0))
        }
        None => CentralDifference::from_system(b.system, b.lumped, &law, dt, b.u0, b.v0),
    }
    .map_err(|e| e.to_string())?;
    let scheme_s = t.elapsed().as_secs_f64();
    let (step_ms_1, cpu_ms_1) = median_step(&mut cd, steps, 1)?;
    let (step_ms_2, _) = median_step(&mut cd, steps, 2)?;
    let bytes = cd.streamed_bytes().ok_or("the step's bytes are not counted for this stiffness")?;
    Ok(Row {
        method,
        shape,
        cells,
        unknowns,
        assembly_s,
        lumped_s,
        scheme_s,
        dt,
        step_ms_1,
        step_ms_2,
        cpu_ms_1,
        peak_mib: peak_mib(),
        bytes_per_unknown: bytes as f64 / unknowns as f64,
        triad_gbs_1,
        triad_gbs_2,
    })
}

/// One tetra10 case (issue 31: the cell-by-cell kernel against the assembled matrix on P2
/// tetrahedra): the unit cube's N³ Kuhn tetrahedra made quadratic (`Mesh::quadratic`: straight
/// cells), passed as arrays, a body of the paper's material (λ = 0, μ = ½, ρ = 1) at v = (0, 0,
/// −1) onto the plane z = −0.001, the standard mass, central differences at Δt = 0.05/N (below
/// its Δt_c, 0.106/N measured at N = 35), set up and stepped through the scene path
/// (`massredist::run::setup`) with `scheme.operator` = "assembled" (`method` "explicit") or
/// "auto" (the kernel). The set-up (mesh from the arrays, masses, stiffness or kernel, Δt_c) is
/// all "assembly"; the bytes a step moves are not counted on this path (NaN).
fn tetra10(method: &'static str, n: usize, steps: usize) -> Result<Row, String> {
    use massredist::fem::{Cell, Mesh};
    let (triad_gbs_1, triad_gbs_2) = (triad_gbs(1)?, triad_gbs(2)?);
    let mesh =
        Mesh::structured_3d([1.0; 3], [n; 3], Cell::Tet).and_then(|m| m.quadratic()).map_err(|e| e.to_string())?;
    let arrays = massredist::mesh_file::ArrayMesh {
        points: mesh.points.iter().flatten().copied().collect(),
        columns: 3,
        blocks: vec![("tetra10".into(), mesh.cells.iter().map(|&v| v as i64).collect(), 10)],
    };
    drop(mesh);
    reset_peak();
    let operator = if method == "matrix-free" { "auto" } else { "assembled" };
    let dt = 0.05 / n as f64;
    let text = format!(
        "[solid]\ndim = 3\nmesh = \"<arrays>\"\nlame_lambda = 0.0\nlame_mu = 0.5\ndensity = 1.0\ninitial = {{ velocity = [\"0\", \"0\", \"-1\"] }}\n[obstacle]\nnormal = [0.0, 0.0, 1.0]\npoint = [0.0, 0.0, -0.001]\n[mass]\nkind = \"standard\"\n[scheme]\nkind = \"central-difference\"\noperator = \"{operator}\"\n[time]\ndt = {dt}\nend = {}\n",
        1000.0 * dt
    );
    let t = Instant::now();
    let inputs = massredist::mesh_file::MeshInputs { base: Path::new("."), arrays: Some(&arrays) };
    use massredist::scene::Registered;
    let any = massredist::scene::AnyScene::from_toml_with(&text, inputs).map_err(|e| e.to_string())?;
    let scene = massredist::solid::SolidSpec::from_any(any).map_err(|e| e.to_string())?;
    let mut setup = massredist::run::setup(&scene).map_err(|e| e.to_string())?;
    let assembly_s = t.elapsed().as_secs_f64();
    drop(arrays);
    let unknowns = setup.problem.system.dofs.len();
    let (step_ms_1, cpu_ms_1) = median_step(setup.scheme.as_mut(), steps, 1)?;
    let (step_ms_2, _) = median_step(setup.scheme.as_mut(), steps, 2)?;
    Ok(Row {
        method,
        shape: "tetra10",
        cells: [n; 3],
        unknowns,
        assembly_s,
        lumped_s: 0.0,
        scheme_s: 0.0,
        dt,
        step_ms_1,
        step_ms_2,
        cpu_ms_1,
        peak_mib: peak_mib(),
        bytes_per_unknown: f64::NAN,
        triad_gbs_1,
        triad_gbs_2,
    })
}

/// One implicit case: Crank–Nicolson at Δt = 0.01 (its factor built once).
fn implicit(n: usize, steps: usize) -> Result<Row, String> {
    reset_peak();
    let (p, assembly_s) = assemble([n; 3], &MassKind::Mod3)?;
    let t = Instant::now();
    let spec = massredist::scene::SchemeSpec::CrankNicolson { formulation: massredist::scene::Formulation::Full };
    let mut s = p.scheme(&spec, 0.01).map_err(|e| e.to_string())?;
    let scheme_s = t.elapsed().as_secs_f64();
    let (step, cpu_ms_1) = median_step(s.as_mut(), steps, 1)?;
    let unknowns = p.system.system().stiffness.dim();
    let (dt, lumped_s) = (0.01, 0.0);
    Ok(Row {
        method: "implicit",
        shape: "cube",
        cells: [n; 3],
        unknowns,
        assembly_s,
        lumped_s,
        scheme_s,
        dt,
        step_ms_1: step,
        step_ms_2: step,
        cpu_ms_1,
        peak_mib: peak_mib(),
        bytes_per_unknown: f64::NAN,
        triad_gbs_1: f64::NAN,
        triad_gbs_2: f64::NAN,
    })
}

/// The sizes: (implicit cubes, explicit cubes, explicit rods' N, tetra10 cubes); quick: small
/// ones.
pub fn sizes(quick: bool) -> (Vec<usize>, Vec<usize>, Vec<usize>, Vec<usize>) {
    if quick {
        (vec![4, 6], vec![6, 10], vec![20, 40], vec![4])
    } else {
        (vec![6, 10, 14, 20, 24], vec![10, 20, 34, 50, 69], vec![100, 300, 1000, 3300], vec![10, 20, 35])
    }
}

/// The environment variable that makes the process measure one case and print its CSV row
/// (each case runs in a process of its own, so that its peak memory is its own).
pub const CASE_VAR: &str = "MASSREDIST_EXPLICIT_CASE";
/// Set: redraw the table and figure from the CSV as it is, measuring nothing.
pub const REDRAW_VAR: &str = "MASSREDIST_EXPLICIT_REDRAW";

/// One case by name: `method shape nx ny nz`.
fn one_case(name: &str, steps: usize) -> Result<Row, String> {
    let f: Vec<&str> = name.split_whitespace().collect();
    let n = |k: usize| f.get(k).and_then(|x| x.parse::<usize>().ok()).ok_or(format!("bad case `{name}`"));
    match (f.first().copied(), f.get(1).copied()) {
        (Some("implicit"), _) => implicit(n(2)?, steps.min(10)),
        (Some("explicit"), Some("cube")) => explicit("explicit", "cube", [n(2)?; 3], MassKind::Standard, steps),
        (Some("matrix-free"), Some("cube")) => explicit("matrix-free", "cube", [n(2)?; 3], MassKind::Standard, steps),
        (Some("explicit"), Some("rod")) => explicit("explicit", "rod", [n(2)?, n(3)?, n(4)?], MassKind::Mod1, steps),
        (Some("explicit"), Some("tetra10")) => tetra10("explicit", n(2)?, steps),
        (Some("matrix-free"), Some("tetra10")) => tetra10("matrix-free", n(2)?, steps),
        _ => Err(format!("bad case `{name}`")),
    }
}

/// A row back from its CSV line ([`to_csv`]'s columns).
fn from_csv_line(line: &str) -> Result<Row, String> {
    let f: Vec<&str> = line.trim().split(',').collect();
    let x = |k: usize| f.get(k).and_then(|v| v.parse::<f64>().ok()).ok_or(format!("bad row `{line}`"));
    let method = match f[0] {
        "implicit" => "implicit",
        "matrix-free" => "matrix-free",
        _ => "explicit",
    };
    let shape = match f.get(1) {
        Some(&"rod") => "rod",
        Some(&"tetra10") => "tetra10",
        _ => "cube",
    };
    let cells = [x(2)? as usize, x(3)? as usize, x(4)? as usize];
    Ok(Row {
        method,
        shape,
        cells,
        unknowns: x(5)? as usize,
        assembly_s: x(6)?,
        lumped_s: x(7)?,
        scheme_s: x(8)?,
        dt: x(9)?,
        step_ms_1: x(10)?,
        step_ms_2: x(11)?,
        cpu_ms_1: x(12)?,
        peak_mib: x(15)?,
        // Absent from a CSV written before they were measured: NaN.
        bytes_per_unknown: x(16).unwrap_or(f64::NAN),
        triad_gbs_1: x(17).unwrap_or(f64::NAN),
        triad_gbs_2: x(18).unwrap_or(f64::NAN),
    })
}

/// Runs every case (each in a child process: this executable with [`CASE_VAR`] set), writes
/// `csv`, its Markdown table (`.md`) and figure (`.png`, `.svg`); returns the paths written.
/// With [`CASE_VAR`] set: measures that case, prints its row, writes nothing.
pub fn run(csv: &Path, quick: bool, steps: usize) -> Result<Vec<PathBuf>, String> {
    if let Ok(name) = std::env::var(CASE_VAR) {
        println!("{}", to_csv(&[one_case(&name, steps)?]).lines().nth(1).unwrap_or_default());
        return Ok(Vec::new());
    }
    if std::env::var_os(REDRAW_VAR).is_some() {
        let text = std::fs::read_to_string(csv).map_err(|e| format!("{}: {e}", csv.display()))?;
        let rows = text.lines().skip(1).map(from_csv_line).collect::<Result<Vec<_>, _>>()?;
        return write_outputs(csv, &rows);
    }
    let (imp, cube, rod, tet10) = sizes(quick);
    let names = imp
        .iter()
        .map(|n| format!("implicit cube {n} {n} {n}"))
        .chain(cube.iter().map(|n| format!("explicit cube {n} {n} {n}")))
        .chain(cube.iter().map(|n| format!("matrix-free cube {n} {n} {n}")))
        .chain(rod.iter().map(|n| format!("explicit rod {n} 10 10")))
        .chain(tet10.iter().flat_map(|n| ["explicit", "matrix-free"].map(|m| format!("{m} tetra10 {n} {n} {n}"))));
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let mut rows = Vec::new();
    for name in names {
        let o = std::process::Command::new(&exe)
            .args(std::env::args_os().skip(1))
            .env(CASE_VAR, &name)
            .output()
            .map_err(|e| format!("{name}: {e}"))?;
        let text = String::from_utf8_lossy(&o.stdout);
        let line = text
            .lines()
            .last()
            .filter(|_| o.status.success())
            .ok_or_else(|| format!("{name}: exit {:?}: {}", o.status.code(), String::from_utf8_lossy(&o.stderr)))?;
        rows.push(from_csv_line(line)?);
        eprintln!("{name}: {line}");
    }
    std::fs::write(csv, to_csv(&rows)).map_err(|e| format!("{}: {e}", csv.display()))?;
    write_outputs(csv, &rows)
}

/// The Markdown table and the figures of `rows` next to `csv`; returns the paths.
fn write_outputs(csv: &Path, rows: &[Row]) -> Result<Vec<PathBuf>, String> {
    let mut out = vec![csv.to_path_buf()];
    let md = csv.with_extension("md");
    std::fs::write(&md, to_markdown(rows)).map_err(|e| format!("{}: {e}", md.display()))?;
    out.push(md);
    for ext in ["png", "svg"] {
        let path = csv.with_extension(ext);
        draw_file(&path, rows)?;
        out.push(path);
    }
    Ok(out)
}

const HEADER: &str = "method,shape,nx,ny,nz,unknowns,assembly_s,lumped_s,scheme_s,dt,step_ms_1,step_ms_2,cpu_ms_1,cpu_ns_per_unknown_1,speedup_2,peak_mib,bytes_per_unknown,triad_gbs_1,triad_gbs_2,floor_ratio_1,floor_ratio_2";

pub fn to_csv(rows: &[Row]) -> String {
    let mut s = format!("{HEADER}\n");
    for r in rows {
        let [x, y, z] = r.cells;
        let ns = r.cpu_ms_1 * 1e6 / r.unknowns as f64;
        let _ = writeln!(
            s,
            "{},{},{x},{y},{z},{},{:.4},{:.4},{:.4},{:.6e},{:.4},{:.4},{:.4},{:.2},{:.3},{:.1},{:.1},{:.2},{:.2},{:.3},{:.3}",
            r.method,
            r.shape,
            r.unknowns,
            r.assembly_s,
            r.lumped_s,
            r.scheme_s,
            r.dt,
            r.step_ms_1,
            r.step_ms_2,
            r.cpu_ms_1,
            ns,
            r.step_ms_1 / r.step_ms_2,
            r.peak_mib,
            r.bytes_per_unknown,
            r.triad_gbs_1,
            r.triad_gbs_2,
            r.floor_ratio(1),
            r.floor_ratio(2)
        );
    }
    s
}

pub fn to_markdown(rows: &[Row]) -> String {
    let mut s = String::from(PREAMBLE);
    s.push_str(&time_table(rows));
    s.push_str(FLOOR_TEXT);
    s.push_str(&floor_table(rows));
    s
}

/// What the file holds (written by the command with the tables).
const PREAMBLE: &str = "# Explicit at scale: implicit against explicit on 3D hex solids

Written by `massredist bench --explicit-scaling docs/bench/explicit-scaling.csv` (with the CSV
and the figure `explicit-scaling.png`/`.svg`); what the numbers show is in
[`../bench.md`](../bench.md). Each case runs in a process of its own, so that its peak resident
memory (VmHWM) is its own. Cases (the plane-wave solid's paper data, λ + 2μ = ρ = 1):

- **implicit cube**: N³ Q1 hexahedra, mod3, Crank–Nicolson at Δt = 0.01 with a direct solver (the scene's set-up;
  one sparse Cholesky factor: \"scheme s\"; a step is two triangular solves).
- **explicit cube**: N³, the standard mass (contact by the forward-increment multipliers, one
  closed form per contact node), central differences at 0.9 Δt_c.
- **matrix-free cube**: the explicit cube with K u applied matrix-free (`scheme.operator =
  \"matrix-free\"`: the box's stencil, `src/solid/stencil.rs`), set up by
  `SolidSpec::explicit_box_matrix_free`: no global matrix (the stiffness's rows of the massless
  unknowns only, none for the standard mass), Δt_c by Lanczos on the operator without a stored
  basis above 50 000 unknowns, then the Gershgorin bound from the operator's `|K| 1`.
- **explicit rod**: N × 10 × 10 (h = 1/10), mod1 (the contact layer massless: its quasi-static
  problem with exact Signorini is solved every step), central differences at 0.9 Δt_c.
- **explicit tetra10 / matrix-free tetra10**: the unit cube's N³ Kuhn tetrahedra made quadratic
  (straight P2 cells, about 24.6 N³ unknowns), a body of the same material dropped at v = 1 onto
  the plane 0.001 below it, the standard mass, central differences at Δt = 0.05/N (below Δt_c),
  set up through the scene path (`massredist run`'s) with `scheme.operator = \"assembled\"`
  (the matrix in row-run form) or `\"auto\"` (the cell-by-cell kernel, `src/solid/kernel.rs`:
  no stiffness matrix); all of the set-up counts as \"assembly\", and the bytes a step moves
  are not counted on this path (NaN in the floor table).

The explicit set-up is `SolidSpec::explicit_box` (the stiffness straight into compressed
columns, the lumped mass as the mass matrix, no consistent mass) and
`CentralDifference::from_system` (Δt_c by Lanczos, capped at 30 steps above 50 000 unknowns,
then the Gershgorin bound; the stiffness moved into the row-run form `sparse::RunMat`). Step
times: medians of 21 steps timed alone on rayon pools of 1 and 2 threads in the same process;
\"CPU\" is the stepping thread's CPU time (`/proc/thread-self/stat`, the mean over about 2 s).

";

const FLOOR_TEXT: &str = "
## The floor: bytes moved against the triad's bandwidth

Per explicit case, in the same process: STREAM's triad `a = b + s c` on three arrays of 2²⁴
values (3 × 128 MiB, each 4× the L3 cache), the best of 10 passes, on 1 and 2 threads, in GB/s
at 24 bytes per element. The bytes a step moves are counted from its data structures
(`CentralDifference::streamed_bytes`, STREAM's convention: each array read or written in a pass
counts once, no write-allocate): the stiffness in row-run form (values, runs and the two
pointer arrays, `RunMat::bytes`) or, matrix-free, the stencil's passes (the free unknowns
scattered into its layout and gathered back, its input read once and its output written once:
`Operator::streamed_bytes`), and 15 vectors of n values (`VECTOR_PASSES`); the contact law's
work on the contact nodes is not counted. The floor is bytes ÷ triad bandwidth; the ratio
is the median wall step over it.

";

/// The time and memory table.
fn time_table(rows: &[Row]) -> String {
    let mut s = String::from(
        "| method | shape | cells | unknowns | assembly s | lumped mass s | scheme s (Δt_c / factor) | step ms, 1 thread (wall) | step ms, 1 thread (CPU) | CPU ns per unknown | step ms, 2 threads (wall) | speed-up (wall) | peak MiB |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        let [x, y, z] = r.cells;
        let _ = writeln!(
            s,
            "| {} | {} | {x}×{y}×{z} | {} | {:.3} | {:.3} | {:.3} | {:.2} | {:.2} | {:.1} | {:.2} | {:.2} | {:.0} |",
            r.method,
            r.shape,
            r.unknowns,
            r.assembly_s,
            r.lumped_s,
            r.scheme_s,
            r.step_ms_1,
            r.cpu_ms_1,
            r.cpu_ms_1 * 1e6 / r.unknowns as f64,
            r.step_ms_2,
            r.step_ms_1 / r.step_ms_2,
            r.peak_mib
        );
    }
    s
}

/// The floor table of the explicit rows.
fn floor_table(rows: &[Row]) -> String {
    let mut s = String::from(
        "| method | shape | cells | unknowns | bytes per unknown per step | triad GB/s, 1 thread | floor ms, 1 thread | step ms, 1 thread | ratio, 1 thread | triad GB/s, 2 threads | floor ms, 2 threads | step ms, 2 threads | ratio, 2 threads |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows.iter().filter(|r| r.method != "implicit") {
        let [x, y, z] = r.cells;
        let cells = [
            r.method.to_string(),
            r.shape.to_string(),
            format!("{x}×{y}×{z}"),
            r.unknowns.to_string(),
            format!("{:.0}", r.bytes_per_unknown),
            format!("{:.1}", r.triad_gbs_1),
            format!("{:.2}", r.floor_ms(1)),
            format!("{:.2}", r.step_ms_1),
            format!("{:.2}", r.floor_ratio(1)),
            format!("{:.1}", r.triad_gbs_2),
            format!("{:.2}", r.floor_ms(2)),
            format!("{:.2}", r.step_ms_2),
            format!("{:.2}", r.floor_ratio(2)),
        ];
        let _ = writeln!(s, "| {} |", cells.join(" | "));
    }
    s
}

/// The figure: the CPU time of a step on one thread (left: what a shared machine's wall clock
/// cannot give) and the peak memory (right) against unknowns, log–log; one line per (method,
/// shape).
fn draw<DB: plotters::prelude::DrawingBackend>(
    root: plotters::prelude::DrawingArea<DB, plotters::coord::Shift>,
    rows: &[Row],
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let (top, body) = root.split_vertically(34);
    top.titled("3D hex solids: implicit (CN) against explicit (central differences)", ("sans-serif", 18)).map_err(e)?;
    let panels = body.split_evenly((1, 2));
    let series: [(&str, &str, RGBColor); 6] = [
        ("implicit", "cube", RGBColor(214, 39, 40)),
        ("explicit", "cube", RGBColor(31, 119, 180)),
        ("matrix-free", "cube", RGBColor(148, 103, 189)),
        ("explicit", "rod", RGBColor(44, 160, 44)),
        ("explicit", "tetra10", RGBColor(255, 127, 14)),
        ("matrix-free", "tetra10", RGBColor(140, 86, 75)),
    ];
    let span = |v: Vec<f64>| {
        let (lo, hi) = v.iter().filter(|x| **x > 0.0).fold((f64::INFINITY, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
        if lo.is_finite() { (lo / 1.5, hi * 1.5) } else { (1.0, 10.0) }
    };
    let x = span(rows.iter().map(|r| r.unknowns as f64).collect());
    let metrics: [(&str, fn(&Row) -> f64); 2] =
        [("CPU time per step, one thread [ms]", |r| r.cpu_ms_1), ("peak resident memory [MiB]", |r| r.peak_mib)];
    for (area, (label, f)) in panels.iter().zip(metrics) {
        let y = span(rows.iter().map(f).collect());
        let mut chart = crate::plot::log_log_chart(area, label, x, y, ("unknowns", label), true)?;
        for (method, shape, colour) in series {
            let mine: Vec<&Row> = rows.iter().filter(|r| r.method == method && r.shape == shape).collect();
            let pts: Vec<(f64, f64)> = mine.iter().map(|r| (r.unknowns as f64, f(r))).collect();
            if pts.is_empty() {
                continue;
            }
            chart
                .draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))
                .map_err(e)?
                .label(format!("{method} {shape}"))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2)));
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, colour.filled()))).map_err(e)?;
        }
        crate::plot::draw_log_legend(&mut chart, SeriesLabelPosition::UpperLeft, 13.0)?;
    }
    root.present().map_err(e)
}

fn draw_file(path: &Path, rows: &[Row]) -> Result<(), String> {
    use plotters::prelude::*;
    let size = (1400, 600);
    let r = if path.extension().is_some_and(|e| e == "svg") {
        draw(SVGBackend::new(path, size).into_drawing_area(), rows)
    } else {
        draw(BitMapBackend::new(path, size).into_drawing_area(), rows)
    };
    r.map_err(|m| format!("cannot draw {}: {m}", path.display()))
}
