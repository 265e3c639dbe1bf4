//! Reading the tree with errors that carry positions: typed getters, unknown-key
//! checks with suggestions, and placing physics errors at the key they name.

use super::*;

pub(super) struct Ctx<'a> {
    pub(super) source: &'a str,
    pub(super) text: &'a str,
}

impl Ctx<'_> {
    pub(super) fn locate(&self, origin: &Origin) -> Location {
        match origin {
            Origin::File(span) => {
                let offset = span.start.min(self.text.len());
                let before = &self.text[..offset];
                let line = before.matches('\n').count() + 1;
                let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
                Location {
                    source: self.source.to_owned(),
                    line: Some(line),
                    column: Some(column),
                    set: None,
                }
            }
            Origin::Set(s) => Location {
                source: self.source.to_owned(),
                line: None,
                column: None,
                set: Some(s.to_string()),
            },
        }
    }

    /// The value as the user wrote it, on one line and at most 60 characters.
    pub(super) fn value_text(&self, node: &Node) -> String {
        let raw = match (&node.origin, &node.value) {
            // A [table] header: its span is the header, not the value.
            (Origin::File(span), Value::Table(_))
                if !self
                    .text
                    .get(span.clone())
                    .is_some_and(|s| s.trim_start().starts_with('{')) =>
            {
                "a table".to_owned()
            }
            (Origin::File(span), _) => self
                .text
                .get(span.clone())
                .map_or_else(|| node.render(), str::to_owned),
            (Origin::Set(_), _) => node.render(),
        };
        let one_line = raw.split_whitespace().collect::<Vec<_>>().join(" ");
        if one_line.chars().count() > 60 {
            format!("{}…", one_line.chars().take(59).collect::<String>())
        } else {
            one_line
        }
    }

    pub(super) fn error(
        &self,
        kind: ErrorKind,
        origin: &Origin,
        key: Option<String>,
        value: Option<String>,
        rule: impl Into<String>,
    ) -> ScenarioError {
        ScenarioError {
            kind,
            location: self.locate(origin),
            key,
            value,
            rule: rule.into(),
        }
    }

    pub(super) fn syntax(&self, e: &toml::de::Error, set: Option<&str>) -> ScenarioError {
        let origin = match set {
            Some(s) => Origin::Set(s.into()),
            None => Origin::File(e.span().unwrap_or(0..0)),
        };
        self.error(
            ErrorKind::Syntax,
            &origin,
            None,
            None,
            format!("TOML syntax error: {}", e.message()),
        )
    }

    /// A physics-layer error, placed at the key it names.
    pub(super) fn model(&self, tree: &Node, err: &ModelError) -> ScenarioError {
        let scenario_like = Locator { tree };
        self.error(
            ErrorKind::Invalid,
            &scenario_like.origin_of(err.key()),
            Some(err.quantity().to_owned()),
            Some(err.value()),
            err.rule().to_owned(),
        )
    }
}

/// Finds the origin of a physics quantity's key in a tree (see [`Scenario::locate`]).
pub(super) struct Locator<'t> {
    pub(super) tree: &'t Node,
}

impl Locator<'_> {
    /// The origin of a key (a dotted path), or of the nearest table holding it.
    pub(super) fn origin_of(&self, key: &str) -> Origin {
        let path: Vec<String> = key.split('.').map(str::to_owned).collect();
        // A quantity may name a key's degree twin or general form, or a key left to its
        // default (body.b defaults to body.a).
        let mut candidates = vec![path.clone()];
        if let Some((last, head)) = path.split_last() {
            for alt in [format!("{last}_deg"), format!("{last}_vector")] {
                let mut p = head.to_vec();
                p.push(alt);
                candidates.push(p);
            }
        }
        if path == ["body", "b"] {
            candidates.push(vec!["body".into(), "a".into()]);
        }
        // Then the table: "initial" → [initial]; "solver" → [solver].
        candidates.extend(path.first().map(|first| vec![first.clone()]));
        candidates
            .iter()
            .find_map(|c| self.tree.find(c))
            .unwrap_or(Origin::File(0..0))
    }
}

// ---------------------------------------------------------------------------------
// Reading tables.

/// A table of the document being read, with its dotted path.
pub(super) struct Sec<'t> {
    pub(super) path: String,
    pub(super) node: &'t Node,
}

/// A key found in a table.
#[derive(Clone, Copy)]
pub(super) struct Got<'t> {
    pub(super) key: &'t str,
    pub(super) entry: &'t Entry,
}

