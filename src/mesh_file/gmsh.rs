//! Gmsh `.msh` files in pure Rust, at the scene's edge: MSH 2.2 and 4.1, ASCII and binary
//! (little-endian, 8-byte `size_t`), as gmsh documents them ("File formats", gmsh reference
//! manual, sections "MSH file format" and "Legacy formats: MSH file format version 2").
//!
//! What is read: the nodes (any tags ≥ 1, numbered in the file's order), every element whose
//! type is in [`TYPES`] grouped by type into blocks (node tags turned into node indices, tetra10
//! re-ordered from gmsh's order to ours: [`Cell::gmsh_order`]), and the physical groups: each
//! becomes a node set (the nodes of its elements, of any dimension), named by `$PhysicalNames`
//! or else by its tag. 2.2 takes an element's physical tag from its first tag; 4.1 from the
//! `$Entities` the element belongs to. Other sections (`$Periodic`, `$NodeData`, …) are
//! skipped. No panic on any input: every malformed byte is an error naming the section.

use crate::fem::Cell;
use std::collections::{BTreeMap, HashMap};
use thiserror::Error;

/// Gmsh element types known here: (type, meshio name, dimension, nodes).
pub const TYPES: [(i64, &str, usize, usize); 23] = [
    (1, "line", 1, 2),
    (2, "triangle", 2, 3),
    (3, "quad", 2, 4),
    (4, "tetra", 3, 4),
    (5, "hexahedron", 3, 8),
    (6, "wedge", 3, 6),
    (7, "pyramid", 3, 5),
    (8, "line3", 1, 3),
    (9, "triangle6", 2, 6),
    (10, "quad9", 2, 9),
    (11, "tetra10", 3, 10),
    (12, "hexahedron27", 3, 27),
    (13, "wedge18", 3, 18),
    (14, "pyramid14", 3, 14),
    (15, "vertex", 0, 1),
    (16, "quad8", 2, 8),
    (17, "hexahedron20", 3, 20),
    (18, "wedge15", 3, 15),
    (19, "pyramid13", 3, 13),
    (20, "triangle9", 2, 9),
    (21, "triangle10", 2, 10),
    (26, "line4", 1, 4),
    (29, "tetra20", 3, 20),
];

#[derive(Debug, Clone, PartialEq, Error)]
pub enum GmshError {
    #[error("not a gmsh file: it does not start with $MeshFormat")]
    NotGmsh,
    #[error(
        "gmsh format \"{version}\" (file type {file_type}, data size {size}): read are 2.2 and 4.1, ASCII or binary with data size 8"
    )]
    Version { version: String, file_type: String, size: String },
    #[error("a big-endian binary gmsh file: read are little-endian ones (write it on this machine, or as ASCII)")]
    BigEndian,
    #[error("section {section}: {what}")]
    Syntax { section: &'static str, what: String },
    #[error("section {section} ends early (the file is truncated)")]
    Truncated { section: &'static str },
    #[error("element {element} has gmsh type {code}: not a type this reader knows (known: 1-21, 26, 29)")]
    UnknownType { element: i64, code: i64 },
    #[error("gmsh element {element} refers to node tag {node}, which no $Nodes entry defines")]
    NodeTag { element: i64, node: i64 },
    #[error("gmsh element {element} refers to node tag {node}: gmsh node tags start at 1")]
    LowTag { element: i64, node: i64 },
    #[error("node tag {tag} is defined twice (or is < 1: gmsh node tags start at 1)")]
    BadNodeTag { tag: i64 },
    #[error("the file has no $Nodes or no $Elements section")]
    Missing,
    #[error(
        "section $Entities: entity {dim}/{entity} carries {tags} physical tags, so the physical groups would list {entries} nodes, more than the file has bytes ({limit}): at most one group entry per byte read is allowed"
    )]
    Groups { dim: usize, entity: i64, tags: usize, entries: usize, limit: usize },
}

/// One block: meshio type name, node indices (flat, our node order), nodes per element.
pub type Block = (String, Vec<i64>, usize);

/// A gmsh file as read (module docs): 3 coordinates per node, blocks by element type, groups.
#[derive(Debug, Clone, PartialEq)]
pub struct GmshFile {
    pub points: Vec<f64>,
    pub blocks: Vec<Block>,
    pub groups: BTreeMap<String, Vec<usize>>,
}

