//! The NumPy array file (`.npy`, format versions 1.0, 2.0 and 3.0): its header read and
//! checked, and a float32 array written. The format (numpy's `numpy/lib/format.py`, "NPY
//! format"): the magic `\x93NUMPY`, the major and minor version bytes, the header's length (a
//! little-endian `u16` in version 1.0, `u32` in 2.0 and 3.0), then the header, a Python dict
//! literal `{'descr': '<f8', 'fortran_order': False, 'shape': (n, 6), }` padded with spaces to
//! a multiple of 64 bytes of preamble and ended by `\n` (Latin-1 text in 1.0 and 2.0, UTF-8 in
//! 3.0), then the array's bytes, `shape`'s product items of `descr`.

use std::fmt;
use std::io::Read;

/// The magic string every `.npy` file begins with.
const MAGIC: &[u8; 6] = b"\x93NUMPY";

/// The longest header this reader takes: numpy's own reader refuses longer ones (10 000 bytes,
/// `_MAX_HEADER_SIZE`) unless told to trust the file.
const MAX_HEADER: usize = 10_000;

/// The element type of an array this reader takes: little-endian floats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Dtype {
    /// `<f8`, 64-bit.
    F8,
    /// `<f4`, 32-bit.
    F4,
}

impl Dtype {
    /// The bytes of one item.
    pub(crate) fn size(self) -> usize {
        match self {
            Dtype::F8 => 8,
            Dtype::F4 => 4,
        }
    }

    /// The value of the little-endian item `bytes` (of [`Dtype::size`] bytes).
    pub(crate) fn value(self, bytes: &[u8]) -> f64 {
        match self {
            Dtype::F8 => f64::from_le_bytes(bytes.try_into().expect("8 bytes")),
            Dtype::F4 => f32::from_le_bytes(bytes.try_into().expect("4 bytes")) as f64,
        }
    }
}

impl fmt::Display for Dtype {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Dtype::F8 => "<f8",
            Dtype::F4 => "<f4",
        })
    }
}

/// A checked `.npy` header: a C-ordered array of little-endian floats.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Header {
    pub(crate) dtype: Dtype,
    pub(crate) shape: Vec<u64>,
    /// The bytes before the data: magic, version, length and header.
    pub(crate) data_offset: u64,
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Str(s) => write!(f, "'{s}'"),
            Value::Bool(b) => f.write_str(if *b { "True" } else { "False" }),
            Value::Tuple(t) => f.write_str(&shape_text(t)),
            Value::List(l) => f.write_str(l),
        }
    }
}

impl Header {
    /// The bytes of the data the header declares, `None` where that overflows.
    pub(crate) fn data_len(&self) -> Option<u64> {
        self.shape
            .iter()
            .try_fold(self.dtype.size() as u64, |a, &d| a.checked_mul(d))
    }

    /// The shape as Python writes it: `(5, 6)`, `(5,)`, `()`.
    pub(crate) fn shape_text(&self) -> String {
        shape_text(&self.shape)
    }
}

