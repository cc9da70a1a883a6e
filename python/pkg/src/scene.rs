//! Scenes for Python: TOML text, a TOML file or a dict, validated by the crate's own
//! `AnyScene` (so the checks and messages are the CLI's), with the source table kept so that a
//! sweep can change a few keys and validate again.

use crate::errors::{scene_error, scene_error_msg, scene_error_unwritten};
use massredist::scene::AnyScene;
use massredist::scene::mesh_file::{ARRAY_MESH, ArrayMesh, Block, MeshInputs};
use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use std::path::{Path, PathBuf};

/// A validated scene (the `[bar]`, `[plate]` or `[solid]` table and the shared sections).
#[pyclass(module = "massredist._core", frozen)]
pub struct Scene {
    pub any: AnyScene,
    /// The tables as given (before defaults), for [`Scene::replace`].
    source: toml::Table,
    /// The folder a mesh file is relative to.
    base: PathBuf,
    /// A mesh given as arrays (`mesh=`), standing for `<table>.mesh = "<arrays>"`.
    arrays: Option<ArrayMesh>,
}

/// The `mesh=` argument: points (n × 2 or 3), cells (c × vertices), meshio's cell kind.
type MeshArg<'py> = (PyReadonlyArray2<'py, f64>, PyReadonlyArray2<'py, i64>, String);

impl Scene {
    /// Whether a geometry table names a mesh file (then `base` is part of the scene).
    fn reads_mesh_file(&self) -> bool {
        self.source
            .values()
            .filter_map(toml::Value::as_table)
            .any(|t| t.get("mesh").and_then(toml::Value::as_str).is_some_and(|m| m != ARRAY_MESH))
    }

    /// Validates `source`, serialised by the package: its errors quote no TOML position (the
    /// user did not write that text; `from_toml` and `from_file` validate the user's own).
    fn new(py: Python<'_>, mut source: toml::Table, base: PathBuf, arrays: Option<ArrayMesh>) -> PyResult<Self> {
        if arrays.is_some() {
            let table = ["plate", "solid"].into_iter().find(|t| source.contains_key(*t));
            let Some(toml::Value::Table(t)) = table.and_then(|t| source.get_mut(t)) else {
                let msg = "mesh: a mesh given as arrays needs a [plate] or [solid] table".to_string();
                return Err(scene_error_msg(py, msg, Some("mesh".into())));
            };
            t.insert("mesh".into(), toml::Value::String(ARRAY_MESH.into()));
        }
        let text = toml::to_string(&source).map_err(|e| scene_error_msg(py, e.to_string(), None))?;
        // Validation (with the mesh file it may read, or the arrays given) runs without the GIL.
        let inputs = MeshInputs { base: &base, arrays: arrays.as_ref() };
        let parsed = py.detach(|| AnyScene::from_toml_with(&text, inputs));
        let any = parsed.map_err(|e| scene_error_unwritten(py, &e))?;
        Ok(Self { any, source, base, arrays })
    }
}

/// The most rows of `mesh=`'s points and of its cells: a mesh's cell limit
/// ([`massredist::scene::MAX_ELEMENTS`]), checked before the arrays are copied (issue 32, E9: a
/// 10⁸-value points array aborted the interpreter on the copy).
const MAX_MESH_ROWS: usize = massredist::scene::MAX_ELEMENTS;

/// The arrays of `mesh=` as a file's blocks.
fn array_mesh(py: Python<'_>, mesh: Option<MeshArg<'_>>) -> PyResult<Option<ArrayMesh>> {
    let Some((points, cells, kind)) = mesh else { return Ok(None) };
    let columns = points.shape()[1];
    let verts = cells.shape()[1];
    for (what, rows) in [("points", points.shape()[0]), ("cells", cells.shape()[0])] {
        if rows > MAX_MESH_ROWS {
            let msg = format!("mesh: {rows} {what}, over the limit of {MAX_MESH_ROWS} rows for a mesh given as arrays");
            return Err(scene_error_msg(py, msg, Some("mesh".into())));
        }
    }
    let points = points.as_array().iter().copied().collect();
    let cells = cells.as_array().iter().copied().collect();
    Ok(Some(ArrayMesh { points, columns, blocks: vec![(kind, cells, verts)] }))
}

/// Parses TOML text into a table, with the CLI's message (and key) for a syntax error.
fn parse_table(py: Python<'_>, text: &str) -> PyResult<toml::Table> {
    match toml::from_str::<toml::Table>(text) {
        Ok(t) => Ok(t),
        // The crate's parser makes the message (key, line, column) the CLI prints.
        Err(_) => match AnyScene::from_toml(text) {
            Err(e) => Err(scene_error(py, &e)),
            Ok(_) => Err(scene_error_msg(py, "the scene is not a TOML table".into(), None)),
        },
    }
}

