//! Reading PLY (ASCII, binary little- and big-endian) into a [`TriangleMesh`]: the positions of
//! `element vertex` (`x`, `y`, `z`), the polygons of `element face` (`vertex_indices` or
//! `vertex_index`), fan-triangulated as the OBJ reader triangulates polygons, and the strips of
//! `element tristrips` (`vertex_indices`, `-1` restarting a strip). Other elements and
//! properties are read past.
//!
//! A reader of its own, small, rather than a crate's: the maintained PLY crate needs a newer
//! Rust than the workspace's, the older one allocates from declared counts; here every declared
//! count is checked against the bytes that follow the header before anything is made of it, an
//! ASCII file's errors name their line, and a binary file's the element.

use std::path::Path;

use glam::DVec3;

use crate::corners::from_corners;
use crate::mesh::{MeshError, TriangleMesh};
use crate::mesh_format::MeshFormat;

/// A `MeshError::Format` of the PLY file `path`.
fn error(path: &Path, line: Option<usize>, message: String) -> MeshError {
    MeshError::Format {
        path: path.to_path_buf(),
        format: MeshFormat::Ply,
        line,
        message,
    }
}

/// A scalar type of the format.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn named(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    /// The range of an integer type (`None` for the floating-point ones).
    fn range(self) -> Option<(i64, i64)> {
        Some(match self {
            Scalar::I8 => (i8::MIN.into(), i8::MAX.into()),
            Scalar::U8 => (0, u8::MAX.into()),
            Scalar::I16 => (i16::MIN.into(), i16::MAX.into()),
            Scalar::U16 => (0, u16::MAX.into()),
            Scalar::I32 => (i32::MIN.into(), i32::MAX.into()),
            Scalar::U32 => (0, u32::MAX.into()),
            Scalar::F32 | Scalar::F64 => return None,
        })
    }
}

/// A property: a scalar, or a list of `item`s preceded by its length as a `count`.
enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

struct Property {
    name: String,
    kind: Kind,
}

struct Element {
    name: String,
    count: usize,
    /// The header line that declares it.
    line: usize,
    properties: Vec<Property>,
}

impl Element {
    /// The fewest bytes one element takes: binary, its scalars and list lengths; ASCII, two
    /// characters (a digit and a separator) per value.
    fn least_bytes(&self, ascii: bool) -> usize {
        self.properties
            .iter()
            .map(|p| match (ascii, &p.kind) {
                (true, _) => 2,
                (false, Kind::Scalar(t) | Kind::List { count: t, .. }) => t.size(),
            })
            .sum()
    }

    /// The index of the list property of indices (`vertex_indices` or `vertex_index`).
    fn index_list(&self) -> Option<usize> {
        self.properties.iter().position(|p| {
            matches!(p.kind, Kind::List { .. })
                && matches!(p.name.as_str(), "vertex_indices" | "vertex_index")
        })
    }
}

