//! VTK XML output for ParaView, for any mesh of [`crate::fem`] or the plate's: one `.vtu`
//! (UnstructuredGrid, binary) per frame and a `.pvd` collection with the frame times, plus a
//! reader for the files written here (read-back tests).
//!
//! A frame is VTK XML with every array in the appended section, raw little-endian bytes (the
//! format VTK itself writes by default; ParaView and meshio read it): each array a block of a
//! UInt64 byte count and the values. [`Layout`] serialises what every frame of a run shares once
//! — the XML with every array's offset, the points, the cells (VTK_TRIANGLE = 5, VTK_QUAD = 9,
//! VTK_TETRA = 10, VTK_HEXAHEDRON = 12, VTK_QUADRATIC_TRIANGLE = 22, VTK_QUADRATIC_TETRA = 24:
//! the P2 cells as such, our node order being VTK's; connectivity and offsets as Int32) and the constant
//! cell arrays — and [`Layout::write`] appends one state's point arrays to a copy of it: a
//! frame costs a copy of the geometry's bytes and of the values, no number formatting (the ASCII
//! frames took about 8 shortest-round-trip numbers per node, 6.6× the steps of a 100 × 100
//! plate at a frame every step). The values are the `f64`s themselves, so reading them back
//! gives the same numbers bit for bit. The geometries choose their arrays (plates: `u`, `v`,
//! `warp`, `weight` in `crate::plate::vtu`; solids: the displacement and velocity vectors and
//! the contact pressure in `crate::solid::vtu`).

use super::cell::Cell;
use crate::numfmt::fmt_f64;
use std::fmt::Write as _;
use std::io::Write;
use thiserror::Error;

/// VTK cell type codes.
pub fn vtk_type(kind: Cell) -> u8 {
    kind.vtk()
}

/// A named data array: `components` values per point (or cell).
#[derive(Debug, Clone, Copy)]
pub struct Array<'a> {
    pub name: &'a str,
    pub components: usize,
    pub values: &'a [f64],
}

/// The mesh part of a frame: points in ℝ³, cells with `verts` vertices each, VTK type `kind`.
#[derive(Debug, Clone, Copy)]
pub struct Grid<'a> {
    pub points: &'a [[f64; 3]],
    pub cells: &'a [usize],
    pub verts: usize,
    pub kind: u8,
}

/// Appends one block of the appended section: the UInt64 byte count, then the bytes.
fn block(out: &mut Vec<u8>, bytes: impl ExactSizeIterator<Item = u8>) {
    out.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
    out.extend(bytes);
}

fn f64_bytes(values: &[f64]) -> impl ExactSizeIterator<Item = u8> + '_ {
    values.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>().into_iter()
}

fn i32_bytes(values: impl Iterator<Item = usize>) -> impl ExactSizeIterator<Item = u8> {
    let to_i32 = |x: usize| i32::try_from(x).expect("meshes have fewer than 2³¹ vertices and cell entries");
    values.flat_map(move |x| to_i32(x).to_le_bytes()).collect::<Vec<u8>>().into_iter()
}

/// The frames of one mesh in the appended raw format (module docs), everything but the point
/// arrays serialised once: the XML up to the appended data's `_`, the blocks of the geometry
/// and the cell arrays, and the point arrays' names and sizes.
#[derive(Debug, Clone)]
pub struct Layout {
    head: Vec<u8>,
    fixed: Vec<u8>,
    /// (name, components) of each point array, in the order [`Layout::write`] takes them.
    point_arrays: Vec<(String, usize)>,
    n_points: usize,
}

const TAIL: &[u8] = b"\n  </AppendedData>\n</VTKFile>\n";

