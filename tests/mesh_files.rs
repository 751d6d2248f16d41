//! Scene files' glTF and PLY meshes: the same triangles given as OBJ, glTF and PLY make the same
//! scene and the same image on every technique of both back ends; files that other tools wrote
//! (`fixtures/meshfiles/`) load to the triangles they hold.

use std::fmt::Write as _;
use std::path::PathBuf;

use penumbra::geom::{HalfEdgeMesh, MeshFormat, Scene, TriangleMesh, compare};
use penumbra::glam::{DMat4, DQuat, DVec3};
use penumbra::{Backend, RenderOptions, Renderer, Runs, Technique};

use crate::common::{differing_pixels, gpu_renderer, load};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn f32s(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

fn base64(bytes: &[u8]) -> String {
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

/// The local geometry of the test's glTF meshes, each primitive `(positions, indices, mode)`.
struct Primitive {
    positions: Vec<[f32; 3]>,
    indices: Option<(Vec<u32>, usize)>,
    mode: u32,
}

/// The triangles of a primitive as glTF defines them (`None` for points).
fn triangles(p: &Primitive) -> Vec<[usize; 3]> {
    let v: Vec<usize> = match &p.indices {
        Some((i, _)) => i.iter().map(|&i| i as usize).collect(),
        None => (0..p.positions.len()).collect(),
    };
    match p.mode {
        4 => v.chunks(3).map(|t| [t[0], t[1], t[2]]).collect(),
        5 => (0..v.len() - 2)
            .map(|k| match k % 2 {
                0 => [v[k], v[k + 1], v[k + 2]],
                _ => [v[k], v[k + 2], v[k + 1]],
            })
            .collect(),
        6 => (0..v.len() - 2)
            .map(|k| [v[k + 1], v[k + 2], v[0]])
            .collect(),
        _ => Vec::new(),
    }
}

/// The test's meshes: a ground quad, a box (with a points primitive that is passed over), a
/// hexagonal fan and two strips.
fn meshes() -> Vec<Vec<Primitive>> {
    let h = 0.5f32;
    let quad = vec![[-h, 0.0, -h], [-h, 0.0, h], [h, 0.0, h], [h, 0.0, -h]];
    let cube: Vec<[f32; 3]> = (0..8)
        .map(|c| [c & 1, c >> 1 & 1, c >> 2 & 1].map(|b| if b == 1 { h } else { -h }))
        .collect();
    let cube_faces = vec![
        0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2,
        1, 3, 7, 1, 7, 5,
    ];
    let hexagon: Vec<[f32; 3]> = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.5, 0.0, 0.875],
        [-0.5, 0.0, 0.875],
        [-1.0, 0.0, 0.0],
        [-0.5, 0.0, -0.875],
        [0.5, 0.0, -0.875],
        [1.0, 0.0, 0.0],
    ]
    .to_vec();
    let zigzag = |dz: f32| -> Vec<[f32; 3]> {
        (0..6)
            .map(|k| {
                [
                    k as f32 * 0.25,
                    (k % 2) as f32 * 0.5,
                    (k / 2) as f32 * 0.125 + dz,
                ]
            })
            .collect()
    };
    vec![
        vec![Primitive {
            positions: quad,
            indices: Some((vec![0, 1, 2, 0, 2, 3], 4)),
            mode: 4,
        }],
        vec![
            Primitive {
                positions: cube.clone(),
                indices: None,
                mode: 0,
            },
            Primitive {
                positions: cube,
                indices: Some((cube_faces, 2)),
                mode: 4,
            },
        ],
        vec![Primitive {
            positions: hexagon,
            indices: None,
            mode: 6,
        }],
        vec![
            Primitive {
                positions: zigzag(0.0),
                indices: Some((vec![0, 1, 2, 3, 4, 5], 1)),
                mode: 5,
            },
            Primitive {
                positions: zigzag(0.5),
                indices: Some((vec![5, 4, 3, 2], 1)),
                mode: 5,
            },
        ],
    ]
}

