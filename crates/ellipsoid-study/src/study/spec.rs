//! Study files (docs/studies.md): a TOML document naming a base scenario, changes common
//! to every point, axes and outcomes. Read with spans, so that every error names the
//! file, line and column, the key, the value and the rule, like a scenario's:
//!
//! ```text
//! study.toml:9:12: axis[1].linspace = [0, 1, 1000000000]: n must be an integer from 1 to 10000000 (points per axis)
//! ```
//! Input is bounded before any work is done: the file's size, the nesting depth (the
//! TOML parser's own limit), the number of axes, keys and values, and the number of
//! points (checked as a product before any point is made).

#![allow(clippy::result_large_err)] // one error per failed parse, off the hot path (the scenario parser's own choice)

use std::ops::Range;
use std::path::Path;

use ellipsoid_core::scenario::{ErrorKind, Location, ScenarioError, ScenarioErrors};
use toml::Spanned;
use toml::de::{DeTable, DeValue};

use super::axes;
use super::plan::{
    Axis, Base, Combine, Dim, MAX_AXES, MAX_KEYS, MAX_POINTS, Outcomes, Places, Plan, Values,
    parse_path,
};

/// Largest study file read [bytes].
pub const MAX_STUDY_BYTES: usize = 8 << 20;
/// Largest base scenario file read [bytes].
pub const MAX_BASE_BYTES: usize = 8 << 20;

const TOP_KEYS: [&str; 5] = ["base", "combine", "set", "axis", "outcomes"];
const AXIS_KEYS: [&str; 8] = [
    "key",
    "keys",
    "also",
    "values",
    "linspace",
    "logspace",
    "random",
    "latin_hypercube",
];
const GENERATORS: [&str; 5] = [
    "values",
    "linspace",
    "logspace",
    "random",
    "latin_hypercube",
];
const OUTCOME_KEYS: [&str; 7] = [
    "observables",
    "final",
    "min",
    "max",
    "drift",
    "wall_time",
    "rhs_evals",
];

/// How axes are named in messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Naming {
    /// `axis[i]`, with the line and column in the study file.
    File,
    /// `axes["key"]`, without a place (the document was made from Python arguments).
    Python,
}

struct Doc<'a> {
    source: &'a str,
    text: &'a str,
    naming: Naming,
    /// Where the parts were written, by the labels of [`Places`].
    places: std::cell::RefCell<Places>,
}

type Res<T> = Result<T, ScenarioError>;
/// A table's entries with their spans.
type Entries<'t, 'i> = Vec<(
    &'t Spanned<std::borrow::Cow<'i, str>>,
    &'t Spanned<DeValue<'i>>,
)>;