/// A cursor over the bytes; `section` names the part being read for errors.
struct Cursor<'a> {
    data: &'a [u8],
    pos: usize,
    binary: bool,
    section: &'static str,
}

impl<'a> Cursor<'a> {
    fn err(&self, what: impl Into<String>) -> GmshError {
        GmshError::Syntax { section: self.section, what: what.into() }
    }

    fn skip_space(&mut self) {
        while self.pos < self.data.len() && self.data[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    /// The next whitespace-separated token (None at the end).
    fn token(&mut self) -> Option<&'a [u8]> {
        self.skip_space();
        let start = self.pos;
        while self.pos < self.data.len() && !self.data[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        (self.pos > start).then(|| &self.data[start..self.pos])
    }

    fn text(&mut self) -> Result<&'a str, GmshError> {
        let t = self.token().ok_or(GmshError::Truncated { section: self.section })?;
        std::str::from_utf8(t).map_err(|_| self.err("a token is not text"))
    }

    fn ascii_int(&mut self) -> Result<i64, GmshError> {
        let t = self.text()?;
        t.parse().map_err(|_| self.err(format!("\"{t}\" is not an integer")))
    }

    fn bytes<const N: usize>(&mut self) -> Result<[u8; N], GmshError> {
        let b = self.data.get(self.pos..self.pos + N).ok_or(GmshError::Truncated { section: self.section })?;
        self.pos += N;
        Ok(b.try_into().expect("N bytes"))
    }

    /// An `int` (4 bytes binary).
    fn int(&mut self) -> Result<i64, GmshError> {
        if self.binary { Ok(i32::from_le_bytes(self.bytes()?) as i64) } else { self.ascii_int() }
    }

    /// A `size_t` (8 bytes binary).
    fn size(&mut self) -> Result<i64, GmshError> {
        if !self.binary {
            return self.ascii_int();
        }
        let v = u64::from_le_bytes(self.bytes()?);
        i64::try_from(v).map_err(|_| self.err(format!("size {v} out of range")))
    }

    fn float(&mut self) -> Result<f64, GmshError> {
        if self.binary {
            return Ok(f64::from_le_bytes(self.bytes()?));
        }
        let t = self.text()?;
        t.parse().map_err(|_| self.err(format!("\"{t}\" is not a number")))
    }

    /// A count, checked against what the remaining bytes can hold (`min_bytes` each), so that a
    /// corrupt count allocates nothing big.
    fn count(&mut self, v: i64, min_bytes: usize) -> Result<usize, GmshError> {
        let left = self.data.len().saturating_sub(self.pos) / min_bytes.max(1);
        usize::try_from(v)
            .ok()
            .filter(|&n| n <= left)
            .ok_or_else(|| self.err(format!("count {v} is negative or more than the file holds")))
    }

    /// Steps over the newline between a binary section's text header and its data; the end of
    /// the file there is a truncation of this section.
    fn skip_newline(&mut self) -> Result<(), GmshError> {
        if self.binary {
            if self.pos >= self.data.len() {
                return Err(GmshError::Truncated { section: self.section });
            }
            self.pos += 1;
        }
        Ok(())
    }

    /// The section's `$End<name>` right after its content: anything else means the count in
    /// the section's header (`what`) disagrees with what the section holds.
    fn close(&mut self, name: &str, what: &str) -> Result<(), GmshError> {
        let tag = format!("$End{name}");
        self.skip_space();
        if self.data.get(self.pos..).is_some_and(|rest| rest.starts_with(tag.as_bytes())) {
            self.pos += tag.len();
            return Ok(());
        }
        let rest = self.data.get(self.pos..).unwrap_or_default();
        if tag.as_bytes().starts_with(rest) {
            return Err(GmshError::Truncated { section: self.section });
        }
        Err(self.err(format!("more follows the {what} than its count says (expected {tag})")))
    }

    /// Skips to the line after `$End<name>`.
    fn end(&mut self, name: &str) -> Result<(), GmshError> {
        let tag = format!("$End{name}");
        let rest = self.data.get(self.pos..).unwrap_or_default();
        let at = rest
            .windows(tag.len())
            .position(|w| w == tag.as_bytes())
            .ok_or(GmshError::Truncated { section: self.section })?;
        self.pos += at + tag.len();
        Ok(())
    }
}

/// The node size of an element type ([`TYPES`]).
fn type_of(element: i64, code: i64) -> Result<(&'static str, usize, usize), GmshError> {
    TYPES.iter().find(|t| t.0 == code).map(|t| (t.1, t.2, t.3)).ok_or(GmshError::UnknownType { element, code })
}

/// What the sections give before the blocks and groups are assembled.
#[derive(Default)]
struct Raw {
    v4: bool,
    points: Vec<f64>,
    /// Node tag → index.
    index: HashMap<i64, usize>,
    names: HashMap<(usize, i64), String>,
    /// 4.1: (entity dim, entity tag) → physical tags.
    entities: HashMap<(usize, i64), Vec<i64>>,
    /// Per element type in order of appearance: (gmsh type, flat node indices in our order).
    blocks: Vec<(i64, Vec<i64>)>,
    /// (dim, physical tag) → node indices.
    group_nodes: BTreeMap<(usize, i64), Vec<usize>>,
    /// 4.1: (element dim, entity dim, entity tag) → the nodes of the entity's elements, given to
    /// its physical groups once at the end ([`Raw::entity_groups`]).
    entity_nodes: BTreeMap<(usize, usize, i64), Vec<usize>>,
    has_nodes: bool,
    has_elements: bool,
}

/// Reads a gmsh file's bytes (module docs).
pub fn parse(data: &[u8]) -> Result<GmshFile, GmshError> {
    let mut c = Cursor { data, pos: 0, binary: false, section: "$MeshFormat" };
    if c.token() != Some(b"$MeshFormat") {
        return Err(GmshError::NotGmsh);
    }
    let (version, file_type, size) = (c.text()?.to_string(), c.text()?.to_string(), c.text()?.to_string());
    let mut raw = Raw { v4: version == "4.1", ..Default::default() };
    if !(version == "2.2" || raw.v4) || !(file_type == "0" || file_type == "1") || size != "8" {
        return Err(GmshError::Version { version, file_type, size });
    }
    c.binary = file_type == "1";
    if c.binary {
        // One int 1 after the newline: its bytes tell the endianness.
        c.skip_newline()?;
        if c.bytes::<4>()? != 1i32.to_le_bytes() {
            return Err(GmshError::BigEndian);
        }
    }
    c.end("MeshFormat")?;
    while let Some(t) = c.token() {
        match t {
            b"$PhysicalNames" => names(&mut c, &mut raw)?,
            b"$Entities" => entities(&mut c, &mut raw)?,
            b"$Nodes" => nodes(&mut c, &mut raw)?,
            b"$Elements" => elements(&mut c, &mut raw)?,
            t if t.starts_with(b"$") && !t.starts_with(b"$End") => {
                let name = String::from_utf8_lossy(&t[1..]).into_owned();
                c.section = "(skipped)";
                c.end(&name)?;
            }
            _ => return Err(c.err(format!("unexpected \"{}\" between sections", String::from_utf8_lossy(t)))),
        }
    }
    if !(raw.has_nodes && raw.has_elements) {
        return Err(GmshError::Missing);
    }
    raw.entity_groups(data.len().max(1 << 12))?;
    let mut groups: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for ((dim, tag), mut nodes) in std::mem::take(&mut raw.group_nodes) {
        let name = raw.names.get(&(dim, tag)).cloned().unwrap_or_else(|| tag.to_string());
        let set = groups.entry(name).or_default();
        set.append(&mut nodes);
        set.sort_unstable();
        set.dedup();
    }
    let blocks = raw
        .blocks
        .into_iter()
        .map(|(code, flat)| {
            let (name, _, n) = type_of(0, code).expect("known when read");
            (name.to_string(), flat, n)
        })
        .collect();
    Ok(GmshFile { points: raw.points, blocks, groups })
}

impl Raw {
    /// 4.1: each entity's nodes into each of its physical groups. An entity may list thousands
    /// of physical tags (issue 32, E1: a 0.47 MB file asked for 4 GB): the copies are counted
    /// first and refused beyond `limit` entries, the file's size in bytes (a node takes at
    /// least 16 bytes to write, so this allows every node in 16 groups or more).
    fn entity_groups(&mut self, limit: usize) -> Result<(), GmshError> {
        let mut entries = 0usize;
        for ((_, dim, entity), nodes) in self.entity_nodes.iter_mut() {
            nodes.sort_unstable();
            nodes.dedup();
            let tags = self.entities.get_mut(&(*dim, *entity)).expect("an entity with nodes has tags");
            tags.sort_unstable();
            tags.dedup();
            entries = entries.saturating_add(tags.len().saturating_mul(nodes.len()));
            if entries > limit {
                let (dim, entity, tags) = (*dim, *entity, tags.len());
                return Err(GmshError::Groups { dim, entity, tags, entries, limit });
            }
        }
        for ((element_dim, dim, entity), nodes) in std::mem::take(&mut self.entity_nodes) {
            for &p in &self.entities[&(dim, entity)] {
                self.group_nodes.entry((element_dim, p)).or_default().extend_from_slice(&nodes);
            }
        }
        Ok(())
    }
}

/// `$PhysicalNames` (ASCII in every format): `n`, then `dim tag "name"` per line.
fn names(c: &mut Cursor, raw: &mut Raw) -> Result<(), GmshError> {
    c.section = "$PhysicalNames";
    let binary = std::mem::replace(&mut c.binary, false);
    let n = c.ascii_int()?;
    let n = c.count(n, 6)?;
    for _ in 0..n {
        let dim = c.ascii_int()?;
        let tag = c.ascii_int()?;
        c.skip_space();
        let rest = &c.data[c.pos..];
        let line = rest.split(|&b| b == b'\n').next().unwrap_or_default();
        c.pos += line.len();
        let name = String::from_utf8_lossy(line).trim().trim_matches('"').to_string();
        let dim = usize::try_from(dim).ok().filter(|&d| d <= 3).ok_or_else(|| c.err(format!("dimension {dim}")))?;
        raw.names.insert((dim, tag), name);
    }
    c.binary = binary;
    c.end("PhysicalNames")
}

/// `$Entities` (4.1): each entity's physical tags (points, curves, surfaces, volumes).
fn entities(c: &mut Cursor, raw: &mut Raw) -> Result<(), GmshError> {
    c.section = "$Entities";
    c.skip_newline()?; // the newline after the section's name
    let mut counts = [0; 4];
    for n in counts.iter_mut() {
        let v = c.size()?;
        *n = c.count(v, 4)?;
    }
    for (dim, &n) in counts.iter().enumerate() {
        for _ in 0..n {
            let tag = c.int()?;
            for _ in 0..if dim == 0 { 3 } else { 6 } {
                c.float()?;
            }
            let np = c.size()?;
            let np = c.count(np, 4)?;
            let phys = (0..np).map(|_| c.int()).collect::<Result<Vec<_>, _>>()?;
            raw.entities.insert((dim, tag), phys);
            if dim > 0 {
                let nb = c.size()?;
                for _ in 0..c.count(nb, 4)? {
                    c.int()?;
                }
            }
        }
    }
    c.end("Entities")
}

/// Registers node `tag` with its coordinates.
fn add_node(raw: &mut Raw, tag: i64, x: [f64; 3]) -> Result<(), GmshError> {
    let i = raw.points.len() / 3;
    if tag < 1 || raw.index.insert(tag, i).is_some() {
        return Err(GmshError::BadNodeTag { tag });
    }
    raw.points.extend_from_slice(&x);
    Ok(())
}

/// `$Nodes`: 2.2 `n` then `tag x y z`; 4.1 blocks of tags then coordinates (module docs).
fn nodes(c: &mut Cursor, raw: &mut Raw) -> Result<(), GmshError> {
    c.section = "$Nodes";
    raw.has_nodes = true;
    if !raw.v4 {
        let n = c.ascii_int()?;
        let n = c.count(n, 16)?;
        c.skip_newline()?; // the newline before binary data
        raw.points.reserve(3 * n);
        for _ in 0..n {
            let tag = c.int()?;
            let x = [c.float()?, c.float()?, c.float()?];
            add_node(raw, tag, x)?;
        }
        return c.close("Nodes", "nodes");
    }
    c.skip_newline()?; // the newline after the section's name
    let blocks = c.size()?;
    let total = c.size()?;
    raw.points.reserve(3 * c.count(total, 16)?);
    c.size()?;
    c.size()?;
    for _ in 0..c.count(blocks, 16)? {
        let (dim, _tag, parametric) = (c.int()?, c.int()?, c.int()?);
        let n = c.size()?;
        let n = c.count(n, 16)?;
        let tags = (0..n).map(|_| c.size()).collect::<Result<Vec<_>, _>>()?;
        let extra = if parametric == 1 { usize::try_from(dim).unwrap_or(0).min(3) } else { 0 };
        for tag in tags {
            let x = [c.float()?, c.float()?, c.float()?];
            for _ in 0..extra {
                c.float()?;
            }
            add_node(raw, tag, x)?;
        }
    }
    c.close("Nodes", "node blocks")
}

/// Where an element's nodes go besides its block: the physical group of its first tag (2.2), or
/// its entity's node list (4.1, [`Raw::entity_groups`]).
enum Groups {
    Tag(Option<i64>),
    Entity(Option<(usize, i64)>),
}

/// Appends one element: its nodes (gmsh order → ours), and its nodes to its groups.
fn add_element(raw: &mut Raw, element: i64, code: i64, tags: &[i64], groups: Groups) -> Result<(), GmshError> {
    let (_, dim, _) = type_of(element, code)?;
    let mut idx = Vec::with_capacity(tags.len());
    for &node in tags {
        if node < 1 {
            return Err(GmshError::LowTag { element, node });
        }
        idx.push(*raw.index.get(&node).ok_or(GmshError::NodeTag { element, node })?);
    }
    let block = match raw.blocks.iter().position(|b| b.0 == code) {
        Some(b) => b,
        None => {
            raw.blocks.push((code, Vec::new()));
            raw.blocks.len() - 1
        }
    };
    let order: Vec<usize> = match Cell::from_gmsh(code as u32) {
        Some(kind) if code > 0 => kind.gmsh_order().to_vec(),
        _ => (0..idx.len()).collect(),
    };
    raw.blocks[block].1.extend(order.iter().map(|&a| idx[a] as i64));
    match groups {
        Groups::Tag(Some(p)) => raw.group_nodes.entry((dim, p)).or_default().extend_from_slice(&idx),
        Groups::Entity(Some((d, e))) => raw.entity_nodes.entry((dim, d, e)).or_default().extend_from_slice(&idx),
        Groups::Tag(None) | Groups::Entity(None) => {}
    }
    Ok(())
}

/// `$Elements`: 2.2 `tag type ntags tags… nodes…` (binary: blocks of one type with a header);
/// 4.1 blocks `dim entity type n` of `tag nodes…`.
fn elements(c: &mut Cursor, raw: &mut Raw) -> Result<(), GmshError> {
    c.section = "$Elements";
    raw.has_elements = true;
    let mut nodes = Vec::new();
    if raw.v4 {
        c.skip_newline()?; // the newline after the section's name
        let blocks = c.size()?;
        for _ in 0..3 {
            c.size()?;
        }
        for _ in 0..c.count(blocks, 16)? {
            let (dim, entity, code) = (c.int()?, c.int()?, c.int()?);
            let n = c.size()?;
            let n = c.count(n, 8)?;
            let (_, _, nv) = type_of(-1, code)?;
            let dim = usize::try_from(dim).map_err(|_| c.err(format!("dimension {dim}")))?;
            let grouped = raw.entities.get(&(dim, entity)).is_some_and(|p| !p.is_empty());
            for _ in 0..n {
                let element = c.size()?;
                nodes.clear();
                for _ in 0..nv {
                    nodes.push(c.size()?);
                }
                add_element(raw, element, code, &nodes, Groups::Entity(grouped.then_some((dim, entity))))?;
            }
        }
        return c.close("Elements", "element blocks");
    }
    let n = c.ascii_int()?;
    let mut left = c.count(n, 8)?;
    c.skip_newline()?;
    while left > 0 {
        // Binary: a header (type, count, tags per element); ASCII: one element per line.
        let (code, count, ntags) = if c.binary { (c.int()?, c.int()?, c.int()?) } else { (-1, 1, -1) };
        let count = c.count(count, 4)?;
        if count == 0 {
            return Err(c.err("an element block of 0 elements"));
        }
        if count > left {
            return Err(c.err(format!("a block of {count} elements passes the section's count ({left} left)")));
        }
        for _ in 0..count {
            let element = c.int()?;
            let (code, ntags) = if c.binary { (code, ntags) } else { (c.int()?, c.int()?) };
            let (_, _, nv) = type_of(element, code)?;
            let ntags = c.count(ntags, 4)?;
            let tags = (0..ntags).map(|_| c.int()).collect::<Result<Vec<_>, _>>()?;
            nodes.clear();
            for _ in 0..nv {
                nodes.push(c.int()?);
            }
            // The physical tag is the first tag; 0 means none.
            let phys = tags.first().copied().filter(|&p| p != 0);
            add_element(raw, element, code, &nodes, Groups::Tag(phys))?;
        }
        left -= count;
    }
    c.close("Elements", "elements")
}

#[cfg(test)]
mod tests {
    use super::*;

