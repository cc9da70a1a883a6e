//! Plates and solids against the independent scipy baseline (`python/scripts/scipy_baseline.py`, run
//! as a subprocess), and the growth of set-up and step time with the number of unknowns on 3D
//! hex meshes (issue 13).
//!
//! The problem on both sides: the unit square or cube with N cells per axis (Q1), the paper's
//! data u0 = ((1 − x)/2, 0[, 0]), v0 = 0, mass mod3, Crank–Nicolson, Δt as given; the contact
//! face is in contact for t ∈ (1, 2). Set-up is everything before the first step (mesh,
//! assembly, factorisation, contact operator); the free step is the mean over t < 1, the contact
//! step the mean over t > 1; the exact L² pass is one evaluation of `‖u_h − u‖_{L²}` against the
//! closed form. Both sides are timed by wall clock inside their own process, in the same run.
//!
//! Timing is at the edge by nature: nothing here is used by a test.

use massredist::mass::MassKind;
use massredist::models::{PaperPlate, PlaneWaveSolid};
use massredist::problem::{Geometry, Problem};
use massredist::scene::{Formulation, SchemeSpec};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Which body: the scalar plate (dim 2) or the elastic solid (dim 2 or 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Case {
    pub kind: &'static str,
    pub dim: usize,
    /// Cells per axis.
    pub n: usize,
}

impl Case {
    pub fn label(&self) -> String {
        match self.kind {
            "plate" => format!("plate Q1 {0}×{0}", self.n),
            _ if self.dim == 2 => format!("solid 2D Q1 {0}×{0}", self.n),
            _ => format!("solid 3D hex {0}×{0}×{0}", self.n),
        }
    }
}

/// One side's timings of a case (seconds).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Timing {
    pub unknowns: usize,
    pub contact: usize,
    pub setup_s: f64,
    pub free_step_s: f64,
    pub contact_step_s: f64,
    /// `‖U‖₂` after the last step (the two sides solve the same problem).
    pub unorm: f64,
}

/// The JSON of `python/scripts/scipy_baseline.py` (its set-up split into phases).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Scipy {
    pub unknowns: usize,
    pub contact: usize,
    pub assemble_s: f64,
    pub factor_s: f64,
    pub schur_s: f64,
    pub setup_s: f64,
    pub free_step_s: f64,
    pub contact_step_s: f64,
    pub unorm: f64,
}

/// A case on both sides.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    pub case: Case,
    pub steps: usize,
    pub dt: f64,
    pub rust: Timing,
    /// One exact L² error pass, seconds (None without a closed form).
    pub l2_pass_s: Option<f64>,
    pub scipy: Option<Scipy>,
}

/// One size of the 3D scaling table (massredist only).
#[derive(Debug, Clone, Serialize)]
pub struct ScalingRow {
    pub n: usize,
    pub unknowns: usize,
    pub setup_s: f64,
    pub step_s: f64,
    /// The process's peak resident memory after this size (sizes increase, so it is this
    /// size's), MiB; None where /proc is not available.
    pub peak_mib: Option<f64>,
}

#[derive(Debug, Clone, Serialize)]
pub struct BaselineReport {
    pub rows: Vec<Row>,
    pub scaling: Vec<ScalingRow>,
    /// Least-squares slopes of log(seconds) against log(unknowns): (set-up, step).
    pub exponents: Option<(f64, f64)>,
    /// Why the scipy side is missing, if it is.
    pub note: Option<String>,
}

fn cn() -> SchemeSpec {
    SchemeSpec::CrankNicolson { formulation: Formulation::Full }
}

/// Steps and timings of a built problem: `steps` steps of `dt` ([`windows`]), and one exact L²
/// error pass (the mean of 5, after one untimed).
fn step_timings<G: Geometry>(problem: &Problem<G>, dt: f64, steps: usize) -> Result<(Timing, Option<f64>), String> {
    let t = Instant::now();
    let mut scheme = problem.scheme(&cn(), dt).map_err(|e| e.to_string())?;
    let scheme_s = t.elapsed().as_secs_f64();
    // Each step timed alone; a window's figure is its median (robust to other processes).
    let mut times = Vec::with_capacity(steps);
    for _ in 0..steps {
        let t = Instant::now();
        scheme.step().map_err(|e| e.to_string())?;
        times.push(t.elapsed().as_secs_f64());
    }
    let (free, contact) = windows(&times, dt);
    let u = scheme.state().u.to_vec();
    let sys = &problem.system;
    let l2 = problem.exact.as_ref().map(|exact| {
        // One untimed pass first: a plate builds its cell table on the first one.
        let reps = 5;
        std::hint::black_box(sys.l2_error(&u, exact, steps as f64 * dt));
        let t = Instant::now();
        let mut sink = 0.0;
        for _ in 0..reps {
            sink += sys.l2_error(std::hint::black_box(&u), exact, steps as f64 * dt);
        }
        std::hint::black_box(sink);
        t.elapsed().as_secs_f64() / reps as f64
    });
    let timing = Timing {
        unknowns: u.len(),
        contact: sys.contact().len(),
        setup_s: scheme_s,
        free_step_s: free,
        contact_step_s: contact,
        unorm: u.iter().map(|x| x * x).sum::<f64>().sqrt(),
    };
    Ok((timing, l2))
}

