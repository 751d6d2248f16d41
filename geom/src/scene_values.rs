//! The scene file's vectors and scales, read strictly: an array of exactly the documented length
//! of numbers that fit the GPU's `f32` (so that every back end sees the same scene), and a scale
//! that is one number or three. Errors say what was expected; the scene parser adds the file and
//! line.

use serde::de::{self, Deserializer, SeqAccess, Visitor};

/// Largest magnitude of a scene coordinate or parameter: `f32`'s largest finite value, as the GPU
/// stores positions in `f32`.
pub const MAX_MAGNITUDE: f64 = f32::MAX as f64;

/// A number that fits `f32`, as an `f64`, or why not.
fn fits(x: f64) -> Result<f64, String> {
    if !x.is_finite() {
        Err(format!("{x} is not a finite number"))
    } else if x.abs() > MAX_MAGNITUDE {
        Err(format!(
            "{x:e} does not fit in 32-bit floats (largest magnitude {MAX_MAGNITUDE:.1e})"
        ))
    } else {
        Ok(x)
    }
}

/// An array of exactly `N` numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Vector<const N: usize>(pub [f64; N]);

struct VectorVisitor<const N: usize>;

impl<'de, const N: usize> Visitor<'de> for VectorVisitor<N> {
    type Value = Vector<N>;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "an array of exactly {N} numbers")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vector<N>, A::Error> {
        let mut out = [0.0; N];
        let mut n = 0;
        while let Some(x) = seq.next_element::<f64>()? {
            if n < N {
                out[n] = fits(x).map_err(de::Error::custom)?;
            }
            n += 1;
        }
        if n != N {
            return Err(de::Error::custom(format!(
                "expected an array of exactly {N} numbers, found {n}"
            )));
        }
        Ok(Vector(out))
    }
}

impl<'de, const N: usize> serde::Deserialize<'de> for Vector<N> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_seq(VectorVisitor::<N>)
    }
}

/// A mesh's scale: one number for all axes, or three.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Scale {
    /// The same on every axis.
    Uniform(f64),
    /// Per axis.
    PerAxis([f64; 3]),
}

struct ScaleVisitor;

impl<'de> Visitor<'de> for ScaleVisitor {
    type Value = Scale;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a number or an array of 3 numbers")
    }

    fn visit_f64<E: de::Error>(self, x: f64) -> Result<Scale, E> {
        fits(x).map(Scale::Uniform).map_err(E::custom)
    }

    fn visit_i64<E: de::Error>(self, x: i64) -> Result<Scale, E> {
        self.visit_f64(x as f64)
    }

    fn visit_u64<E: de::Error>(self, x: u64) -> Result<Scale, E> {
        self.visit_f64(x as f64)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Scale, A::Error> {
        VectorVisitor::<3>
            .visit_seq(seq)
            .map(|v| Scale::PerAxis(v.0))
    }
}

impl<'de> serde::Deserialize<'de> for Scale {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(ScaleVisitor)
    }
}

/// A table written once (`[camera]`): an array of tables (`[[camera]]`) is refused with a
/// message that says so, where serde would read its first table's keys as array items.
#[derive(Debug)]
pub(crate) struct Table<T>(pub T);

struct TableVisitor<T>(std::marker::PhantomData<T>);

impl<'de, T: serde::Deserialize<'de>> Visitor<'de> for TableVisitor<T> {
    type Value = Table<T>;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("one table, written `[name]` (not `[[name]]`, which makes an array of tables)")
    }

    fn visit_map<A: de::MapAccess<'de>>(self, map: A) -> Result<Table<T>, A::Error> {
        T::deserialize(de::value::MapAccessDeserializer::new(map)).map(Table)
    }
}

impl<'de, T: serde::Deserialize<'de>> serde::Deserialize<'de> for Table<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_map(TableVisitor(std::marker::PhantomData))
    }
}

/// A table written once (`[light]`) or an array of tables (`[[light]]`), each read as its own
/// type: the scene file's one light or its several named ones.
#[derive(Debug)]
pub(crate) enum OneOrMany<T, U> {
    /// `[name]`.
    One(T),
    /// `[[name]]`, every entry with its span.
    Many(Vec<toml::Spanned<Entry<U>>>),
}