/// A shape as Python writes a tuple.
pub(crate) fn shape_text(shape: &[u64]) -> String {
    match shape {
        [d] => format!("({d},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(u64::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// Reads and checks the header at the start of `r`: the error says what is wrong, in words
/// for a message that names the file first.
pub(crate) fn read_header(r: &mut impl Read) -> Result<Header, String> {
    let mut start = [0u8; 8];
    let got = read_up_to(r, &mut start)?;
    if got == 0 {
        return Err("the file is empty: a .npy file begins with a NumPy header".into());
    }
    if got < 6 || &start[..6] != MAGIC {
        return Err(
            "not a NumPy .npy file: it does not begin with the magic string \\x93NUMPY".into(),
        );
    }
    if got < 8 {
        return Err("the header is truncated: the file ends within its version".into());
    }
    let (major, minor) = (start[6], start[7]);
    let length_bytes = match (major, minor) {
        (1, 0) => 2,
        (2, 0) | (3, 0) => 4,
        _ => {
            return Err(format!(
                "NumPy format version {major}.{minor} is not supported (1.0, 2.0 and 3.0 are)"
            ));
        }
    };
    let mut len = [0u8; 4];
    if read_up_to(r, &mut len[..length_bytes])? < length_bytes {
        return Err("the header is truncated: the file ends within its length".into());
    }
    let header_len = u32::from_le_bytes(len) as usize;
    if header_len > MAX_HEADER {
        return Err(format!(
            "the header declares {header_len} bytes, more than the {MAX_HEADER} a NumPy header takes"
        ));
    }
    let mut text = vec![0u8; header_len];
    let got = read_up_to(r, &mut text)?;
    if got < header_len {
        return Err(format!(
            "the header is truncated: it declares {header_len} bytes and the file holds {got} of them"
        ));
    }
    // Latin-1 in versions 1 and 2: every byte is the character of its code.
    let text: String = if major == 3 {
        String::from_utf8(text).map_err(|_| "the header is not UTF-8 text".to_string())?
    } else {
        text.iter().map(|&b| b as char).collect()
    };
    let dict = parse_dict(&text).map_err(|e| format!("bad header {:?}: {e}", text.trim_end()))?;
    let data_offset = (8 + length_bytes + header_len) as u64;
    header_of(&dict).map(|(dtype, shape)| Header {
        dtype,
        shape,
        data_offset,
    })
}

/// Reads into `buf` until it is full or the reader ends; the number of bytes read.
fn read_up_to(r: &mut impl Read, buf: &mut [u8]) -> Result<usize, String> {
    let mut n = 0;
    while n < buf.len() {
        match r.read(&mut buf[n..]) {
            Ok(0) => break,
            Ok(k) => n += k,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e.to_string()),
        }
    }
    Ok(n)
}

/// A value of the header's dict.
#[derive(Clone, Debug, PartialEq)]
enum Value {
    Str(String),
    Bool(bool),
    /// A tuple of non-negative integers.
    Tuple(Vec<u64>),
    /// A list (`descr` of a structured array), kept as text for the message.
    List(String),
}

/// The dtype and shape of a header's dict, checked: the three keys numpy writes and no other.
fn header_of(dict: &[(String, Value)]) -> Result<(Dtype, Vec<u64>), String> {
    let get = |key: &str| dict.iter().find(|(k, _)| k == key).map(|(_, v)| v);
    if let Some((k, _)) = dict
        .iter()
        .find(|(k, _)| !["descr", "fortran_order", "shape"].contains(&k.as_str()))
    {
        return Err(format!(
            "the header has the key {k:?}; a NumPy header has only 'descr', 'fortran_order' and 'shape'"
        ));
    }
    let dtype = match get("descr") {
        None => return Err("the header has no 'descr' (the dtype)".into()),
        Some(Value::Str(d)) => match d.as_str() {
            "<f8" => Dtype::F8,
            "<f4" => Dtype::F4,
            ">f8" | ">f4" => {
                return Err(format!(
                    "dtype '{d}' is big-endian; little-endian '<f8' or '<f4' is read (numpy: a.astype('<f8'))"
                ));
            }
            _ => {
                return Err(format!(
                    "dtype '{d}' is not read: the points are little-endian floats, '<f8' or '<f4' (numpy: a.astype('<f8'))"
                ));
            }
        },
        Some(Value::List(l)) => {
            return Err(format!(
                "dtype {l} is a structured dtype; the points are a plain array of '<f8' or '<f4'"
            ));
        }
        Some(v) => return Err(format!("'descr' is {v}, not a dtype string")),
    };
    match get("fortran_order") {
        None => return Err("the header has no 'fortran_order'".into()),
        Some(Value::Bool(false)) => {}
        Some(Value::Bool(true)) => {
            return Err(
                "the array is in Fortran (column-major) order, which is not read: save a C-ordered array (numpy: np.ascontiguousarray(a))"
                    .into(),
            );
        }
        Some(v) => return Err(format!("'fortran_order' is {v}, not True or False")),
    }
    let shape = match get("shape") {
        None => return Err("the header has no 'shape'".into()),
        Some(Value::Tuple(s)) => s.clone(),
        Some(v) => return Err(format!("'shape' is {v}, not a tuple of integers")),
    };
    Ok((dtype, shape))
}

/// Parses the Python dict literal of a header: string keys, values strings, `True`/`False`
/// or tuples of integers (lists kept as text); a trailing comma and surrounding spaces allowed.
fn parse_dict(text: &str) -> Result<Vec<(String, Value)>, String> {
    let mut p = Parser {
        s: text.as_bytes(),
        at: 0,
    };
    p.space();
    p.expect(b'{')?;
    let mut dict: Vec<(String, Value)> = Vec::new();
    loop {
        p.space();
        if p.eat(b'}') {
            break;
        }
        let key = p.string()?;
        p.space();
        p.expect(b':')?;
        p.space();
        let value = p.value()?;
        if dict.iter().any(|(k, _)| *k == key) {
            return Err(format!("the key {key:?} is given twice"));
        }
        dict.push((key, value));
        p.space();
        if p.eat(b',') {
            continue;
        }
        p.space();
        p.expect(b'}')?;
        break;
    }
    p.space();
    if p.at < p.s.len() {
        return Err(format!("text after the dict at byte {}", p.at));
    }
    Ok(dict)
}

/// A cursor over a header's text.
struct Parser<'a> {
    s: &'a [u8],
    at: usize,
}

impl Parser<'_> {
    fn peek(&self) -> Option<u8> {
        self.s.get(self.at).copied()
    }

    fn space(&mut self) {
        while matches!(self.peek(), Some(b' ' | b'\t' | b'\n' | b'\r')) {
            self.at += 1;
        }
    }

    fn eat(&mut self, c: u8) -> bool {
        if self.peek() == Some(c) {
            self.at += 1;
            true
        } else {
            false
        }
    }

    fn expect(&mut self, c: u8) -> Result<(), String> {
        if self.eat(c) {
            Ok(())
        } else {
            Err(format!(
                "expected '{}' at byte {}, found {}",
                c as char,
                self.at,
                self.found()
            ))
        }
    }

    fn found(&self) -> String {
        match self.peek() {
            None => "the end".into(),
            Some(c) => format!("{:?}", c as char),
        }
    }

    /// A quoted string, `'...'` or `"..."`, without escapes.
    fn string(&mut self) -> Result<String, String> {
        let quote = match self.peek() {
            Some(q @ (b'\'' | b'"')) => q,
            _ => {
                return Err(format!(
                    "expected a quoted string at byte {}, found {}",
                    self.at,
                    self.found()
                ));
            }
        };
        self.at += 1;
        let start = self.at;
        while let Some(c) = self.peek() {
            if c == b'\\' {
                return Err(format!("an escape in a string at byte {}", self.at));
            }
            if c == quote {
                let s = String::from_utf8_lossy(&self.s[start..self.at]).into_owned();
                self.at += 1;
                return Ok(s);
            }
            self.at += 1;
        }
        Err("a string without its closing quote".into())
    }

    fn value(&mut self) -> Result<Value, String> {
        match self.peek() {
            Some(b'\'' | b'"') => Ok(Value::Str(self.string()?)),
            Some(b'(') => {
                self.at += 1;
                let mut items = Vec::new();
                loop {
                    self.space();
                    if self.eat(b')') {
                        break;
                    }
                    items.push(self.integer()?);
                    self.space();
                    if self.eat(b',') {
                        continue;
                    }
                    self.expect(b')')?;
                    break;
                }
                Ok(Value::Tuple(items))
            }
            Some(b'[') => {
                // A structured dtype's list of fields: kept whole, brackets balanced.
                let start = self.at;
                let mut depth = 0usize;
                while let Some(c) = self.peek() {
                    self.at += 1;
                    match c {
                        b'[' => depth += 1,
                        b']' => {
                            depth -= 1;
                            if depth == 0 {
                                let text = String::from_utf8_lossy(&self.s[start..self.at]);
                                return Ok(Value::List(text.into_owned()));
                            }
                        }
                        _ => {}
                    }
                }
                Err("a list without its closing bracket".into())
            }
            _ if self.s[self.at..].starts_with(b"True") => {
                self.at += 4;
                Ok(Value::Bool(true))
            }
            _ if self.s[self.at..].starts_with(b"False") => {
                self.at += 5;
                Ok(Value::Bool(false))
            }
            _ => Err(format!(
                "expected a value at byte {}, found {}",
                self.at,
                self.found()
            )),
        }
    }

    /// A non-negative integer, with Python 2's `L` suffix allowed.
    fn integer(&mut self) -> Result<u64, String> {
        let start = self.at;
        while matches!(self.peek(), Some(b'0'..=b'9')) {
            self.at += 1;
        }
        if start == self.at {
            return Err(format!(
                "expected a non-negative integer at byte {}, found {}",
                self.at,
                self.found()
            ));
        }
        let digits = std::str::from_utf8(&self.s[start..self.at]).expect("ASCII digits");
        let n = digits
            .parse::<u64>()
            .map_err(|_| format!("the dimension {digits} is too large"))?;
        self.eat(b'L');
        Ok(n)
    }
}