impl Doc<'_> {
    fn err(
        &self,
        kind: ErrorKind,
        span: &Range<usize>,
        key: &str,
        value: Option<String>,
        rule: impl Into<String>,
    ) -> ScenarioError {
        let (line, column) = self.place(span).unzip();
        ScenarioError {
            kind,
            location: Location {
                source: self.source.to_owned(),
                line,
                column,
                set: None,
            },
            key: (!key.is_empty()).then(|| key.to_owned()),
            value,
            rule: rule.into(),
        }
    }

    /// Line and column (1-based, in characters) of `span`'s start; None for a document
    /// made from Python arguments.
    fn place(&self, span: &Range<usize>) -> Option<(usize, usize)> {
        if self.naming == Naming::Python {
            return None;
        }
        let mut offset = span.start.min(self.text.len());
        while !self.text.is_char_boundary(offset) {
            offset -= 1;
        }
        let before = &self.text[..offset];
        Some((
            before.matches('\n').count() + 1,
            before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1,
        ))
    }

    /// Records where the part `label` was written.
    fn mark(&self, label: String, span: &Range<usize>) {
        if let Some(p) = self.place(span) {
            self.places.borrow_mut().0.insert(label, p);
        }
    }

    /// The value as written (cut), for messages.
    fn shown(&self, v: &Spanned<DeValue<'_>>) -> String {
        let s = self.text.get(v.span()).unwrap_or("");
        let s: String = s
            .chars()
            .take(80)
            .map(|c| if c.is_control() { ' ' } else { c })
            .collect();
        s
    }

    fn invalid(
        &self,
        v: &Spanned<DeValue<'_>>,
        key: &str,
        rule: impl Into<String>,
    ) -> ScenarioError {
        self.err(
            ErrorKind::Invalid,
            &v.span(),
            key,
            Some(self.shown(v)),
            rule,
        )
    }

    fn type_err(
        &self,
        v: &Spanned<DeValue<'_>>,
        key: &str,
        rule: impl Into<String>,
    ) -> ScenarioError {
        self.err(ErrorKind::Type, &v.span(), key, Some(self.shown(v)), rule)
    }

    /// A table's entries in file order, refusing keys not in `known`.
    fn entries<'t, 'i>(
        &self,
        table: &'t DeTable<'i>,
        path: &str,
        known: &[&str],
    ) -> Res<Entries<'t, 'i>> {
        let mut v: Vec<_> = table.iter().collect();
        v.sort_by_key(|(k, _)| k.span().start);
        for (k, _) in &v {
            if !known.contains(&k.get_ref().as_ref()) {
                let full = if path.is_empty() {
                    k.get_ref().to_string()
                } else {
                    format!("{path}.{}", k.get_ref())
                };
                return Err(self.err(
                    ErrorKind::UnknownKey,
                    &k.span(),
                    &full,
                    None,
                    format!(
                        "unknown key in {}; expected one of {}",
                        if path.is_empty() {
                            "the study".into()
                        } else {
                            format!("[{path}]")
                        },
                        known.join(", ")
                    ),
                ));
            }
        }
        Ok(v)
    }

    fn number(&self, v: &Spanned<DeValue<'_>>, key: &str) -> Res<f64> {
        let x = match v.get_ref() {
            DeValue::Float(f) => f
                .as_str()
                .replace('_', "")
                .parse::<f64>()
                .unwrap_or(f64::NAN),
            DeValue::Integer(i) => {
                match i64::from_str_radix(&i.as_str().replace('_', ""), i.radix()) {
                    Ok(i) => i as f64,
                    Err(_) => {
                        return Err(self.invalid(v, key, "integer out of TOML's 64-bit range"));
                    }
                }
            }
            _ => return Err(self.type_err(v, key, "expected a number")),
        };
        if !x.is_finite() {
            return Err(self.invalid(v, key, "expected a finite number"));
        }
        Ok(x)
    }

    fn count(&self, v: &Spanned<DeValue<'_>>, key: &str) -> Res<usize> {
        let rule = format!("n must be an integer from 1 to {MAX_POINTS} (points per axis)");
        match v.get_ref() {
            DeValue::Integer(i) => {
                match i64::from_str_radix(&i.as_str().replace('_', ""), i.radix()) {
                    Ok(n) if (1..=MAX_POINTS as i64).contains(&n) => Ok(n as usize),
                    _ => Err(self.invalid(v, key, rule)),
                }
            }
            _ => Err(self.type_err(v, key, rule)),
        }
    }

    fn seed(&self, v: Option<&Spanned<DeValue<'_>>>, key: &str) -> Res<u64> {
        let Some(v) = v else { return Ok(0) };
        match v.get_ref() {
            DeValue::Integer(i) => {
                match i64::from_str_radix(&i.as_str().replace('_', ""), i.radix()) {
                    Ok(n) if n >= 0 => Ok(n as u64),
                    _ => Err(self.invalid(v, key, "the seed is an integer from 0 to 2^63 - 1")),
                }
            }
            _ => Err(self.type_err(v, key, "the seed is an integer from 0 to 2^63 - 1")),
        }
    }

    fn string<'v>(&self, v: &'v Spanned<DeValue<'_>>, key: &str) -> Res<&'v str> {
        match v.get_ref() {
            DeValue::String(s) => Ok(s.as_ref()),
            _ => Err(self.type_err(v, key, "expected a string")),
        }
    }

    fn boolean(&self, v: &Spanned<DeValue<'_>>, key: &str) -> Res<bool> {
        match v.get_ref() {
            DeValue::Boolean(b) => Ok(*b),
            _ => Err(self.type_err(v, key, "expected true or false")),
        }
    }

    fn array<'v, 'i>(
        &self,
        v: &'v Spanned<DeValue<'i>>,
        key: &str,
        max: usize,
    ) -> Res<&'v [Spanned<DeValue<'i>>]> {
        self.array_of(v, key, max, "at most {max} values")
    }

    /// An array of at most `max` entries; `rule` (with `{max}` in it) says what bounds
    /// them.
    fn array_of<'v, 'i>(
        &self,
        v: &'v Spanned<DeValue<'i>>,
        key: &str,
        max: usize,
        rule: &str,
    ) -> Res<&'v [Spanned<DeValue<'i>>]> {
        match v.get_ref() {
            DeValue::Array(a) if a.len() <= max => Ok(&a[..]),
            DeValue::Array(a) => Err(self.err(
                ErrorKind::Invalid,
                &v.span(),
                key,
                Some(format!("an array of {} values", a.len())),
                rule.replace("{max}", &max.to_string()),
            )),
            _ => Err(self.type_err(v, key, "expected an array")),
        }
    }

    /// An array of at most `max` strings; `rule` as for [`Doc::array_of`].
    fn strings(
        &self,
        v: &Spanned<DeValue<'_>>,
        key: &str,
        max: usize,
        rule: &str,
    ) -> Res<Vec<String>> {
        self.array_of(v, key, max, rule)?
            .iter()
            .map(|s| self.string(s, key).map(str::to_owned))
            .collect()
    }

    fn table<'v, 'i>(&self, v: &'v Spanned<DeValue<'i>>, key: &str) -> Res<&'v DeTable<'i>> {
        match v.get_ref() {
            DeValue::Table(t) => Ok(t),
            _ => Err(self.type_err(v, key, "expected a table")),
        }
    }

    /// A TOML value for a scenario key (any type; numbers finite).
    fn value(&self, v: &Spanned<DeValue<'_>>, key: &str) -> Res<toml::Value> {
        Ok(match v.get_ref() {
            DeValue::String(s) => toml::Value::String(s.to_string()),
            DeValue::Integer(i) => {
                match i64::from_str_radix(&i.as_str().replace('_', ""), i.radix()) {
                    Ok(i) => toml::Value::Integer(i),
                    Err(_) => {
                        return Err(self.invalid(v, key, "integer out of TOML's 64-bit range"));
                    }
                }
            }
            DeValue::Float(_) => toml::Value::Float(self.number(v, key)?),
            DeValue::Boolean(b) => toml::Value::Boolean(*b),
            DeValue::Datetime(d) => toml::Value::Datetime(*d),
            DeValue::Array(a) => {
                toml::Value::Array(a.iter().map(|e| self.value(e, key)).collect::<Res<_>>()?)
            }
            DeValue::Table(t) => {
                let mut out = toml::Table::new();
                for (k, e) in t.iter() {
                    out.insert(k.get_ref().to_string(), self.value(e, key)?);
                }
                toml::Value::Table(out)
            }
        })
    }

    /// `[set]`: nested tables flattened to dotted keys; arrays and inline values kept whole.
    fn flatten(
        &self,
        t: &DeTable<'_>,
        prefix: &str,
        out: &mut Vec<(String, toml::Value)>,
    ) -> Res<()> {
        let mut v: Vec<_> = t.iter().collect();
        v.sort_by_key(|(k, _)| k.span().start);
        for (k, e) in v {
            let key = if prefix.is_empty() {
                k.get_ref().to_string()
            } else {
                format!("{prefix}.{}", k.get_ref())
            };
            if out.len() >= MAX_KEYS {
                return Err(self.invalid(
                    e,
                    &format!("set.{key}"),
                    format!("[set] holds at most {MAX_KEYS} keys"),
                ));
            }
            match e.get_ref() {
                DeValue::Table(sub) if !k.get_ref().contains('.') => {
                    self.flatten(sub, &key, out)?
                }
                _ => {
                    self.mark(format!("set.{key}"), &e.span());
                    parse_path(&key).map_err(|r| self.invalid(e, &format!("set.{key}"), r))?;
                    out.push((key.clone(), self.value(e, &format!("set.{key}"))?));
                }
            }
        }
        Ok(())
    }
}

