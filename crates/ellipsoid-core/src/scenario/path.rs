//! Key paths: the one grammar of the keys that `--set`, Python's `Scenario.replace` and
//! a study's axes name — dotted names, each optionally followed by `[i]` indexes
//! (`body.mass`, `body.inertia[0]`, `body.sphere[1].radius`, `observe[0].crosses`).

use std::fmt;

/// The rule of a key path, in messages.
pub const KEY_RULE: &str = "a key is a dotted path of scenario keys, each [A-Za-z0-9_-]+ and optionally followed by [i] to pick element i of an array (e.g. body.inertia[0], observe[0].crosses)";

/// Largest index a path may name (arrays of the format are far shorter).
pub const MAX_INDEX: usize = 999_999;

/// One segment of a key path.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Seg {
    /// A key of a table.
    Name(String),
    /// An element of an array.
    Index(usize),
}

/// A parsed key path: a name first, then names and indexes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct KeyPath {
    segs: Vec<Seg>,
}

/// Why a text is not a key path.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PathError {
    /// Not of the grammar ([`KEY_RULE`]).
    Syntax,
    /// An index beyond [`MAX_INDEX`].
    Index,
}

impl fmt::Display for PathError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PathError::Syntax => f.write_str(KEY_RULE),
            PathError::Index => write!(f, "{KEY_RULE}; an index is 0 to {MAX_INDEX}"),
        }
    }
}

/// Whether `name` is a key name of the grammar.
fn is_name(name: &str) -> bool {
    !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

impl KeyPath {
    /// Parses `text` (surrounding spaces of each segment allowed, as in `--set`).
    pub fn parse(text: &str) -> Result<KeyPath, PathError> {
        let mut segs = Vec::new();
        for part in text.trim().split('.') {
            let part = part.trim();
            let (name, mut rest) = part.split_at(part.find('[').unwrap_or(part.len()));
            if !is_name(name) {
                return Err(PathError::Syntax);
            }
            segs.push(Seg::Name(name.to_owned()));
            while !rest.is_empty() {
                let close = rest.find(']').ok_or(PathError::Syntax)?;
                let digits = &rest[1..close];
                if digits.is_empty() || !digits.chars().all(|c| c.is_ascii_digit()) {
                    return Err(PathError::Syntax);
                }
                let i: usize = digits
                    .parse()
                    .ok()
                    .filter(|i| *i <= MAX_INDEX)
                    .ok_or(PathError::Index)?;
                segs.push(Seg::Index(i));
                rest = &rest[close + 1..];
                if !rest.is_empty() && !rest.starts_with('[') {
                    return Err(PathError::Syntax);
                }
            }
        }
        Ok(KeyPath { segs })
    }

    /// Its segments, in order.
    pub fn segs(&self) -> &[Seg] {
        &self.segs
    }

    /// Whether an index appears in it.
    pub fn is_indexed(&self) -> bool {
        self.segs.iter().any(|s| matches!(s, Seg::Index(_)))
    }

    /// The path of the names before the first index (`body.inertia` for `body.inertia[0]`).
    pub fn head(&self) -> KeyPath {
        KeyPath {
            segs: self
                .segs
                .iter()
                .take_while(|s| matches!(s, Seg::Name(_)))
                .cloned()
                .collect(),
        }
    }

    /// The first `n` segments, written as a path.
    pub fn prefix(&self, n: usize) -> String {
        write_segs(&self.segs[..n.min(self.segs.len())])
    }
}

/// Segments written as a path: `a.b[0].c`.
fn write_segs(segs: &[Seg]) -> String {
    let mut out = String::new();
    for s in segs {
        match s {
            Seg::Name(n) => {
                if !out.is_empty() {
                    out.push('.');
                }
                out.push_str(n);
            }
            Seg::Index(i) => out.push_str(&format!("[{i}]")),
        }
    }
    out
}

impl fmt::Display for KeyPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&write_segs(&self.segs))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_of_names_and_indexes() {
        let p = KeyPath::parse("body.sphere[1].radius").unwrap();
        assert_eq!(
            p.segs(),
            [
                Seg::Name("body".into()),
                Seg::Name("sphere".into()),
                Seg::Index(1),
                Seg::Name("radius".into())
            ]
        );
        assert!(p.is_indexed());
        assert_eq!(p.head().to_string(), "body.sphere");
        assert_eq!(p.to_string(), "body.sphere[1].radius");
        assert_eq!(p.prefix(3), "body.sphere[1]");
        let q = KeyPath::parse(" body . mass ").unwrap();
        assert_eq!(q.to_string(), "body.mass");
        assert!(!q.is_indexed());
        assert_eq!(KeyPath::parse("a[0][2]").unwrap().to_string(), "a[0][2]");
        for bad in [
            "", "a..b", "a.", "[0]", "a[", "a[]", "a[x]", "a[-1]", "a[0]b", "a b", "é",
        ] {
            assert_eq!(KeyPath::parse(bad), Err(PathError::Syntax), "{bad}");
        }
        assert_eq!(KeyPath::parse("a[1000000]"), Err(PathError::Index));
        assert_eq!(
            PathError::Index.to_string(),
            format!("{KEY_RULE}; an index is 0 to 999999")
        );
    }
}
