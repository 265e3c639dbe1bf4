//! Errors of the physics layer. Every message names the quantity, its value and the rule.

use crate::integrate::IntegrateError;

use nalgebra::{Matrix3, Vector3};
use std::fmt;

/// The rule of [`ModelError::Solver`].
const SOLVER_RULE: &str = "the integrator rejected these settings";

/// Invalid input to the physics layer (body, initial state, settings).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// A parameter breaks a physical rule: `field = value: rule`, formatted only here
    /// (and by [`ModelError::value`] for the scenario layer's messages).
    #[error("{field} = {value}: {rule}")]
    Invalid {
        /// What is at fault, and where in the scenario.
        field: Field,
        /// Its offending value, typed.
        value: Value,
        /// The rule it breaks.
        rule: String,
    },
    /// The integrator rejected the solver settings (its error kept whole), placed at the
    /// `solver` table: `solver = <the integrator's message>: <rule>`.
    #[error("solver = {0}: {SOLVER_RULE}")]
    Solver(IntegrateError),
}

/// The quantity at fault in a [`ModelError::Invalid`] and its place in the scenario.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Field {
    /// A scenario key as a dotted path (`body.mass`): named and placed by it.
    Key(String),
    /// A quantity derived from several keys (`initial normal force N`), placed at the
    /// table they belong to (`initial`).
    Derived {
        /// The table the error is placed at.
        table: &'static str,
        /// The quantity's name in the message.
        quantity: &'static str,
    },
}

impl fmt::Display for Field {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Field::Key(key) => f.write_str(key),
            Field::Derived { quantity, .. } => f.write_str(quantity),
        }
    }
}

/// The offending value of a [`ModelError::Invalid`], kept typed; its `Display` is the one
/// place it is written out.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A number printed by [`number`], followed by its unit unless that is empty:
    /// `0.3`, `-0.84 N`.
    Number(f64, &'static str),
    /// A count followed by what is counted unless that is empty: `3 entries`, `7`.
    Count(u64, &'static str),
    /// Several numbers (a vector, a list of values), in `brackets`, each printed by
    /// `digits`: `[0, 1e-20, 2]`, `(0.5, 0, 1)`.
    Numbers {
        /// The numbers.
        values: Vec<f64>,
        /// How each is printed.
        digits: Digits,
        /// What encloses them.
        brackets: Brackets,
    },
    /// A 3 × 3 matrix as a list of its rows: `[[a, b, c], [d, e, f], [g, h, i]]` (boxed,
    /// so that errors stay small).
    Matrix(Box<Matrix3<f64>>, Digits),
    /// A state (ζ, ω) of the reduced steady dynamics, as nalgebra prints the transposes.
    State(Box<[Vector3<f64>; 2]>),
    /// A name from the scenario in quotes, escaped as Rust's `{:?}` does: `"stem"`.
    Name(String),
    /// A choice among fixed names (a contact model, a family), in quotes as given:
    /// `"viscous"`.
    Choice(String),
    /// A word or phrase, as is: `present`, `true`, a column's name.
    Text(String),
    /// A named quantity derived from the inputs with its unit (or what it is measured
    /// against): `the normal force N = NaN N`, `|f(x0)| = 0.02 of the field's scale`.
    Named {
        /// The quantity's name.
        name: &'static str,
        /// Its value, printed by [`number`].
        value: f64,
        /// Its unit.
        unit: &'static str,
    },
    /// Two values in the wrong order: `later after earlier`.
    After {
        /// The value that comes second and should be larger.
        later: f64,
        /// The value before it.
        earlier: f64,
    },
}

/// How a [`Value`] prints each of several numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Digits {
    /// By [`number`]: plain within 1e-4 ≤ |x| < 1e15, scientific outside.
    Short,
    /// As `{}` prints an `f64`: every digit, never scientific.
    Plain,
    /// As `{:?}` prints an `f64`: `1.0`, `NaN`.
    Debug,
    /// With six decimals (`{:.6}`).
    Fixed6,
}

