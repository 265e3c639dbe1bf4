//! Errors of the physics layer. Every message names the quantity, its value and the rule.

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

#[cfg(test)]
mod tests {
    use super::number;

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
