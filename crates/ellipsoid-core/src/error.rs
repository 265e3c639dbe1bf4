//! Errors of the physics layer. Every message names the quantity, its value and the rule.

use crate::integrate::IntegrateError;

/// The rule of [`ModelError::Solver`].
const SOLVER_RULE: &str = "the integrator rejected these settings";

/// Invalid input to the physics layer (body, initial state, settings).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// A parameter breaks a physical rule.
    #[error("{quantity} = {value}: {rule}")]
    Invalid {
        /// The scenario key at fault as a dotted path (`body.mass`), or for a quantity
        /// derived from several keys the table they belong to (`initial`).
        key: String,
        /// The quantity's name in the message: the key itself, or the derived quantity
        /// (`initial normal force N`).
        quantity: String,
        /// Its offending value, formatted.
        value: String,
        /// The rule it breaks.
        rule: String,
    },
    /// The integrator rejected the solver settings (its error kept whole), placed at the
    /// `solver` table: `solver = <the integrator's message>: <rule>`.
    #[error("solver = {0}: {SOLVER_RULE}")]
    Solver(IntegrateError),
}

impl ModelError {
    /// A scenario key's value breaks `rule`; `key` is its dotted path.
    pub fn invalid(
        key: impl Into<String>,
        value: impl std::fmt::Display,
        rule: impl Into<String>,
    ) -> Self {
        let key = key.into();
        ModelError::Invalid {
            quantity: key.clone(),
            key,
            value: value.to_string(),
            rule: rule.into(),
        }
    }

    /// A quantity derived from the keys of `table` (e.g. the initial normal force from
    /// `[initial]` and `[body]`) breaks `rule`.
    pub fn derived(
        table: &str,
        quantity: impl Into<String>,
        value: impl std::fmt::Display,
        rule: impl Into<String>,
    ) -> Self {
        ModelError::Invalid {
            key: table.to_owned(),
            quantity: quantity.into(),
            value: value.to_string(),
            rule: rule.into(),
        }
    }

    /// The scenario key at fault as a dotted path, or the table of a derived quantity.
    pub fn key(&self) -> &str {
        match self {
            ModelError::Invalid { key, .. } => key,
            ModelError::Solver(_) => "solver",
        }
    }

    /// The quantity's name in the message.
    pub fn quantity(&self) -> &str {
        match self {
            ModelError::Invalid { quantity, .. } => quantity,
            ModelError::Solver(_) => "solver",
        }
    }

    /// The offending value, formatted (the integrator's message for [`ModelError::Solver`]).
    pub fn value(&self) -> String {
        match self {
            ModelError::Invalid { value, .. } => value.clone(),
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
    use super::{number, shorten_numbers};

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
