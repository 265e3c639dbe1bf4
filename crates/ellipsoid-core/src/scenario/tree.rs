//! The spanned document tree: every key and value with where it came from (a byte
//! span of the file or a `--set` override), and the overrides applied to it.

use super::*;

/// Where a key or value came from.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Origin {
    /// A byte range of the file.
    File(Range<usize>),
    /// A `--set key=value` override (its text).
    Set(String),
}

#[derive(Debug, Clone, PartialEq)]
pub(super) enum Value {
    Str(String),
    Int(i64),
    Float(f64),
    Bool(bool),
    Datetime(String),
    Array(Vec<Node>),
    Table(Vec<Entry>),
}

#[derive(Debug, Clone, PartialEq)]
pub(super) struct Node {
    pub(super) value: Value,
    pub(super) origin: Origin,
}

#[derive(Debug, Clone, PartialEq)]
pub(super) struct Entry {
    pub(super) key: String,
    pub(super) key_origin: Origin,
    pub(super) node: Node,
}

impl Node {
    pub(super) fn from_table(table: DeTable<'_>, origin: Origin) -> Node {
        let mut entries: Vec<Entry> = table
            .into_iter()
            .map(|(k, v)| {
                let key_origin = Origin::File(k.span());
                Entry {
                    key: k.into_inner().into_owned(),
                    key_origin,
                    node: Node::from_value(v.span(), v.into_inner(), None),
                }
            })
            .collect();
        // In file order, so that the first error reported is the first in the file.
        entries.sort_by_key(|e| match &e.key_origin {
            Origin::File(r) => r.start,
            Origin::Set(_) => usize::MAX,
        });
        Node {
            value: Value::Table(entries),
            origin,
        }
    }

    /// Converts a parsed value; with `set`, every node's origin is that override.
    pub(super) fn from_value(span: Range<usize>, value: DeValue<'_>, set: Option<&str>) -> Node {
        let origin = match set {
            Some(s) => Origin::Set(s.to_owned()),
            None => Origin::File(span),
        };
        let value = match value {
            DeValue::String(s) => Value::Str(s.into_owned()),
            DeValue::Integer(i) => match i64::from_str_radix(i.as_str(), i.radix()) {
                Ok(v) => Value::Int(v),
                // Beyond i64: no key of the format needs it; keep it as a number (its
                // nearest float, or ±inf), which the range checks then reject.
                Err(_) => Value::Float(
                    if i.radix() == 10 {
                        i.as_str().parse().ok()
                    } else {
                        None
                    }
                    .unwrap_or(if i.as_str().starts_with('-') {
                        f64::NEG_INFINITY
                    } else {
                        f64::INFINITY
                    }),
                ),
            },
            DeValue::Float(f) => Value::Float(f.as_str().parse().unwrap_or(f64::NAN)),
            DeValue::Boolean(b) => Value::Bool(b),
            DeValue::Datetime(d) => Value::Datetime(d.to_string()),
            DeValue::Array(a) => Value::Array(
                a.into_iter()
                    .map(|e| Node::from_value(e.span(), e.into_inner(), set))
                    .collect(),
            ),
            DeValue::Table(t) => {
                let mut node = Node::from_table(t, origin.clone());
                if let (Some(s), Value::Table(entries)) = (set, &mut node.value) {
                    for e in entries.iter_mut() {
                        e.key_origin = Origin::Set(s.to_owned());
                        set_origin(&mut e.node, s);
                    }
                }
                return node;
            }
        };
        Node { value, origin }
    }

    pub(super) fn entries(&self) -> &[Entry] {
        match &self.value {
            Value::Table(e) => e,
            _ => &[],
        }
    }

    /// The origin of the key at `path` (dotted segments), if present.
    pub(super) fn find(&self, path: &[String]) -> Option<Origin> {
        let (first, rest) = path.split_first()?;
        let entry = self.entries().iter().find(|e| &e.key == first)?;
        if rest.is_empty() {
            Some(entry.key_origin.clone())
        } else {
            entry.node.find(rest)
        }
    }

    pub(super) fn as_f64(&self) -> Option<f64> {
        match self.value {
            Value::Int(i) => Some(i as f64),
            Value::Float(f) => Some(f),
            _ => None,
        }
    }