#[pymethods]
impl Scene {
    /// A scene from TOML text; a mesh file it names is relative to `base`.
    #[staticmethod]
    #[pyo3(signature = (text, base = None, mesh = None))]
    fn from_toml(py: Python<'_>, text: &str, base: Option<PathBuf>, mesh: Option<MeshArg<'_>>) -> PyResult<Self> {
        let source = parse_table(py, text)?;
        let (base, arrays) = (base.unwrap_or_else(|| PathBuf::from(".")), array_mesh(py, mesh)?);
        if arrays.is_some() {
            return Self::new(py, source, base, arrays);
        }
        // The user's text itself, so that an error's line and column are the user's.
        let inputs = MeshInputs { base: &base, arrays: None };
        let any = py.detach(|| AnyScene::from_toml_with(text, inputs)).map_err(|e| scene_error(py, &e))?;
        Ok(Self { any, source, base, arrays: None })
    }

    /// A scene from a TOML file (read as the CLI reads it: at most 16 MB, UTF-8).
    #[staticmethod]
    fn from_file(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        // The CLI's reader first: its size limit and its messages for a missing or binary file.
        let any = py.detach(|| AnyScene::from_file(&path)).map_err(|e| scene_error(py, &e))?;
        let text = std::fs::read_to_string(&path).map_err(|e| scene_error_msg(py, e.to_string(), None))?;
        let source = parse_table(py, &text)?;
        let base = path.parent().map_or_else(|| PathBuf::from("."), Path::to_path_buf);
        Ok(Self { any, source, base, arrays: None })
    }

    /// A scene from a dict of tables (`{"bar": {...}, "time": {"dt": 0.01}}`).
    #[staticmethod]
    #[pyo3(signature = (tables, base = None, mesh = None))]
    fn from_dict(
        py: Python<'_>,
        tables: &Bound<'_, PyDict>,
        base: Option<PathBuf>,
        mesh: Option<MeshArg<'_>>,
    ) -> PyResult<Self> {
        let toml::Value::Table(source) = to_toml(tables.as_any(), "", &mut Budget::default())? else {
            unreachable!("a dict is a table")
        };
        Self::new(py, source, base.unwrap_or_else(|| PathBuf::from(".")), array_mesh(py, mesh)?)
    }

    /// A new scene with keys changed: `{"time.dt": 0.005, "mass.kind": "mod2"}` (dotted keys)
    /// and/or tables as keywords, `time={"dt": 0.005}`; None removes a key, so that its
    /// default applies.
    #[pyo3(signature = (changes = None, **tables))]
    fn replace(
        &self,
        py: Python<'_>,
        changes: Option<&Bound<'_, PyDict>>,
        tables: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let mut source = self.source.clone();
        let budget = &mut Budget::default();
        for (table, values) in tables.map(|t| t.iter().collect::<Vec<_>>()).unwrap_or_default() {
            let table: String = table.extract()?;
            match values.cast::<PyDict>() {
                Ok(d) => {
                    for (k, v) in d.iter() {
                        set_key(py, &mut source, &format!("{table}.{}", k.extract::<String>()?), &v, budget)?;
                    }
                }
                Err(_) => set_key(py, &mut source, &table, &values, budget)?,
            }
        }
        for (k, v) in changes.map(|c| c.iter().collect::<Vec<_>>()).unwrap_or_default() {
            set_key(py, &mut source, &k.extract::<String>()?, &v, budget)?;
        }
        Self::new(py, source, self.base.clone(), self.arrays.clone())
    }

    /// The scene with every default filled in, as TOML (`massredist check` prints it).
    fn resolved_toml(&self) -> String {
        self.any.resolved_toml()
    }

    /// The tables as given (no defaults filled in), as TOML.
    fn source_toml(&self) -> String {
        toml::to_string(&self.source).unwrap_or_default()
    }