/// What encloses the numbers of a [`Value::Numbers`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Brackets {
    /// `[a, b]`.
    Square,
    /// `(a, b)`.
    Round,
    /// `a, b` (one number printed alone).
    None,
}

impl Digits {
    fn write(self, f: &mut fmt::Formatter<'_>, x: f64) -> fmt::Result {
        match self {
            Digits::Short => f.write_str(&number(x)),
            Digits::Plain => write!(f, "{x}"),
            Digits::Debug => write!(f, "{x:?}"),
            Digits::Fixed6 => write!(f, "{x:.6}"),
        }
    }

    fn list(self, f: &mut fmt::Formatter<'_>, values: &[f64], brackets: Brackets) -> fmt::Result {
        let (open, close) = match brackets {
            Brackets::Square => ("[", "]"),
            Brackets::Round => ("(", ")"),
            Brackets::None => ("", ""),
        };
        f.write_str(open)?;
        for (i, &x) in values.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            self.write(f, x)?;
        }
        f.write_str(close)
    }
}

impl Value {
    /// A vector of three numbers printed by [`number`] in square brackets.
    pub fn vector(v: &Vector3<f64>) -> Self {
        Value::Numbers {
            values: v.as_slice().to_vec(),
            digits: Digits::Short,
            brackets: Brackets::Square,
        }
    }
}

impl From<f64> for Value {
    fn from(x: f64) -> Self {
        Value::Number(x, "")
    }
}

impl From<u64> for Value {
    fn from(n: u64) -> Self {
        Value::Count(n, "")
    }
}

impl From<usize> for Value {
    fn from(n: usize) -> Self {
        Value::Count(n as u64, "")
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Number(x, "") => f.write_str(&number(*x)),
            Value::Number(x, unit) => write!(f, "{} {unit}", number(*x)),
            Value::Count(n, "") => write!(f, "{n}"),
            Value::Count(n, what) => write!(f, "{n} {what}"),
            Value::Numbers {
                values,
                digits,
                brackets,
            } => digits.list(f, values, *brackets),
            Value::Matrix(m, digits) => {
                f.write_str("[")?;
                for i in 0..3 {
                    if i > 0 {
                        f.write_str(", ")?;
                    }
                    let row = [m[(i, 0)], m[(i, 1)], m[(i, 2)]];
                    digits.list(f, &row, Brackets::Square)?;
                }
                f.write_str("]")
            }
            Value::State(state) => {
                let [zeta, omega] = &**state;
                write!(f, "({}, {})", zeta.transpose(), omega.transpose())
            }
            Value::Name(name) => write!(f, "{name:?}"),
            Value::Choice(name) => write!(f, "\"{name}\""),
            Value::Text(text) => f.write_str(text),
            Value::Named { name, value, unit } => write!(f, "{name} = {} {unit}", number(*value)),
            Value::After { later, earlier } => {
                write!(f, "{} after {}", number(*later), number(*earlier))
            }
        }
    }
}

impl ModelError {
    /// A scenario key's value breaks `rule`; `key` is its dotted path.
    pub fn invalid(
        key: impl Into<String>,
        value: impl Into<Value>,
        rule: impl Into<String>,
    ) -> Self {
        ModelError::Invalid {
            field: Field::Key(key.into()),
            value: value.into(),
            rule: rule.into(),
        }
    }

    /// A quantity derived from the keys of `table` (e.g. the initial normal force from
    /// `[initial]` and `[body]`) breaks `rule`.
    pub fn derived(
        table: &'static str,
        quantity: &'static str,
        value: impl Into<Value>,
        rule: impl Into<String>,
    ) -> Self {
        ModelError::Invalid {
            field: Field::Derived { table, quantity },
            value: value.into(),
            rule: rule.into(),
        }
    }