    pub(super) fn type_name(&self) -> &'static str {
        match self.value {
            Value::Str(_) => "a string",
            Value::Int(_) => "an integer",
            Value::Float(_) => "a float",
            Value::Bool(_) => "a boolean",
            Value::Datetime(_) => "a date-time",
            Value::Array(_) => "an array",
            Value::Table(_) => "a table",
        }
    }

    /// The value in TOML syntax (for values that did not come from the file).
    pub(super) fn render(&self) -> String {
        match &self.value {
            Value::Str(s) => format!("{s:?}"),
            Value::Int(i) => i.to_string(),
            Value::Float(f) => crate::error::number(*f),
            Value::Bool(b) => b.to_string(),
            Value::Datetime(d) => d.clone(),
            Value::Array(a) => format!(
                "[{}]",
                a.iter().map(Node::render).collect::<Vec<_>>().join(", ")
            ),
            Value::Table(e) => format!(
                "{{ {} }}",
                e.iter()
                    .map(|e| format!("{} = {}", e.key, e.node.render()))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }
    }
}

pub(super) fn set_origin(node: &mut Node, set: &str) {
    node.origin = Origin::Set(set.to_owned());
    match &mut node.value {
        Value::Array(a) => a.iter_mut().for_each(|n| set_origin(n, set)),
        Value::Table(t) => t.iter_mut().for_each(|e| {
            e.key_origin = Origin::Set(set.to_owned());
            set_origin(&mut e.node, set);
        }),
        _ => {}
    }
}

/// Applies one `key.path=value` override to the document.
pub(super) fn apply_override(ctx: &Ctx<'_>, tree: &mut Node, set: &str) -> Result<()> {
    let location = Location {
        source: ctx.source.to_owned(),
        line: None,
        column: None,
        set: Some(set.to_owned()),
    };
    let fail = |key: Option<String>, value: Option<String>, rule: String| ScenarioError {
        kind: ErrorKind::Override,
        location: location.clone(),
        key,
        value,
        rule,
    };
    let Some((key, raw)) = set.split_once('=') else {
        return Err(fail(
            None,
            None,
            "an override must have the form key=value, e.g. --set output.t_end=1.0".into(),
        ));
    };
    let path: Vec<&str> = key.trim().split('.').map(str::trim).collect();
    if path.iter().any(|s| {
        s.is_empty()
            || !s
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    }) {
        return Err(fail(
            Some(key.trim().to_owned()),
            None,
            "the key must be a dotted path of names such as body.mass".into(),
        ));
    }
    let raw = raw.trim();
    let node = match DeValue::parse(raw) {
        Ok(v) => Node::from_value(v.span(), v.into_inner(), Some(set)),
        // A bare word (`--set contact.model=rolling`) is a string.
        Err(_)
            if !raw.is_empty()
                && raw
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || "_-+.".contains(c)) =>
        {
            Node {
                value: Value::Str(raw.to_owned()),
                origin: Origin::Set(set.to_owned()),
            }
        }
        Err(e) => {
            return Err(fail(
                Some(key.trim().to_owned()),
                Some(raw.to_owned()),
                format!("not a TOML value: {}", e.message()),
            ));
        }
    };
    let mut table = tree;
    for (i, seg) in path.iter().enumerate() {
        let Value::Table(entries) = &mut table.value else {
            return Err(fail(
                Some(path[..i].join(".")),
                None,
                format!("is not a table, so {} cannot be set", path.join(".")),
            ));
        };
        let pos = match entries.iter().position(|e| e.key == *seg) {
            Some(p) => p,
            None => {
                let empty = Node {
                    value: Value::Table(Vec::new()),
                    origin: Origin::Set(set.to_owned()),
                };
                entries.push(Entry {
                    key: (*seg).to_owned(),
                    key_origin: Origin::Set(set.to_owned()),
                    node: empty,
                });
                entries.len() - 1
            }
        };
        let entry = &mut entries[pos];
        if i + 1 == path.len() {
            entry.key_origin = Origin::Set(set.to_owned());
            entry.node = node;
            return Ok(());
        }
        table = &mut entry.node;
    }
    unreachable!("the loop returns at the last segment of a non-empty path")
}
