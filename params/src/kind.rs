//! The kinds of the parameters' values ([`Kind`], with their ranges) and the values themselves
//! ([`Value`]): how each is read from TOML, shown, and checked against its range.

/// The kind of a parameter's value, with its range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// An integer in `min..=max`.
    Int {
        /// Smallest value.
        min: u32,
        /// Largest value.
        max: u32,
    },
    /// A number in `[min, max]`, or `(min, max]` when `above`; `max` may be infinite.
    Real {
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
        /// Whether `min` itself is excluded.
        above: bool,
    },
    /// `true` or `false`.
    Bool,
    /// One of these names.
    Choice(&'static [&'static str]),
}

/// A parameter's value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// Of [`Kind::Int`].
    Int(u32),
    /// Of [`Kind::Real`].
    Real(f64),
    /// Of [`Kind::Bool`].
    Bool(bool),
    /// Of [`Kind::Choice`]: one of its names.
    Choice(&'static str),
}

impl Value {
    pub(crate) fn int(self) -> u32 {
        match self {
            Value::Int(v) => v,
            v => panic!("{v:?} is not an integer"),
        }
    }

    pub(crate) fn real(self) -> f64 {
        match self {
            Value::Real(v) => v,
            v => panic!("{v:?} is not a number"),
        }
    }

    pub(crate) fn bool(self) -> bool {
        match self {
            Value::Bool(v) => v,
            v => panic!("{v:?} is not a boolean"),
        }
    }

    pub(crate) fn choice(self) -> &'static str {
        match self {
            Value::Choice(v) => v,
            v => panic!("{v:?} is not a name"),
        }
    }
}

impl std::fmt::Display for Value {
    /// As TOML writes it (names quoted, numbers with a decimal point).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Value::Int(v) => write!(f, "{v}"),
            Value::Real(v) => write!(f, "{v:?}"),
            Value::Bool(v) => write!(f, "{v}"),
            Value::Choice(v) => write!(f, "\"{v}\""),
        }
    }
}

fn number(v: f64) -> String {
    if v == v.trunc() && v.abs() < 1e15 {
        format!("{v:.0}")
    } else {
        format!("{v}")
    }
}

/// A value in a message: as [`number`], with an exponent when very large or small.
fn shown(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e15).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        number(v)
    }
}

impl Kind {
    /// A TOML value of this kind, if it is one (a number for a real may be written as an
    /// integer).
    pub fn from_toml(&self, value: &toml::Value) -> Option<Value> {
        match (self, value) {
            (Kind::Int { .. }, toml::Value::Integer(i)) => u32::try_from(*i).ok().map(Value::Int),
            (Kind::Real { .. }, toml::Value::Float(x)) => Some(Value::Real(*x)),
            (Kind::Real { .. }, toml::Value::Integer(i)) => Some(Value::Real(*i as f64)),
            (Kind::Bool, toml::Value::Boolean(b)) => Some(Value::Bool(*b)),
            (Kind::Choice(names), toml::Value::String(s)) => {
                names.iter().find(|n| *n == s).map(|n| Value::Choice(n))
            }
            _ => None,
        }
    }

    /// What a value of this kind is, for messages: "an integer", "a number", ...
    pub fn expected(&self) -> String {
        match self {
            Kind::Int { .. } => "an integer".to_string(),
            Kind::Real { .. } => "a number".to_string(),
            Kind::Bool => "true or false".to_string(),
            Kind::Choice(names) => {
                let quoted: Vec<String> = names.iter().map(|n| format!("\"{n}\"")).collect();
                match quoted.split_last() {
                    Some((last, rest)) if !rest.is_empty() => {
                        format!("{} or {last}", rest.join(", "))
                    }
                    _ => quoted.join(""),
                }
            }
        }
    }

    /// The range, as the docs and messages write it: `3..=5`, `[0, 0.5]`, `(0, 8]`, `> 0`;
    /// empty for booleans and names.
    pub fn range(&self) -> String {
        match *self {
            Kind::Int { min, max } => format!("{min}..={max}"),
            Kind::Real { min, max, above } if max.is_infinite() => {
                format!("{} {}", if above { ">" } else { ">=" }, number(min))
            }
            Kind::Real { min, max, above } => {
                format!(
                    "{}{}, {}]",
                    if above { "(" } else { "[" },
                    number(min),
                    number(max)
                )
            }
            Kind::Bool | Kind::Choice(_) => String::new(),
        }
    }

    /// Why `value` is outside the range, if it is.
    pub fn out_of_range(&self, value: Value) -> Option<String> {
        match (*self, value) {
            (Kind::Int { min, max }, Value::Int(v)) => {
                (!(min..=max).contains(&v)).then(|| format!("{v} is not in {}", self.range()))
            }
            (Kind::Real { min, max, above }, Value::Real(v)) => {
                let within = if max.is_infinite() { "" } else { "in " };
                let ok = |v: f64| (if above { v > min } else { v >= min }) && v <= max;
                // The back ends compute in 32-bit floats: the value must be one, and stay in
                // range once rounded to one.
                let single = v as f32 as f64;
                if !v.is_finite() {
                    Some(format!("{} is not finite", shown(v)))
                } else if v.abs() > f32::MAX as f64 {
                    Some(format!(
                        "{} does not fit in 32-bit floats (largest magnitude 3.4e38)",
                        shown(v)
                    ))
                } else if !ok(v) {
                    Some(format!("{} is not {within}{}", shown(v), self.range()))
                } else if !ok(single) {
                    Some(format!(
                        "{} is {} in 32-bit floats, which is not {within}{}",
                        shown(v),
                        shown(single),
                        self.range()
                    ))
                } else {
                    None
                }
            }
            _ => None,
        }
    }
}