/// Reads the study file at `path` (its `base` path is relative to the file's directory).
pub fn load(path: &Path) -> Result<Plan, ScenarioErrors> {
    let source = path.display().to_string();
    let fail =
        |rule: String| ScenarioErrors::from(super::plan::study_error(&source, None, None, rule));
    let bytes = ellipsoid_core::scenario::read_bounded(path, MAX_STUDY_BYTES as u64)
        .map_err(|e| fail(format!("cannot read the study file: {e}")))?;
    let text = String::from_utf8(bytes).map_err(|e| {
        // Where the first bad byte is: line and column (in characters) of the text before it.
        let bytes = e.as_bytes();
        let good = std::str::from_utf8(&bytes[..e.utf8_error().valid_up_to()]).unwrap_or_default();
        let mut error = super::plan::study_error(
            &source,
            None,
            None,
            format!(
                "the study file is not UTF-8 text, as TOML must be: byte 0x{:02x} does not begin a UTF-8 character (save the file as UTF-8)",
                bytes[good.len()]
            ),
        );
        error.location.line = Some(good.matches('\n').count() + 1);
        error.location.column = Some(good.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1);
        ScenarioErrors::from(error)
    })?;
    let dir = path.parent().unwrap_or(Path::new(""));
    parse(&text, &source, Some(dir), None, Naming::File)
}

