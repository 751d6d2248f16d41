//! Tests of the glTF reader (`gltf.rs`), on documents made here.

use std::path::Path;

use glam::DVec3;

use crate::mesh::{MeshError, TriangleMesh};
use crate::mesh_format::MeshFormat;

/// Base64 of `bytes`, padded.
pub(crate) fn base64_of(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in bytes.chunks(3) {
        let n = c
            .iter()
            .enumerate()
            .fold(0u32, |n, (i, &b)| n | u32::from(b) << (16 - 8 * i));
        for k in 0..=c.len() {
            s.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
        }
        for _ in c.len()..3 {
            s.push('=');
        }
    }
    s
}

/// A glTF document under construction: one buffer, its views and accessors, meshes and nodes.
#[derive(Default)]
pub(crate) struct Doc {
    pub(crate) bin: Vec<u8>,
    pub(crate) views: Vec<String>,
    pub(crate) accessors: Vec<String>,
    pub(crate) meshes: Vec<String>,
    pub(crate) nodes: Vec<String>,
}

impl Doc {
    /// Appends `bytes` as a buffer view (4-byte aligned), returning its index.
    pub(crate) fn view(&mut self, bytes: &[u8]) -> usize {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        self.views.push(format!(
            r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#,
            self.bin.len(),
            bytes.len()
        ));
        self.bin.extend_from_slice(bytes);
        self.views.len() - 1
    }

    /// A VEC3 FLOAT accessor of `p`.
    pub(crate) fn positions(&mut self, p: &[[f32; 3]]) -> usize {
        let bytes: Vec<u8> = p.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
        let v = self.view(&bytes);
        self.accessor(&format!(
            r#"{{"bufferView": {v}, "componentType": 5126, "type": "VEC3", "count": {}}}"#,
            p.len()
        ))
    }

    /// A SCALAR accessor of `indices` as `size`-byte unsigned integers.
    pub(crate) fn indices(&mut self, indices: &[u32], size: usize) -> usize {
        let bytes: Vec<u8> = indices
            .iter()
            .flat_map(|&i| i.to_le_bytes()[..size].to_vec())
            .collect();
        let v = self.view(&bytes);
        let ty = match size {
            1 => 5121,
            2 => 5123,
            _ => 5125,
        };
        self.accessor(&format!(
            r#"{{"bufferView": {v}, "componentType": {ty}, "type": "SCALAR", "count": {}}}"#,
            indices.len()
        ))
    }

    pub(crate) fn accessor(&mut self, json: &str) -> usize {
        self.accessors.push(json.to_string());
        self.accessors.len() - 1
    }