    /// The scenario key at fault as a dotted path, or the table of a derived quantity.
    pub fn key(&self) -> &str {
        match self {
            ModelError::Invalid {
                field: Field::Key(key),
                ..
            } => key,
            ModelError::Invalid {
                field: Field::Derived { table, .. },
                ..
            } => table,
            ModelError::Solver(_) => "solver",
        }
    }

    /// The quantity's name in the message.
    pub fn quantity(&self) -> &str {
        match self {
            ModelError::Invalid {
                field: Field::Key(key),
                ..
            } => key,
            ModelError::Invalid {
                field: Field::Derived { quantity, .. },
                ..
            } => quantity,
            ModelError::Solver(_) => "solver",
        }
    }

    /// The offending value written out, as messages show it (the integrator's message
    /// for [`ModelError::Solver`]).
    pub fn value(&self) -> String {
        match self {
            ModelError::Invalid { value, .. } => value.to_string(),
            ModelError::Solver(e) => e.to_string(),
        }
    }

    /// The rule broken.
    pub fn rule(&self) -> &str {
        match self {
            ModelError::Invalid { rule, .. } => rule,
            ModelError::Solver(_) => SOLVER_RULE,
        }
    }
}

/// A number as messages print it: plain for 1e-4 ≤ |x| < 1e15 (and 0), otherwise in
/// scientific notation, so 1e-300 is not spelled out in 300 digits; NaN and ±inf as such.
pub fn number(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || !x.is_finite() || (1e-4..1e15).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// `text` with every decimal number longer than 24 characters reprinted by [`number`]
/// (a subnormal 5e-324 formatted with `{}` is 330 characters); shorter ones, and
/// anything that is not a number, unchanged. For messages built by code that formats
/// floats with `{}`.
pub fn shorten_numbers(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(start) = rest.find(|c: char| c.is_ascii_digit()) {
        // Include a sign right before the digits.
        let start = if start > 0 && rest.as_bytes()[start - 1] == b'-' {
            start - 1
        } else {
            start
        };
        out.push_str(&rest[..start]);
        let tail = &rest[start..];
        let mut end = tail
            .find(|c: char| !(c.is_ascii_digit() || "+-.eE".contains(c)))
            .unwrap_or(tail.len());
        // Trailing punctuation is not part of the number ("= 1.5." ends a sentence).
        while end > 1 && !tail.as_bytes()[end - 1].is_ascii_digit() {
            end -= 1;
        }
        let token = &tail[..end];
        match token.parse::<f64>() {
            Ok(x) if token.len() > 24 => out.push_str(&number(x)),
            _ => out.push_str(token),
        }
        rest = &tail[end..];
    }
    out.push_str(rest);
    out
}

/// The message of a panic's payload (from `std::panic::catch_unwind`, a thread's `join` or
/// a panic hook): its `&str` or `String`, else "a panic without a message".
pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without a message".into())
}

#[cfg(test)]
mod tests {
    use super::{Brackets, Digits, Field, ModelError, Value, number, shorten_numbers};
    use nalgebra::{Matrix3, Vector3};

