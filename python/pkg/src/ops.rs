//! What a scene assembles, for Python: the mesh (points, cells, cell weights, contact nodes)
//! of each geometry, the operators of the contact system `M Ü + S U = F − Σ_c λ_c e_c`
//! (paper eq. (3.1)) as CSR arrays, and the exact solution of a bar by characteristics
//! (`massredist::characteristics`; the paper's closed form (4.2) for its benchmark).

use crate::errors::{run_error, scene_error_msg};
use crate::scene::Scene;
use massredist::bar::BarSystem;
use massredist::exact::Exact;
use massredist::linalg::SymMatrix;
use massredist::plate::PlateSystem;
use massredist::problem::Geometry;
use massredist::run::{GeometrySpec, setup};
use massredist::scene::{AnyScene, Registered};
use massredist::solid::SolidSystem;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The mesh of an assembled geometry, as flat arrays.
pub struct MeshArrays {
    /// n × 3 (unused coordinates 0).
    pub points: Vec<f64>,
    pub dim: usize,
    /// Vertex indices, `verts` per cell.
    pub cells: Vec<usize>,
    pub verts: usize,
    /// "line", "triangle", "quad", "tetra", "hexahedron" (meshio's names).
    pub kind: &'static str,
}

/// What Python reads of a geometry's assembled system besides the contact system.
pub trait Meshed: Geometry {
    fn mesh_arrays(&self) -> MeshArrays;
    /// One weight per cell (the mass redistribution, paper §3).
    fn cell_weights(&self) -> &[f64];
    /// The mesh node of each contact unknown (contact order).
    fn contact_nodes(&self) -> Vec<usize>;
}

impl Meshed for BarSystem {
    fn mesh_arrays(&self) -> MeshArrays {
        let m = self.bar.elements;
        let points = (0..=m).flat_map(|i| [self.bar.x(i), 0.0, 0.0]).collect();
        let cells = (0..m).flat_map(|i| [i, i + 1]).collect();
        MeshArrays { points, dim: 1, cells, verts: 2, kind: "line" }
    }
    fn cell_weights(&self) -> &[f64] {
        &self.weights
    }
    fn contact_nodes(&self) -> Vec<usize> {
        // Unknown i of a bar is node i.
        self.system.contact.clone()
    }
}

fn fem_mesh(mesh: &massredist::fem::Mesh) -> MeshArrays {
    MeshArrays {
        points: mesh.points.iter().flatten().copied().collect(),
        dim: mesh.dim,
        cells: mesh.cells.clone(),
        verts: mesh.kind.verts(),
        kind: mesh.kind.data().meshio,
    }
}

impl Meshed for PlateSystem {
    fn mesh_arrays(&self) -> MeshArrays {
        fem_mesh(&self.mesh)
    }
    fn cell_weights(&self) -> &[f64] {
        &self.weights
    }
    fn contact_nodes(&self) -> Vec<usize> {
        self.system.contact.iter().map(|&c| self.dofs[c]).collect()
    }
}

impl Meshed for SolidSystem {
    fn mesh_arrays(&self) -> MeshArrays {
        fem_mesh(&self.mesh)
    }
    fn cell_weights(&self) -> &[f64] {
        &self.weights
    }
    fn contact_nodes(&self) -> Vec<usize> {
        self.contact_nodes.clone()
    }
}

/// Puts the mesh of `body` into `d`: points (n × dim), cells (c × verts), cell_kind, weights,
/// contact_nodes.
pub fn put_mesh<B: Meshed>(py: Python<'_>, system: &B, d: &Bound<'_, PyDict>) -> PyResult<()> {
    let m = system.mesh_arrays();
    let n = m.points.len() / 3;
    let points: Vec<f64> = m.points.chunks(3).flat_map(|p| p[..m.dim].to_vec()).collect();
    let points = Array2::from_shape_vec((n, m.dim), points).expect("n × dim values");
    let cells: Vec<i64> = m.cells.iter().map(|&c| c as i64).collect();
    let cells = Array2::from_shape_vec((cells.len() / m.verts, m.verts), cells).expect("c × verts values");
    d.set_item("points", points.into_pyarray(py))?;
    d.set_item("cells", cells.into_pyarray(py))?;
    d.set_item("cell_kind", m.kind)?;
    d.set_item("weights", PyArray1::from_slice(py, system.cell_weights()))?;
    let contact: Vec<i64> = system.contact_nodes().iter().map(|&c| c as i64).collect();
    d.set_item("contact_nodes", PyArray1::from_vec(py, contact))?;
    Ok(())
}

/// A symmetric matrix as CSR arrays (data, indices, indptr), rows sorted by column.
fn csr<A: SymMatrix>(py: Python<'_>, a: &A) -> PyResult<Py<PyAny>> {
    let n = a.dim();
    let mut rows: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
    a.for_each_entry(&mut |i, j, v| rows[i].push((j, v)));
    let (mut data, mut indices, mut indptr) = (Vec::new(), Vec::new(), vec![0i64]);
    for mut row in rows {
        row.sort_by_key(|e| e.0);
        for (j, v) in row {
            indices.push(j as i64);
            data.push(v);
        }
        indptr.push(indices.len() as i64);
    }
    let t = (PyArray1::from_vec(py, data), PyArray1::from_vec(py, indices), PyArray1::from_vec(py, indptr), (n, n));
    Ok(t.into_pyobject(py)?.into_any().unbind())
}