impl Layout {
    /// The layout of frames of `grid` with the point arrays `point_arrays` (name, components;
    /// the first is the active scalar, `vectors` the active vector) and the constant cell
    /// arrays `cell_data` (the first is the active scalar).
    pub fn new(grid: &Grid, point_arrays: &[(&str, usize)], vectors: &str, cell_data: &[Array]) -> Self {
        let (np, nc) = (grid.points.len(), grid.cells.len() / grid.verts);
        assert!(cell_data.iter().all(|a| a.values.len() == a.components * nc));
        // The fixed blocks first (offsets from the `_`), then the point arrays.
        let mut fixed = Vec::new();
        let mut offsets = Vec::new();
        let mut put = |fixed: &mut Vec<u8>, bytes: &mut dyn ExactSizeIterator<Item = u8>| {
            offsets.push(fixed.len());
            block(fixed, bytes);
        };
        let points: Vec<f64> = grid.points.iter().flat_map(|p| *p).collect();
        put(&mut fixed, &mut f64_bytes(&points));
        put(&mut fixed, &mut i32_bytes(grid.cells.iter().copied()));
        put(&mut fixed, &mut i32_bytes((1..=nc).map(|c| c * grid.verts)));
        put(&mut fixed, &mut std::iter::repeat_n(grid.kind, nc));
        for a in cell_data {
            put(&mut fixed, &mut f64_bytes(a.values));
        }
        let mut at = fixed.len();
        let mut point_offsets = Vec::new();
        for &(_, c) in point_arrays {
            point_offsets.push(at);
            at += 8 + 8 * c * np;
        }
        let array = |s: &mut String, ty: &str, name: &str, comps: usize, offset: usize| {
            let _ = writeln!(
                s,
                "        <DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{comps}\" format=\"appended\" offset=\"{offset}\"/>"
            );
        };
        let mut s = String::from("<?xml version=\"1.0\"?>\n");
        s.push_str(
            "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n",
        );
        let _ = writeln!(s, "  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"{np}\" NumberOfCells=\"{nc}\">");
        let scalars = point_arrays.first().map_or("", |a| a.0);
        let _ = writeln!(s, "      <PointData Scalars=\"{scalars}\" Vectors=\"{vectors}\">");
        for (&(name, c), &o) in point_arrays.iter().zip(&point_offsets) {
            array(&mut s, "Float64", name, c, o);
        }
        let cell_scalars = cell_data.first().map_or("", |a| a.name);
        let _ = writeln!(s, "      </PointData>\n      <CellData Scalars=\"{cell_scalars}\">");
        for (a, &o) in cell_data.iter().zip(&offsets[4..]) {
            array(&mut s, "Float64", a.name, a.components, o);
        }
        s.push_str("      </CellData>\n      <Points>\n");
        array(&mut s, "Float64", "Points", 3, offsets[0]);
        s.push_str("      </Points>\n      <Cells>\n");
        array(&mut s, "Int32", "connectivity", 1, offsets[1]);
        array(&mut s, "Int32", "offsets", 1, offsets[2]);
        array(&mut s, "UInt8", "types", 1, offsets[3]);
        s.push_str("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _");
        let point_arrays = point_arrays.iter().map(|&(n, c)| (n.to_string(), c)).collect();
        Self { head: s.into_bytes(), fixed, point_arrays, n_points: np }
    }

    /// The size of one frame in bytes.
    pub fn frame_bytes(&self) -> usize {
        self.head.len()
            + self.fixed.len()
            + self.point_arrays.iter().map(|a| 8 + 8 * a.1 * self.n_points).sum::<usize>()
            + TAIL.len()
    }

    /// Writes one frame: the point arrays' `values` in the layout's order.
    pub fn write(&self, out: &mut dyn Write, values: &[&[f64]]) -> std::io::Result<()> {
        assert_eq!(values.len(), self.point_arrays.len());
        out.write_all(&self.head)?;
        out.write_all(&self.fixed)?;
        let mut bytes = Vec::new();
        for (v, &(_, c)) in values.iter().zip(&self.point_arrays) {
            assert_eq!(v.len(), c * self.n_points);
            bytes.resize(8 + 8 * v.len(), 0);
            bytes[..8].copy_from_slice(&(8 * v.len() as u64).to_le_bytes());
            for (b, x) in bytes[8..].chunks_exact_mut(8).zip(v.iter()) {
                b.copy_from_slice(&x.to_le_bytes());
            }
            out.write_all(&bytes)?;
        }
        out.write_all(TAIL)
    }