/// Parses a study document named `source`. `dir` resolves a relative `base` path; `base`,
/// when given, is the base scenario (the document's own `base` is then not allowed).
pub fn parse(
    text: &str,
    source: &str,
    dir: Option<&Path>,
    base: Option<Base>,
    naming: Naming,
) -> Result<Plan, ScenarioErrors> {
    let doc = Doc {
        source,
        text,
        naming,
        places: Default::default(),
    };
    parse_doc(&doc, dir, base).map_err(ScenarioErrors::from)
}

fn parse_doc(doc: &Doc<'_>, dir: Option<&Path>, given: Option<Base>) -> Res<Plan> {
    if doc.text.len() > MAX_STUDY_BYTES {
        return Err(doc.err(
            ErrorKind::Invalid,
            &(0..0),
            "",
            None,
            format!(
                "the study has {} bytes; at most {MAX_STUDY_BYTES} are read",
                doc.text.len()
            ),
        ));
    }
    let root = DeTable::parse(doc.text).map_err(|e| {
        doc.err(
            ErrorKind::Syntax,
            &e.span().unwrap_or(0..0),
            "",
            None,
            format!("TOML syntax error: {}", e.message()),
        )
    })?;
    let root_span = root.span();
    let root = root.get_ref();
    let entries = doc.entries(root, "", &TOP_KEYS)?;
    let get = |name: &str| {
        entries
            .iter()
            .find(|(k, _)| k.get_ref() == name)
            .map(|(_, v)| *v)
    };
    for name in ["base", "combine"] {
        if let Some(v) = get(name) {
            doc.mark(name.into(), &v.span());
        }
    }

    let base = match (get("base"), given) {
        (Some(v), Some(_)) => return Err(doc.invalid(v, "base", "the base scenario is given twice (as an argument and in the study)")),
        (None, Some(b)) => b,
        (None, None) => return Err(doc.err(ErrorKind::Missing, &root_span, "base", None, "a study needs a base scenario: base = \"scenario.toml\" (relative to the study file), or a [base] table holding the scenario's tables")),
        (Some(v), None) => match v.get_ref() {
            DeValue::String(p) => {
                let path = dir.map_or_else(|| Path::new(p.as_ref()).to_owned(), |d| d.join(p.as_ref()));
                let shown = path.display().to_string();
                let cannot = |e: String| doc.invalid(v, "base", format!("cannot read the base scenario {shown}: {e}"));
                let bytes = ellipsoid_core::scenario::read_bounded(&path, MAX_BASE_BYTES as u64).map_err(cannot)?;
                let text = String::from_utf8(bytes).map_err(|_| cannot("the file is not UTF-8 text, as TOML must be".into()))?;
                Base { text, source: shown, overrides: Vec::new() }
            }
            DeValue::Table(_) => {
                let value = doc.value(v, "base")?;
                let text = toml::to_string(&value).map_err(|e| doc.invalid(v, "base", e.to_string()))?;
                Base { text, source: format!("{} [base]", doc.source), overrides: Vec::new() }
            }
            _ => return Err(doc.type_err(v, "base", "expected a scenario file path (string) or a [base] table")),
        },
    };

    let combine = match get("combine") {
        None => Combine::Grid,
        Some(v) => match doc.string(v, "combine")? {
            "grid" => Combine::Grid,
            "zip" => Combine::Zip,
            _ => return Err(doc.invalid(v, "combine", "expected \"grid\" (every combination, the last axis varying fastest) or \"zip\" (the i-th value of every axis)")),
        },
    };

    let mut set = Vec::new();
    if let Some(v) = get("set") {
        doc.flatten(doc.table(v, "set")?, "", &mut set)?;
    }

    let mut axes_out = Vec::new();
    if let Some(v) = get("axis") {
        if get("combine").is_none() {
            doc.mark("combine".into(), &v.span());
        }
        let list = doc.array(v, "axis", MAX_AXES)?;
        // The grid's size, from the counts the axes declare, before any value is made.
        if combine == Combine::Grid {
            // (An axis of more than MAX_POINTS values is left to read_axis, which names it.)
            let declared: Vec<usize> = list
                .iter()
                .filter_map(declared_count)
                .filter(|n| *n <= MAX_POINTS)
                .collect();
            super::plan::grid_points(&declared).map_err(|rule| {
                doc.err(
                    ErrorKind::Invalid,
                    &v.span(),
                    "combine",
                    Some("grid".into()),
                    rule,
                )
            })?;
        }
        for (i, a) in list.iter().enumerate() {
            axes_out.push(read_axis(doc, a, i)?);
        }
    }

    let outcomes = match get("outcomes") {
        None => Outcomes::default(),
        Some(v) => read_outcomes(doc, doc.table(v, "outcomes")?)?,
    };

    Ok(Plan {
        source: doc.source.to_owned(),
        base,
        set,
        axes: axes_out,
        combine,
        outcomes,
        places: doc.places.take(),
    })
}

