//! Errors of the physics layer. Every message names the quantity, its value and the rule.

/// Invalid input to the physics layer (body, initial state, settings).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// A parameter breaks a physical rule.
    #[error("{quantity} = {value}: {rule}")]
    Invalid {
        /// The quantity's name as the user wrote it (e.g. `body.mass`).
        quantity: String,
        /// Its offending value, formatted.
        value: String,
        /// The rule it breaks.
        rule: String,
    },
}

impl ModelError {
    /// Shorthand for [`ModelError::Invalid`].
    pub fn invalid(quantity: impl Into<String>, value: impl std::fmt::Display, rule: impl Into<String>) -> Self {
        ModelError::Invalid { quantity: quantity.into(), value: value.to_string(), rule: rule.into() }
    }
}