    #[test]
    fn a_typed_value_is_written_as_messages_always_wrote_it() {
        let list = |digits, brackets| Value::Numbers {
            values: vec![1.0, f64::NAN, 1e-20],
            digits,
            brackets,
        };
        let m = Matrix3::new(1.0, 0.5, 0.0, 0.5, 1e-6, 0.0, 0.0, 0.0, 2.0);
        for (value, text) in [
            (Value::from(0.3), "0.3"),
            (Value::Number(-0.84, "N"), "-0.84 N"),
            (Value::from(7usize), "7"),
            (Value::Count(3, "entries"), "3 entries"),
            (list(Digits::Short, Brackets::Square), "[1, NaN, 1e-20]"),
            (
                list(Digits::Plain, Brackets::Round),
                "(1, NaN, 0.00000000000000000001)",
            ),
            (list(Digits::Debug, Brackets::Square), "[1.0, NaN, 1e-20]"),
            (
                list(Digits::Fixed6, Brackets::Round),
                "(1.000000, NaN, 0.000000)",
            ),
            (
                Value::Numbers {
                    values: vec![1e20],
                    digits: Digits::Plain,
                    brackets: Brackets::None,
                },
                "100000000000000000000",
            ),
            (
                Value::Matrix(Box::new(m), Digits::Short),
                "[[1, 0.5, 0], [0.5, 1e-6, 0], [0, 0, 2]]",
            ),
            (
                Value::Matrix(Box::new(m), Digits::Plain),
                "[[1, 0.5, 0], [0.5, 0.000001, 0], [0, 0, 2]]",
            ),
            (Value::Name("a\"b".into()), "\"a\\\"b\""),
            (Value::Choice("viscous".into()), "\"viscous\""),
            (Value::Text("present".into()), "present"),
            (
                Value::Named {
                    name: "|f(x0)|",
                    value: 2e-5,
                    unit: "of the field's scale",
                },
                "|f(x0)| = 2e-5 of the field's scale",
            ),
            (
                Value::After {
                    later: 0.25,
                    earlier: 0.5,
                },
                "0.25 after 0.5",
            ),
        ] {
            assert_eq!(value.to_string(), text);
        }
        let (zeta, omega) = (Vector3::new(0.0, 0.0, 1.0), Vector3::new(0.0, 0.0, 5.0));
        assert_eq!(
            Value::State(Box::new([zeta, omega])).to_string(),
            format!("({}, {})", zeta.transpose(), omega.transpose())
        );
    }

    #[test]
    fn an_error_names_its_field_and_is_placed_at_its_key_or_table() {
        let e = ModelError::invalid("body.mass", 0.0, "the mass must be positive");
        assert_eq!(e.to_string(), "body.mass = 0: the mass must be positive");
        assert_eq!((e.key(), e.quantity()), ("body.mass", "body.mass"));
        let e = ModelError::derived(
            "initial",
            "initial normal force N",
            Value::Number(-1.5, "N"),
            "the plane must push",
        );
        assert_eq!(
            e.to_string(),
            "initial normal force N = -1.5 N: the plane must push"
        );
        assert_eq!(
            (e.key(), e.quantity()),
            ("initial", "initial normal force N")
        );
        assert!(matches!(
            e,
            ModelError::Invalid {
                field: Field::Derived { table: "initial", .. },
                value: Value::Number(n, "N"),
                ..
            } if n == -1.5
        ));
    }

    #[test]
    fn long_numbers_in_text_are_reprinted_short() {
        let subnormal = format!("{}", 5e-324);
        assert!(subnormal.len() > 300);
        assert_eq!(
            shorten_numbers(&format!("body.a = {subnormal}: a rule")),
            "body.a = 5e-324: a rule"
        );
        assert_eq!(
            shorten_numbers(&format!("[{subnormal}, -{subnormal}]")),
            "[5e-324, -5e-324]"
        );
        let big = format!("{}", 1e300);
        assert_eq!(shorten_numbers(&format!("x = {big}.")), "x = 1e300.");
        // Short numbers and non-numbers are kept as written.
        for keep in [
            "g^T A^-2 g = 1.306122 must be < 1",
            "10·EPS ≈ 2.2e-15 and 1e-2",
            "N = -0.84 N",
            "dop853, rk4 step 1e-4",
            "2026-12-01",
        ] {
            assert_eq!(shorten_numbers(keep), keep);
        }
    }

    #[test]
    fn numbers_print_short_at_any_magnitude() {
        assert_eq!(number(0.0), "0");
        assert_eq!(number(0.05), "0.05");
        assert_eq!(number(-2.5e6), "-2500000");
        assert_eq!(number(1e-300), "1e-300");
        assert_eq!(number(-3.2e20), "-3.2e20");
        assert_eq!(number(f64::INFINITY), "inf");
        assert_eq!(number(f64::NAN), "NaN");
    }
}