impl<'t> Got<'t> {
    pub(super) fn node(&self) -> &'t Node {
        &self.entry.node
    }
}

impl<'a> Ctx<'a> {
    /// The table `key` of `parent`, its keys checked against `allowed`.
    pub(super) fn section<'t>(
        &self,
        parent: &Sec<'t>,
        key: &str,
        allowed: &[&str],
        what: &str,
    ) -> Result<Option<Sec<'t>>> {
        let Some(got) = parent.get(key) else {
            return Ok(None);
        };
        self.table_of(
            &parent.full(key),
            got.node(),
            &got.entry.key_origin,
            allowed,
            what,
        )
        .map(Some)
    }

    /// `node` as a table at `path`, its keys checked against `allowed`.
    pub(super) fn table_of<'t>(
        &self,
        path: &str,
        node: &'t Node,
        key_origin: &Origin,
        allowed: &[&str],
        what: &str,
    ) -> Result<Sec<'t>> {
        let Value::Table(entries) = &node.value else {
            return Err(self.error(
                ErrorKind::Type,
                key_origin,
                Some(path.to_owned()),
                Some(self.value_text(node)),
                format!("expected a table ({what}), found {}", node.type_name()),
            ));
        };
        for e in entries {
            if !allowed.contains(&e.key.as_str()) {
                let full = if path.is_empty() {
                    e.key.clone()
                } else {
                    format!("{path}.{}", e.key)
                };
                let place = if path.is_empty() {
                    "at the top level".to_owned()
                } else {
                    format!("in [{path}]")
                };
                let hint = match suggest(&e.key, allowed) {
                    Some(s) => format!("did you mean `{s}`?"),
                    None => format!("expected one of: {}", allowed.join(", ")),
                };
                let (value, what) = match e.node.value {
                    Value::Table(_) => (None, "unknown table"),
                    _ => (Some(self.value_text(&e.node)), "unknown key"),
                };
                return Err(self.error(
                    ErrorKind::UnknownKey,
                    &e.key_origin,
                    Some(full),
                    value,
                    format!("{what} {place}; {hint}"),
                ));
            }
        }
        Ok(Sec {
            path: path.to_owned(),
            node,
        })
    }

    pub(super) fn missing(
        &self,
        sec: &Sec<'_>,
        key: &str,
        rule: impl Into<String>,
    ) -> ScenarioError {
        self.error(
            ErrorKind::Missing,
            &sec.node.origin,
            Some(sec.full(key)),
            None,
            rule,
        )
    }

    /// An error about the value of a key that is present.
    pub(super) fn bad(
        &self,
        kind: ErrorKind,
        sec: &Sec<'_>,
        got: Got<'_>,
        rule: impl Into<String>,
    ) -> ScenarioError {
        self.error(
            kind,
            &got.entry.key_origin,
            Some(sec.full(got.key)),
            Some(self.value_text(got.node())),
            rule,
        )
    }

    pub(super) fn wrong_type(&self, sec: &Sec<'_>, got: Got<'_>, expected: &str) -> ScenarioError {
        self.bad(
            ErrorKind::Type,
            sec,
            got,
            format!("expected {expected}, found {}", got.node().type_name()),
        )
    }

    /// A number (integer or float), if present.
    pub(super) fn number(
        &self,
        sec: &Sec<'_>,
        key: &str,
        what: &str,
    ) -> Result<Option<(f64, Origin)>> {
        let Some(got) = sec.get(key) else {
            return Ok(None);
        };
        match got.node().as_f64() {
            Some(v) => Ok(Some((v, got.entry.key_origin.clone()))),
            None => Err(self.wrong_type(sec, got, &format!("a number: {what}"))),
        }
    }

    pub(super) fn required(&self, sec: &Sec<'_>, key: &str, what: &str) -> Result<f64> {
        self.number(sec, key, what)?
            .map(|(v, _)| v)
            .ok_or_else(|| self.missing(sec, key, format!("give {what}")))
    }

    /// A number that must be finite and satisfy `ok`, if present.
    pub(super) fn checked(
        &self,
        sec: &Sec<'_>,
        key: &str,
        what: &str,
        ok: impl Fn(f64) -> bool,
        rule: &str,
    ) -> Result<Option<f64>> {
        match self.number(sec, key, what)? {
            Some((v, _)) if !(v.is_finite() && ok(v)) => Err(self.bad(
                ErrorKind::Invalid,
                sec,
                sec.get(key).expect("just read"),
                rule,
            )),
            other => Ok(other.map(|(v, _)| v)),
        }
    }

    /// An array of exactly N numbers, if present.
    pub(super) fn numbers<const N: usize>(
        &self,
        sec: &Sec<'_>,
        key: &str,
        what: &str,
    ) -> Result<Option<[f64; N]>> {
        let Some(got) = sec.get(key) else {
            return Ok(None);
        };
        let expected = || format!("an array of {N} numbers: {what}");
        let Value::Array(items) = &got.node().value else {
            return Err(self.wrong_type(sec, got, &expected()));
        };
        if items.len() != N {
            return Err(self.bad(
                ErrorKind::Type,
                sec,
                got,
                format!("expected {}, found {} element(s)", expected(), items.len()),
            ));
        }
        let mut out = [0.0; N];
        for (o, item) in out.iter_mut().zip(items) {
            *o = item.as_f64().ok_or_else(|| {
                self.bad(
                    ErrorKind::Type,
                    sec,
                    got,
                    format!(
                        "expected {}, found {} among them",
                        expected(),
                        item.type_name()
                    ),
                )
            })?;
        }
        Ok(Some(out))
    }

    /// A string that must be one of `choices`, if present.
    pub(super) fn choice<'t, 'c>(
        &self,
        sec: &Sec<'t>,
        key: &str,
        choices: &[&'c str],
    ) -> Result<Option<(&'c str, Got<'t>)>> {
        let Some(got) = sec.get(key) else {
            return Ok(None);
        };
        let Value::Str(s) = &got.node().value else {
            return Err(self.wrong_type(
                sec,
                got,
                &format!("a string, one of {}", quoted(choices)),
            ));
        };
        match choices.iter().find(|c| **c == s.as_str()) {
            Some(c) => Ok(Some((c, got))),
            None => {
                let hint = suggest(s, choices)
                    .map_or_else(String::new, |c| format!("; did you mean \"{c}\"?"));
                Err(self.bad(
                    ErrorKind::Invalid,
                    sec,
                    got,
                    format!("expected one of {}{hint}", quoted(choices)),
                ))
            }
        }
    }

    /// Rejects giving both `a` and `b`.
    pub(super) fn exclusive(&self, sec: &Sec<'_>, a: &str, b: &str, why: &str) -> Result<()> {
        if let (Some(_), Some(got)) = (sec.get(a), sec.get(b)) {
            let (first, second) = (sec.full(a), sec.full(b));
            return Err(self.bad(
                ErrorKind::Conflict,
                sec,
                got,
                format!("give either {first} or {second}, not both ({why})"),
            ));
        }
        Ok(())
    }

    /// An angle or angular rate in radians from `key` or degrees from `key_deg`.
    pub(super) fn angle(&self, sec: &Sec<'_>, key: &str, what: &str) -> Result<Option<f64>> {
        let deg = format!("{key}_deg");
        self.exclusive(sec, key, &deg, "radians or degrees")?;
        if let Some((v, _)) = self.number(sec, key, what)? {
            return Ok(Some(v));
        }
        Ok(self.number(sec, &deg, what)?.map(|(v, _)| v.to_radians()))
    }
}

