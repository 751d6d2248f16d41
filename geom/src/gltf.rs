//! Reading glTF 2.0 (`.gltf` JSON with external or `data:` buffers, or binary `.glb`) into a
//! [`TriangleMesh`]: the triangles of every mesh its scene places, each node's transform
//! composed down the hierarchy.
//!
//! The `gltf` crate parses and validates the JSON (every index refers to something); the GLB
//! container, the buffers and the accessors' bytes are read here, every offset, stride and count
//! checked against the bytes there are, so that no file makes the reader panic or allocate from
//! a count it does not hold.

use std::borrow::Cow;
use std::path::Path;

use ::gltf::accessor::{Accessor, DataType, Dimensions};
use ::gltf::buffer::{Source, View};
use ::gltf::json::validation::{Checked, Validate};
use ::gltf::mesh::Mode;
use ::gltf::scene::Transform;
use ::gltf::{Node, Primitive, Semantic};
use glam::{DMat4, DQuat, DVec3, DVec4};

use crate::mesh::{MeshError, TriangleMesh};
use crate::mesh_files::{MeshFormat, from_corners};

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
    let mut buffers = Buffers {
        path,
        bin,
        loaded: vec![None; document.buffers().len()],
    };
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
    from_corners(path, MeshFormat::Gltf, &positions, &triangles)
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

/// The file's buffers, each read when an accessor first needs it.
struct Buffers<'a> {
    /// The glTF file (external buffers are relative to its folder).
    path: &'a Path,
    /// A GLB's binary chunk.
    bin: Option<&'a [u8]>,
    loaded: Vec<Option<Cow<'a, [u8]>>>,
}

impl<'a> Buffers<'a> {
    /// The bytes of `view`, checked against its buffer's.
    fn view_bytes(&mut self, view: &View) -> Result<&[u8], String> {
        let buffer = view.buffer();
        let b = buffer.index();
        if self.loaded[b].is_none() {
            let data = self.load(b, buffer.source())?;
            if data.len() < buffer.length() {
                return Err(format!(
                    "buffer {b} holds {} bytes, fewer than its byteLength {}",
                    data.len(),
                    buffer.length()
                ));
            }
            self.loaded[b] = Some(data);
        }
        let data = &self.loaded[b].as_deref().expect("loaded above")[..buffer.length()];
        let (start, length) = (view.offset(), view.length());
        start
            .checked_add(length)
            .and_then(|end| data.get(start..end))
            .ok_or_else(|| {
                format!(
                    "buffer view {} takes bytes {start} to {} of buffer {b}, which has {}",
                    view.index(),
                    start as u128 + length as u128,
                    data.len()
                )
            })
    }

    /// The contents of buffer `b`: the GLB's binary chunk, a `data:` URI's or a file's.
    fn load(&self, b: usize, source: Source) -> Result<Cow<'a, [u8]>, String> {
        let uri = match source {
            Source::Bin => {
                return self.bin.map(Cow::Borrowed).ok_or_else(|| {
                    format!("buffer {b} has no uri and the file has no GLB binary chunk")
                });
            }
            Source::Uri(uri) => uri,
        };
        if let Some(data) = uri.strip_prefix("data:") {
            let (kind, payload) = data
                .split_once(',')
                .ok_or_else(|| format!("buffer {b}: a data: URI without a comma"))?;
            if !kind.ends_with(";base64") {
                return Err(format!(
                    "buffer {b}: data: URI `{kind}` is not base64 (only base64 data URIs are read)"
                ));
            }
            return base64(payload)
                .map(Cow::Owned)
                .map_err(|m| format!("buffer {b}: data: URI: {m}"));
        }
        let scheme = uri
            .split_once(':')
            .is_some_and(|(s, _)| !s.is_empty() && !s.contains('/'));
        if scheme {
            return Err(format!(
                "buffer {b}: uri `{uri}` is neither a file relative to the glTF file nor a data: URI"
            ));
        }
        let name = percent_decoded(uri).ok_or_else(|| {
            format!("buffer {b}: uri `{uri}` has an invalid percent escape or is not UTF-8")
        })?;
        let file = self.path.parent().unwrap_or(Path::new(".")).join(name);
        crate::input::read_bytes(&file)
            .map(Cow::Owned)
            .map_err(|e| format!("buffer {b}: cannot read {}: {e}", file.display()))
    }

    /// The elements of `accessor`, each `size` bytes, packed: from its buffer view where it
    /// has one (zeros where not), with its sparse substitutions.
    fn accessor_bytes(&mut self, accessor: &Accessor, size: usize) -> Result<Vec<u8>, String> {
        let (a, count) = (accessor.index(), accessor.count());
        let too_long = || format!("accessor {a}'s {count} elements run past its buffer view");
        let total = count.checked_mul(size).ok_or_else(too_long)?;
        let mut out = match accessor.view() {
            Some(view) => {
                let stride = view.stride().unwrap_or(size);
                if stride < size {
                    return Err(format!(
                        "buffer view {}'s byteStride {stride} is less than accessor {a}'s element of {size} bytes",
                        view.index()
                    ));
                }
                let data = self.view_bytes(&view)?;
                let start = accessor.offset();
                let end = match count {
                    0 => Some(start),
                    _ => (count - 1)
                        .checked_mul(stride)
                        .and_then(|x| x.checked_add(start))
                        .and_then(|x| x.checked_add(size)),
                };
                if end.is_none_or(|end| end > data.len()) {
                    return Err(too_long());
                }
                let mut out = Vec::with_capacity(total);
                for i in 0..count {
                    out.extend_from_slice(&data[start + i * stride..][..size]);
                }
                out
            }
            None => {
                crate::input::within_memory(total as u64)
                    .map_err(|m| format!("accessor {a} of {count} elements: {m}"))?;
                vec![0; total]
            }
        };
        if let Some(sparse) = accessor.sparse() {
            let n = sparse.count();
            let (indices, values) = (sparse.indices(), sparse.values());
            let index_size = match indices.index_type() {
                ::gltf::accessor::sparse::IndexType::U8 => 1,
                ::gltf::accessor::sparse::IndexType::U16 => 2,
                ::gltf::accessor::sparse::IndexType::U32 => 4,
            };
            let short =
                || format!("accessor {a}'s {n} sparse elements run past their buffer views");
            let slice = |data: &[u8], start: usize, each: usize| -> Result<Vec<u8>, String> {
                n.checked_mul(each)
                    .and_then(|len| data.get(start..start.checked_add(len)?))
                    .map(<[u8]>::to_vec)
                    .ok_or_else(short)
            };
            let at = slice(
                self.view_bytes(&indices.view())?,
                indices.offset(),
                index_size,
            )?;
            let new = slice(self.view_bytes(&values.view())?, values.offset(), size)?;
            for (k, i) in at.chunks_exact(index_size).enumerate() {
                let mut le = [0u8; 4];
                le[..index_size].copy_from_slice(i);
                let i = u32::from_le_bytes(le) as usize;
                if i >= count {
                    return Err(format!(
                        "accessor {a}'s sparse index {k} is {i}, but the accessor has {count} elements"
                    ));
                }
                out[i * size..][..size].copy_from_slice(&new[k * size..][..size]);
            }
        }
        Ok(out)
    }
}

