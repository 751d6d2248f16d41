//! Reading glTF 2.0 (`.gltf` JSON with external or `data:` buffers, or binary `.glb`) into a
//! [`TriangleMesh`]: the triangles of every mesh its scene places, each node's transform
//! composed down the hierarchy.
//!
//! The `gltf` crate parses and validates the JSON (every index refers to something); the GLB
//! container, the buffers and the accessors' bytes are read in `gltf_buffers.rs`, every offset,
//! stride and count checked against the bytes there are, so that no file makes the reader panic
//! or allocate from a count it does not hold.

use std::path::Path;

use ::gltf::accessor::{DataType, Dimensions};
use ::gltf::json::validation::{Checked, Validate};
use ::gltf::mesh::Mode;
use ::gltf::scene::Transform;
use ::gltf::{Node, Primitive, Semantic};
use glam::{DMat4, DQuat, DVec3, DVec4};

use crate::corners::from_corners;
use crate::gltf_buffers::{Buffers, split_glb};
use crate::mesh::{MeshError, TriangleMesh};
use crate::mesh_format::MeshFormat;

/// A `MeshError::Format` of the glTF file `path`.
fn error(path: &Path, line: Option<usize>, message: String) -> MeshError {
    MeshError::Format {
        path: path.to_path_buf(),
        format: MeshFormat::Gltf,
        line,
        message,
    }
}

/// The triangles of the glTF file `path` of contents `bytes` (see the module's documentation;
/// `docs/scene-format.md` is the contract).
pub(crate) fn parse_gltf(path: &Path, bytes: &[u8]) -> Result<TriangleMesh, MeshError> {
    let glb = bytes.starts_with(b"glTF");
    let (json, bin) = if glb {
        split_glb(bytes).map_err(|m| error(path, None, m))?
    } else {
        let text = bytes.strip_prefix("\u{feff}".as_bytes()).unwrap_or(bytes);
        (text, None)
    };
    // The JSON is parsed as JSON whatever its first bytes (the crate's own entry point would
    // take a JSON chunk starting `glTF` for a GLB container).
    let root = ::gltf::json::Root::from_slice(json)
        .map_err(|e| document_error(path, glb, ::gltf::Error::Deserialize(e)))?;
    // The crate's validation indexes the accessors by POSITION unchecked.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (k, primitive) in mesh.primitives.iter().enumerate() {
            let positions = primitive.attributes.iter().find_map(|(semantic, a)| {
                (*semantic == Checked::Valid(::gltf::Semantic::Positions)).then_some(a.value())
            });
            if positions.is_some_and(|a| a >= root.accessors.len()) {
                return Err(error(
                    path,
                    None,
                    format!(
                        "meshes[{m}].primitives[{k}].attributes[\"POSITION\"]: index out of bounds"
                    ),
                ));
            }
        }
    }
    let mut faults = Vec::new();
    root.validate(&root, ::gltf::json::Path::new, &mut |at, e| {
        let at = at();
        // The positions' bounds, which the specification requires, are not needed here.
        let bound = at.as_str().ends_with("\"POSITION\"].min")
            || at.as_str().ends_with("\"POSITION\"].max");
        if !(bound && e == ::gltf::json::validation::Error::Missing) {
            faults.push((at, e));
        }
    });
    if !faults.is_empty() {
        return Err(document_error(path, glb, ::gltf::Error::Validation(faults)));
    }
    let document = ::gltf::Document::from_json_without_validation(root);
    let mut buffers = Buffers::new(path, bin, document.buffers().len());
    let fail = |m: String| error(path, None, m);

    // The default scene, else the first, else every node that is no node's child.
    let roots: Vec<Node> = match document.default_scene().or(document.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut child = vec![false; document.nodes().len()];
            for c in document.nodes().flat_map(|n| n.children()) {
                child[c.index()] = true;
            }
            document.nodes().filter(|n| !child[n.index()]).collect()
        }
    };
    let mut positions: Vec<DVec3> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut skipped = 0usize;
    // Each primitive is read once, however many nodes place its mesh.
    let mut read: Vec<Vec<Option<Option<Local>>>> = document
        .meshes()
        .map(|m| vec![None; m.primitives().len()])
        .collect();
    let mut visited = vec![false; document.nodes().len()];
    let mut stack: Vec<(Node, DMat4)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, DMat4::IDENTITY))
        .collect();
    while let Some((node, parent)) = stack.pop() {
        let n = node.index();
        if std::mem::replace(&mut visited[n], true) {
            return Err(fail(format!(
                "node {n} is reached twice from the scene's roots: the nodes must form trees, each node the child of at most one"
            )));
        }
        let world = parent * local_transform(&node).map_err(|m| fail(format!("node {n}: {m}")))?;
        if let Some(mesh) = node.mesh() {
            for primitive in mesh.primitives() {
                let slot = &mut read[mesh.index()][primitive.index()];
                if slot.is_none() {
                    *slot = Some(read_primitive(&mut buffers, &primitive).map_err(|m| {
                        fail(format!(
                            "mesh {} primitive {}: {m}",
                            mesh.index(),
                            primitive.index()
                        ))
                    })?);
                }
                let Some(Some(local)) = slot else {
                    skipped += 1;
                    continue;
                };
                let (p, t) = (
                    positions.len() + local.positions.len(),
                    triangles.len() + local.triangles.len(),
                );
                // Welding keeps about as much again as the corners.
                let bytes = 3 * (24 * p as u64 + 12 * t as u64);
                if let Err(m) = crate::input::within_memory(bytes) {
                    return Err(fail(format!(
                        "the scene's nodes place {t} triangles of {p} vertices, {m}"
                    )));
                }
                if p >= u32::MAX as usize {
                    return Err(fail(format!(
                        "the scene's nodes place {p} vertices, more than 32-bit indices can number"
                    )));
                }
                let base = positions.len() as u32;
                for (i, v) in local.positions.iter().enumerate() {
                    let w = world.transform_point3(DVec3::from(v.map(f64::from)));
                    if !w.is_finite() {
                        return Err(fail(format!(
                            "node {n} takes vertex {i} of mesh {} primitive {} to a non-finite point",
                            mesh.index(),
                            primitive.index()
                        )));
                    }
                    positions.push(w);
                }
                triangles.extend(local.triangles.iter().map(|t| t.map(|i| base + i)));
            }
        }
        let children: Vec<Node> = node.children().collect();
        stack.extend(children.into_iter().rev().map(|c| (c, world)));
    }
    if triangles.is_empty() && skipped > 0 {
        return Err(fail(format!(
            "no triangles: the scene's {skipped} primitives are points or lines, which cast no shadow"
        )));
    }
    from_corners(path, &positions, &triangles)
}