    /// The geometry table: "bar", "plate" or "solid".
    #[getter]
    fn table(&self) -> &'static str {
        self.any.table()
    }

    /// The time step Δt.
    #[getter]
    fn dt(&self) -> f64 {
        self.any.time().dt
    }

    /// The end time T.
    #[getter]
    fn end(&self) -> f64 {
        self.any.time().end
    }

    /// The number of steps T / Δt.
    #[getter]
    fn steps(&self) -> usize {
        self.any.time().steps
    }

    /// The folder a mesh file is relative to (a str, as the stub says).
    #[getter]
    fn base(&self) -> String {
        self.base.to_string_lossy().into_owned()
    }

    fn __repr__(&self) -> String {
        let t = self.any.time();
        format!("Scene([{}], dt={}, end={}, steps={})", self.any.table(), t.dt, t.end, t.steps)
    }

    /// The value of a dotted key in the resolved scene, every default filled in
    /// (`scene["time.dt"]`, `scene["mass.kind"]`; a table gives a dict): what `check` prints.
    /// A key the resolved scene does not have raises KeyError naming it.
    fn __getitem__<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        let resolved: toml::Table =
            toml::from_str(&self.any.resolved_toml()).map_err(|e| scene_error_msg(py, e.to_string(), None))?;
        let mut parts = key.split('.');
        let first = parts.next().unwrap_or_default();
        let missing = || pyo3::exceptions::PyKeyError::new_err(key.to_string());
        let mut value = resolved.get(first).ok_or_else(missing)?;
        for part in parts {
            value = value.as_table().and_then(|t| t.get(part)).ok_or_else(missing)?;
        }
        to_python(py, value)
    }

    /// Equal when the resolved scenes (every default filled in), the meshes given as arrays
    /// and, for a scene that reads a mesh file, the folder it is relative to are equal.
    fn __eq__(&self, other: PyRef<'_, Scene>) -> bool {
        self.any.resolved_toml() == other.any.resolved_toml()
            && self.arrays == other.arrays
            && (!self.reads_mesh_file() || self.base == other.base)
    }

    /// Consistent with `__eq__`: the resolved scene, the folder and the arrays.
    fn __hash__(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        self.any.resolved_toml().hash(&mut h);
        if self.reads_mesh_file() {
            self.base.hash(&mut h);
        }
        if let Some(a) = &self.arrays {
            a.points.iter().for_each(|x| x.to_bits().hash(&mut h));
            a.columns.hash(&mut h);
            a.blocks.hash(&mut h);
        }
        h.finish()
    }

    /// Pickling (multiprocessing, joblib): the tables as given, the folder and the arrays; the
    /// copy is validated again when it is loaded.
    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, (String, String, Option<(Vec<f64>, usize, Vec<Block>)>))> {
        let s = slf.get();
        let source = toml::to_string(&s.source).map_err(|e| scene_error_msg(slf.py(), e.to_string(), None))?;
        let arrays = s.arrays.as_ref().map(|a| (a.points.clone(), a.columns, a.blocks.clone()));
        Ok((slf.get_type().getattr("_from_state")?, (source, s.base(), arrays)))
    }

    /// The inverse of `__reduce__`.
    #[staticmethod]
    fn _from_state(
        py: Python<'_>,
        source: &str,
        base: PathBuf,
        arrays: Option<(Vec<f64>, usize, Vec<Block>)>,
    ) -> PyResult<Self> {
        let arrays = arrays.map(|(points, columns, blocks)| ArrayMesh { points, columns, blocks });
        Self::new(py, parse_table(py, source)?, base, arrays)
    }
}

/// A TOML value as the Python value `tomllib` gives (a datetime as its text).
fn to_python<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    use pyo3::IntoPyObjectExt;
    Ok(match v {
        toml::Value::String(s) => s.into_bound_py_any(py)?,
        toml::Value::Integer(i) => i.into_bound_py_any(py)?,
        toml::Value::Float(f) => f.into_bound_py_any(py)?,
        toml::Value::Boolean(b) => b.into_bound_py_any(py)?,
        toml::Value::Datetime(d) => d.to_string().into_bound_py_any(py)?,
        toml::Value::Array(a) => {
            let items = a.iter().map(|x| to_python(py, x)).collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        toml::Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, x) in t {
                d.set_item(k, to_python(py, x)?)?;
            }
            d.into_any()
        }
    })
}

/// `check`: sets the scene up as `massredist check` does (assembly, exact solution,
/// factorisation) and returns the resolved scene as TOML.
#[pyfunction]
pub fn check(py: Python<'_>, scene: &Scene) -> PyResult<String> {
    py.detach(|| massredist::run::check(&scene.any)).map_err(|e| scene_error(py, &e))?;
    Ok(scene.any.resolved_toml())
}

