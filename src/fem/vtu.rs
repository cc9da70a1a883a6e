//! VTK XML output for ParaView, for any mesh of [`crate::fem`] or the plate's: one `.vtu`
//! (UnstructuredGrid, ASCII) per frame and a `.pvd` collection with the frame times, plus a
//! reader for the files written here (read-back tests).
//!
//! [`grid_string`] writes points (z = 0 in 2D), cells (VTK_TRIANGLE = 5, VTK_QUAD = 9,
//! VTK_TETRA = 10, VTK_HEXAHEDRON = 12) and named point and cell arrays of any component
//! count; the geometries choose their arrays (plates: `u`, `v`, `warp`, `weight` in
//! `crate::plate::vtu`; solids: the displacement and velocity vectors and the contact pressure
//! in `crate::solid::vtu`). Numbers are written with Rust's shortest round-trip formatting, so
//! reading them back gives the same `f64` bit for bit.

use super::mesh::Cell;
use crate::numfmt::fmt_f64;
use std::fmt::Write as _;
use thiserror::Error;

/// VTK cell type codes.
pub fn vtk_type(kind: Cell) -> u8 {
    match kind {
        Cell::Triangle => 5,
        Cell::Quad => 9,
        Cell::Tet => 10,
        Cell::Hex => 12,
    }
}

/// A named data array: `components` values per point (or cell).
#[derive(Debug, Clone, Copy)]
pub struct Array<'a> {
    pub name: &'a str,
    pub components: usize,
    pub values: &'a [f64],
}

fn data_array(out: &mut String, name: &str, components: usize, values: impl Iterator<Item = f64>) {
    let _ = write!(
        out,
        "        <DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"{components}\" format=\"ascii\">\n         "
    );
    for (k, x) in values.enumerate() {
        if k > 0 && k % 12 == 0 {
            out.push_str("\n         ");
        }
        out.push(' ');
        out.push_str(&fmt_f64(x));
    }
    out.push_str("\n        </DataArray>\n");
}

/// The mesh part of a frame: points in ℝ³, cells with `verts` vertices each, VTK type `kind`.
#[derive(Debug, Clone, Copy)]
pub struct Grid<'a> {
    pub points: &'a [[f64; 3]],
    pub cells: &'a [usize],
    pub verts: usize,
    pub kind: u8,
}

