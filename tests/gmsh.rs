//! The pure-Rust gmsh reader against meshio, on files gmsh wrote (`python/meshes/generate.py
//! --fixtures`: a curved P2 disc and a tetra10 sphere, each in MSH 2.2 and 4.1, ASCII and
//! binary, with meshio's reading stored beside them), and the body meshes built from them.

use massredist::fem::{Cell, Mesh};
use massredist::scene::gmsh::{GmshFile, parse};
use massredist::scene::mesh_file::{MeshFileError, read, read_body};
use serde_json::Value;
use std::path::PathBuf;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/meshes").join(name)
}

const FORMATS: [&str; 4] = ["22a", "22b", "41a", "41b"];

/// meshio's reading (generate.py's `meshio_view`).
fn meshio(name: &str) -> Value {
    serde_json::from_str(&std::fs::read_to_string(fixture(&format!("{name}.meshio.json"))).unwrap()).unwrap()
}

/// Our reading equals meshio's: the same block types with the same node indices (meshio maps
/// gmsh's tetra10 to VTK order as we do), the same group node sets, and the points to 1e-15
/// of the size: gmsh's ASCII prints %.16g, so its binary files differ from its ASCII ones in the
/// last bit (exact for the ASCII files, which meshio's reading came from).
fn assert_as_meshio(ours: &GmshFile, theirs: &Value, exact: bool, what: &str) {
    let pts: Vec<f64> = theirs["points"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|p| p.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
        .collect();
    assert_eq!(ours.points.len(), pts.len(), "{what}");
    let worst = ours.points.iter().zip(&pts).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(if exact { worst == 0.0 } else { worst <= 1e-15 * 40.0 }, "{what}: points differ by {worst}");
    let blocks: Vec<(String, Vec<i64>)> = theirs["blocks"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| {
            let cells =
                b[1].as_array().unwrap().iter().flat_map(|c| c.as_array().unwrap().iter().map(|v| v.as_i64().unwrap()));
            (b[0].as_str().unwrap().to_string(), cells.collect())
        })
        .collect();
    let ours_blocks: Vec<(String, Vec<i64>)> = ours.blocks.iter().map(|b| (b.0.clone(), b.1.clone())).collect();
    assert_eq!(ours_blocks, blocks, "{what}");
    let groups = theirs["groups"].as_object().unwrap();
    assert_eq!(ours.groups.len(), groups.len(), "{what}");
    for (name, nodes) in groups {
        let nodes: Vec<usize> = nodes.as_array().unwrap().iter().map(|v| v.as_u64().unwrap() as usize).collect();
        assert_eq!(ours.groups[name], nodes, "{what}: group {name}");
    }
}

/// mutations, as run: `Cell::gmsh_order` of tetra10 the identity -> the sphere's blocks differ
/// from meshio's (and the edge-node check below fails); the binary 4.1 entities' newline skip
/// removed -> the 41b files are refused (Syntax in $Entities).
#[test]
fn four_formats_read_as_meshio_reads_them_and_give_one_body_mesh() {
    for (name, kind, dim) in [("disc_p2", Cell::Triangle6, 2), ("sphere_tet10", Cell::Tet10, 3)] {
        let theirs = meshio(&format!("{name}_22a"));
        let mut meshes: Vec<Mesh> = Vec::new();
        for f in FORMATS {
            let path = fixture(&format!("{name}_{f}.msh"));
            let ours = parse(&std::fs::read(&path).unwrap()).unwrap();
            assert_as_meshio(&ours, &theirs, f.ends_with('a'), &format!("{name}_{f}"));
            let m = read_body("solid.mesh", &path, dim).unwrap();
            assert_eq!(m.kind, kind);
            meshes.push(m);
        }
        for m in &meshes[1..] {
            assert_eq!((&m.cells, &m.groups), (&meshes[0].cells, &meshes[0].groups), "{name}");
            let worst = m
                .points
                .iter()
                .flatten()
                .zip(meshes[0].points.iter().flatten())
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(worst <= 40.0 * 1e-15, "{name}: {worst}");
        }
        let m = &meshes[0];
        // The group "bottom" is the one node at the origin.
        assert_eq!(m.groups["bottom"].len(), 1);
        assert!(m.points[m.groups["bottom"][0]].iter().all(|x| approx::relative_eq!(
            *x,
            0.0,
            epsilon = 1e-12,
            max_relative = 0.0
        )));
        // Every edge node lies near its edge's midpoint (VTK edges): within a quarter of the
        // edge (boundary edges bulge by their sagitta, far less at these sizes). A swapped
        // tetra10 pair would sit half an edge away.
        let edges: &[[usize; 2]] =
            if dim == 2 { &[[0, 1], [1, 2], [2, 0]] } else { &[[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]] };
        for c in 0..m.n_cells() {
            let p = m.cell_points(c);
            for (e, &[a, b]) in edges.iter().enumerate() {
                let mid: Vec<f64> = (0..3).map(|k| 0.5 * (p[a][k] + p[b][k])).collect();
                let off = (0..3).map(|k| (p[dim + 1 + e][k] - mid[k]).powi(2)).sum::<f64>().sqrt();
                let len = (0..3).map(|k| (p[a][k] - p[b][k]).powi(2)).sum::<f64>().sqrt();
                assert!(off <= 0.25 * len, "{name} cell {c} edge {e}: {off} from the midpoint of {len}");
            }
        }
    }
}

/// The disc of radius 20: P1 (inscribed polygon) has less area than π R², P2 (parabolic
/// sides through three points of the circle) is within 1e-4 relative at h = 8 (its error is
/// O(h⁴/R⁴)); the sphere's P2 volume likewise within 1e-2 (coarse: h = R).
#[test]
fn curved_p2_bodies_measure_nearly_the_exact_shape() {
    let area = std::f64::consts::PI * 400.0;
    let p1 = read_body("solid.mesh", &fixture("disc_p1.msh"), 2).unwrap();
    let p2 = read_body("solid.mesh", &fixture("disc_p2_41b.msh"), 2).unwrap();
    let (a1, a2) = (p1.total_measure(), p2.total_measure());
    assert!(a1 < area && (a2 - area).abs() < 1e-4 * area && (a2 - area).abs() < (a1 - area).abs(), "{a1} {a2} {area}");
    let vol = 4.0 / 3.0 * std::f64::consts::PI * 8000.0;
    let s = read_body("solid.mesh", &fixture("sphere_tet10_22b.msh"), 3).unwrap();
    assert!(
        approx::relative_eq!(s.total_measure(), vol, epsilon = 1e-2 * vol, max_relative = 0.0),
        "{}",
        s.total_measure()
    );
    let top = &read_body("solid.mesh", &fixture("half_disc_p2.msh"), 2).unwrap();
    assert!(top.groups["top"].iter().all(|&v| approx::relative_eq!(
        top.points[v][1],
        20.0,
        epsilon = 1e-12,
        max_relative = 0.0
    )));
    let hemi = read_body("solid.mesh", &fixture("hemisphere_tet.msh"), 3).unwrap();
    assert!(hemi.groups["top"].iter().all(|&v| approx::relative_eq!(
        hemi.points[v][2],
        20.0,
        epsilon = 1e-12,
        max_relative = 0.0
    )));
    assert_eq!(hemi.kind, Cell::Tet);
}

/// The wrong dimension and a box scene's mesh of P2 cells are refused by name.
#[test]
fn wrong_dimension_and_p2_boxes_are_refused() {
    let err = read_body("solid.mesh", &fixture("disc_p2_22a.msh"), 3).unwrap_err();
    assert!(matches!(err, MeshFileError::Dimension { found: 2, dim: 3, kind: "triangle6", .. }), "{err}");
    let err = read("solid.mesh", &fixture("disc_p2_22a.msh")).unwrap_err();
    assert!(err.to_string().contains("triangle6 cells in a box mesh"), "{err}");
    // The box fixture still reads, without Python.
    let m = read("plate.mesh", &fixture("square_4x3_tri.msh")).unwrap();
    assert_eq!(m.kind, Cell::Triangle);
}

/// A binary MSH 2.2 square: 4 nodes, 2 triangles in one block (physical tag 9), `count` in the
/// `$Elements` header.
fn binary_22_square(count: usize) -> Vec<u8> {
    let mut b = b"$MeshFormat\n2.2 1 8\n".to_vec();
    b.extend(1i32.to_le_bytes());
    b.extend(b"\n$EndMeshFormat\n$Nodes\n4\n");
    for (tag, x, y) in [(1, 0.0, 0.0), (2, 1.0, 0.0), (3, 1.0, 1.0), (4, 0.0, 1.0)] {
        b.extend((tag as i32).to_le_bytes());
        for v in [x, y, 0.0f64] {
            b.extend(v.to_le_bytes());
        }
    }
    b.extend(format!("\n$EndNodes\n$Elements\n{count}\n").as_bytes());
    for v in [2i32, 2, 2] {
        b.extend(v.to_le_bytes()); // type triangle, 2 elements, 2 tags each
    }
    for e in [[1i32, 9, 1, 1, 2, 3], [2, 9, 1, 1, 3, 4]] {
        e.iter().for_each(|v| b.extend(v.to_le_bytes()));
    }
    b.extend(b"\n$EndElements\n");
    b
}

/// E3 (issue 32): a 48-byte binary MSH 2.2 file ending right after `$Nodes 0` panicked (exit
/// 101): the binary reader stepped over the newline past the end. Every truncation of a binary
/// file is now a refusal naming the file and the section (prefixes of the small square, and of
/// gmsh's own binary files at a stride).
#[test]
fn every_truncation_of_a_binary_file_is_refused_naming_file_and_section() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("cut.msh");
    let mut repro = b"$MeshFormat\n2.2 1 8\n".to_vec();
    repro.extend(1i32.to_le_bytes());
    repro.extend(b"\n$EndMeshFormat\n$Nodes\n0");
    assert_eq!(repro.len(), 48);
    std::fs::write(&path, &repro).unwrap();
    let err = read("solid.mesh", &path).unwrap_err().to_string();
    assert!(err.contains("cut.msh") && err.contains("$Nodes"), "{err}");
    let square = binary_22_square(2);
    assert!(parse(&square).is_ok());
    let sections = ["$MeshFormat", "$Nodes", "$Elements", "(skipped)"];
    // Every prefix but the whole file less its last newline (complete after `$EndElements`).
    for k in 0..square.len() - 1 {
        let err = parse(&square[..k]).expect_err("a strict prefix is incomplete").to_string();
        assert!(
            sections.iter().any(|s| err.contains(s)) || err.contains("not a gmsh file") || err.contains("no $Nodes"),
            "{k}: {err}"
        );
    }
    for name in ["disc_p2_22b.msh", "disc_p2_41b.msh", "sphere_tet10_22b.msh", "sphere_tet10_41b.msh"] {
        let bytes = std::fs::read(fixture(name)).unwrap();
        for k in (0..bytes.len()).step_by(bytes.len() / 1500 + 1) {
            assert!(parse(&bytes[..k]).is_err(), "{name}[..{k}]");
        }
    }
}