/// One entry of an array of tables, refused with a message that says so where it is not a
/// table (`light = [3]`), where serde would name the Rust type it wanted.
#[derive(Debug)]
pub(crate) struct Entry<T>(pub T);

struct EntryVisitor<T>(std::marker::PhantomData<T>);

impl<'de, T: serde::Deserialize<'de>> Visitor<'de> for EntryVisitor<T> {
    type Value = Entry<T>;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a table, one entry of the array of tables `[[name]]`")
    }

    fn visit_map<A: de::MapAccess<'de>>(self, map: A) -> Result<Entry<T>, A::Error> {
        T::deserialize(de::value::MapAccessDeserializer::new(map)).map(Entry)
    }
}

impl<'de, T: serde::Deserialize<'de>> serde::Deserialize<'de> for Entry<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_map(EntryVisitor(std::marker::PhantomData))
    }
}

struct OneOrManyVisitor<T, U>(std::marker::PhantomData<(T, U)>);

impl<'de, T: serde::Deserialize<'de>, U: serde::Deserialize<'de>> Visitor<'de>
    for OneOrManyVisitor<T, U>
{
    type Value = OneOrMany<T, U>;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("one table, `[name]`, or an array of tables, `[[name]]`")
    }

    fn visit_map<A: de::MapAccess<'de>>(self, map: A) -> Result<OneOrMany<T, U>, A::Error> {
        T::deserialize(de::value::MapAccessDeserializer::new(map)).map(OneOrMany::One)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<OneOrMany<T, U>, A::Error> {
        let mut out = Vec::new();
        while let Some(x) = seq.next_element()? {
            out.push(x);
        }
        Ok(OneOrMany::Many(out))
    }
}

impl<'de, T: serde::Deserialize<'de>, U: serde::Deserialize<'de>> serde::Deserialize<'de>
    for OneOrMany<T, U>
{
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(OneOrManyVisitor(std::marker::PhantomData))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Deserialize, Debug)]
    struct T {
        v: Vector<3>,
        s: Option<Scale>,
    }

    fn parse(text: &str) -> Result<T, String> {
        toml::from_str::<T>(text).map_err(|e| e.message().to_string())
    }

    #[test]
    fn vectors_take_exactly_their_length_of_numbers_that_fit_f32() {
        assert_eq!(
            parse("v = [1, 2.5, -3]").unwrap().v,
            Vector([1.0, 2.5, -3.0])
        );
        let long = parse("v = [1, 2, 3, 4]").unwrap_err();
        assert!(long.contains("exactly 3 numbers, found 4"), "{long}");
        let short = parse("v = [1, 2]").unwrap_err();
        assert!(short.contains("exactly 3 numbers, found 2"), "{short}");
        let big = parse("v = [0, 1e39, 0]").unwrap_err();
        assert!(big.contains("does not fit in 32-bit floats"), "{big}");
        let nan = parse("v = [0, nan, 0]").unwrap_err();
        assert!(nan.contains("not a finite number"), "{nan}");
        let text = parse("v = [0, \"x\", 0]").unwrap_err();
        assert!(text.contains("f64") || text.contains("float"), "{text}");
    }

    #[test]
    fn tables_are_written_once() {
        #[derive(serde::Deserialize, Debug)]
        struct Doc {
            #[allow(dead_code)]
            camera: Table<T>,
        }
        assert!(toml::from_str::<Doc>("[camera]\nv = [1, 2, 3]").is_ok());
        let e = toml::from_str::<Doc>("[[camera]]\nv = [1, 2, 3]").unwrap_err();
        assert!(e.message().contains("not `[[name]]`"), "{}", e.message());
    }

    #[test]
    fn scales_are_one_number_or_three() {
        assert_eq!(
            parse("v = [0, 0, 0]\ns = 2").unwrap().s,
            Some(Scale::Uniform(2.0))
        );
        assert_eq!(
            parse("v = [0, 0, 0]\ns = [1, 2, 3]").unwrap().s,
            Some(Scale::PerAxis([1.0, 2.0, 3.0]))
        );
        let two = parse("v = [0, 0, 0]\ns = [1, 2]").unwrap_err();
        assert!(two.contains("exactly 3 numbers, found 2"), "{two}");
        let word = parse("v = [0, 0, 0]\ns = \"big\"").unwrap_err();
        assert!(word.contains("a number or an array of 3 numbers"), "{word}");
    }
}