    const SQUARE_22: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n1 7 \"left side\"\n2 9 \"body\"\n$EndPhysicalNames\n$Nodes\n5\n10 0 0 0\n20 1 0 0\n30 1 1 0\n40 0 1 0\n50 9 9 0\n$EndNodes\n$Elements\n3\n1 1 2 7 1 40 10\n2 2 2 9 1 10 20 30\n3 2 2 9 1 10 30 40\n$EndElements\n";

    #[test]
    fn an_ascii_22_file_gives_nodes_blocks_and_named_groups() {
        let f = parse(SQUARE_22.as_bytes()).unwrap();
        assert_eq!(f.points.len(), 15);
        assert_eq!(f.blocks, vec![("line".into(), vec![3, 0], 2), ("triangle".into(), vec![0, 1, 2, 0, 2, 3], 3)]);
        assert_eq!(f.groups["left side"], vec![0, 3]);
        assert_eq!(f.groups["body"], vec![0, 1, 2, 3]);
    }

    /// mutations, as run: the node-tag lookup `ok_or(NodeTag)` -> `unwrap_or(&0)` -> the
    /// NodeTag assertion fails; `c.count` without the bound -> the huge count allocates (the
    /// test aborts on memory) .
    #[test]
    fn malformed_files_are_refused_by_name() {
        let bad = SQUARE_22.replace("3 2 2 9 1 10 30 40", "3 2 2 9 1 10 30 41");
        assert_eq!(parse(bad.as_bytes()).unwrap_err(), GmshError::NodeTag { element: 3, node: 41 });
        let bad = SQUARE_22.replace("3 2 2 9 1 10 30 40", "3 2 2 9 1 10 30 0");
        assert_eq!(parse(bad.as_bytes()).unwrap_err(), GmshError::LowTag { element: 3, node: 0 });
        let bad = SQUARE_22.replace("50 9 9 0", "0 9 9 0");
        assert_eq!(parse(bad.as_bytes()).unwrap_err(), GmshError::BadNodeTag { tag: 0 });
        let bad = SQUARE_22.replace("2.2 0 8", "3.0 0 8");
        assert!(matches!(parse(bad.as_bytes()), Err(GmshError::Version { .. })));
        let bad = SQUARE_22.replace("$Nodes\n5\n", "$Nodes\n500000000000\n");
        assert!(matches!(parse(bad.as_bytes()), Err(GmshError::Syntax { section: "$Nodes", .. })));
        let bad = SQUARE_22.replace("3 2 2 9 1", "3 6 2 9 1");
        // A wedge reads 6 nodes: the next is "$EndElements".
        assert!(matches!(parse(bad.as_bytes()), Err(GmshError::Syntax { section: "$Elements", .. })));
        assert_eq!(parse(b"hello").unwrap_err(), GmshError::NotGmsh);
        let cut = &SQUARE_22.as_bytes()[..SQUARE_22.len() - 40];
        assert!(parse(cut).is_err());
        // Every prefix of the file is refused or read, never a panic.
        for k in 0..SQUARE_22.len() {
            let _ = parse(&SQUARE_22.as_bytes()[..k]);
        }
    }
}