/// E6 (issue 32): an MSH 2.2 `$Elements` count smaller than the elements that follow silently
/// dropped the rest (half a body). A count that disagrees with the section's content is refused,
/// naming the section, in ASCII and in binary.
#[test]
fn an_elements_count_that_disagrees_with_the_section_is_refused() {
    let ascii = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n\
                 $Elements\n2\n1 2 2 9 1 1 2 3\n2 2 2 9 1 1 3 4\n$EndElements\n";
    assert_eq!(parse(ascii.as_bytes()).unwrap().blocks[0].1.len(), 6);
    for bad in [ascii.replace("$Elements\n2\n", "$Elements\n1\n"), ascii.replace("$Nodes\n4\n", "$Nodes\n3\n")] {
        let err = parse(bad.as_bytes()).unwrap_err().to_string();
        assert!(err.contains("$Elements") || err.contains("$Nodes"), "{err}");
        assert!(err.contains("count"), "{err}");
    }
    let err = parse(&binary_22_square(1)).unwrap_err().to_string();
    assert!(err.contains("$Elements") && err.contains("count"), "{err}");
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("half.msh");
    std::fs::write(&path, ascii.replace("$Elements\n2\n", "$Elements\n1\n")).unwrap();
    let err = read("solid.mesh", &path).unwrap_err().to_string();
    assert!(err.contains("half.msh") && err.contains("$Elements"), "{err}");
}