impl<'t> Sec<'t> {
    pub(super) fn get(&self, key: &str) -> Option<Got<'t>> {
        self.node
            .entries()
            .iter()
            .find(|e| e.key == key)
            .map(|entry| Got {
                key: entry.key.as_str(),
                entry,
            })
    }

    pub(super) fn full(&self, key: &str) -> String {
        if self.path.is_empty() {
            key.to_owned()
        } else {
            format!("{}.{key}", self.path)
        }
    }
}

pub(super) fn quoted(choices: &[&str]) -> String {
    choices
        .iter()
        .map(|c| format!("\"{c}\""))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The allowed name closest to `key` in edit distance, if close enough to be a typo.
pub(super) fn suggest<'c>(key: &str, allowed: &[&'c str]) -> Option<&'c str> {
    let limit = (key.chars().count() / 3).clamp(1, 3);
    // No allowed name is within `limit` edits of a much longer key (a 20 MB key took 12 s).
    let longest = allowed.iter().map(|c| c.chars().count()).max().unwrap_or(0);
    if key.len() > 4 * (longest + limit) {
        return None;
    }
    let key = key.to_lowercase();
    allowed
        .iter()
        .map(|c| (levenshtein(&key, c), *c))
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

/// Edit distance (insertions, deletions, substitutions) between two strings.
pub(super) fn levenshtein(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diag = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let next = (diag + usize::from(ca != *cb))
                .min(row[j] + 1)
                .min(row[j + 1] + 1);
            diag = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}