/// The nodes `(mesh, transform as glTF JSON, transform as a matrix, children)`: a ground, a
/// chain of three (a box, a box turned by a matrix, a fan mirrored), and the strips, a child of
/// the chain's first, last (PLY's strips follow its faces).
fn nodes() -> Vec<(Option<usize>, String, DMat4, Vec<usize>)> {
    let quarter_turn_y = DMat4::from_cols_array(&[
        0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.25, 0.0, 0.5, 1.0,
    ]);
    let cols = quarter_turn_y
        .to_cols_array()
        .map(|x| x.to_string())
        .join(", ");
    let trs = |t: [f64; 3], q: [f64; 4], s: [f64; 3]| {
        DMat4::from_scale_rotation_translation(s.into(), DQuat::from_array(q), t.into())
    };
    vec![
        (
            Some(0),
            r#""scale": [8, 1, 8]"#.into(),
            trs([0.0; 3], [0.0, 0.0, 0.0, 1.0], [8.0, 1.0, 8.0]),
            vec![],
        ),
        (
            Some(1),
            r#""translation": [0, 0.75, 0], "children": [2, 4]"#.into(),
            DMat4::from_translation(DVec3::new(0.0, 0.75, 0.0)),
            vec![2, 4],
        ),
        (
            Some(1),
            format!(r#""matrix": [{cols}], "children": [3]"#),
            quarter_turn_y,
            vec![3],
        ),
        (
            Some(2),
            r#""translation": [0.5, 1.5, 0], "rotation": [0, 1, 0, 0], "scale": [-0.5, 0.5, 0.5]"#
                .into(),
            trs([0.5, 1.5, 0.0], [0.0, 1.0, 0.0, 0.0], [-0.5, 0.5, 0.5]),
            vec![],
        ),
        (
            Some(3),
            r#""translation": [1.5, 0.25, -1]"#.into(),
            DMat4::from_translation(DVec3::new(1.5, 0.25, -1.0)),
            vec![],
        ),
    ]
}

/// The `.gltf` text of [`meshes`] and [`nodes`], its buffer embedded.
fn gltf_text() -> String {
    let (mut bin, mut views, mut accessors, mut json_meshes) = (vec![], vec![], vec![], vec![]);
    let mut view = |bin: &mut Vec<u8>, bytes: Vec<u8>| {
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
        views.push(format!(
            r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#,
            bin.len(),
            bytes.len()
        ));
        bin.extend(bytes);
        views.len() - 1
    };
    for mesh in meshes() {
        let mut primitives = vec![];
        for p in &mesh {
            let v = view(&mut bin, f32s(&p.positions.concat()));
            accessors.push(format!(
                r#"{{"bufferView": {v}, "componentType": 5126, "type": "VEC3", "count": {}, "min": [-9, -9, -9], "max": [9, 9, 9]}}"#,
                p.positions.len()
            ));
            let mut json = format!(
                r#"{{"attributes": {{"POSITION": {}}}, "mode": {}"#,
                accessors.len() - 1,
                p.mode
            );
            if let Some((indices, size)) = &p.indices {
                let bytes = indices
                    .iter()
                    .flat_map(|i| i.to_le_bytes()[..*size].to_vec())
                    .collect();
                let v = view(&mut bin, bytes);
                let ty = [0, 5121, 5123, 0, 5125][*size];
                accessors.push(format!(
                    r#"{{"bufferView": {v}, "componentType": {ty}, "type": "SCALAR", "count": {}}}"#,
                    indices.len()
                ));
                let _ = write!(json, r#", "indices": {}"#, accessors.len() - 1);
            }
            primitives.push(json + "}");
        }
        json_meshes.push(format!(r#"{{"primitives": [{}]}}"#, primitives.join(", ")));
    }
    let json_nodes: Vec<String> = nodes()
        .iter()
        .map(|(mesh, t, _, _)| match mesh {
            Some(m) => format!(r#"{{"mesh": {m}, {t}}}"#),
            None => format!("{{{t}}}"),
        })
        .collect();
    format!(
        "{{\"asset\": {{\"version\": \"2.0\"}},\n\"scene\": 0,\n\"scenes\": [{{\"nodes\": [0, 1]}}],\n\
         \"nodes\": [\n{}\n],\n\"meshes\": [\n{}\n],\n\"accessors\": [\n{}\n],\n\
         \"bufferViews\": [\n{}\n],\n\"buffers\": [{{\"byteLength\": {}, \"uri\": \"data:application/octet-stream;base64,{}\"}}]}}\n",
        json_nodes.join(",\n"),
        json_meshes.join(",\n"),
        accessors.join(",\n"),
        views.join(",\n"),
        bin.len(),
        base64(&bin)
    )
}

/// The world-space triangles of the glTF scene, in its order: each node's own before its
/// children's, placed by the matrices of [`nodes`] (written out here, not read from the JSON).
fn world_triangles() -> Vec<[DVec3; 3]> {
    let (meshes, nodes) = (meshes(), nodes());
    let mut out = Vec::new();
    let mut stack = vec![(1, DMat4::IDENTITY), (0, DMat4::IDENTITY)];
    while let Some((n, parent)) = stack.pop() {
        let (mesh, _, local, children) = &nodes[n];
        let world = parent * *local;
        for p in mesh.iter().flat_map(|&m| &meshes[m]) {
            for t in triangles(p) {
                out.push(
                    t.map(|i| world.transform_point3(DVec3::from(p.positions[i].map(f64::from)))),
                );
            }
        }
        stack.extend(children.iter().rev().map(|&c| (c, world)));
    }
    out
}

/// The world triangles as OBJ text (one vertex per corner; welding joins them) and as a binary
/// PLY: faces, the last mesh's strips as `element tristrips` restarting at `-1`.
fn obj_and_ply() -> (String, Vec<u8>) {
    let world = world_triangles();
    let strips: Vec<Primitive> = meshes().pop().unwrap();
    let strip_triangles: usize = strips.iter().map(|p| triangles(p).len()).sum();
    let faces = &world[..world.len() - strip_triangles];
    let mut obj = String::from("# penumbra mesh_files test: the glTF scene's world triangles\n");
    for t in &world {
        for c in t {
            let _ = writeln!(obj, "v {} {} {}", c.x, c.y, c.z);
        }
    }
    for k in 0..world.len() {
        let _ = writeln!(obj, "f {} {} {}", 3 * k + 1, 3 * k + 2, 3 * k + 3);
    }
    // The PLY: every face corner, then the strip meshes' own vertices placed by their nodes.
    let nodes = nodes();
    let local = nodes[1].2 * nodes[4].2;
    let strip_vertices: Vec<DVec3> = strips
        .iter()
        .flat_map(|p| {
            p.positions
                .iter()
                .map(|v| local.transform_point3(DVec3::from(v.map(f64::from))))
        })
        .collect();
    let vertices: Vec<DVec3> = faces
        .iter()
        .flatten()
        .copied()
        .chain(strip_vertices)
        .collect();
    let mut strip: Vec<i32> = Vec::new();
    let mut base = faces.len() * 3;
    for p in &strips {
        if !strip.is_empty() {
            strip.push(-1);
        }
        strip.extend(
            p.indices
                .as_ref()
                .unwrap()
                .0
                .iter()
                .map(|&i| (base + i as usize) as i32),
        );
        base += p.positions.len();
    }
    let mut ply = format!(
        "ply\nformat binary_little_endian 1.0\ncomment penumbra mesh_files test\n\
         element vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
         element face {}\nproperty list uchar int vertex_indices\n\
         element tristrips 1\nproperty list int int vertex_indices\nend_header\n",
        vertices.len(),
        faces.len()
    )
    .into_bytes();
    for v in &vertices {
        ply.extend(f32s(&v.to_array().map(|x| x as f32)));
    }
    for k in 0..faces.len() {
        ply.push(3);
        for i in 0..3 {
            ply.extend(((3 * k + i) as i32).to_le_bytes());
        }
    }
    ply.extend((strip.len() as i32).to_le_bytes());
    for i in strip {
        ply.extend(i.to_le_bytes());
    }
    (obj, ply)
}

/// A scene file of the mesh file `key = "name"`, under the entry's own transform.
fn scene_text(key: &str, name: &str) -> String {
    format!(
        "[camera]\neye = [4.0, 6.0, 7.0]\ntarget = [0.0, 1.0, 0.0]\nup = [0.0, 1.0, 0.0]\n\
         fov_y_deg = 45.0\nwidth = 48\nheight = 36\n\n[light]\ncenter = [-1.0, 6.0, 1.0]\n\
         normal = [0.0, -1.0, 0.0]\ntangent = [1.0, 0.0, 0.0]\nsize = [2.0, 1.5]\n\n\
         [shadow_map]\nresolution = 256\n\n[[mesh]]\n{key} = \"{name}\"\nscale = 1.5\n\
         rotate_axis_angle = [0, 1, 0, 20]\ntranslate = [0.25, 0, -0.5]\n"
    )
}

/// The three scenes, written to a folder of their own.
fn three_scenes() -> [Scene; 3] {
    let dir = std::env::temp_dir().join(format!("penumbra-mesh-files-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (obj, ply) = obj_and_ply();
    std::fs::write(dir.join("nodes.obj"), obj).unwrap();
    std::fs::write(dir.join("nodes.gltf"), gltf_text()).unwrap();
    std::fs::write(dir.join("nodes.ply"), ply).unwrap();
    let scenes = [
        ("obj", "nodes.obj"),
        ("gltf", "nodes.gltf"),
        ("ply", "nodes.ply"),
    ]
    .map(|(k, n)| {
        let path = dir.join(format!("{k}.toml"));
        std::fs::write(&path, scene_text(k, n)).unwrap();
        Scene::load(&path).unwrap_or_else(|e| panic!("{e}"))
    });
    std::fs::remove_dir_all(&dir).unwrap();
    scenes
}

#[test]
fn a_gltf_node_hierarchy_and_a_binary_ply_are_the_triangles_of_their_obj() {
    let [obj, gltf, ply] = three_scenes();
    let want = &obj.meshes[0].mesh;
    // 2 ground, 12 box, 12 turned box, 6 mirrored fan, 4 + 2 strip triangles.
    assert_eq!(want.triangles.len(), 38);
    assert_eq!((want.dropped_degenerate, want.dropped_duplicate), (0, 0));
    for s in [&gltf, &ply] {
        assert_eq!(&s.meshes[0].mesh, want, "{}", s.meshes[0].source.display());
        assert_eq!(s.meshes[0].transform, obj.meshes[0].transform);
    }
}

const OPTIONS: RenderOptions = RenderOptions {
    samples: 16,
    jitter: false,
};

#[test]
fn the_same_triangles_from_each_format_render_the_same_image_on_the_cpu() {
    let scenes = three_scenes();
    let mut cpu = Renderer::new(Backend::Cpu);
    let techniques: Vec<Technique> = Technique::ALL
        .into_iter()
        .filter(|&t| Runs::of(t) != Runs::GpuOnly)
        .collect();
    assert_eq!(techniques.len(), 6);
    for t in techniques {
        let images: Vec<_> = scenes
            .iter()
            .map(|s| cpu.render(s, t, &OPTIONS).unwrap())
            .collect();
        assert!(images[0].data.iter().any(|&v| v < 0.5), "{t}: no shadow");
        for (format, image) in ["glTF", "PLY"].iter().zip(&images[1..]) {
            let n = differing_pixels(&image.data, &images[0].data);
            assert_eq!(n, 0, "{t}: {format} differs from OBJ at {n} pixels");
        }
    }
}

#[test]
fn the_same_triangles_from_each_format_render_the_same_image_on_the_gpu() {
    let Some(mut gpu) = gpu_renderer() else {
        return;
    };
    let scenes = three_scenes();
    let techniques: Vec<Technique> = Technique::ALL
        .into_iter()
        .filter(|&t| Runs::of(t) != Runs::CpuOnly)
        .collect();
    assert_eq!(techniques.len(), 9);
    for t in techniques {
        let frames: Vec<_> = scenes
            .iter()
            .map(|s| {
                gpu.render_frame(&s.lit(0), t, &OPTIONS, None, &|_| {})
                    .unwrap()
            })
            .collect();
        assert!(
            frames[0].detail.starts_with("gpu: "),
            "{t}: {}",
            frames[0].detail
        );
        for (format, frame) in ["glTF", "PLY"].iter().zip(&frames[1..]) {
            let n = differing_pixels(&frame.image.data, &frames[0].image.data);
            assert_eq!(n, 0, "{t}: {format} differs from OBJ at {n} pixels");
        }
    }
}

#[test]
fn a_glb_exported_by_trimesh_is_its_obj_and_renders_its_image() {
    let glb = TriangleMesh::load(
        &root().join("fixtures/meshfiles/spot.glb"),
        MeshFormat::Gltf,
    )
    .unwrap();
    let obj = TriangleMesh::load_obj(&root().join("fixtures/meshes/spot.obj")).unwrap();
    assert_eq!(glb.triangles.len(), 5856);
    assert_eq!(glb.triangles, obj.triangles);
    // glTF holds 32-bit floats, as the OBJ reader does: at most their rounding apart.
    for (a, b) in glb.positions.iter().zip(&obj.positions) {
        assert!(
            (*a - *b).abs().max_element() <= b.abs().max_element() * f64::from(f32::EPSILON),
            "{a} against {b}"
        );
    }
    let mut by_obj = load("spot");
    let mut by_glb = Scene::load(&root().join("fixtures/meshfiles/spot-glb.toml")).unwrap();
    for s in [&mut by_obj, &mut by_glb] {
        s.camera.width = 48;
        s.camera.height = 36;
    }
    let mut cpu = Renderer::new(Backend::Cpu);
    for t in [Technique::Reference, Technique::WedgesBlend] {
        let a = cpu.render(&by_glb, t, &OPTIONS).unwrap();
        let b = cpu.render(&by_obj, t, &OPTIONS).unwrap();
        let c = compare(&a, &b).unwrap();
        assert!(c.all.max <= 1e-6, "{t}: {c:?}");
    }
}

#[test]
fn igea_s_triangle_strip_loads_closed_and_renders_beside_a_glb() {
    let path = root().join("fixtures/meshfiles/igea.ply");
    let igea = TriangleMesh::load(&path, MeshFormat::Ply).unwrap();
    assert_eq!(igea.positions.len(), 134_345);
    assert_eq!(igea.triangles.len(), 268_686);
    let h = HalfEdgeMesh::build(&igea);
    assert!(h.is_closed() && !h.has_inconsistent_orientation());
    let mut scene = Scene::load(&root().join("fixtures/meshfiles/igea-and-spot.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.triangle_count(), 2 + 268_686 + 5856);
    scene.camera.width = 48;
    scene.camera.height = 36;
    let image = Renderer::new(Backend::Cpu)
        .render(&scene, Technique::Hard, &OPTIONS)
        .unwrap();
    let shadowed = image.data.iter().filter(|&&v| v == 0.0).count();
    assert!(shadowed > 20, "{shadowed} pixels in shadow");
}
