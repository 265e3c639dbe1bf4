//! Several errors at once: every independent error of a scenario, in file order, like a
//! compiler (at most [`MAX_ERRORS`]).
//!
//! The readers of `format` stop at their first error. Here each table is read on its
//! own, so an error in `[body]` does not hide one in `[output]`; an unknown key is
//! independent of everything else, so after one the table is read again without it,
//! which finds the next. Rules that combine tables (`Scene::validate`, the initial
//! state) run only when every table is clean, since their errors may be consequences.
//! Integers beyond TOML's 64-bit range are found in a walk of the parsed document.

use super::*;

/// Most errors reported for one scenario.
pub const MAX_ERRORS: usize = 20;

/// Builds the scene, or returns every independent error (sorted by position; errors of
/// `--set` values after those in the file).
pub(super) fn build_all(
    ctx: &Ctx<'_>,
    tree: &Node,
) -> std::result::Result<(Scene, Check), Vec<ScenarioError>> {
    // The scene is built by `build` alone; the passes below only look for more errors.
    let first = match build(ctx, tree) {
        Ok(v) => return Ok(v),
        Err(e) => e,
    };
    let mut found = Found {
        errs: vec![first],
        emptied: Vec::new(),
    };
    let mut clean = tree.clone();
    // The top level: unknown tables and keys.
    retry(ctx, &mut clean, &mut found, |t| {
        ctx.table_of("", t, &t.origin, &keys(""), "the scenario")
            .map(|_| ())
    });
    let body = retry(ctx, &mut clean, &mut found, |t| read_body(ctx, t, &root(t)));
    // The observables' columns are the body's (its per-surface ones).
    let layout = body.as_ref().map_or_else(Layout::fixed, Layout::of);
    let contact = retry(ctx, &mut clean, &mut found, |t| read_contact(ctx, &root(t)));
    if let Some(contact) = contact {
        retry(ctx, &mut clean, &mut found, |t| {
            read_disc(ctx, &root(t), contact).map(|_| ())
        });
    }
    // With the contact model unknown, read the state as for a model without extra rules.
    retry(ctx, &mut clean, &mut found, |t| {
        read_initial(ctx, &root(t), contact.unwrap_or(ContactModel::Frictionless)).map(|_| ())
    });
    retry(ctx, &mut clean, &mut found, |t| {
        read_effects(ctx, &root(t)).map(|_| ())
    });
    retry(ctx, &mut clean, &mut found, |t| {
        read_solver(ctx, &root(t)).map(|_| ())
    });
    retry(ctx, &mut clean, &mut found, |t| {
        read_output(ctx, &root(t)).map(|_| ())
    });
    retry(ctx, &mut clean, &mut found, |t| {
        read_check(ctx, &root(t)).map(|_| ())
    });
    let before = found.errs.len();
    retry(ctx, &mut clean, &mut found, |t| {
        read_observe(ctx, &root(t), &layout).map(|_| ())
    });
    if body.is_none() {
        // Without the body its per-surface columns are unknown: an observable's column is
        // not checked against a table that failed (its error would be a consequence).
        let pass = found.errs.split_off(before);
        found.errs.extend(pass.into_iter().filter(|e| {
            !e.key
                .as_deref()
                .is_some_and(|k| k.starts_with("observe") && k.ends_with(".column"))
        }));
    }
    // A key missing from a table that had an unknown key is most likely that key,
    // misspelt (`mas` for `mass`): not an error of its own. (The first error, `build`'s,
    // is never such a consequence: it stops at the unknown key.)
    let emptied = found.emptied;
    let mut errs = found.errs;
    errs.retain(|e| {
        !(e.kind == ErrorKind::Missing
            && emptied
                .iter()
                .any(|p| Some(p.as_str()) == e.key.as_deref().map(parent)))
    });
    Err(ordered(errs))
}

/// What the passes found: errors (each once), and the tables unknown keys were removed from.
struct Found {
    errs: Vec<ScenarioError>,
    emptied: Vec<String>,
}

/// The dotted path of the table holding `key`.
fn parent(key: &str) -> &str {
    key.rsplit_once('.').map_or("", |(p, _)| p)
}

/// Runs `read` on `tree`; an unknown-key error is recorded, the key removed and `read`
/// run again, until it succeeds or fails otherwise (that error recorded too).
fn retry<T>(
    ctx: &Ctx<'_>,
    tree: &mut Node,
    found: &mut Found,
    read: impl Fn(&Node) -> Result<T>,
) -> Option<T> {
    for _ in 0..=MAX_ERRORS {
        match read(tree) {
            Ok(v) => return Some(v),
            Err(e) => {
                let again = e.kind == ErrorKind::UnknownKey && remove(ctx, tree, &e);
                if again {
                    found
                        .emptied
                        .push(parent(e.key.as_deref().unwrap_or("")).to_owned());
                }
                if !found.errs.contains(&e) {
                    found.errs.push(e);
                }
                if !again {
                    return None;
                }
            }
        }
    }
    None
}

/// Removes the entry an unknown-key error names (found by its last key segment and its
/// place); false if there is none.
fn remove(ctx: &Ctx<'_>, node: &mut Node, e: &ScenarioError) -> bool {
    let key = e.key.as_deref().unwrap_or("");
    match &mut node.value {
        Value::Table(entries) => {
            if let Some(i) = entries.iter().position(|en| {
                key.ends_with(en.key.as_str()) && ctx.locate(&en.key_origin) == e.location
            }) {
                entries.remove(i);
                return true;
            }
            entries.iter_mut().any(|en| remove(ctx, &mut en.node, e))
        }
        Value::Array(items) => items.iter_mut().any(|n| remove(ctx, n, e)),
        _ => false,
    }
}

/// Sorted by place in the file (`--set` values last, in order), at most [`MAX_ERRORS`].
fn ordered(mut errs: Vec<ScenarioError>) -> Vec<ScenarioError> {
    errs.sort_by_key(|e| {
        (
            e.location.line.is_none(),
            e.location.line,
            e.location.column,
        )
    });
    errs.truncate(MAX_ERRORS);
    errs
}

/// The first integer of the document beyond TOML's 64-bit range (the spec: "If an
/// integer cannot be represented losslessly, an error must be thrown"): its span.
pub(super) fn wide_integer_table(table: &DeTable<'_>) -> Option<Range<usize>> {
    table
        .iter()
        .find_map(|(_, v)| wide_integer(v.get_ref(), v.span()))
}

pub(super) fn wide_integer(value: &DeValue<'_>, span: Range<usize>) -> Option<Range<usize>> {
    match value {
        DeValue::Integer(i) => i64::from_str_radix(i.as_str(), i.radix())
            .is_err()
            .then_some(span),
        DeValue::Array(a) => a.iter().find_map(|e| wide_integer(e.get_ref(), e.span())),
        DeValue::Table(t) => wide_integer_table(t),
        _ => None,
    }
}

/// The rule for an integer beyond 64 bits.
pub(super) const WIDE_INTEGER: &str = "integer out of TOML's range (-2^63 to 2^63 - 1, about ±9.2e18); write it as a float, e.g. 9.3e18";

/// The document's root as a table to read from.
fn root(tree: &Node) -> Sec<'_> {
    Sec {
        path: String::new(),
        node: tree,
    }
}