    /// One frame in memory ([`Layout::write`]).
    pub fn frame(&self, values: &[&[f64]]) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.frame_bytes());
        self.write(&mut out, values).expect("writing to memory");
        out
    }
}

/// Writes `vtu/frame_NNNNN.vtu` (one per frame, from `frame`) and the collection
/// `<name>.pvd` into `dir`.
pub fn write_series(
    dir: &std::path::Path,
    name: &str,
    times: &[f64],
    mut frame: impl FnMut(usize) -> Vec<u8>,
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

/// The content of a `.vtu` file written by [`Layout::write`].
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

/// The values of one `DataArray` element (`tag` from `<DataArray` to its `>`; `body` what
/// follows it): ASCII text up to `</DataArray>`, or a block of the appended section at the
/// tag's offset (Float64, Int32, Int64 or UInt8 little-endian values, read as f64).
fn array_values(tag: &str, body: &str, appended: &[u8]) -> Result<Vec<f64>, VtuError> {
    let bad = |m: String| VtuError::Malformed(m);
    if attr(tag, "format").as_deref() != Some("appended") {
        let end = body.find("</DataArray>").ok_or_else(|| bad("unterminated DataArray".into()))?;
        return body[..end]
            .split_whitespace()
            .map(|w| w.parse::<f64>().map_err(|_| bad(format!("not a number: {w}"))))
            .collect();
    }
    let offset: usize = attr(tag, "offset").and_then(|o| o.parse().ok()).ok_or_else(|| bad("no offset".into()))?;
    let count = appended.get(offset..offset + 8).ok_or_else(|| bad(format!("offset {offset} past the data")))?;
    let n = u64::from_le_bytes(count.try_into().expect("8 bytes")) as usize;
    let data =
        appended.get(offset + 8..offset + 8 + n).ok_or_else(|| bad(format!("block at {offset} past the data")))?;
    let ty = attr(tag, "type").unwrap_or_default();
    let values = match ty.as_str() {
        "Float64" => data.chunks_exact(8).map(|b| f64::from_le_bytes(b.try_into().expect("8"))).collect(),
        "Int64" => data.chunks_exact(8).map(|b| i64::from_le_bytes(b.try_into().expect("8")) as f64).collect(),
        "Int32" => data.chunks_exact(4).map(|b| i32::from_le_bytes(b.try_into().expect("4")) as f64).collect(),
        "UInt8" => data.iter().map(|&b| b as f64).collect(),
        _ => return Err(bad(format!("appended type {ty}"))),
    };
    Ok(values)
}

/// Parses the `.vtu` files written by this module, binary (appended raw) or ASCII (not a general
/// VTK reader).
pub fn read_vtu(file: impl AsRef<[u8]>) -> Result<VtuData, VtuError> {
    let bytes = file.as_ref();
    let bad = |m: &str| VtuError::Malformed(m.to_string());
    // The XML part ends where the appended data begins (raw bytes after its `_`).
    let tag = b"<AppendedData";
    let (xml_end, appended) = match bytes.windows(tag.len()).position(|w| w == tag) {
        Some(a) => {
            let us = a + bytes[a..].iter().position(|&b| b == b'_').ok_or_else(|| bad("no _ in <AppendedData>"))?;
            (a, &bytes[us + 1..])
        }
        None => (bytes.len(), &bytes[..0]),
    };
    let text = std::str::from_utf8(&bytes[..xml_end]).map_err(|_| bad("the XML is not UTF-8"))?;
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
            out.push(DataArray {
                name: attr(tag, "Name").unwrap_or_default(),
                components: attr(tag, "NumberOfComponents").and_then(|v| v.parse().ok()).unwrap_or(1),
                values: array_values(tag, &rest[tag_end + 1..], appended)?,
            });
            rest = &rest[tag_end..];
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