/// The medians of the step times with t_k < 1 (free) and t_k > 1 + Δt (in contact); NaN for
/// an empty window. The steps reaching t = 1 and 1 + Δt (impact) are in neither.
fn windows(times: &[f64], dt: f64) -> (f64, f64) {
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        if v.is_empty() { f64::NAN } else { v[v.len() / 2] }
    };
    let t = |k: usize| (k + 1) as f64 * dt;
    let free = times.iter().enumerate().filter(|(k, _)| t(*k) < 1.0 - dt / 2.0).map(|p| *p.1).collect();
    let contact = times.iter().enumerate().filter(|(k, _)| t(*k) > 1.0 + 1.5 * dt).map(|p| *p.1).collect();
    (median(free), median(contact))
}

/// massredist on a case: problem and scheme built and stepped in this process.
pub fn time_rust(case: Case, dt: f64, steps: usize) -> Result<(Timing, Option<f64>), String> {
    let t = Instant::now();
    let mass = MassKind::Mod3;
    let (timing, l2) = if case.kind == "plate" {
        let plate = PaperPlate::square(case.n, massredist::fem::Cell::Quad);
        let problem = plate.problem(&mass).map_err(|e| e.to_string())?;
        let build = t.elapsed().as_secs_f64();
        let (mut tm, l2) = step_timings(&problem, dt, steps)?;
        tm.setup_s += build;
        (tm, l2)
    } else {
        let solid = PlaneWaveSolid { dim: case.dim, cells: [case.n; 3] };
        let problem = solid.problem(&mass, steps as f64 * dt).map_err(|e| e.to_string())?;
        let build = t.elapsed().as_secs_f64();
        let (mut tm, l2) = step_timings(&problem, dt, steps)?;
        tm.setup_s += build;
        (tm, l2)
    };
    Ok((timing, l2))
}

/// Runs `python/scripts/scipy_baseline.py` on a case; the error says why it could not.
pub fn time_scipy(case: Case, dt: f64, steps: usize) -> Result<Scipy, String> {
    let args = [("--kind", case.kind.to_string()), ("--dim", case.dim.to_string()), ("--n", case.n.to_string())];
    let more = [("--steps", steps.to_string()), ("--dt", dt.to_string())];
    let args: Vec<String> = args.into_iter().chain(more).flat_map(|(k, v)| [k.to_string(), v]).collect();
    super::env::run_json("scipy_baseline.py", &args)
}

