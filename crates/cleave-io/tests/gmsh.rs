//! Tests of the Gmsh reader (`cleave_io::gmsh`) on the fixtures of `tests/data/gmsh/`, which
//! Gmsh itself wrote (`gen.py` there says how), against the counts Gmsh found when it read them
//! back (`expected.json`), the exact volumes and areas of the box, and on small hand-written
//! files for the rules and the errors. Gmsh is not needed to run them.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use cleave_core::element::hex8;
use cleave_io::deck::{parse_deck, read_deck};
use cleave_io::gmsh::{keyword_text, parse_msh, read_msh, At, Mesh, MshError, SolidKind, Version};
use serde_json::Value;

const MESHES: [&str; 4] = ["tet", "hex", "prism", "mixed"];
const ENCODINGS: [&str; 4] = ["41a", "41b", "22a", "22b"];

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gmsh")
}

fn fixture(mesh: &str, enc: &str) -> PathBuf {
    dir().join(format!("{mesh}-{enc}.msh"))
}

fn read(mesh: &str, enc: &str) -> Mesh {
    read_msh(&fixture(mesh, enc)).unwrap_or_else(|e| panic!("{e}"))
}

fn expected() -> Value {
    let text = std::fs::read_to_string(dir().join("expected.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// Each solid's volume computed here, independently of the reader's own: the hexahedron and
/// the collapsed prism by cleave's hexahedron volume, the tetrahedron by its triple product.
fn volumes(m: &Mesh) -> Vec<f64> {
    let x = m.coords();
    m.solids
        .iter()
        .map(|s| {
            let c = s.nodes.map(|n| x[&n]);
            match s.kind {
                SolidKind::Tet4 => {
                    let d = [sub(c[1], c[0]), sub(c[2], c[0]), sub(c[3], c[0])];
                    let k = cross(d[0], d[1]);
                    (k[0] * d[2][0] + k[1] * d[2][1] + k[2] * d[2][2]) / 6.0
                }
                SolidKind::Hex8 | SolidKind::Prism6 => hex8::volume(&c),
            }
        })
        .collect()
}

#[test]
fn the_four_encodings_give_the_same_mesh() {
    for name in MESHES {
        let a = read(name, "41a");
        for enc in ENCODINGS {
            let b = read(name, enc);
            let (version, binary) = match enc {
                "41a" => (Version::V41, false),
                "41b" => (Version::V41, true),
                "22a" => (Version::V22, false),
                _ => (Version::V22, true),
            };
            assert_eq!((b.format.version, b.format.binary), (version, binary));
            // Gmsh numbers elements in MSH 2.2 its own way where a mesh has several element
            // types (mixed: by type, tetrahedra first): the same solids, the tags aside
            let key = |m: &Mesh| {
                let mut k: Vec<_> = m.solids.iter().map(|s| (s.kind, s.nodes, s.part)).collect();
                k.sort_unstable();
                k
            };
            assert_eq!(key(&a), key(&b), "{name}-{enc}");
            if name != "mixed" {
                assert_eq!(a.solids, b.solids, "{name}-{enc}");
            }
            assert_eq!(a.groups, b.groups, "{name}-{enc}");
            assert_eq!(a.element_counts, b.element_counts, "{name}-{enc}");
            assert_eq!(a.reoriented, b.reoriented);
            assert_eq!(a.nodes.len(), b.nodes.len());
            // Gmsh writes ASCII coordinates with 16 significant digits, binary ones exactly:
            // the two agree to the last digit Gmsh writes
            for (p, q) in a.nodes.iter().zip(&b.nodes) {
                assert_eq!(p.tag, q.tag);
                for k in 0..3 {
                    assert!(
                        (p.x[k] - q.x[k]).abs() <= 1e-15,
                        "{name}-{enc}: {p:?} {q:?}"
                    );
                }
            }
        }
        // the two ASCII files, and the two binary ones, hold the same numbers
        let same = |p: Mesh, q: Mesh| {
            assert_eq!(p.nodes, q.nodes, "{name}");
            assert_eq!(p.groups, q.groups, "{name}");
        };
        same(read(name, "41a"), read(name, "22a"));
        same(read(name, "41b"), read(name, "22b"));
        assert_eq!(read(name, "22a").solids, read(name, "22b").solids);
    }
}

#[test]
fn counts_are_those_gmsh_reads_back() {
    let exp = expected();
    for name in MESHES {
        for enc in ENCODINGS {
            let m = read(name, enc);
            let e = &exp["meshes"][name]["files"][enc];
            assert_eq!(
                m.nodes.len() as u64,
                e["nodes"].as_u64().unwrap(),
                "{name}-{enc}"
            );
            let counts: HashMap<String, u64> = m
                .element_counts
                .iter()
                .map(|(t, n)| (t.to_string(), *n as u64))
                .collect();
            let want: HashMap<String, u64> = e["elements"]
                .as_object()
                .unwrap()
                .iter()
                .map(|(k, v)| (k.clone(), v.as_u64().unwrap()))
                .collect();
            assert_eq!(counts, want, "{name}-{enc}");
            for (kind, ty) in [
                (SolidKind::Tet4, "4"),
                (SolidKind::Hex8, "5"),
                (SolidKind::Prism6, "6"),
            ] {
                let n = m.solids.iter().filter(|s| s.kind == kind).count() as u64;
                assert_eq!(n, want.get(ty).copied().unwrap_or(0), "{name}-{enc} {ty}");
            }
            let groups = e["groups"].as_array().unwrap();
            assert_eq!(m.groups.len(), groups.len(), "{name}-{enc}");
            for g in groups {
                let (dim, tag) = (g["dim"].as_u64().unwrap() as u8, g["tag"].as_i64().unwrap());
                let ours = m
                    .groups
                    .iter()
                    .find(|h| h.dim == dim && h.tag == tag)
                    .unwrap_or_else(|| panic!("{name}-{enc}: no group {dim} {tag}"));
                assert_eq!(ours.name, g["name"].as_str().unwrap());
                assert_eq!(ours.nodes.len() as u64, g["nodes"].as_u64().unwrap());
                let n: u64 = g["elements"]
                    .as_object()
                    .unwrap()
                    .values()
                    .map(|v| v.as_u64().unwrap())
                    .sum();
                assert_eq!(ours.elements as u64, n, "{name}-{enc} group {dim} {tag}");
                if dim == 2 {
                    assert_eq!(ours.faces.len() as u64, n);
                }
                if dim == 3 {
                    // a physical volume is a part, of as many solids
                    let solids = m.solids.iter().filter(|s| s.part == tag).count() as u64;
                    assert_eq!(solids, n);
                }
            }
        }
    }
}

#[test]
fn volumes_are_positive_and_fill_the_box() {
    let exp = expected();
    for name in MESHES {
        let exact = &exp["meshes"][name]["exact"];
        let total = exact["total_volume"].as_f64().unwrap_or(0.48);
        for enc in ENCODINGS {
            let m = read(name, enc);
            assert_eq!(m.reoriented, 0, "Gmsh writes every element positive");
            let v = volumes(&m);
            let own = m.volumes();
            for (k, (&a, &b)) in v.iter().zip(&own).enumerate() {
                assert!(
                    a > 0.0,
                    "{name}-{enc}: element {} has volume {a}",
                    m.solids[k].tag
                );
                assert!(rel(b, a) < 1e-13, "{name}-{enc}: {a} {b}");
            }
            let sum: f64 = v.iter().sum();
            assert!(rel(sum, total) < 1e-12, "{name}-{enc}: {sum} vs {total}");
            for (part, want) in exact["volumes"].as_object().unwrap() {
                let p: i64 = part.parse().unwrap();
                let got: f64 = m
                    .solids
                    .iter()
                    .zip(&v)
                    .filter(|(s, _)| s.part == p)
                    .map(|(_, v)| v)
                    .sum();
                assert!(
                    rel(got, want.as_f64().unwrap()) < 1e-12,
                    "{name}-{enc} part {p}: {got}"
                );
                // and Gmsh's own element volumes agree
                let g = exp["meshes"][name]["files"][enc]["groups"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .find(|g| g["dim"] == 3 && g["tag"] == p)
                    .unwrap()["gmsh_volume"]
                    .as_f64()
                    .unwrap();
                assert!(
                    rel(got, g) < 1e-12,
                    "{name}-{enc} part {p}: {got} vs Gmsh {g}"
                );
            }
        }
    }
}

#[test]
fn segment_sets_cover_exactly_their_surface() {
    let exp = expected();
    for name in MESHES {
        let areas = &exp["meshes"][name]["exact"]["areas"];
        for enc in ENCODINGS {
            let m = read(name, enc);
            let x = m.coords();
            for g in m.groups.iter().filter(|g| g.dim == 2) {
                let mut area = 0.0;
                for f in &g.faces {
                    let p = f.map(|n| x[&n]);
                    // a planar quadrangle's area is half its diagonals' cross product; a
                    // triangle (N3 = N4) is the same formula
                    area += 0.5 * norm(cross(sub(p[2], p[0]), sub(p[3], p[1])));
                }
                let want = areas[g.tag.to_string()].as_f64().unwrap();
                assert!(
                    rel(area, want) < 1e-12,
                    "{name}-{enc} set {}: {area}",
                    g.tag
                );
                // every node of the set is a node of its faces and the other way round
                let mut face_nodes: Vec<i64> = g.faces.iter().flatten().copied().collect();
                face_nodes.sort_unstable();
                face_nodes.dedup();
                assert_eq!(face_nodes, g.nodes);
            }
        }
    }
}

/// The `*NODE` cards of keyword text, read back: (NID, x, y, z), fixed or free format.
fn node_cards(text: &str) -> Vec<(i64, [f64; 3])> {
    let mut out = Vec::new();
    let mut in_nodes = false;
    for l in text.lines() {
        if l.starts_with('*') {
            in_nodes = l == "*NODE";
            continue;
        }
        if !in_nodes || l.starts_with('$') {
            continue;
        }
        let f: Vec<String> = if l.contains(',') {
            l.split(',').map(|s| s.trim().to_string()).collect()
        } else {
            [(0, 8), (8, 24), (24, 40), (40, 56)]
                .iter()
                .map(|&(a, b)| l.get(a..b.min(l.len())).unwrap_or("").trim().to_string())
                .collect()
        };
        out.push((
            f[0].parse().unwrap(),
            [
                f[1].parse().unwrap(),
                f[2].parse().unwrap(),
                f[3].parse().unwrap(),
            ],
        ));
    }
    out
}

#[test]
fn keyword_text_keeps_coordinates_bit_for_bit_and_lists_sets() {
    for name in MESHES {
        for enc in ENCODINGS {
            let m = read(name, enc);
            let text = keyword_text(&m, "mesh.msh");
            let nodes = node_cards(&text);
            assert_eq!(nodes.len(), m.nodes.len());
            for (n, (tag, x)) in m.nodes.iter().zip(&nodes) {
                assert_eq!(n.tag, *tag);
                // bit for bit (a -0.0 is written as 0.0)
                for (a, b) in n.x.iter().zip(x) {
                    assert_eq!((a + 0.0).to_bits(), b.to_bits(), "{name}-{enc}");
                }
            }
            let count = |kw: &str| text.lines().filter(|l| *l == kw).count();
            let named = |kw: &str| count(kw) + count(&format!("{kw}_TITLE"));
            let sets = m.groups.iter().filter(|g| g.dim < 3).count();
            let surfaces = m.groups.iter().filter(|g| g.dim == 2).count();
            assert_eq!(named("*SET_NODE_LIST"), sets, "{name}-{enc}");
            assert_eq!(named("*SET_SEGMENT"), surfaces, "{name}-{enc}");
            assert_eq!(count("*ELEMENT_SOLID"), 1);
            assert!(text.starts_with("$ LS-DYNA keywords of a Gmsh mesh"));
            assert!(text.ends_with("*END\n"));
        }
    }
    // a prism's card: EID PID and a c f d b b e e
    let m = read("prism", "41a");
    let s = &m.solids[0];
    assert_eq!(s.kind, SolidKind::Prism6);
    assert!(s.nodes[4] == s.nodes[5] && s.nodes[6] == s.nodes[7] && s.nodes[3] != s.nodes[4]);
    let t = read("tet", "41a");
    let s = &t.solids[0];
    assert!(s.nodes[3..].iter().all(|&n| n == s.nodes[3]));
}

/// A deck that includes the hexahedral mesh and gives its physical volume a part, a section
/// and a material, the mesh's node sets fixing one end.
fn hex_deck(msh: &str) -> String {
    format!(
        "*KEYWORD
*CONTROL_TERMINATION
1.0e-5
*INCLUDE
{msh}
*PART
block
1,1,1
*SECTION_SOLID
1,1
*MAT_ELASTIC
1,7800.0,2.0e11,0.3
*BOUNDARY_SPC_SET
2,0,1,1,1
*END
"
    )
}

#[test]
fn a_deck_includes_the_hexahedral_mesh() {
    for enc in ENCODINGS {
        let msh = fixture("hex", enc);
        let deck_path = dir().join("deck-under-test.k");
        let text = hex_deck(msh.to_str().unwrap());
        let d = parse_deck(&text, deck_path.to_str().unwrap()).unwrap_or_else(|e| panic!("{e}"));
        let m = &d.model;
        let mesh = read("hex", enc);
        assert_eq!(m.num_elements(), 24);
        assert_eq!(m.num_nodes(), 60);
        assert_eq!(m.parts.len(), 1);
        assert_eq!(m.parts[0].id, 1);
        assert_eq!(
            m.elem_ids,
            mesh.solids.iter().map(|s| s.tag).collect::<Vec<_>>()
        );
        // node sets 2, 3 (surfaces) and 4 (the tip point), segment sets 2 and 3
        let ns: Vec<(i64, usize)> = m.node_sets.iter().map(|s| (s.id, s.nodes.len())).collect();
        assert_eq!(ns, vec![(4, 1), (2, 12), (3, 12)]);
        let ss: Vec<(i64, usize)> = m
            .segment_sets
            .iter()
            .map(|s| (s.id, s.segments.len()))
            .collect();
        assert_eq!(ss, vec![(2, 6), (3, 6)]);
        // coordinates reach the model bit for bit
        for (id, x) in m.node_ids.iter().zip(&m.x0) {
            let n = mesh.nodes.iter().find(|n| n.tag == *id).unwrap();
            assert_eq!(n.x.map(f64::to_bits), x.map(f64::to_bits));
        }
        // the clamped end is x = 0
        let spc = &m.node_sets[1];
        assert!(spc.nodes.iter().all(|&n| m.x0[n as usize][0] == 0.0));
    }
}

#[test]
fn a_committed_deck_with_a_relative_include_reads() {
    let d = read_deck(&dir().join("hex.k")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(d.model.num_elements(), 24);
    assert_eq!(d.model.parts[0].title.trim(), "block");
}

#[test]
fn errors_in_an_included_mesh_name_the_mesh() {
    let tmp = std::env::temp_dir().join(format!("cleave-gmsh-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    // a node the element refers to is missing: line 13 of the .msh
    let bad = TET22.replace("1 4 2 7 1 1 2 3 4", "1 4 2 7 1 1 2 3 9");
    std::fs::write(tmp.join("bad.msh"), bad).unwrap();
    let deck = tmp.join("deck.k");
    let e = parse_deck(&hex_deck("bad.msh"), deck.to_str().unwrap()).unwrap_err();
    assert!(e.file.ends_with("bad.msh"), "{e}");
    assert_eq!(e.line, Some(13), "{e}");
    assert!(e.message.contains("node 9"), "{e}");
    // a mesh part the deck does not define: the converted text is named, with its line
    std::fs::write(tmp.join("one.msh"), TET22.replace("2 7 1 1", "2 1 1 1")).unwrap();
    let mut text = hex_deck("one.msh");
    text = text.replace("*PART\nblock\n1,1,1\n", "*PART\nother\n2,1,1\n");
    text = text.replace("*BOUNDARY_SPC_SET\n2,0,1,1,1\n", "");
    let e = parse_deck(&text, deck.to_str().unwrap()).unwrap_err();
    assert!(e.file.contains("one.msh"), "{e}");
    assert!(e.to_string().contains("part 1"), "{e}");
    std::fs::remove_dir_all(&tmp).ok();
}

// ---- hand-written files -------------------------------------------------------------------

/// One tetrahedron in physical volume 7, MSH 2.2 ASCII. Line 13 is the element.
const TET22: &str = "$MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
4
1 0 0 0
2 1 0 0
3 0 1 0
4 0 0 1
$EndNodes
$Elements
1
1 4 2 7 1 1 2 3 4
$EndElements
";

/// A tetrahedron and one of its faces, MSH 4.1 ASCII: volume entity 1 in physical volume 5
/// "body", surface entity 1 in physical surface 6 "face". Line 31 is the tetrahedron.
const TET41: &str = "$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
2 6 \"face\"
3 5 \"body\"
$EndPhysicalNames
$Entities
0 0 1 1
1 0 0 0 1 1 0 1 6 0
1 0 0 0 1 1 1 1 5 1 1
$EndEntities
$Nodes
1 4 1 4
3 1 0 4
1
2
3
4
0 0 0
1 0 0
0 1 0
0 0 1
$EndNodes
$Elements
2 2 1 2
2 1 2 1
1 1 3 2
3 1 4 1
2 1 2 3 4
$EndElements
";

fn parse(text: &str) -> Result<Mesh, MshError> {
    parse_msh(text.as_bytes(), "hand.msh")
}

fn err(text: &str) -> MshError {
    parse(text).expect_err("an error")
}

#[test]
fn hand_written_files_read() {
    let m = parse(TET41).unwrap();
    assert_eq!(m.solids.len(), 1);
    assert_eq!(m.solids[0].part, 5);
    assert_eq!(m.solids[0].nodes, [1, 2, 3, 4, 4, 4, 4, 4]);
    assert_eq!(m.groups.len(), 2);
    assert_eq!((m.groups[0].dim, m.groups[0].tag), (2, 6));
    assert_eq!(m.groups[0].faces, vec![[1, 3, 2, 2]]);
    assert_eq!(m.groups[1].name, "body");
    let m = parse(TET22).unwrap();
    assert_eq!(m.solids[0].part, 7);
    assert!(rel(m.volumes()[0], 1.0 / 6.0) < 1e-15);
}

#[test]
fn an_inverted_element_is_turned_and_counted() {
    let m = parse(&TET22.replace("1 4 2 7 1 1 2 3 4", "1 4 2 7 1 1 3 2 4")).unwrap();
    assert_eq!(m.reoriented, 1);
    assert_eq!(m.solids[0].nodes, [1, 2, 3, 4, 4, 4, 4, 4]);
    assert!(m.volumes()[0] > 0.0);
    // a flat one cannot be turned
    let e = err(&TET22.replace("4 0 0 1\n", "4 1 1 0\n"));
    assert_eq!(e.line(), Some(13));
    assert!(e.message.contains("no volume"), "{e}");
}

#[test]
fn an_element_in_no_physical_volume_takes_its_entity_tag() {
    let m = parse(&TET22.replace("1 4 2 7 1 1", "1 4 2 0 3 1")).unwrap();
    assert_eq!(m.solids[0].part, 3);
    assert!(m.groups.is_empty());
    // 4.1 without physical groups: the entity's tag
    let m = parse(&TET41.replace("1 0 0 0 1 1 1 1 5 1 1", "1 0 0 0 1 1 1 0 1 1")).unwrap();
    assert_eq!(m.solids[0].part, 1);
}

#[test]
fn an_element_in_two_physical_volumes_is_an_error() {
    let e = err(&TET41.replace("1 0 0 0 1 1 1 1 5 1 1", "1 0 0 0 1 1 1 2 5 8 1 1"));
    assert_eq!(e.line(), Some(31));
    assert!(e.message.contains("physical volumes 5 and 8"), "{e}");
    // MSH 2.2 writes it twice
    let two = TET22
        .replace("$Elements\n1\n", "$Elements\n2\n")
        .replace("1 2 3 4\n$EndE", "1 2 3 4\n2 4 2 8 1 1 2 3 4\n$EndE");
    let e = err(&two);
    assert_eq!(e.line(), Some(14));
    assert!(
        e.message.contains("elements 1 and 2 have the same nodes"),
        "{e}"
    );
    assert!(e.message.contains("parts 7 and 8"), "{e}");
}

#[test]
fn groups_that_would_share_a_set_id_are_an_error() {
    // physical surface 6 and a physical curve 6: both node set 6
    let text = TET41
        .replace(
            "$Entities\n0 0 1 1\n",
            "$Entities\n0 1 1 1\n1 0 0 0 1 0 0 1 6 0\n",
        )
        .replace("2 2 1 2\n", "3 3 1 3\n1 1 1 1\n3 1 2\n");
    let e = err(&text);
    assert!(e.message.contains("physical curve 6"), "{e}");
    assert!(e.message.contains("physical surface 6 \"face\""), "{e}");
    assert!(e.message.contains("renumber"), "{e}");
    // a physical volume and a physical surface may share a tag (a part and a set)
    let m = parse(
        &TET41
            .replace("1 1 6 0", "1 1 5 0")
            .replace("2 6 \"face\"", "2 5 \"face\""),
    )
    .unwrap();
    assert_eq!(m.groups.len(), 2);
}

#[test]
fn second_order_elements_are_refused_by_type_and_tag() {
    let text = TET41.replace("3 1 4 1\n2 1 2 3 4\n", "3 1 11 1\n2 1 2 3 4 1 2 3 4 1 2\n");
    let e = err(&text);
    assert_eq!(e.file, "hand.msh");
    assert_eq!(e.line(), Some(31));
    for s in [
        "element 2",
        "Tetrahedron 10",
        "type 11",
        "second-order",
        "order 1",
    ] {
        assert!(e.to_string().contains(s), "{e}");
    }
    let e = err(&TET22.replace("1 4 2 7 1 1 2 3 4", "1 11 2 7 1 1 2 3 4 1 2 3 4 1 2"));
    assert_eq!(e.line(), Some(13));
    assert!(e.message.contains("type 11"), "{e}");
    // a second-order triangle in no physical group is read past; in one, it is refused
    let text = TET41.replace("2 1 2 1\n1 1 3 2\n", "2 1 9 1\n1 1 3 2 1 2 3\n");
    let e = err(&text);
    assert!(e.message.contains("Triangle 6"), "{e}");
    let quiet = text.replace("1 0 0 0 1 1 0 1 6 0", "1 0 0 0 1 1 0 0 0");
    assert_eq!(parse(&quiet).unwrap().groups.len(), 1);
}

#[test]
fn malformed_files_name_file_and_line() {
    let cases: Vec<(String, usize, &str)> = vec![
        (TET22.replace("2.2 0 8", "3.0 0 8"), 2, "version 3.0"),
        (
            TET22.replace("2.2 0 8", "2.2 0"),
            2,
            "version file-type data-size",
        ),
        ("hello\n".to_string(), 1, "$MeshFormat"),
        (
            TET22.replace("1 4 2 7 1 1 2 3 4", "1 4 2 7 1 1 2 3 9"),
            13,
            "node 9",
        ),
        (
            TET22.replace("1 4 2 7 1 1 2 3 4", "1 4 2 7 1 1 2 3"),
            13,
            "values are missing",
        ),
        (
            TET22.replace("1 4 2 7 1 1 2 3 4", "1 4 2 7 1 1 2 3 4 5"),
            13,
            "more values",
        ),
        (TET22.replace("3 0 1 0", "3 0 x 0"), 8, "'x'"),
        (TET22.replace("$Nodes\n4\n", "$Nodes\n3\n"), 9, "$EndNodes"),
        (
            TET22.replace("$Elements\n1\n", "$Elements\n2\n"),
            14,
            "$EndElements",
        ),
        (
            TET22.replace("1 4 2 7", "1 999 2 7"),
            13,
            "unknown element type 999",
        ),
        (
            TET22.replace("3 0 1 0", "2 0 1 0"),
            8,
            "node 2 is defined twice",
        ),
        (TET41.replace("1 4 1 4\n", "1 5 1 4\n"), 15, "5 nodes"),
        (TET41.replace("2 2 1 2\n", "3 2 1 2\n"), 32, "$EndElements"),
        (
            TET41.replace("3 5 \"body\"", "3 5 body"),
            7,
            "double quotes",
        ),
        // truncated: the error is at the end (0 below: the last line)
        (TET22[..TET22.len() - 20].to_string(), 0, "truncated"),
        (TET41[..200].to_string(), 0, "truncated"),
    ];
    for (text, line, needle) in cases {
        let line = if line == 0 {
            text.matches('\n').count() + 1
        } else {
            line
        };
        let e = err(&text);
        assert_eq!(e.file, "hand.msh");
        assert_eq!(e.line(), Some(line), "{needle}: {e}");
        assert!(e.to_string().contains(needle), "{needle}: {e}");
        assert!(
            e.to_string().starts_with(&format!("hand.msh:{line}: ")),
            "{e}"
        );
    }
    let e = err("");
    assert!(e.message.contains("empty"), "{e}");
    let e = err(&TET22.replace("$Elements\n1\n1 4 2 7 1 1 2 3 4\n$EndElements\n", ""));
    assert!(e.message.contains("no $Elements"), "{e}");
}

#[test]
fn unknown_sections_are_skipped() {
    let extra = "$NodeData\n1\n\"u\"\n1\n0.0\n3\n0\n1\n4\n1 0\n2 0\n3 0\n4 0\n$EndNodeData\n$Comments\n$EndComments\n";
    let a = parse(TET22).unwrap();
    let b = parse(&TET22.replace("$Nodes\n", &format!("{extra}$Nodes\n"))).unwrap();
    assert_eq!(a, b);
    let b = parse(&format!("{TET22}{extra}")).unwrap();
    assert_eq!(a, b);
    let e = err(&format!("{TET22}$NodeData\n1\n"));
    assert!(e.message.contains("$EndNodeData"), "{e}");
}

/// `TET22` in binary MSH 2.2, little- or big-endian; with the byte offset of the element.
fn tet22_binary(big: bool, last_node: i32) -> (Vec<u8>, usize) {
    let i = |v: i32| {
        if big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        }
    };
    let d = |v: f64| {
        if big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        }
    };
    let mut b = b"$MeshFormat\n2.2 1 8\n".to_vec();
    b.extend(i(1));
    b.extend(b"\n$EndMeshFormat\n$Nodes\n4\n");
    for (k, x) in [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ]
    .iter()
    .enumerate()
    {
        b.extend(i(k as i32 + 1));
        for v in x {
            b.extend(d(*v));
        }
    }
    b.extend(b"\n$EndNodes\n$Elements\n1\n");
    for v in [4, 1, 2] {
        b.extend(i(v));
    }
    let at = b.len();
    for v in [1, 7, 1, 1, 2, 3, last_node] {
        b.extend(i(v));
    }
    b.extend(b"\n$EndElements\n");
    (b, at)
}

#[test]
fn binary_files_of_either_byte_order_read_the_same() {
    let ascii = parse(TET22).unwrap();
    for big in [false, true] {
        let (b, at) = tet22_binary(big, 4);
        let m = parse_msh(&b, "b.msh").unwrap();
        assert!(m.format.binary);
        assert_eq!(
            m,
            Mesh {
                format: m.format,
                ..ascii.clone()
            }
        );
        // an unknown node: the element's byte offset
        let (b, at2) = tet22_binary(big, 9);
        assert_eq!(at, at2);
        let e = parse_msh(&b, "b.msh").unwrap_err();
        assert_eq!(e.at, Some(At::Byte(at)), "{e}");
        assert!(
            e.to_string().starts_with(&format!("b.msh: byte {at}: ")),
            "{e}"
        );
        // truncated anywhere: an error, never a panic
        for cut in 0..b.len() {
            let e = parse_msh(&b[..cut], "b.msh").unwrap_err();
            assert_eq!(e.file, "b.msh");
        }
    }
}

#[test]
fn truncated_fixtures_are_errors_at_their_end() {
    for name in MESHES {
        for enc in ENCODINGS {
            let bytes = std::fs::read(fixture(name, enc)).unwrap();
            // every cut in the first kilobyte, then every 97th byte
            for cut in (0..bytes.len().min(1024)).chain((1024..bytes.len()).step_by(97)) {
                let e = match parse_msh(&bytes[..cut], "t.msh") {
                    Err(e) => e,
                    // a cut just before the last $EndElements' newline still reads
                    Ok(_) => continue,
                };
                assert_eq!(e.file, "t.msh");
                assert!(
                    e.at.is_some() || cut == 0 || e.message.contains("no $"),
                    "{e}"
                );
            }
            // flipped bytes: errors or meshes, never a panic
            let mut b = bytes.clone();
            for k in (0..b.len()).step_by(37) {
                b[k] ^= 0x5a;
                let _ = parse_msh(&b, "f.msh");
                b[k] ^= 0x5a;
            }
        }
    }
}

/// The tetrahedral, prism and mixed meshes through a deck (`*INCLUDE` of the `.msh`), each
/// physical volume a part: the model holds Gmsh's solids with the shapes Gmsh wrote (tet4
/// as tetrahedra, prism6 as wedges, hex8 as hexahedra), every part's volume is its exact
/// volume to 1e-12 relative (the solver's volume of each shape), and the solver's setup takes
/// the mesh, lumping rho V in total.
#[test]
fn decks_include_tetrahedral_prism_and_mixed_meshes() {
    use cleave_core::element::shape::shape_of;
    use cleave_core::element::{volume, Shape};
    let exp = expected();
    for kind in ["tet", "prism", "mixed"] {
        let e = &exp["meshes"][kind];
        for enc in ENCODINGS {
            let groups = e["files"][enc]["groups"].as_array().unwrap();
            let parts: Vec<i64> = groups
                .iter()
                .filter(|g| g["dim"] == 3)
                .map(|g| g["tag"].as_i64().unwrap())
                .collect();
            let mut text = format!(
                "*KEYWORD\n*CONTROL_TERMINATION\n1.0e-5\n*INCLUDE\n{}\n*SECTION_SOLID\n1,1\n*MAT_ELASTIC\n1,7800.0,2.0e11,0.3\n",
                fixture(kind, enc).to_str().unwrap()
            );
            for p in &parts {
                text.push_str(&format!("*PART\npart {p}\n{p},1,1\n"));
            }
            text.push_str("*END\n");
            let d = parse_deck(&text, "deck-under-test.k").unwrap_or_else(|e| panic!("{e}"));
            let m = &d.model;
            let counts = &e["files"][enc]["elements"];
            let want = |t: &str| counts[t].as_u64().unwrap_or(0) as usize;
            let mut shapes = [0usize; 3];
            let mut part_vol = vec![0.0; m.parts.len()];
            for (c, &p) in m.conn.iter().zip(&m.elem_part) {
                let s = shape_of(c).expect("a known shape");
                shapes[s as usize] += 1;
                part_vol[p as usize] += volume(s, &c.map(|n| m.x0[n as usize]));
            }
            assert_eq!(shapes[Shape::Hex as usize], want("5"), "{kind} {enc}");
            assert_eq!(shapes[Shape::Wedge as usize], want("6"), "{kind} {enc}");
            assert_eq!(shapes[Shape::Tet as usize], want("4"), "{kind} {enc}");
            for (p, v) in m.parts.iter().zip(&part_vol) {
                let exact = e["exact"]["volumes"][p.id.to_string()].as_f64().unwrap();
                assert!(rel(*v, exact) < 1e-12, "{kind} {enc} part {}: {v}", p.id);
            }
            let setup = cleave_core::setup::Setup::new(m).unwrap_or_else(|e| panic!("{e}"));
            let mass: f64 = setup.mass.iter().sum();
            let v: f64 = part_vol.iter().sum();
            assert!(rel(mass, 7800.0 * v) < 1e-12, "{kind} {enc}: mass {mass}");
        }
    }
}