/// An ASCII MSH 4.1 unit square of 10 × 10 × 2 triangles on one surface entity that carries
/// `tags` physical tags.
fn square_41_with_tags(tags: usize) -> String {
    let n = 11;
    let phys: Vec<String> = (1..=tags).map(|t| t.to_string()).collect();
    let mut s = format!(
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 1 0\n1 0 0 0 1 1 0 {tags} {} 0\n$EndEntities\n",
        phys.join(" ")
    );
    s += &format!("$Nodes\n1 {0} 1 {0}\n2 1 0 {0}\n", n * n);
    (1..=n * n).for_each(|t| s += &format!("{t}\n"));
    (0..n * n).for_each(|k| s += &format!("{} {} 0\n", (k % n) as f64 / 10.0, (k / n) as f64 / 10.0));
    s += &format!("$EndNodes\n$Elements\n1 {0} 1 {0}\n2 1 2 {0}\n", 2 * (n - 1) * (n - 1));
    let mut e = 0;
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = j * n + i + 1;
            for tri in [[a, a + 1, a + n + 1], [a, a + n + 1, a + n]] {
                e += 1;
                s += &format!("{e} {} {} {}\n", tri[0], tri[1], tri[2]);
            }
        }
    }
    s + "$EndElements\n"
}

/// E1 (issue 32): one entity listing thousands of physical tags made the 4.1 reader copy the
/// entity's nodes once per tag and per element (a 0.47 MB file allocated over 4 GB). The groups
/// are now gathered per entity and expanded once, and an expansion larger than the file itself
/// (one node entry per byte read) is refused by name. Unfixed: the 5000-tag square was read
/// (600,000 node entries from 46 kB).
#[test]
fn many_physical_tags_on_one_entity_are_bounded_by_the_file_size() {
    let ok = parse(square_41_with_tags(3).as_bytes()).unwrap();
    assert_eq!(ok.groups.len(), 3);
    assert!(ok.groups.values().all(|g| g.len() == 121 && g.windows(2).all(|w| w[0] < w[1])));
    let text = square_41_with_tags(5000);
    let err = parse(text.as_bytes()).unwrap_err().to_string();
    assert!(err.contains("$Entities") && err.contains("5000 physical tags"), "{err}");
}

/// E8 (issue 32): a mesh path that is a symlink to a file of /proc reports size 0, passed the
/// size cap and was read until memory ran out (/proc/self/pagemap: 256 GB of page entries).
/// It is refused by name, before meshio or the gmsh reader reads it.
#[cfg(target_os = "linux")]
#[test]
fn a_proc_file_behind_a_symlink_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("pagemap.msh");
    std::os::unix::fs::symlink("/proc/self/pagemap", &path).unwrap();
    let err = read_body("solid.mesh", &path, 3).unwrap_err().to_string();
    assert!(err.contains("solid.mesh") && err.contains("pagemap.msh") && err.contains("/proc"), "{err}");
}