/// One primitive in its mesh's own space: positions as stored, triangles as indices into them.
#[derive(Clone)]
struct Local {
    positions: Vec<[f32; 3]>,
    triangles: Vec<[u32; 3]>,
}

/// The node's own transform (`matrix`, or `translation * rotation * scale`), checked: finite,
/// affine, a unit rotation.
fn local_transform(node: &Node) -> Result<DMat4, String> {
    match node.transform() {
        Transform::Matrix { matrix } => {
            let m = DMat4::from_cols_array_2d(&matrix.map(|c| c.map(f64::from)));
            if !m.is_finite() {
                return Err(format!("matrix {:?} is not finite", m.to_cols_array()));
            }
            let last_row = m.row(3);
            if last_row != DVec4::W {
                return Err(format!(
                    "matrix's last row {last_row} is not (0, 0, 0, 1): a node's transform is affine"
                ));
            }
            Ok(m)
        }
        Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let (t, s) = (
                DVec3::from(translation.map(f64::from)),
                DVec3::from(scale.map(f64::from)),
            );
            let q = DQuat::from_array(rotation.map(f64::from));
            if !t.is_finite() || !s.is_finite() || !q.is_finite() {
                return Err(format!(
                    "translation {translation:?}, rotation {rotation:?} or scale {scale:?} is not finite"
                ));
            }
            if (q.length() - 1.0).abs() > 1e-3 {
                return Err(format!(
                    "rotation {rotation:?} is not a unit quaternion (length {})",
                    q.length()
                ));
            }
            Ok(DMat4::from_scale_rotation_translation(s, q.normalize(), t))
        }
    }
}