/// The preamble of a version-1.0 file holding a C-ordered little-endian float32 array of
/// `shape`, its header padded with spaces so that the data starts at a multiple of 64 bytes.
pub(crate) fn f4_preamble(shape: &[u64]) -> Vec<u8> {
    let dict = format!(
        "{{'descr': '<f4', 'fortran_order': False, 'shape': {}, }}",
        shape_text(shape)
    );
    // Magic, version and length take 10 bytes; the header ends in '\n'.
    let unpadded = 10 + dict.len() + 1;
    let padding = unpadded.next_multiple_of(64) - unpadded;
    let header = format!("{dict}{}\n", " ".repeat(padding));
    let mut out = Vec::with_capacity(10 + header.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&[1, 0]);
    let len = u16::try_from(header.len()).expect("a shape of a few numbers fits version 1.0");
    out.extend_from_slice(&len.to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(dict: &str) -> Vec<u8> {
        let mut b = MAGIC.to_vec();
        b.extend_from_slice(&[1, 0]);
        b.extend_from_slice(&(dict.len() as u16).to_le_bytes());
        b.extend_from_slice(dict.as_bytes());
        b
    }

    #[test]
    fn the_written_preamble_reads_back_and_aligns_the_data() {
        for shape in [vec![5], vec![7, 2], vec![123_456_789, 12]] {
            let pre = f4_preamble(&shape);
            assert_eq!(pre.len() % 64, 0);
            assert_eq!(pre.last(), Some(&b'\n'));
            let h = read_header(&mut pre.as_slice()).unwrap();
            assert_eq!((h.dtype, &h.shape), (Dtype::F4, &shape));
            assert_eq!(h.data_offset, pre.len() as u64);
        }
    }

    #[test]
    fn headers_numpy_writes_are_read() {
        let h = read_header(
            &mut header("{'descr': '<f8', 'fortran_order': False, 'shape': (3, 6), }      \n")
                .as_slice(),
        )
        .unwrap();
        assert_eq!((h.dtype, h.shape), (Dtype::F8, vec![3, 6]));
        // Version 2.0 (a u32 length), double quotes, Python 2's long integers, no trailing comma.
        let dict = "{\"shape\": (4L, 3L), \"fortran_order\": False, \"descr\": \"<f4\"}\n";
        let mut b = MAGIC.to_vec();
        b.extend_from_slice(&[2, 0]);
        b.extend_from_slice(&(dict.len() as u32).to_le_bytes());
        b.extend_from_slice(dict.as_bytes());
        let h = read_header(&mut b.as_slice()).unwrap();
        assert_eq!((h.dtype, h.shape), (Dtype::F4, vec![4, 3]));
    }

    #[test]
    fn bad_headers_say_what_is_wrong() {
        let bad = |bytes: &[u8], want: &str| {
            let e = read_header(&mut &bytes[..]).unwrap_err();
            assert!(e.contains(want), "{want:?} in {e:?}");
        };
        bad(b"", "empty");
        bad(b"PK\x03\x04zip", "magic");
        bad(b"\x93NUMPY\x04\x00", "version 4.0");
        bad(b"\x93NUMPY\x01\x00\x40", "truncated");
        bad(
            &header("{'descr': '<f8', 'fortran_order': False, 'sha"),
            "bad header",
        );
        bad(
            &header("{'descr': '<i4', 'fortran_order': False, 'shape': (3, 6), }\n"),
            "'<i4'",
        );
        bad(
            &header("{'descr': '>f8', 'fortran_order': False, 'shape': (3, 6), }\n"),
            "big-endian",
        );
        bad(
            &header("{'descr': [('x', '<f8')], 'fortran_order': False, 'shape': (3,), }\n"),
            "structured",
        );
        bad(
            &header("{'descr': '<f8', 'fortran_order': True, 'shape': (3, 6), }\n"),
            "Fortran",
        );
        bad(
            &header("{'descr': '<f8', 'fortran_order': False, 'shape': (-3, 6), }\n"),
            "non-negative integer",
        );
        bad(
            &header(
                "{'descr': '<f8', 'fortran_order': False, 'shape': (99999999999999999999, 6), }\n",
            ),
            "too large",
        );
        bad(
            &header("{'descr': '<f8', 'fortran_order': False, 'shape': (3, 6), 'x': 1}\n"),
            "'x'",
        );
        bad(
            &header("{'descr': '<f8', 'shape': (3, 6)}\n"),
            "fortran_order",
        );
        let mut long = MAGIC.to_vec();
        long.extend_from_slice(&[2, 0]);
        long.extend_from_slice(&u32::MAX.to_le_bytes());
        bad(&long, "more than");
    }
}
