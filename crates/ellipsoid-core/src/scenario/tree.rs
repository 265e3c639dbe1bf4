//! The spanned document tree: every key and value with where it came from (a byte
//! span of the file or a `--set` override), and the overrides applied to it.

use super::*;

/// Where a key or value came from.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Origin {
    /// A byte range of the file.
    File(Range<usize>),
    /// A `--set key=value` override (its text, shared by every node it made: a long
    /// array given by one override must not copy the override once per element).
    Set(Arc<str>),
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
    pub(super) fn from_value(
        span: Range<usize>,
        value: DeValue<'_>,
        set: Option<&Arc<str>>,
    ) -> Node {
        let origin = match set {
            Some(s) => Origin::Set(Arc::clone(s)),
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
                        e.key_origin = Origin::Set(Arc::clone(s));
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

    /// The origin of the key at `path` (dotted segments, each a key optionally followed by
    /// indices into arrays, `sphere[0]`), if present.
    pub(super) fn find(&self, path: &[String]) -> Option<Origin> {
        let (first, rest) = path.split_first()?;
        let (key, indices) = match first.split_once('[') {
            Some((key, tail)) => (key, Some(tail)),
            None => (first.as_str(), None),
        };
        let entry = self.entries().iter().find(|e| e.key == key)?;
        let mut node = &entry.node;
        if let Some(tail) = indices {
            for index in tail.split('[') {
                let k: usize = index.strip_suffix(']')?.parse().ok()?;
                match &node.value {
                    Value::Array(items) => node = items.get(k)?,
                    _ => return None,
                }
            }
        }
        match (rest.is_empty(), indices) {
            (true, None) => Some(entry.key_origin.clone()),
            (true, Some(_)) => Some(node.origin.clone()),
            (false, _) => node.find(rest),
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

pub(super) fn set_origin(node: &mut Node, set: &Arc<str>) {
    node.origin = Origin::Set(Arc::clone(set));
    match &mut node.value {
        Value::Array(a) => a.iter_mut().for_each(|n| set_origin(n, set)),
        Value::Table(t) => t.iter_mut().for_each(|e| {
            e.key_origin = Origin::Set(Arc::clone(set));
            set_origin(&mut e.node, set);
        }),
        _ => {}
    }
}

/// Why a value could not be set at a path: the segment at `depth` (0-based) does not
/// fit the document.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Blocked {
    /// A name where the document has no table.
    NotTable,
    /// An index where the document has no array.
    NotArray,
    /// An index beyond the array's `len` elements.
    OutOfRange { len: usize },
}

/// A value that cannot be set at a path: where it is blocked and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SetError {
    pub blocked: Blocked,
    /// The segment of the path that does not fit (0-based).
    pub depth: usize,
}

impl SetError {
    /// The error of the change `set` (`key=value`) of the scenario `source` that set
    /// `path`, as `--set` reports it: the key is the path up to the segment that does not fit.
    pub fn error(&self, source: &str, path: &KeyPath, set: &str) -> ScenarioError {
        override_error(
            source,
            set,
            Some(path.prefix(self.depth)),
            None,
            self.rule(path),
        )
    }

    /// The rule, as `--set` reports it.
    fn rule(&self, path: &KeyPath) -> String {
        let what = match self.blocked {
            Blocked::NotTable => "is not a table".to_owned(),
            Blocked::NotArray => "is not an array".to_owned(),
            Blocked::OutOfRange { len } => {
                let index = match path.segs().get(self.depth) {
                    Some(Seg::Index(i)) => *i,
                    _ => 0,
                };
                format!("has {len} element(s), no index {index}")
            }
        };
        format!("{what}, so {path} cannot be set")
    }
}

/// Sets `node` at `path` in `tree`, making tables (or, before an index, empty arrays) for
/// names that are absent; an index must name an element that exists. The keys and nodes
/// from the last name of the path down take `node`'s origin, so that a message about
/// the changed key or array names the change. A key set replaces its twins in the same
/// table ([`twins`]): `initial.theta=0.2` on a file with `theta_deg` changes θ.
pub(super) fn set_node(
    tree: &mut Node,
    path: &KeyPath,
    node: Node,
) -> std::result::Result<(), SetError> {
    let origin = node.origin.clone();
    let segs = path.segs();
    let last_name = segs
        .iter()
        .rposition(|s| matches!(s, Seg::Name(_)))
        .unwrap_or(0);
    let mut cur = tree;
    let mut node = Some(node);
    for (depth, seg) in segs.iter().enumerate() {
        let blocked = |blocked| SetError { blocked, depth };
        let last = depth + 1 == segs.len();
        let slot = match seg {
            Seg::Name(name) => {
                let Value::Table(entries) = &mut cur.value else {
                    return Err(blocked(Blocked::NotTable));
                };
                if last {
                    let twins = twins(name);
                    entries.retain(|e| !twins.contains(&e.key));
                }
                let pos = entries
                    .iter()
                    .position(|e| &e.key == name)
                    .unwrap_or_else(|| {
                        let empty = match segs.get(depth + 1) {
                            Some(Seg::Index(_)) => Value::Array(Vec::new()),
                            _ => Value::Table(Vec::new()),
                        };
                        entries.push(Entry {
                            key: name.clone(),
                            key_origin: origin.clone(),
                            node: Node {
                                value: empty,
                                origin: origin.clone(),
                            },
                        });
                        entries.len() - 1
                    });
                let entry = &mut entries[pos];
                if depth >= last_name {
                    entry.key_origin = origin.clone();
                }
                &mut entry.node
            }
            Seg::Index(i) => {
                let Value::Array(items) = &mut cur.value else {
                    return Err(blocked(Blocked::NotArray));
                };
                let len = items.len();
                items
                    .get_mut(*i)
                    .ok_or_else(|| blocked(Blocked::OutOfRange { len }))?
            }
        };
        if last {
            *slot = node.take().expect("set once, at the last segment");
            return Ok(());
        }
        if depth >= last_name {
            slot.origin = origin.clone();
        }
        cur = slot;
    }
    unreachable!("a key path has at least one segment")
}

/// The keys a table may hold instead of `name`, one of them at most: a quantity in
/// radians and its degree twin (`theta`, `theta_deg`), a scalar and its general form
/// (`com_offset`, `com_offset_vector`), and the output's sampling (`dt`, `times`).
fn twins(name: &str) -> Vec<String> {
    if name == "dt" || name == "times" {
        return vec![if name == "dt" { "times" } else { "dt" }.to_owned()];
    }
    match name
        .strip_suffix("_deg")
        .or_else(|| name.strip_suffix("_vector"))
    {
        Some(base) => vec![base.to_owned()],
        None => vec![format!("{name}_deg"), format!("{name}_vector")],
    }
}

/// The `--set` form `key.path=value`: the path and the value, the value in TOML syntax or
/// a bare word, taken as a string (`--set contact.model=rolling`).
pub(super) fn parse_override(ctx: &Ctx<'_>, set: &str) -> Result<(KeyPath, Node)> {
    let fail = |key: Option<String>, value: Option<String>, rule: String| {
        override_error(ctx.source, set, key, value, rule)
    };
    let Some((key, raw)) = set.split_once('=') else {
        return Err(fail(
            None,
            None,
            "an override must have the form key=value, e.g. --set output.t_end=1.0".into(),
        ));
    };
    let path = parse_key(ctx.source, set, key)?;
    let raw = raw.trim();
    let shared: Arc<str> = Arc::from(set);
    let node = match DeValue::parse(raw) {
        Ok(v) if super::collect::wide_integer(v.get_ref(), v.span()).is_some() => {
            return Err(fail(
                Some(key.trim().to_owned()),
                Some(raw.to_owned()),
                super::collect::WIDE_INTEGER.to_owned(),
            ));
        }
        Ok(v) => Node::from_value(v.span(), v.into_inner(), Some(&shared)),
        // A bare word (`--set contact.model=rolling`) is a string.
        Err(_)
            if !raw.is_empty()
                && raw
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || "_-+.".contains(c)) =>
        {
            Node {
                value: Value::Str(raw.to_owned()),
                origin: Origin::Set(Arc::clone(&shared)),
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
    Ok((path, node))
}

/// An error of the change `set` (`key=value`) of the scenario `source`.
pub(super) fn override_error(
    source: &str,
    set: &str,
    key: Option<String>,
    value: Option<String>,
    rule: String,
) -> ScenarioError {
    ScenarioError {
        kind: ErrorKind::Override,
        location: Location {
            source: source.to_owned(),
            line: None,
            column: None,
            set: Some(set.to_owned()),
        },
        key,
        value,
        rule,
    }
}

/// The key path `key` of the change `set`, or the error naming it.
pub(super) fn parse_key(source: &str, set: &str, key: &str) -> Result<KeyPath> {
    KeyPath::parse(key).map_err(|e| {
        override_error(
            source,
            set,
            Some(key.trim().to_owned()),
            None,
            e.to_string(),
        )
    })
}

/// Applies one `key.path=value` override to the document.
pub(super) fn apply_override(ctx: &Ctx<'_>, tree: &mut Node, set: &str) -> Result<()> {
    let (path, node) = parse_override(ctx, set)?;
    set_node(tree, &path, node).map_err(|e| e.error(ctx.source, &path, set))
}

impl Node {
    /// A value of the `toml` crate (a study's, or Python's) as a node from the change `set`.
    pub(super) fn from_toml(value: &toml::Value, set: &Arc<str>) -> Node {
        let value = match value {
            toml::Value::String(s) => Value::Str(s.clone()),
            toml::Value::Integer(i) => Value::Int(*i),
            toml::Value::Float(f) => Value::Float(*f),
            toml::Value::Boolean(b) => Value::Bool(*b),
            toml::Value::Datetime(d) => Value::Datetime(d.to_string()),
            toml::Value::Array(a) => {
                Value::Array(a.iter().map(|v| Node::from_toml(v, set)).collect())
            }
            toml::Value::Table(t) => Value::Table(
                t.iter()
                    .map(|(k, v)| Entry {
                        key: k.clone(),
                        key_origin: Origin::Set(Arc::clone(set)),
                        node: Node::from_toml(v, set),
                    })
                    .collect(),
            ),
        };
        Node {
            value,
            origin: Origin::Set(Arc::clone(set)),
        }
    }

    /// The node as a value of the `toml` crate (the canonical form of the document).
    pub(super) fn to_toml(&self) -> toml::Value {
        match &self.value {
            Value::Str(s) => toml::Value::String(s.clone()),
            Value::Int(i) => toml::Value::Integer(*i),
            Value::Float(f) => toml::Value::Float(*f),
            Value::Bool(b) => toml::Value::Boolean(*b),
            Value::Datetime(d) => d
                .parse()
                .map_or_else(|_| toml::Value::String(d.clone()), toml::Value::Datetime),
            Value::Array(a) => toml::Value::Array(a.iter().map(Node::to_toml).collect()),
            Value::Table(e) => toml::Value::Table(
                e.iter()
                    .map(|e| (e.key.clone(), e.node.to_toml()))
                    .collect(),
            ),
        }
    }

    /// The node at `path`, if present.
    pub(super) fn get(&self, path: &KeyPath) -> Option<&Node> {
        path.segs().iter().try_fold(self, |node, seg| match seg {
            Seg::Name(n) => node.entries().iter().find(|e| &e.key == n).map(|e| &e.node),
            Seg::Index(i) => match &node.value {
                Value::Array(a) => a.get(*i),
                _ => None,
            },
        })
    }
}