/// The triangles of the PLY file `path` of contents `bytes` (see the module's documentation;
/// `docs/scene-format.md` is the contract).
pub(crate) fn parse_ply(path: &Path, bytes: &[u8]) -> Result<TriangleMesh, MeshError> {
    let Header {
        encoding,
        elements,
        data,
        first_line,
    } = header(path, bytes)?;
    let at = |line: usize, m: String| error(path, Some(line), m);
    // Every declared count against the bytes there are, before anything is allocated.
    let ascii = matches!(encoding, Encoding::Ascii);
    let mut need: u128 = 0;
    for e in &elements {
        need += e.count as u128 * e.least_bytes(ascii) as u128;
        // (+ 1: the last line of an ASCII file may lack its newline)
        if need > data.len() as u128 + 1 {
            return Err(at(
                e.line,
                format!(
                    "element {} of {} elements, with those before it, needs at least {need} bytes; {} follow the header",
                    e.name,
                    e.count,
                    data.len()
                ),
            ));
        }
    }
    let mut vertex = None;
    for (k, e) in elements.iter().enumerate() {
        match e.name.as_str() {
            "vertex" if vertex.is_some() => {
                return Err(at(e.line, "a second `element vertex`".into()));
            }
            "vertex" => vertex = Some(k),
            "face" | "tristrips" if e.index_list().is_none() => {
                return Err(at(
                    e.line,
                    format!(
                        "element {} has no list property `vertex_indices` (or `vertex_index`)",
                        e.name
                    ),
                ));
            }
            _ => {}
        }
    }
    let Some(vertex) = vertex else {
        return Err(error(path, None, "no `element vertex`".into()));
    };
    let v = &elements[vertex];
    let mut xyz = [0; 3];
    for (c, name) in ["x", "y", "z"].iter().enumerate() {
        xyz[c] = v
            .properties
            .iter()
            .position(|p| p.name == *name && matches!(p.kind, Kind::Scalar(_)))
            .ok_or_else(|| {
                at(
                    v.line,
                    format!("element vertex has no scalar property {name}"),
                )
            })?;
    }
    if v.count >= u32::MAX as usize {
        return Err(at(
            v.line,
            format!("{} vertices, more than 32-bit indices can number", v.count),
        ));
    }
    if !elements
        .iter()
        .any(|e| matches!(e.name.as_str(), "face" | "tristrips"))
    {
        return Err(error(
            path,
            None,
            "no `element face` or `element tristrips`: points cast no shadow".into(),
        ));
    }
    let mut reader = match encoding {
        Encoding::Ascii => {
            let text = std::str::from_utf8(data).map_err(|e| {
                let line = first_line
                    + data[..e.valid_up_to()]
                        .iter()
                        .filter(|&&b| b == b'\n')
                        .count();
                at(line, "not ASCII text".into())
            })?;
            Values::Ascii {
                lines: text.split('\n'),
                line: first_line - 1,
                tokens: "".split_ascii_whitespace(),
            }
        }
        Encoding::Binary { big } => Values::Binary { data, at: 0, big },
    };
    let mut positions: Vec<DVec3> = Vec::with_capacity(v.count);
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut list: Vec<f64> = Vec::new();
    for e in &elements {
        if e.properties.is_empty() {
            continue;
        }
        let indices = e
            .index_list()
            .filter(|_| matches!(e.name.as_str(), "face" | "tristrips"));
        for i in 0..e.count {
            let mut p = DVec3::ZERO;
            let mut read = || -> Result<(), String> {
                reader.begin()?;
                for (k, prop) in e.properties.iter().enumerate() {
                    match prop.kind {
                        Kind::Scalar(t) => {
                            let x = reader.value(t)?;
                            if let Some(c) = xyz
                                .iter()
                                .position(|&c| c == k)
                                .filter(|_| e.name == "vertex")
                            {
                                p[c] = x;
                            }
                        }
                        Kind::List { count, item } => {
                            let n = reader.value(count)?;
                            if n < 0.0 {
                                return Err(format!("{} has a negative length {n}", prop.name));
                            }
                            list.clear();
                            reader.list(
                                n as usize,
                                item,
                                (indices == Some(k)).then_some(&mut list),
                            )?;
                        }
                    }
                }
                reader.end()
            };
            read().map_err(|m| error(path, reader.line(), format!("{} {i}: {m}", e.name)))?;
            let fail = |m: String| error(path, reader.line(), format!("{} {i}: {m}", e.name));
            if e.name == "vertex" {
                if !p.is_finite() {
                    return Err(fail(format!("a non-finite coordinate {p}")));
                }
                positions.push(p);
                continue;
            }
            let Some(_) = indices else { continue };
            let strip = e.name == "tristrips";
            for (k, &x) in list.iter().enumerate() {
                if !(x == x.trunc() && (0.0..v.count as f64).contains(&x) || strip && x == -1.0) {
                    return Err(fail(format!(
                        "index {k} is {x}, but the file has {} vertices",
                        v.count
                    )));
                }
            }
            if strip {
                // Each run between `-1`s is a strip, its triangle k (k, k+1, k+2) for even k
                // and (k, k+2, k+1) for odd k, as glTF's strips are.
                for run in list.split(|&x| x == -1.0) {
                    for k in 0..run.len().saturating_sub(2) {
                        let t = match k % 2 {
                            0 => [run[k], run[k + 1], run[k + 2]],
                            _ => [run[k], run[k + 2], run[k + 1]],
                        };
                        triangles.push(t.map(|x| x as u32));
                    }
                }
            } else if e.name == "face" {
                if list.len() < 3 {
                    return Err(fail(format!(
                        "a face needs at least 3 vertices, found {}",
                        list.len()
                    )));
                }
                // A fan around the first corner, as the OBJ reader's.
                for k in 1..list.len() - 1 {
                    triangles.push([list[0], list[k], list[k + 1]].map(|x| x as u32));
                }
            }
        }
    }
    from_corners(path, &positions, &triangles)
}