/// Refuses a generator range from `a` to `b` whose width `b − a` overflows: the values
/// made from it would be infinite or NaN.
fn finite_span(doc: &Doc<'_>, v: &Spanned<DeValue<'_>>, key: &str, a: f64, b: f64) -> Res<()> {
    if (b - a).is_finite() {
        Ok(())
    } else {
        Err(doc.invalid(
            v,
            key,
            format!("the ends {a:e} and {b:e} are too far apart: their difference must be a finite number (below 1.8e308), or the values would be infinite or NaN"),
        ))
    }
}

/// The number of values axis `v` declares (its generator's `n`, or its list's length),
/// read without making any; None for an axis [`read_axis`] will refuse.
fn declared_count(v: &Spanned<DeValue<'_>>) -> Option<usize> {
    fn field<'a, 'i>(t: &'a DeTable<'i>, name: &str) -> Option<&'a DeValue<'i>> {
        t.iter()
            .find(|(k, _)| k.get_ref() == name)
            .map(|(_, v)| v.get_ref())
    }
    let int = |v: &DeValue<'_>| match v {
        DeValue::Integer(i) => i64::from_str_radix(&i.as_str().replace('_', ""), i.radix())
            .ok()
            .and_then(|n| usize::try_from(n).ok()),
        _ => None,
    };
    let DeValue::Table(t) = v.get_ref() else {
        return None;
    };
    GENERATORS.iter().find_map(|g| match (*g, field(t, g)?) {
        ("values", DeValue::Array(a)) => Some(a.len()),
        ("linspace" | "logspace", DeValue::Array(a)) => a.get(2).and_then(|n| int(n.get_ref())),
        ("random" | "latin_hypercube", DeValue::Table(r)) => field(r, "n").and_then(int),
        _ => None,
    })
}