/// Sets the dotted `key` of `source` to `v` (None removes it), creating tables on the way.
fn set_key(
    py: Python<'_>,
    source: &mut toml::Table,
    key: &str,
    v: &Bound<'_, PyAny>,
    budget: &mut Budget,
) -> PyResult<()> {
    let parts: Vec<&str> = key.split('.').collect();
    let (last, tables) = parts.split_last().expect("split yields one part at least");
    let mut table = source;
    for (i, part) in tables.iter().enumerate() {
        let entry = table.entry(part.to_string()).or_insert_with(|| toml::Value::Table(toml::Table::new()));
        table = match entry {
            toml::Value::Table(t) => t,
            _ => {
                let msg = format!("{key}: {} is not a table", parts[..=i].join("."));
                return Err(scene_error_msg(py, msg, Some(key.to_string())));
            }
        };
    }
    if v.is_none() {
        table.remove(*last);
    } else {
        table.insert(last.to_string(), to_toml(v, key, budget)?);
    }
    Ok(())
}

/// What a scene built from Python values may hold (issue 32, E2 and E9): tables and lists nested
/// at most [`Budget::MAX_DEPTH`] deep (a dict that contains itself, or one nested 20,000 deep,
/// overflowed the stack: a segfault), and at most [`Budget::MAX_VALUES`] values (a 10⁷-entry
/// list aborted on allocation), checked before a list is converted.
#[derive(Default)]
struct Budget {
    depth: usize,
    values: usize,
}

impl Budget {
    /// Far above any scene (its tables are 2 levels deep, expressions' lists 3).
    const MAX_DEPTH: usize = 32;
    /// A scene file holds at most `MAX_SCENE_BYTES` bytes, and a TOML value takes 2 at least
    /// (`0,`): a dict cannot hold more values than a file could.
    const MAX_VALUES: usize = (massredist::scene::MAX_SCENE_BYTES / 2) as usize;

    /// Takes one value.
    fn take(&mut self, py: Python<'_>, key: &str) -> PyResult<()> {
        self.room(py, 1, key)?;
        self.values += 1;
        Ok(())
    }

    /// Whether `n` more values fit (a list's length, checked before its items are converted).
    fn room(&self, py: Python<'_>, n: usize, key: &str) -> PyResult<()> {
        if self.values.saturating_add(n) > Self::MAX_VALUES {
            let msg = format!(
                "{key}: the scene would hold more than {} values (a scene file holds at most {} bytes)",
                Self::MAX_VALUES,
                massredist::scene::MAX_SCENE_BYTES
            );
            return Err(scene_error_msg(py, msg, Some(key.to_string())));
        }
        Ok(())
    }

    /// One level deeper, refused beyond [`Self::MAX_DEPTH`].
    fn enter(&mut self, py: Python<'_>, key: &str) -> PyResult<()> {
        self.depth += 1;
        if self.depth > Self::MAX_DEPTH {
            let msg = format!(
                "{key}: dicts and lists nested more than {} levels deep (a dict or list that contains itself?)",
                Self::MAX_DEPTH
            );
            return Err(scene_error_msg(py, msg, Some(key.to_string())));
        }
        Ok(())
    }
}

/// A Python value as a TOML value: bool, int, float, str, list/tuple (or anything with
/// `tolist`, e.g. numpy arrays and scalars) and dict, within `budget`.
fn to_toml(v: &Bound<'_, PyAny>, key: &str, budget: &mut Budget) -> PyResult<toml::Value> {
    budget.enter(v.py(), key)?;
    let value = to_toml_at(v, key, budget);
    budget.depth -= 1;
    value
}

fn to_toml_at(v: &Bound<'_, PyAny>, key: &str, budget: &mut Budget) -> PyResult<toml::Value> {
    let py = v.py();
    budget.take(py, key)?;
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        return Ok(toml::Value::Integer(v.extract()?));
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(v.extract()?));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(v.extract()?));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut t = toml::Table::new();
        for (k, x) in d.iter() {
            let name: String = k.extract()?;
            let sub = if key.is_empty() { name.clone() } else { format!("{key}.{name}") };
            if !x.is_none() {
                t.insert(name, to_toml(&x, &sub, budget)?);
            }
        }
        return Ok(toml::Value::Table(t));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        budget.room(py, v.len()?, key)?;
        let items: PyResult<Vec<_>> = v.try_iter()?.map(|x| to_toml(&x?, key, budget)).collect();
        return Ok(toml::Value::Array(items?));
    }
    if v.hasattr("tolist")? {
        // A numpy array's size before `tolist` makes a Python list of it.
        if let Ok(size) = v.getattr("size").and_then(|s| s.extract::<usize>()) {
            budget.room(py, size, key)?;
        }
        return to_toml(&v.call_method0("tolist")?, key, budget);
    }
    let type_name = v.get_type().name().map(|n| n.to_string()).unwrap_or_default();
    Err(scene_error_msg(
        py,
        format!("{key}: a value of type {type_name} is not a TOML value (bool, int, float, str, list, dict)"),
        Some(key.to_string()),
    ))
}