fn operators_of<G: GeometrySpec + Registered + Sync>(
    py: Python<'_>,
    scene: &massredist::scene::Scene<G>,
) -> PyResult<Py<PyDict>>
where
    G::System: Meshed + Send,
{
    let set = py.detach(|| setup(scene)).map_err(|e| run_error(py, &massredist::run::RunError::Setup(e)))?;
    let geometry = &set.problem.system;
    let s = geometry.system();
    let d = PyDict::new(py);
    d.set_item("mass", csr(py, &s.mass)?)?;
    d.set_item("stiffness", csr(py, &s.stiffness)?)?;
    d.set_item("load", PyArray1::from_slice(py, &s.load))?;
    let contact: Vec<i64> = s.contact.iter().map(|&c| c as i64).collect();
    d.set_item("contact", PyArray1::from_vec(py, contact))?;
    d.set_item("lower", PyArray1::from_slice(py, &s.lower))?;
    d.set_item("massless", PyArray1::from_slice(py, &s.massless))?;
    d.set_item("u0", PyArray1::from_slice(py, &set.problem.u0))?;
    d.set_item("v0", PyArray1::from_slice(py, &set.problem.v0))?;
    put_mesh(py, geometry, &d)?;
    Ok(d.unbind())
}

/// The assembled operators of a scene: `mass`, `stiffness` (CSR triples over the free
/// unknowns), `load`, `contact` (contact unknowns), `lower` (obstacle bounds), `massless`,
/// `u0`, `v0` and the mesh (`points`, `cells`, `cell_kind`, `weights`, `contact_nodes`).
#[pyfunction]
pub fn operators(py: Python<'_>, scene: &Scene) -> PyResult<Py<PyDict>> {
    massredist::with_scene!(&scene.any, s => operators_of(py, s))
}

/// The exact solution of a bar scene (`exact(scene)`).
#[pyclass(module = "massredist._core", frozen)]
pub struct ExactBar {
    exact: Exact,
    length: f64,
    end: f64,
}

impl ExactBar {
    /// `f(x_k, t_k)` for contiguous arrays, checked inside [0, L] × [0, T] (without the GIL).
    fn map2<'py>(
        &self,
        py: Python<'py>,
        x: PyReadonlyArray1<'py, f64>,
        t: PyReadonlyArray1<'py, f64>,
        f: impl Fn(&Exact, f64, f64) -> f64 + Send + Sync,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (x, t) = (x.as_slice()?, t.as_slice()?);
        let bad_x = x.iter().find(|&&v| !(0.0..=self.length).contains(&v));
        let bad_t = t.iter().find(|&&v| !(0.0..=self.end).contains(&v));
        if let Some(v) = bad_x {
            return Err(scene_error_msg(py, format!("x = {v}: allowed range is [0, {}]", self.length), None));
        }
        if let Some(v) = bad_t {
            return Err(scene_error_msg(py, format!("t = {v}: allowed range is [0, time.end = {}]", self.end), None));
        }
        let out: Vec<f64> = py.detach(|| x.iter().zip(t).map(|(&x, &t)| f(&self.exact, x, t)).collect());
        Ok(PyArray1::from_vec(py, out))
    }
}

#[pymethods]
impl ExactBar {
    /// u(x_k, t_k), elementwise over two 1D float64 arrays of one length.
    fn u<'py>(
        &self,
        py: Python<'py>,
        x: PyReadonlyArray1<'py, f64>,
        t: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.map2(py, x, t, |e, x, t| e.u(x, t))
    }

    /// u(0, t_k).
    fn u0<'py>(&self, py: Python<'py>, t: PyReadonlyArray1<'py, f64>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let x = PyArray1::zeros(py, t.len()?, false).readonly();
        self.map2(py, x, t, |e, _, t| e.u0(t))
    }

    /// λ(t_k) = E u_x(0, t_k) ≤ 0, the contact reaction.
    fn reaction<'py>(&self, py: Python<'py>, t: PyReadonlyArray1<'py, f64>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let x = PyArray1::zeros(py, t.len()?, false).readonly();
        self.map2(py, x, t, |e, _, t| e.lambda(t))
    }

    #[getter]
    fn length(&self) -> f64 {
        self.length
    }

    #[getter]
    fn end(&self) -> f64 {
        self.end
    }
}

/// The exact solution of a bar scene up to its `time.end` (the paper's closed form for its
/// benchmark, characteristics for any other bar without body force); a `SceneError` for
/// other scenes.
#[pyfunction]
pub fn exact(py: Python<'_>, scene: &Scene) -> PyResult<ExactBar> {
    let AnyScene::Bar(bar) = &scene.any else {
        let msg = format!("exact: a [bar] scene is needed, this is a [{}] scene", scene.any.table());
        return Err(scene_error_msg(py, msg, None));
    };
    let problem = py.detach(|| massredist::bar::BarSpec::problem(bar));
    let problem = problem.map_err(|e| scene_error_msg(py, e.to_string(), Some("bar".into())))?;
    let Some(exact) = problem.exact else {
        let msg = "exact: this bar has no exact solution (a body force: bar.force)".to_string();
        return Err(scene_error_msg(py, msg, Some("bar.force".into())));
    };
    Ok(ExactBar { exact, length: bar.geometry.length, end: bar.time.end })
}