fn read_axis(doc: &Doc<'_>, v: &Spanned<DeValue<'_>>, i: usize) -> Res<Axis> {
    let t = doc.table(v, &format!("axis[{i}]"))?;
    let key_of = |t: &DeTable<'_>| {
        t.iter()
            .find(|(k, _)| k.get_ref() == "key")
            .and_then(|(_, v)| match v.get_ref() {
                DeValue::String(s) => Some(s.to_string()),
                _ => None,
            })
    };
    let label = match doc.naming {
        Naming::File => format!("axis[{i}]"),
        Naming::Python => format!("axes[{:?}]", key_of(t).unwrap_or_default()),
    };
    let entries = doc.entries(t, &label, &AXIS_KEYS)?;
    let get = |name: &str| {
        entries
            .iter()
            .find(|(k, _)| k.get_ref() == name)
            .map(|(_, v)| *v)
    };
    doc.mark(format!("axis[{i}]"), &v.span());
    for (name, field) in [("key", "key"), ("keys", "key"), ("also", "also")] {
        if let Some(x) = get(name) {
            doc.mark(format!("axis[{i}].{field}"), &x.span());
        }
    }
    let gens: Vec<&str> = GENERATORS
        .iter()
        .copied()
        .filter(|g| get(g).is_some())
        .collect();
    let generator = match gens.as_slice() {
        [g] => *g,
        [] => return Err(doc.err(ErrorKind::Missing, &v.span(), &label, None, "an axis needs one of values = [...], linspace = [start, stop, n], logspace = [start, stop, n], random = { low, high, n, seed }, latin_hypercube = { low = [...], high = [...], n, seed }")),
        [_, g2, ..] => return Err(doc.err(ErrorKind::Conflict, &get(g2).map_or(v.span(), |x| x.span()), &format!("{label}.{g2}"), None, format!("an axis has one generator, found {}", gens.join(" and ")))),
    };
    let key = get("key");
    let keys = get("keys");
    let path_check = |kv: &Spanned<DeValue<'_>>, k: &str, name: &str| -> Res<()> {
        parse_path(k)
            .map(|_| ())
            .map_err(|r| doc.invalid(kv, &format!("{label}.{name}"), r))
    };
    let also = match get("also") {
        None => Vec::new(),
        Some(a) => {
            if generator == "latin_hypercube" {
                return Err(doc.err(ErrorKind::Conflict, &a.span(), &format!("{label}.also"), None, "a Latin hypercube sets each of its keys to its own value; `also` belongs to single-key axes"));
            }
            let list = doc.strings(
                a,
                &format!("{label}.also"),
                MAX_KEYS,
                "an axis sets at most {max} more keys to its value (also)",
            )?;
            for k in &list {
                path_check(a, k, "also")?;
            }
            list
        }
    };
    if generator == "latin_hypercube" {
        let keys_v =
            match (key, keys) {
                (_, Some(k)) if key.is_none() => k,
                (Some(k), _) => {
                    return Err(doc.err(
                        ErrorKind::Conflict,
                        &k.span(),
                        &format!("{label}.key"),
                        None,
                        "a Latin hypercube spans several keys: keys = [\"a.b\", \"c.d\"]",
                    ));
                }
                _ => return Err(doc.err(
                    ErrorKind::Missing,
                    &v.span(),
                    &format!("{label}.keys"),
                    None,
                    "a Latin hypercube needs keys = [\"a.b\", \"c.d\", ...] (one per dimension)",
                )),
            };
        let names = doc.strings(
            keys_v,
            &format!("{label}.keys"),
            MAX_AXES,
            "a Latin hypercube spans at most {max} keys",
        )?;
        if names.is_empty() {
            return Err(doc.invalid(keys_v, &format!("{label}.keys"), "at least one key"));
        }
        for k in &names {
            path_check(keys_v, k, "keys")?;
        }
        let lh = get("latin_hypercube").expect("the generator");
        let lname = format!("{label}.latin_hypercube");
        let lt = doc.table(lh, &lname)?;
        let le = doc.entries(lt, &lname, &["low", "high", "n", "seed"])?;
        let lget = |name: &str| {
            le.iter()
                .find(|(k, _)| k.get_ref() == name)
                .map(|(_, v)| *v)
        };
        let need = |name: &str| {
            lget(name).ok_or_else(|| doc.err(ErrorKind::Missing, &lh.span(), &format!("{lname}.{name}"), None, "latin_hypercube = { low = [...], high = [...], n, seed }: low and high give one bound per key"))
        };
        let bounds = |name: &str| -> Res<Vec<f64>> {
            let v = need(name)?;
            let list = doc.array(v, &format!("{lname}.{name}"), MAX_AXES)?;
            if list.len() != names.len() {
                return Err(doc.invalid(
                    v,
                    &format!("{lname}.{name}"),
                    format!("one bound per key: {} keys", names.len()),
                ));
            }
            list.iter()
                .map(|x| doc.number(x, &format!("{lname}.{name}")))
                .collect()
        };
        let (low, high) = (bounds("low")?, bounds("high")?);
        if let Some(j) = (0..low.len()).find(|&j| low[j] >= high[j]) {
            return Err(doc.invalid(
                need("high")?,
                &format!("{lname}.high"),
                format!(
                    "each low must be below its high: {} is not below {} for {}",
                    low[j], high[j], names[j]
                ),
            ));
        }
        for (lo, hi) in low.iter().zip(&high) {
            finite_span(doc, need("high")?, &format!("{lname}.high"), *lo, *hi)?;
        }
        let n = doc.count(need("n")?, &format!("{lname}.n"))?;
        let seed = doc.seed(lget("seed"), &format!("{lname}.seed"))?;
        let cols = axes::latin_hypercube(&low, &high, n, seed);
        return Ok(Axis {
            dims: names
                .into_iter()
                .zip(cols)
                .map(|(key, v)| Dim {
                    key,
                    also: Vec::new(),
                    values: Values::Floats(v),
                })
                .collect(),
        });
    }
    let key_v = match (key, keys) {
        (Some(k), None) => k,
        (_, Some(k)) => return Err(doc.err(ErrorKind::Conflict, &k.span(), &format!("{label}.keys"), None, "keys = [...] is for a Latin hypercube; this axis sets one key (key = \"a.b\"), and others to the same value with also = [...]")),
        (None, None) => return Err(doc.err(ErrorKind::Missing, &v.span(), &format!("{label}.key"), None, "an axis needs the dotted key it varies: key = \"contact.friction\"")),
    };
    let key_name = doc.string(key_v, &format!("{label}.key"))?.to_owned();
    path_check(key_v, &key_name, "key")?;
    let gv = get(generator).expect("the generator");
    let gname = format!("{label}.{generator}");
    let values = match generator {
        "values" => {
            let list = doc.array(gv, &gname, MAX_POINTS)?;
            if list.is_empty() {
                return Err(doc.invalid(gv, &gname, "at least one value"));
            }
            Values::Given(
                list.iter()
                    .map(|x| doc.value(x, &gname))
                    .collect::<Res<_>>()?,
            )
        }
        "linspace" | "logspace" => {
            let list = doc.array(gv, &gname, 3)?;
            if list.len() != 3 {
                return Err(doc.invalid(gv, &gname, format!("{generator} = [start, stop, n]")));
            }
            let (a, b) = (doc.number(&list[0], &gname)?, doc.number(&list[1], &gname)?);
            let n = doc.count(&list[2], &gname)?;
            finite_span(doc, gv, &gname, a, b)?;
            if generator == "logspace" {
                if !(a > 0.0 && b > 0.0) {
                    return Err(doc.invalid(gv, &gname, "logspace = [start, stop, n] spaces the values geometrically: start and stop must be > 0 (they are the values, not their exponents)"));
                }
                Values::Floats(axes::logspace(a, b, n))
            } else {
                Values::Floats(axes::linspace(a, b, n))
            }
        }
        "random" => {
            let rt = doc.table(gv, &gname)?;
            let re = doc.entries(rt, &gname, &["low", "high", "n", "seed"])?;
            let rget = |name: &str| {
                re.iter()
                    .find(|(k, _)| k.get_ref() == name)
                    .map(|(_, v)| *v)
            };
            let need = |name: &str| {
                rget(name).ok_or_else(|| doc.err(ErrorKind::Missing, &gv.span(), &format!("{gname}.{name}"), None, "random = { low, high, n, seed }: n values uniform in [low, high); seed defaults to 0"))
            };
            let low = doc.number(need("low")?, &format!("{gname}.low"))?;
            let high = doc.number(need("high")?, &format!("{gname}.high"))?;
            if low >= high {
                return Err(doc.invalid(
                    need("high")?,
                    &format!("{gname}.high"),
                    format!("low must be below high ({low} is not below {high})"),
                ));
            }
            finite_span(doc, need("high")?, &format!("{gname}.high"), low, high)?;
            let n = doc.count(need("n")?, &format!("{gname}.n"))?;
            let seed = doc.seed(rget("seed"), &format!("{gname}.seed"))?;
            Values::Floats(axes::random(low, high, n, seed))
        }
        _ => unreachable!("one of GENERATORS"),
    };
    Ok(Axis {
        dims: vec![Dim {
            key: key_name,
            also,
            values,
        }],
    })
}