/// Peak resident memory of this process (VmHWM), MiB.
fn peak_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// Least-squares slope of log y against log x.
pub fn log_slope(points: &[(f64, f64)]) -> Option<f64> {
    let pts: Vec<(f64, f64)> =
        points.iter().filter(|p| p.0 > 0.0 && p.1 > 0.0).map(|&(x, y)| (x.ln(), y.ln())).collect();
    if pts.len() < 2 {
        return None;
    }
    let m = pts.len() as f64;
    let (sx, sy) = pts.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
    let (mx, my) = (sx / m, sy / m);
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// The cases, Δt and steps of a run (quick: small sizes, Δt = 0.02 to t = 2; full: Δt = 0.01).
pub fn cases(quick: bool) -> (Vec<Case>, f64, usize, Vec<usize>) {
    let c = |kind, dim, n| Case { kind, dim, n };
    if quick {
        (vec![c("plate", 2, 60), c("solid", 2, 40), c("solid", 3, 8)], 0.02, 100, vec![4, 6, 8])
    } else {
        let cases = vec![
            c("plate", 2, 100),
            c("plate", 2, 200),
            c("solid", 2, 100),
            c("solid", 2, 200),
            c("solid", 3, 10),
            c("solid", 3, 16),
        ];
        (cases, 0.01, 200, vec![6, 10, 14, 20, 28])
    }
}

/// Runs every case on both sides and the 3D scaling sizes (10 steps of Δt = 0.01 each).
pub fn run(quick: bool) -> BaselineReport {
    let (list, dt, steps, scaling_sizes) = cases(quick);
    let mut rows = Vec::new();
    let mut note = None;
    for case in list {
        let (rust, l2_pass_s) = match time_rust(case, dt, steps) {
            Ok(r) => r,
            Err(e) => {
                note = Some(format!("{}: massredist failed: {e}", case.label()));
                continue;
            }
        };
        let scipy = time_scipy(case, dt, steps).map_err(|e| note = Some(e)).ok();
        rows.push(Row { case, steps, dt, rust, l2_pass_s, scipy });
    }
    let scaling: Vec<ScalingRow> = scaling_sizes
        .into_iter()
        .filter_map(|n| {
            let case = Case { kind: "solid", dim: 3, n };
            let (t, _) = time_rust(case, 0.01, 10).ok()?;
            Some(ScalingRow {
                n,
                unknowns: t.unknowns,
                setup_s: t.setup_s,
                step_s: t.free_step_s,
                peak_mib: peak_mib(),
            })
        })
        .collect();
    let fit =
        |f: fn(&ScalingRow) -> f64| log_slope(&scaling.iter().map(|r| (r.unknowns as f64, f(r))).collect::<Vec<_>>());
    let exponents = fit(|r| r.setup_s).zip(fit(|r| r.step_s));
    BaselineReport { rows, scaling, exponents, note }
}

fn opt(v: Option<f64>, f: impl Fn(f64) -> String) -> String {
    v.filter(|x| x.is_finite()).map_or("–".into(), f)
}

/// The ratio tables and the scaling table in Markdown. (One template function of about 90
/// lines on purpose, like [`super::performance_markdown`].)
pub fn markdown(r: &BaselineReport) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Plates and solids against the independent scipy baseline (python/scripts/scipy_baseline.py: vectorised assembly, \
         one `splu`, D = Eᵀ K⁻¹ E by one blocked solve, a primal–dual active set per step). Q1, mod3, \
         Crank–Nicolson, the paper's data on the unit square / cube with N cells per axis; contact on t ∈ (1, 2). \
         Wall-clock seconds inside each process, both in this run. Set-up: everything before the first step \
         (scipy's split: assembly + `splu` | D). Ratios are massredist / scipy (goal ≤ 0.5); steps: the median of the free steps (t < 1) and of the steps in contact (t > 1 + Δt); the last column compares the final states.\n"
    );
    let _ = writeln!(
        s,
        "| case | unknowns | contact | set-up s (rs / scipy: asm+splu, D) | set-up ratio | set-up / scipy asm+splu | \
         free step ms (rs / scipy) | step ratio | contact step ms (rs / scipy) | contact ratio | Δ‖U‖ / ‖U‖ |"
    );
    let _ = writeln!(s, "|---|---:|---:|---|---:|---:|---|---:|---|---:|---:|");
    for row in &r.rows {
        let (rs, sc) = (&row.rust, row.scipy.as_ref());
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.3} / {} | {} | {} | {:.2} / {} | {} | {:.2} / {} | {} | {} |",
            row.case.label(),
            rs.unknowns,
            rs.contact,
            rs.setup_s,
            sc.map_or("–".into(), |p| format!("{:.3}+{:.3}, {:.3}", p.assemble_s, p.factor_s, p.schur_s)),
            opt(sc.map(|p| rs.setup_s / p.setup_s), |x| format!("{x:.2}")),
            opt(sc.map(|p| rs.setup_s / (p.assemble_s + p.factor_s)), |x| format!("{x:.2}")),
            rs.free_step_s * 1e3,
            opt(sc.map(|p| p.free_step_s * 1e3), |x| format!("{x:.2}")),
            opt(sc.map(|p| rs.free_step_s / p.free_step_s), |x| format!("{x:.2}")),
            rs.contact_step_s * 1e3,
            opt(sc.map(|p| p.contact_step_s * 1e3), |x| format!("{x:.2}")),
            opt(sc.map(|p| rs.contact_step_s / p.contact_step_s), |x| format!("{x:.2}")),
            opt(sc.map(|p| (rs.unorm - p.unorm).abs() / p.unorm), |x| format!("{x:.1e}")),
        );
    }
    let _ = writeln!(
        s,
        "\nWithin massredist: a step in contact against a free step (goal ≤ 1.3) and one exact L² error pass against \
         a free step (goal ≤ 0.5).\n"
    );
    let _ = writeln!(s, "| case | contact step / free step | L² pass ms | L² pass / free step |");
    let _ = writeln!(s, "|---|---:|---:|---:|");
    for row in &r.rows {
        let rs = &row.rust;
        let _ = writeln!(
            s,
            "| {} | {:.2} | {} | {} |",
            row.case.label(),
            rs.contact_step_s / rs.free_step_s,
            opt(row.l2_pass_s.map(|x| x * 1e3), |x| format!("{x:.3}")),
            opt(row.l2_pass_s.map(|x| x / rs.free_step_s), |x| format!("{x:.3}")),
        );
    }
    if !r.scaling.is_empty() {
        let _ = writeln!(
            s,
            "\n3D solid, hex N×N×N (massredist; set-up, and the median of 10 free steps of Δt = 0.01). Fitted growth \
             (least squares of log time against log unknowns): set-up ∝ n^{}, step ∝ n^{}. Peak memory: the \
             process's resident high-water mark after that size.\n",
            opt(r.exponents.map(|e| e.0), |x| format!("{x:.2}")),
            opt(r.exponents.map(|e| e.1), |x| format!("{x:.2}")),
        );
        let _ = writeln!(s, "| N | unknowns | set-up s | step ms | peak MiB |");
        let _ = writeln!(s, "|---:|---:|---:|---:|---:|");
        for t in &r.scaling {
            let _ = writeln!(
                s,
                "| {} | {} | {:.3} | {:.2} | {} |",
                t.n,
                t.unknowns,
                t.setup_s,
                t.step_s * 1e3,
                opt(t.peak_mib, |x| format!("{x:.0}"))
            );
        }
        let _ = writeln!(s, "\n![3D scaling](solid_scaling.svg)");
    }
    if let Some(n) = &r.note {
        let _ = writeln!(s, "\nNote: {n}");
    }
    s
}