enum Encoding {
    Ascii,
    Binary { big: bool },
}

/// A PLY file's header, and the bytes after it.
struct Header<'a> {
    encoding: Encoding,
    elements: Vec<Element>,
    /// The bytes after `end_header`.
    data: &'a [u8],
    /// The line they start on.
    first_line: usize,
}

/// The header of the PLY file `path` of contents `bytes`.
fn header<'a>(path: &Path, bytes: &'a [u8]) -> Result<Header<'a>, MeshError> {
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut rest = bytes;
    let mut line = 0;
    loop {
        line += 1;
        let Some(end) = rest.iter().position(|&b| b == b'\n') else {
            return Err(error(
                path,
                Some(line),
                "truncated: the header ends without `end_header`".into(),
            ));
        };
        let raw = &rest[..end];
        rest = &rest[end + 1..];
        let at = |m: String| error(path, Some(line), m);
        let text = std::str::from_utf8(raw.strip_suffix(b"\r").unwrap_or(raw))
            .map_err(|_| at("a header line that is not ASCII text".into()))?;
        let words: Vec<&str> = text.split_ascii_whitespace().collect();
        match words.as_slice() {
            ["ply"] if line == 1 => {}
            _ if line == 1 => return Err(at("the first line is not `ply`".into())),
            [] | ["comment" | "obj_info", ..] => {}
            ["format", kind, "1.0"] if encoding.is_none() => {
                encoding = Some(match *kind {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::Binary { big: false },
                    "binary_big_endian" => Encoding::Binary { big: true },
                    _ => return Err(at(format!("unknown format `{kind}`"))),
                });
            }
            ["format", ..] => {
                return Err(at(format!(
                    "`{text}`: expected one `format ascii|binary_little_endian|binary_big_endian 1.0`"
                )));
            }
            ["element", name, count] => {
                let count = count
                    .parse::<u64>()
                    .ok()
                    .and_then(|c| usize::try_from(c).ok())
                    .ok_or_else(|| at(format!("element {name}: `{count}` is not a count")))?;
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    line,
                    properties: Vec::new(),
                });
            }
            ["property", kind @ .., name] if !kind.is_empty() => {
                let e = elements
                    .last_mut()
                    .ok_or_else(|| at("a property before any element".into()))?;
                let scalar = |t: &str| {
                    Scalar::named(t).ok_or_else(|| at(format!("unknown property type `{t}`")))
                };
                let kind = match *kind {
                    [t] => Kind::Scalar(scalar(t)?),
                    ["list", count, item] => {
                        let (count, item) = (scalar(count)?, scalar(item)?);
                        if count.range().is_none() {
                            return Err(at(format!(
                                "list {name}: its length's type is not an integer type"
                            )));
                        }
                        if matches!(e.name.as_str(), "face" | "tristrips")
                            && (*name == "vertex_indices" || *name == "vertex_index")
                            && item.range().is_none()
                        {
                            return Err(at(format!(
                                "list {name}: vertex indices of a non-integer type"
                            )));
                        }
                        Kind::List { count, item }
                    }
                    _ => {
                        return Err(at(format!(
                            "`{text}`: expected `property TYPE NAME` or `property list COUNT_TYPE ITEM_TYPE NAME`"
                        )));
                    }
                };
                e.properties.push(Property {
                    name: name.to_string(),
                    kind,
                });
            }
            ["end_header"] => break,
            _ => return Err(at(format!("`{text}` is not a header line"))),
        }
    }
    let encoding = encoding.ok_or_else(|| error(path, None, "no `format` line".into()))?;
    Ok(Header {
        encoding,
        elements,
        data: rest,
        first_line: line + 1,
    })
}