/// The primitive's positions and triangles, `None` for points and lines.
fn read_primitive(buffers: &mut Buffers, primitive: &Primitive) -> Result<Option<Local>, String> {
    let mode = primitive.mode();
    if !matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    ) {
        return Ok(None);
    }
    let accessor = primitive
        .get(&Semantic::Positions)
        .ok_or("no POSITION attribute")?;
    let a = accessor.index();
    if accessor.data_type() != DataType::F32 || accessor.dimensions() != Dimensions::Vec3 {
        return Err(format!(
            "POSITION (accessor {a}) is {:?} of {:?}: positions are read as VEC3 of FLOAT (quantized positions are not)",
            accessor.dimensions(),
            accessor.data_type()
        ));
    }
    let bytes = buffers.accessor_bytes(&accessor, 12)?;
    let positions: Vec<[f32; 3]> = bytes
        .chunks_exact(12)
        .map(|c| [0, 4, 8].map(|k| f32::from_le_bytes([c[k], c[k + 1], c[k + 2], c[k + 3]])))
        .collect();
    if let Some(i) = positions
        .iter()
        .position(|p| !p.iter().all(|x| x.is_finite()))
    {
        return Err(format!(
            "vertex {i} of POSITION (accessor {a}) has a non-finite coordinate {:?}",
            positions[i]
        ));
    }
    let indices: Vec<u32> = match primitive.indices() {
        None => (0..positions.len() as u32).collect(),
        Some(ia) => {
            let size = match ia.data_type() {
                DataType::U8 => 1,
                DataType::U16 => 2,
                DataType::U32 => 4,
                other => {
                    return Err(format!(
                        "indices (accessor {}) are {other:?}, not an unsigned integer type",
                        ia.index()
                    ));
                }
            };
            if ia.dimensions() != Dimensions::Scalar {
                return Err(format!(
                    "indices (accessor {}) are {:?}, not SCALAR",
                    ia.index(),
                    ia.dimensions()
                ));
            }
            let bytes = buffers.accessor_bytes(&ia, size)?;
            let indices: Vec<u32> = bytes
                .chunks_exact(size)
                .map(|c| match *c {
                    [a] => u32::from(a),
                    [a, b] => u32::from(u16::from_le_bytes([a, b])),
                    [a, b, c, d] => u32::from_le_bytes([a, b, c, d]),
                    _ => unreachable!("index sizes are 1, 2 and 4"),
                })
                .collect();
            if let Some(k) = indices.iter().position(|&i| i as usize >= positions.len()) {
                return Err(format!(
                    "index {k} (accessor {}) is {}, but POSITION (accessor {a}) has {} vertices",
                    ia.index(),
                    indices[k],
                    positions.len()
                ));
            }
            indices
        }
    };
    let v = &indices;
    let triangles: Vec<[u32; 3]> = match mode {
        Mode::Triangles => {
            if v.len() % 3 != 0 {
                return Err(format!(
                    "TRIANGLES of {} vertices, not a multiple of 3",
                    v.len()
                ));
            }
            v.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect()
        }
        // The specification's orders: a strip's triangle k is (k, k+1, k+2) for even k and
        // (k, k+2, k+1) for odd k, a fan's (k+1, k+2, 0).
        Mode::TriangleStrip => (0..v.len().saturating_sub(2))
            .map(|k| match k % 2 {
                0 => [v[k], v[k + 1], v[k + 2]],
                _ => [v[k], v[k + 2], v[k + 1]],
            })
            .collect(),
        _ => (0..v.len().saturating_sub(2))
            .map(|k| [v[k + 1], v[k + 2], v[0]])
            .collect(),
    };
    Ok(Some(Local {
        positions,
        triangles,
    }))
}

/// The error of a glTF document that does not parse or validate.
fn document_error(path: &Path, glb: bool, e: ::gltf::Error) -> MeshError {
    match e {
        ::gltf::Error::Deserialize(e) => {
            let message = e.to_string();
            let message = message
                .rsplit_once(" at line ")
                .map_or(message.as_str(), |(m, _)| m);
            if glb {
                let message = format!(
                    "the JSON chunk, line {} column {}: {message}",
                    e.line(),
                    e.column()
                );
                error(path, None, message)
            } else {
                let message = format!("{message} (column {})", e.column());
                error(path, Some(e.line()), message)
            }
        }
        ::gltf::Error::Validation(errors) => {
            let mut said: Vec<String> = errors
                .iter()
                .take(3)
                .map(|(at, e)| match e {
                    ::gltf::json::validation::Error::Unsupported => {
                        format!("{at}: an extension required and not read")
                    }
                    e => format!("{at}: {}", e.to_string().to_lowercase()),
                })
                .collect();
            if errors.len() > 3 {
                said.push(format!("and {} more", errors.len() - 3));
            }
            error(path, None, said.join("; "))
        }
        e => error(path, None, e.to_string()),
    }
}