/// The `.vtu` text of one frame: the grid, its point arrays (the first is the active scalar,
/// `vectors` the active vector) and cell arrays (the first is the active scalar).
pub fn grid_string(grid: &Grid, point_data: &[Array], vectors: &str, cell_data: &[Array]) -> String {
    let (np, nc) = (grid.points.len(), grid.cells.len() / grid.verts);
    assert!(point_data.iter().all(|a| a.values.len() == a.components * np));
    assert!(cell_data.iter().all(|a| a.values.len() == a.components * nc));
    let mut s = String::with_capacity(64 * np * point_data.len().max(1));
    s.push_str("<?xml version=\"1.0\"?>\n");
    s.push_str(
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n",
    );
    s.push_str("  <UnstructuredGrid>\n");
    let _ = writeln!(s, "    <Piece NumberOfPoints=\"{np}\" NumberOfCells=\"{nc}\">");
    let scalars = point_data.first().map_or("", |a| a.name);
    let _ = writeln!(s, "      <PointData Scalars=\"{scalars}\" Vectors=\"{vectors}\">");
    for a in point_data {
        data_array(&mut s, a.name, a.components, a.values.iter().copied());
    }
    let cell_scalars = cell_data.first().map_or("", |a| a.name);
    let _ = writeln!(s, "      </PointData>\n      <CellData Scalars=\"{cell_scalars}\">");
    for a in cell_data {
        data_array(&mut s, a.name, a.components, a.values.iter().copied());
    }
    s.push_str("      </CellData>\n      <Points>\n");
    data_array(&mut s, "Points", 3, grid.points.iter().flat_map(|p| *p));
    s.push_str("      </Points>\n      <Cells>\n");
    let ints = |s: &mut String, name: &str, ty: &str, values: &mut dyn Iterator<Item = usize>| {
        let _ = write!(s, "        <DataArray type=\"{ty}\" Name=\"{name}\" format=\"ascii\">\n         ");
        for (j, x) in values.enumerate() {
            if j > 0 && j % 20 == 0 {
                s.push_str("\n         ");
            }
            let _ = write!(s, " {x}");
        }
        s.push_str("\n        </DataArray>\n");
    };
    ints(&mut s, "connectivity", "Int64", &mut grid.cells.iter().copied());
    ints(&mut s, "offsets", "Int64", &mut (1..=nc).map(|c| c * grid.verts));
    ints(&mut s, "types", "UInt8", &mut (0..nc).map(|_| grid.kind as usize));
    s.push_str("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
    s
}

/// Writes `vtu/frame_NNNNN.vtu` (one text per frame, from `frame`) and the collection
/// `<name>.pvd` into `dir`.
pub fn write_series(
    dir: &std::path::Path,
    name: &str,
    times: &[f64],
    frame: impl Fn(usize) -> String,
) -> std::io::Result<()> {
    std::fs::create_dir(dir.join("vtu"))?;
    let mut entries = Vec::with_capacity(times.len());
    for (k, &t) in times.iter().enumerate() {
        let file = format!("vtu/frame_{k:05}.vtu");
        std::fs::write(dir.join(&file), frame(k))?;
        entries.push((t, file));
    }
    std::fs::write(dir.join(format!("{name}.pvd")), pvd_string(&entries))
}

/// The `.pvd` collection of `(time, file)` frames (file names relative to the `.pvd`).
pub fn pvd_string(frames: &[(f64, String)]) -> String {
    let mut s =
        String::from("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\">\n  <Collection>\n");
    for (t, f) in frames {
        let _ = writeln!(s, "    <DataSet timestep=\"{}\" part=\"0\" file=\"{f}\"/>", fmt_f64(*t));
    }
    s.push_str("  </Collection>\n</VTKFile>\n");
    s
}

#[derive(Debug, Clone, PartialEq, Error)]
pub enum VtuError {
    #[error("malformed VTU: {0}")]
    Malformed(String),
}

/// A `DataArray` read back: its name, component count and values.
#[derive(Debug, Clone, PartialEq)]
pub struct DataArray {
    pub name: String,
    pub components: usize,
    pub values: Vec<f64>,
}

/// The content of a `.vtu` file written by [`grid_string`].
#[derive(Debug, Clone, PartialEq)]
pub struct VtuData {
    pub n_points: usize,
    pub n_cells: usize,
    pub points: Vec<f64>,
    pub connectivity: Vec<usize>,
    pub offsets: Vec<usize>,
    pub types: Vec<u8>,
    pub point_data: Vec<DataArray>,
    pub cell_data: Vec<DataArray>,
}

impl VtuData {
    pub fn point_array(&self, name: &str) -> Option<&DataArray> {
        self.point_data.iter().find(|a| a.name == name)
    }

    pub fn cell_array(&self, name: &str) -> Option<&DataArray> {
        self.cell_data.iter().find(|a| a.name == name)
    }
}

fn attr(tag: &str, name: &str) -> Option<String> {
    let key = format!("{name}=\"");
    let i = tag.find(&key)? + key.len();
    let j = tag[i..].find('"')? + i;
    Some(tag[i..j].to_string())
}

/// Parses the ASCII `.vtu` files written by this module (not a general VTK reader).
pub fn read_vtu(text: &str) -> Result<VtuData, VtuError> {
    let bad = |m: &str| VtuError::Malformed(m.to_string());
    let piece_at = text.find("<Piece").ok_or_else(|| bad("no <Piece>"))?;
    let piece_tag =
        &text[piece_at..piece_at + text[piece_at..].find('>').ok_or_else(|| bad("unterminated <Piece>"))?];
    let count = |k: &str| -> Result<usize, VtuError> {
        attr(piece_tag, k).and_then(|v| v.parse().ok()).ok_or_else(|| bad(&format!("Piece without {k}")))
    };
    let (n_points, n_cells) = (count("NumberOfPoints")?, count("NumberOfCells")?);
    let section = |open: &str, close: &str| -> &str {
        match (text.find(open), text.find(close)) {
            (Some(a), Some(b)) if a < b => &text[a..b],
            _ => "",
        }
    };
    let arrays = |sec: &str| -> Result<Vec<DataArray>, VtuError> {
        let mut out = Vec::new();
        let mut rest = sec;
        while let Some(a) = rest.find("<DataArray") {
            let tag_end = a + rest[a..].find('>').ok_or_else(|| bad("unterminated <DataArray>"))?;
            let tag = &rest[a..tag_end];
            let body_end =
                tag_end + rest[tag_end..].find("</DataArray>").ok_or_else(|| bad("unterminated DataArray"))?;
            let values = rest[tag_end + 1..body_end]
                .split_whitespace()
                .map(|w| w.parse::<f64>().map_err(|_| bad(&format!("not a number: {w}"))))
                .collect::<Result<Vec<f64>, _>>()?;
            out.push(DataArray {
                name: attr(tag, "Name").unwrap_or_default(),
                components: attr(tag, "NumberOfComponents").and_then(|v| v.parse().ok()).unwrap_or(1),
                values,
            });
            rest = &rest[body_end..];
        }
        Ok(out)
    };
    let points = arrays(section("<Points>", "</Points>"))?.into_iter().next().ok_or_else(|| bad("no points"))?;
    if points.values.len() != 3 * n_points {
        return Err(bad("point count"));
    }
    let cells = arrays(section("<Cells>", "</Cells>"))?;
    let ints = |name: &str| -> Result<Vec<usize>, VtuError> {
        let a = cells.iter().find(|a| a.name == name).ok_or_else(|| bad(&format!("no {name}")))?;
        Ok(a.values.iter().map(|&x| x as usize).collect())
    };
    let point_data = arrays(section("<PointData", "</PointData>"))?;
    let cell_data = arrays(section("<CellData", "</CellData>"))?;
    if point_data.iter().any(|a| a.values.len() != a.components * n_points)
        || cell_data.iter().any(|a| a.values.len() != a.components * n_cells)
    {
        return Err(bad("data array length"));
    }
    Ok(VtuData {
        n_points,
        n_cells,
        points: points.values,
        connectivity: ints("connectivity")?,
        offsets: ints("offsets")?,
        types: ints("types")?.into_iter().map(|t| t as u8).collect(),
        point_data,
        cell_data,
    })
}

/// Reads the `(timestep, file)` entries of a `.pvd` written by [`pvd_string`].
pub fn read_pvd(text: &str) -> Vec<(f64, String)> {
    text.lines()
        .filter(|l| l.contains("<DataSet"))
        .filter_map(|l| Some((attr(l, "timestep")?.parse().ok()?, attr(l, "file")?)))
        .collect()
}