    /// A mesh of primitives `(positions, indices, mode)`.
    pub(crate) fn mesh(&mut self, primitives: &[(usize, Option<usize>, u32)]) -> usize {
        let p: Vec<String> = primitives
            .iter()
            .map(|(pos, idx, mode)| {
                let idx = idx.map_or(String::new(), |i| format!(r#", "indices": {i}"#));
                format!(r#"{{"attributes": {{"POSITION": {pos}}}{idx}, "mode": {mode}}}"#)
            })
            .collect();
        self.meshes
            .push(format!(r#"{{"primitives": [{}]}}"#, p.join(", ")));
        self.meshes.len() - 1
    }

    pub(crate) fn node(&mut self, json: &str) -> usize {
        self.nodes.push(json.to_string());
        self.nodes.len() - 1
    }

    /// The JSON, its buffer given by `uri` (`None`: a GLB's binary chunk); `more` adds
    /// top-level members (`"scene": 0, "scenes": [...]`).
    pub(crate) fn json(&self, uri: Option<&str>, more: &str) -> String {
        let uri = uri.map_or(String::new(), |u| format!(r#", "uri": "{u}""#));
        let more = if more.is_empty() {
            String::new()
        } else {
            format!(",\n{more}")
        };
        format!(
            "{{\"asset\": {{\"version\": \"2.0\"}},\n\"buffers\": [{{\"byteLength\": {}{uri}}}],\n\"bufferViews\": [{}],\n\"accessors\": [{}],\n\"meshes\": [{}],\n\"nodes\": [{}]{more}}}\n",
            self.bin.len(),
            self.views.join(",\n"),
            self.accessors.join(",\n"),
            self.meshes.join(",\n"),
            self.nodes.join(",\n")
        )
    }

    /// The `.gltf` text with the buffer embedded as a `data:` URI.
    pub(crate) fn embedded(&self, more: &str) -> String {
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            base64_of(&self.bin)
        );
        self.json(Some(&uri), more)
    }

    /// The `.glb` bytes.
    pub(crate) fn glb(&self, more: &str) -> Vec<u8> {
        glb(self.json(None, more).as_bytes(), Some(&self.bin))
    }
}

/// A GLB container of `json` and `bin`.
pub(crate) fn glb(json: &[u8], bin: Option<&[u8]>) -> Vec<u8> {
    let pad = |b: &[u8], with: u8| {
        let mut b = b.to_vec();
        while b.len() % 4 != 0 {
            b.push(with);
        }
        b
    };
    let mut chunks = Vec::new();
    for (kind, body) in [
        (b"JSON", Some(pad(json, b' '))),
        (b"BIN\0", bin.map(|b| pad(b, 0))),
    ] {
        if let Some(body) = body {
            chunks.extend_from_slice(&(body.len() as u32).to_le_bytes());
            chunks.extend_from_slice(kind);
            chunks.extend_from_slice(&body);
        }
    }
    let mut out = b"glTF".to_vec();
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(12 + chunks.len() as u32).to_le_bytes());
    out.extend(chunks);
    out
}

fn parse(name: &str, bytes: &[u8]) -> Result<TriangleMesh, MeshError> {
    TriangleMesh::parse(Path::new(name), MeshFormat::Gltf, bytes)
}

/// The triangles of `m`, corner by corner.
fn corners(m: &TriangleMesh) -> Vec<[DVec3; 3]> {
    (0..m.triangles.len()).map(|t| m.triangle(t)).collect()
}

const TRI: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

/// One triangle in one node, with the node's JSON `node`.
fn one_triangle(node: &str) -> Doc {
    let mut d = Doc::default();
    let p = d.positions(&TRI);
    let m = d.mesh(&[(p, None, 4)]);
    d.node(&node.replace("MESH", &m.to_string()));
    d
}

/// The message of a glTF error, checked to name the file.
fn message(r: Result<TriangleMesh, MeshError>, file: &str) -> String {
    let e = r.expect_err("an error").to_string();
    assert!(e.starts_with(file), "{e}");
    e
}

#[test]
fn embedded_binary_and_external_buffers_give_the_same_triangle() {
    let d = one_triangle(r#"{"mesh": MESH}"#);
    let embedded = parse("a.gltf", d.embedded("").as_bytes()).unwrap();
    let binary = parse("a.glb", &d.glb("")).unwrap();
    let dir = std::env::temp_dir().join(format!("penumbra-gltf-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("sub dir")).unwrap();
    std::fs::write(dir.join("sub dir/a.bin"), &d.bin).unwrap();
    std::fs::write(dir.join("a.gltf"), d.json(Some("sub%20dir/a.bin"), "")).unwrap();
    let external = TriangleMesh::load(&dir.join("a.gltf"), MeshFormat::Gltf).unwrap();
    // A missing buffer file names the glTF file, the buffer and the path it tried.
    std::fs::write(dir.join("b.gltf"), d.json(Some("missing.bin"), "")).unwrap();
    let e = message(
        TriangleMesh::load(&dir.join("b.gltf"), MeshFormat::Gltf),
        &dir.join("b.gltf").display().to_string(),
    );
    assert!(
        e.contains("buffer 0: cannot read") && e.contains("missing.bin"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
    let want = TriangleMesh::from_raw(
        "t",
        &TRI.map(|p| DVec3::from(p.map(f64::from))),
        &[[0, 1, 2]],
    )
    .unwrap();
    for m in [embedded, binary, external] {
        assert_eq!(m, want);
    }
}

#[test]
fn node_transforms_compose_from_root_to_leaf() {
    // A parent translated and scaled by 2, its child rotated a quarter turn about z by a
    // matrix, its grandchild mirrored in x (TRS): each level's triangle placed by all above it.
    let mut d = Doc::default();
    let p = d.positions(&TRI);
    let m = d.mesh(&[(p, None, 4)]);
    d.node(&format!(
        r#"{{"mesh": {m}, "translation": [0, 0, 5], "scale": [2, 2, 2], "children": [1]}}"#
    ));
    d.node(&format!(
        r#"{{"mesh": {m}, "matrix": [0,1,0,0, -1,0,0,0, 0,0,1,0, 1,0,0,1], "children": [2]}}"#
    ));
    d.node(&format!(
        r#"{{"mesh": {m}, "scale": [-1, 1, 1], "rotation": [0, 0, 0, 1]}}"#
    ));
    let more = r#""scene": 0, "scenes": [{"nodes": [0]}]"#;
    let got = corners(&parse("n.gltf", d.embedded(more).as_bytes()).unwrap());
    let v = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    // Root: 2p + (0, 0, 5). Child: root of (rot(p) + (1, 0, 0)), rot(x, y) = (-y, x).
    // Grandchild: child of (-x, y, z); the winding is kept, as under an OBJ's negative scale.
    let want = vec![
        [v(0., 0., 5.), v(2., 0., 5.), v(0., 2., 5.)],
        [v(2., 0., 5.), v(2., 2., 5.), v(0., 0., 5.)],
        [v(2., 0., 5.), v(2., -2., 5.), v(0., 0., 5.)],
    ];
    assert_eq!(got, want);
}

#[test]
fn the_default_scene_else_the_first_else_the_root_nodes_is_read() {
    let mut d = Doc::default();
    let p = d.positions(&TRI);
    let m = d.mesh(&[(p, None, 4)]);
    for x in [0, 10, 20] {
        d.node(&format!(r#"{{"mesh": {m}, "translation": [{x}, 0, 0]}}"#));
    }
    let xs = |more: &str| -> Vec<f64> {
        let m = parse("s.gltf", d.embedded(more).as_bytes()).unwrap();
        corners(&m).iter().map(|t| t[0].x).collect()
    };
    let scenes = r#""scenes": [{"nodes": [0]}, {"nodes": [2, 1]}]"#;
    assert_eq!(xs(&format!(r#""scene": 1, {scenes}"#)), [20.0, 10.0]);
    assert_eq!(xs(scenes), [0.0]);
    assert_eq!(xs(""), [0.0, 10.0, 20.0]);
}

#[test]
fn strips_fans_indices_of_each_size_and_points_are_read_as_specified() {
    let mut d = Doc::default();
    let square = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
        [2.0, 0.5, 0.0],
    ];
    let p = d.positions(&square);
    let i8 = d.indices(&[0, 1, 2, 3, 4], 1);
    let i16 = d.indices(&[4, 3, 1], 2);
    let i32 = d.indices(&[0, 1, 4, 3], 4);
    // Points (0) and lines (1) are passed over.
    let m = d.mesh(&[
        (p, Some(i8), 5),
        (p, Some(i16), 4),
        (p, Some(i32), 6),
        (p, None, 0),
        (p, Some(i8), 1),
    ]);
    d.node(&format!(r#"{{"mesh": {m}}}"#));
    let mesh = parse("s.glb", &d.glb("")).unwrap();
    let got: Vec<[u32; 3]> = corners(&mesh)
        .iter()
        .map(|t| {
            t.map(|c| {
                square
                    .iter()
                    .position(|s| DVec3::from(s.map(f64::from)) == c)
                    .unwrap() as u32
            })
        })
        .collect();
    // Strip 0 1 2 3 4: (0 1 2), (1 3 2), (2 3 4); triangles (4 3 1); fan 0 1 4 3: (1 4 0),
    // (4 3 0).
    assert_eq!(
        got,
        [
            [0, 1, 2],
            [1, 3, 2],
            [2, 3, 4],
            [4, 3, 1],
            [1, 4, 0],
            [4, 3, 0]
        ]
    );
    // Nothing but points: an error that says so.
    let mut d = Doc::default();
    let p = d.positions(&TRI);
    let m = d.mesh(&[(p, None, 0), (p, None, 3)]);
    d.node(&format!(r#"{{"mesh": {m}}}"#));
    let e = message(
        parse("pts.gltf", d.embedded("").as_bytes()),
        "pts.gltf: glTF: ",
    );
    assert!(
        e.contains("no triangles: the scene's 2 primitives are points or lines"),
        "{e}"
    );
}

#[test]
fn sparse_positions_replace_their_elements() {
    let mut d = Doc::default();
    let base = d.view(
        &TRI.iter()
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect::<Vec<u8>>(),
    );
    let at = d.view(&[2u8]);
    let new = d.view(
        &[5f32, 5.0, 0.0]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect::<Vec<u8>>(),
    );
    let p = d.accessor(&format!(
        r#"{{"bufferView": {base}, "componentType": 5126, "type": "VEC3", "count": 3,
            "sparse": {{"count": 1, "indices": {{"bufferView": {at}, "componentType": 5121}},
            "values": {{"bufferView": {new}}}}}}}"#
    ));
    let m = d.mesh(&[(p, None, 4)]);
    d.node(&format!(r#"{{"mesh": {m}}}"#));
    let mesh = parse("sp.gltf", d.embedded("").as_bytes()).unwrap();
    assert_eq!(mesh.triangle(0)[2], DVec3::new(5.0, 5.0, 0.0));
}

#[test]
fn hostile_documents_are_errors_that_name_the_file_and_the_fault() {
    let good = one_triangle(r#"{"mesh": MESH}"#);
    let json = good.embedded("");
    let cases: Vec<(String, Vec<u8>, &str)> = vec![
        // JSON that does not parse: the line of the fault.
        ("bad.gltf:3: glTF: ".into(), b"{\"asset\": {\"version\": \"2.0\"},\n\"nodes\": [\n{\"mesh\": }]}".to_vec(), "column"),
        // An index to nothing, found by the crate's validation.
        ("v.gltf: glTF: ".into(), json.replace(r#""POSITION": 0"#, r#""POSITION": 7"#).into_bytes(), "meshes[0].primitives[0].attributes"),
        // An accessor reaching past its view, a view past its buffer, a count past any memory.
        ("c.gltf: glTF: ".into(), json.replace(r#""count": 3"#, r#""count": 4"#).into_bytes(), "accessor 0's 4 elements run past its buffer view"),
        ("c.gltf: glTF: ".into(), json.replace(r#""count": 3"#, r#""count": 18446744073709551615"#).into_bytes(), "run past its buffer view"),
        ("w.gltf: glTF: ".into(), json.replace(r#""byteLength": 36}"#, r#""byteLength": 40}"#).into_bytes(), "buffer view 0 takes bytes 0 to 40 of buffer 0, which has 36"),
        ("s.gltf: glTF: ".into(), json.replace(r#""byteOffset": 0,"#, r#""byteOffset": 0, "byteStride": 4,"#).into_bytes(), "byteStride"),
        // A buffer shorter than it says, one with no data, one on the network.
        ("l.gltf: glTF: ".into(), json.replace(r#""byteLength": 36,"#, r#""byteLength": 99,"#).into_bytes(), "buffer 0 holds 36 bytes, fewer than its byteLength 99"),
        ("n.gltf: glTF: ".into(), good.json(None, "").into_bytes(), "buffer 0 has no uri and the file has no GLB binary chunk"),
        ("h.gltf: glTF: ".into(), good.json(Some("https://example.com/a.bin"), "").into_bytes(), "neither a file relative to the glTF file nor a data: URI"),
        ("b.gltf: glTF: ".into(), good.json(Some("data:application/octet-stream;base64,AAA*"), "").into_bytes(), "base64 character 3"),
        // Non-finite positions; a NaN matrix; a non-affine one; a cycle of nodes.
        ("f.gltf: glTF: ".into(), {
            let mut d = Doc::default();
            let p = d.positions(&[[0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]]);
            let m = d.mesh(&[(p, None, 4)]);
            d.node(&format!(r#"{{"mesh": {m}}}"#));
            d.embedded("").into_bytes()
        }, "vertex 1 of POSITION (accessor 0) has a non-finite coordinate"),
        ("m.gltf: glTF: ".into(), one_triangle(r#"{"mesh": MESH, "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,1e39,1]}"#).embedded("").into_bytes(), "node 0: matrix"),
        ("m.gltf: glTF: ".into(), one_triangle(r#"{"mesh": MESH, "matrix": [1,0,0,1, 0,1,0,0, 0,0,1,0, 0,0,0,1]}"#).embedded("").into_bytes(), "is not (0, 0, 0, 1)"),
        ("q.gltf: glTF: ".into(), one_triangle(r#"{"mesh": MESH, "rotation": [0, 0, 0, 0]}"#).embedded("").into_bytes(), "not a unit quaternion"),
        ("y.gltf: glTF: ".into(), one_triangle(r#"{"mesh": MESH, "children": [0]}"#).embedded(r#""scenes": [{"nodes": [0]}]"#).into_bytes(), "node 0 is reached twice"),
        // Indices out of range; a triangle list of 4 vertices.
        ("i.gltf: glTF: ".into(), {
            let mut d = Doc::default();
            let p = d.positions(&TRI);
            let i = d.indices(&[0, 1, 3], 2);
            let m = d.mesh(&[(p, Some(i), 4)]);
            d.node(&format!(r#"{{"mesh": {m}}}"#));
            d.embedded("").into_bytes()
        }, "mesh 0 primitive 0: index 2 (accessor 1) is 3, but POSITION (accessor 0) has 3 vertices"),
        ("t.gltf: glTF: ".into(), {
            let mut d = Doc::default();
            let p = d.positions(&TRI);
            let i = d.indices(&[0, 1, 2, 1], 4);
            let m = d.mesh(&[(p, Some(i), 4)]);
            d.node(&format!(r#"{{"mesh": {m}}}"#));
            d.embedded("").into_bytes()
        }, "TRIANGLES of 4 vertices, not a multiple of 3"),
        // Quantized positions; a required extension.
        ("u.gltf: glTF: ".into(), json.replace(r#""componentType": 5126"#, r#""componentType": 5123"#).into_bytes(), "positions are read as VEC3 of FLOAT"),
        ("x.gltf: glTF: ".into(), json.replace(r#""asset""#, r#""extensionsUsed": ["KHR_draco_mesh_compression"], "extensionsRequired": ["KHR_draco_mesh_compression"], "asset""#).into_bytes(), "KHR_draco_mesh_compression"),
    ];
    for (file, bytes, want) in cases {
        let name = file.split(':').next().unwrap().to_string();
        let e = message(parse(&name, &bytes), &file);
        assert!(e.contains(want), "{e}\nwanted: {want}");
    }
}

#[test]
fn hostile_glb_containers_are_errors_not_panics() {
    let d = one_triangle(r#"{"mesh": MESH}"#);
    let good = d.glb("");
    let with_word = |at: usize, w: u32| {
        let mut b = good.clone();
        b[at..at + 4].copy_from_slice(&w.to_le_bytes());
        b
    };
    for (bytes, want) in [
        (
            good[..10].to_vec(),
            "truncated: 10 bytes, less than a GLB header's 12",
        ),
        (
            good[..good.len() - 5].to_vec(),
            "truncated: the GLB header gives a length of",
        ),
        (with_word(4, 1), "GLB version 1"),
        (
            with_word(8, 3),
            "the GLB's first chunk is not its JSON chunk",
        ),
        (
            with_word(12, u32::MAX),
            "truncated: a GLB chunk of 4294967295 bytes",
        ),
        (
            glb(b"glTF\x02\0\0\0\x05\0\0\0", None),
            "the JSON chunk, line 1 column",
        ),
        (
            glb(d.json(None, "").as_bytes(), None),
            "no GLB binary chunk",
        ),
        (
            glb(d.json(None, "").as_bytes(), Some(&d.bin[..20])),
            "buffer 0 holds 20 bytes, fewer than its byteLength 36",
        ),
    ] {
        let e = message(parse("c.glb", &bytes), "c.glb: glTF: ");
        assert!(e.contains(want), "{e}\nwanted: {want}");
    }
    // Every prefix of a good file: errors, never a panic.
    for n in 0..good.len() {
        let _ = TriangleMesh::parse(Path::new("p.glb"), MeshFormat::Gltf, &good[..n]);
    }
}

#[test]
fn base64_and_percent_escapes_decode() {
    for n in 0..8 {
        let bytes: Vec<u8> = (0..n).map(|i| (i * 37 + 200) as u8).collect();
        let text = base64_of(&bytes);
        assert_eq!(crate::gltf_buffers::base64(&text).unwrap(), bytes, "{text}");
        assert_eq!(
            crate::gltf_buffers::base64(text.trim_end_matches('=')).unwrap(),
            bytes
        );
    }
    assert!(crate::gltf_buffers::base64("A").is_err());
    assert_eq!(
        crate::gltf_buffers::percent_decoded("a%20b%2Fc").as_deref(),
        Some("a b/c")
    );
    assert_eq!(crate::gltf_buffers::percent_decoded("a%2"), None);
    assert_eq!(crate::gltf_buffers::percent_decoded("a%+1"), None);
}

#[test]
fn mutated_files_are_read_or_refused_never_a_panic() {
    let mut d = Doc::default();
    let p = d.positions(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ]);
    let i = d.indices(&[0, 1, 2, 3], 2);
    let m = d.mesh(&[(p, Some(i), 5), (p, None, 6)]);
    d.node(&format!(
        r#"{{"mesh": {m}, "children": [1], "scale": [1, 2, 1]}}"#
    ));
    d.node(&format!(r#"{{"mesh": {m}, "rotation": [0, 0.6, 0, 0.8]}}"#));
    let more = r#""scene": 0, "scenes": [{"nodes": [0]}]"#;
    let mut rng = crate::rng::Rng::new(11);
    for good in [d.glb(more), d.embedded(more).into_bytes()] {
        parse("g.gltf", &good).unwrap();
        for _ in 0..3000 {
            let _ = parse("g.gltf", &crate::mesh_files::mutated(&mut rng, &good));
        }
    }
}