fn read_outcomes(doc: &Doc<'_>, t: &DeTable<'_>) -> Res<Outcomes> {
    let mut o = Outcomes::default();
    for (k, v) in doc.entries(t, "outcomes", &OUTCOME_KEYS)? {
        let key = format!("outcomes.{}", k.get_ref());
        doc.mark(key.clone(), &v.span());
        match k.get_ref().as_ref() {
            "observables" => o.observables = doc.boolean(v, &key)?,
            "drift" => o.drift = doc.boolean(v, &key)?,
            "wall_time" => o.wall_time = doc.boolean(v, &key)?,
            "rhs_evals" => o.rhs_evals = doc.boolean(v, &key)?,
            name => {
                let all = match v.get_ref() {
                    DeValue::String(s) => s == "all",
                    DeValue::Array(a) => {
                        a.len() == 1 && matches!(a[0].get_ref(), DeValue::String(s) if s == "all")
                    }
                    _ => false,
                };
                let list = if all {
                    let mut all: Vec<String> = ellipsoid_core::columns::NUMERIC_COLUMNS
                        .iter()
                        .map(|c| c.0.to_owned())
                        .collect();
                    if name == "final" {
                        all.insert(ellipsoid_core::columns::MODE_POSITION, "mode".into());
                    }
                    all
                } else {
                    doc.strings(
                        v,
                        &key,
                        MAX_KEYS,
                        "an outcome list names at most {max} columns",
                    )?
                };
                match name {
                    "final" => o.final_columns = list,
                    "min" => o.min = list,
                    _ => o.max = list,
                }
            }
        }
    }
    Ok(o)
}