/// Log–log figure of the 3D set-up and step times against unknowns (PNG or SVG by extension).
pub fn scaling_figure(path: &std::path::Path, rows: &[ScalingRow]) -> Result<(), String> {
    use plotters::prelude::*;
    fn draw<DB: DrawingBackend>(
        area: DrawingArea<DB, plotters::coord::Shift>,
        rows: &[ScalingRow],
    ) -> Result<(), String>
    where
        DB::ErrorType: 'static,
    {
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        area.fill(&WHITE).map_err(e)?;
        let xs: Vec<f64> = rows.iter().map(|r| r.unknowns as f64).collect();
        let ys: Vec<f64> = rows.iter().flat_map(|r| [r.setup_s, r.step_s]).filter(|y| *y > 0.0).collect();
        let (x0, x1) = (xs.iter().copied().fold(f64::INFINITY, f64::min), xs.iter().copied().fold(0.0, f64::max));
        let (y0, y1) = (ys.iter().copied().fold(f64::INFINITY, f64::min), ys.iter().copied().fold(0.0, f64::max));
        let mut chart = ChartBuilder::on(&area)
            .caption("3D hex solid: set-up and step time", ("sans-serif", 28))
            .margin(20)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d((x0 / 1.5..x1 * 1.5).log_scale(), (y0 / 2.0..y1 * 2.0).log_scale())
            .map_err(e)?;
        chart.configure_mesh().x_desc("unknowns").y_desc("seconds").draw().map_err(e)?;
        let series: [(&str, fn(&ScalingRow) -> f64, RGBColor); 2] =
            [("set-up", |r| r.setup_s, BLUE), ("one step", |r| r.step_s, RED)];
        for (label, f, color) in series {
            let pts: Vec<(f64, f64)> = rows.iter().map(|r| (r.unknowns as f64, f(r))).filter(|p| p.1 > 0.0).collect();
            chart
                .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
                .map_err(e)?
                .label(label)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 4, color.filled()))).map_err(e)?;
        }
        chart.configure_series_labels().border_style(BLACK).background_style(WHITE).draw().map_err(e)?;
        area.present().map_err(e)
    }
    if rows.is_empty() {
        return Ok(());
    }
    let size = (900, 700);
    let r = if path.extension().is_some_and(|e| e == "svg") {
        draw(SVGBackend::new(path, size).into_drawing_area(), rows)
    } else {
        draw(BitMapBackend::new(path, size).into_drawing_area(), rows)
    };
    r.map_err(|m| format!("cannot draw {}: {m}", path.display()))
}
