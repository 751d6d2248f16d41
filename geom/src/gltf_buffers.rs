//! The bytes of a glTF file's meshes: the GLB container, the buffers (a GLB's binary chunk,
//! `data:` URIs, files beside the `.gltf`) and the accessors' elements, every offset, stride and
//! count checked against the bytes there are (`gltf.rs` reads the document that names them).

use std::borrow::Cow;
use std::path::Path;

use ::gltf::accessor::Accessor;
use ::gltf::buffer::{Source, View};

/// The file's buffers, each read when an accessor first needs it.
pub(crate) struct Buffers<'a> {
    /// The glTF file (external buffers are relative to its folder).
    path: &'a Path,
    /// A GLB's binary chunk.
    bin: Option<&'a [u8]>,
    loaded: Vec<Option<Cow<'a, [u8]>>>,
}

impl<'a> Buffers<'a> {
    /// The `count` buffers of the glTF file `path`, a GLB's binary chunk `bin`; none read yet.
    pub(crate) fn new(path: &'a Path, bin: Option<&'a [u8]>, count: usize) -> Self {
        Buffers {
            path,
            bin,
            loaded: vec![None; count],
        }
    }

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
    pub(crate) fn accessor_bytes(
        &mut self,
        accessor: &Accessor,
        size: usize,
    ) -> Result<Vec<u8>, String> {
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
pub(crate) fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
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

/// The bytes of standard base64 text (padding optional, no white space).
pub(crate) fn base64(text: &str) -> Result<Vec<u8>, String> {
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
pub(crate) fn percent_decoded(uri: &str) -> Option<String> {
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