/// The JSON chunk and the binary chunk (if any) of a GLB file.
fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
    let word = |b: &[u8], at: usize| -> Option<u32> {
        Some(u32::from_le_bytes(b.get(at..at + 4)?.try_into().ok()?))
    };
    let (Some(version), Some(length)) = (word(bytes, 4), word(bytes, 8)) else {
        return Err(format!(
            "truncated: {} bytes, less than a GLB header's 12",
            bytes.len()
        ));
    };
    if version != 2 {
        return Err(format!(
            "GLB version {version}: only glTF 2.0 (version 2) is read"
        ));
    }
    let length = length as usize;
    if length > bytes.len() {
        return Err(format!(
            "truncated: the GLB header gives a length of {length} bytes, the file has {}",
            bytes.len()
        ));
    }
    let mut rest = bytes.get(12..length).unwrap_or_default();
    let mut chunks = Vec::new();
    while !rest.is_empty() {
        let (Some(len), Some(kind)) = (word(rest, 0), rest.get(4..8)) else {
            return Err("truncated: a GLB chunk header cut short".to_string());
        };
        let body = rest
            .get(8..)
            .and_then(|r| r.get(..len as usize))
            .ok_or_else(|| {
                format!(
                    "truncated: a GLB chunk of {len} bytes, {} left in the file",
                    rest.len() - 8
                )
            })?;
        chunks.push((kind, body));
        rest = &rest[8 + len as usize..];
    }
    match chunks.as_slice() {
        [(b"JSON", json), more @ ..] => {
            let bin = more.first().filter(|(k, _)| *k == b"BIN\0").map(|c| c.1);
            Ok((json, bin))
        }
        _ => Err("the GLB's first chunk is not its JSON chunk".to_string()),
    }
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

/// The bytes of standard base64 text (padding optional, no white space).
fn base64(text: &str) -> Result<Vec<u8>, String> {
    let digits = text.trim_end_matches('=');
    if text.len() - digits.len() > 2 || digits.len() % 4 == 1 {
        return Err("base64 of a length no encoding has".to_string());
    }
    let mut out = Vec::with_capacity(digits.len() / 4 * 3 + 2);
    let (mut acc, mut bits) = (0u32, 0u32);
    for (i, c) in digits.bytes().enumerate() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return Err(format!("base64 character {i} is {:?}", c as char)),
        };
        acc = (acc << 6) | u32::from(v);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Ok(out)
}

/// `uri` with its `%XX` escapes decoded (`None` if one is malformed or the result not UTF-8).
fn percent_decoded(uri: &str) -> Option<String> {
    let b = uri.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = b
                .get(i + 1..i + 3)
                .filter(|h| h.iter().all(u8::is_ascii_hexdigit))?;
            out.push(u8::from_str_radix(std::str::from_utf8(hex).ok()?, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

#[cfg(test)]
#[path = "gltf_tests.rs"]
pub(crate) mod tests;