/// The values of the elements, read in order.
enum Values<'a> {
    Ascii {
        lines: std::str::Split<'a, char>,
        /// The line of the current element.
        line: usize,
        tokens: std::str::SplitAsciiWhitespace<'a>,
    },
    Binary {
        data: &'a [u8],
        at: usize,
        big: bool,
    },
}

impl Values<'_> {
    /// The current element's line, for an ASCII file.
    fn line(&self) -> Option<usize> {
        match self {
            Values::Ascii { line, .. } => Some(*line),
            Values::Binary { .. } => None,
        }
    }

    /// Starts the next element: in ASCII, its line (blank lines are passed over).
    fn begin(&mut self) -> Result<(), String> {
        if let Values::Ascii {
            lines,
            line,
            tokens,
        } = self
        {
            loop {
                *line += 1;
                let text = lines.next().ok_or("the file ends before it")?;
                *tokens = text.split_ascii_whitespace();
                if tokens.clone().next().is_some() {
                    return Ok(());
                }
            }
        }
        Ok(())
    }

    /// Ends the element: in ASCII, no value may be left on its line.
    fn end(&mut self) -> Result<(), String> {
        match self {
            Values::Ascii { tokens, .. } => match tokens.clone().count() {
                0 => Ok(()),
                n => Err(format!("{n} values more than its properties take")),
            },
            Values::Binary { .. } => Ok(()),
        }
    }

    /// The next value, of type `t`.
    fn value(&mut self, t: Scalar) -> Result<f64, String> {
        match self {
            Values::Ascii { tokens, .. } => {
                let word = tokens
                    .next()
                    .ok_or("fewer values than its properties take")?;
                let bad = || format!("`{word}` is not a {t:?} value");
                match t.range() {
                    Some((lo, hi)) => {
                        let x: i64 = word.parse().map_err(|_| bad())?;
                        if x < lo || x > hi {
                            return Err(format!("{x} is out of range for {t:?}"));
                        }
                        Ok(x as f64)
                    }
                    None if t == Scalar::F32 => {
                        Ok(f64::from(word.parse::<f32>().map_err(|_| bad())?))
                    }
                    None => word.parse().map_err(|_| bad()),
                }
            }
            Values::Binary { data, at, big } => {
                let size = t.size();
                let b = data
                    .get(*at..*at + size)
                    .ok_or("truncated: the file ends in it")?;
                *at += size;
                let mut w = [0u8; 8];
                w[..size].copy_from_slice(b);
                if *big {
                    w[..size].reverse();
                }
                let (w4, w2) = ([w[0], w[1], w[2], w[3]], [w[0], w[1]]);
                Ok(match t {
                    Scalar::I8 => f64::from(w[0] as i8),
                    Scalar::U8 => f64::from(w[0]),
                    Scalar::I16 => f64::from(i16::from_le_bytes(w2)),
                    Scalar::U16 => f64::from(u16::from_le_bytes(w2)),
                    Scalar::I32 => f64::from(i32::from_le_bytes(w4)),
                    Scalar::U32 => f64::from(u32::from_le_bytes(w4)),
                    Scalar::F32 => f64::from(f32::from_le_bytes(w4)),
                    Scalar::F64 => f64::from_le_bytes(w),
                })
            }
        }
    }

    /// A list's `n` items of type `item`, kept in `into` where given, else read past.
    fn list(
        &mut self,
        n: usize,
        item: Scalar,
        mut into: Option<&mut Vec<f64>>,
    ) -> Result<(), String> {
        if let Values::Binary { data, at, .. } = self {
            let left = data.len() - *at;
            if n.checked_mul(item.size()).is_none_or(|b| b > left) {
                return Err(format!(
                    "truncated: a list of {n} items of {} bytes, {left} bytes left",
                    item.size()
                ));
            }
            if into.is_none() {
                *at += n * item.size();
                return Ok(());
            }
        }
        for _ in 0..n {
            let x = self.value(item)?;
            if let Some(v) = into.as_deref_mut() {
                v.push(x);
            }
        }
        Ok(())
    }
}
