//! docs/scenarios.md's key reference is the scenario schema's: the section between its
//! markers must equal `schema::reference()`. `ELLIPSOID_WRITE_DOCS=1 cargo test -p
//! ellipsoid-core --test schema_docs` writes it there (the prose around it is kept).

use std::path::PathBuf;

use ellipsoid_core::scenario::schema;

const BEGIN: &str = "<!-- key reference: written from the scenario schema (crates/ellipsoid-core/src/scenario/schema.rs) -->\n";
const END: &str = "<!-- end of the key reference -->\n";

/// `doc` with its key reference replaced by the schema's, or why it cannot be.
fn rewritten(doc: &str) -> Result<String, String> {
    let (head, rest) = doc
        .split_once(BEGIN)
        .ok_or("the key reference's opening marker is missing")?;
    let (_, tail) = rest
        .split_once(END)
        .ok_or("the key reference's closing marker is missing")?;
    Ok(format!("{head}{BEGIN}{}{END}{tail}", schema::reference()))
}

/// Ok when `doc`'s key reference is the schema's; else the first line that differs.
fn compare(doc: &str) -> Result<(), String> {
    let want = rewritten(doc)?;
    if want == doc {
        return Ok(());
    }
    let first = doc
        .lines()
        .zip(want.lines())
        .find(|(a, b)| a != b)
        .map_or_else(
            || "the document ends early or late".to_owned(),
            |(a, b)| format!("the document has\n  {a}\nthe schema says\n  {b}"),
        );
    Err(format!(
        "docs/scenarios.md's key reference differs from the scenario schema: {first}"
    ))
}

#[test]
fn the_key_reference_of_docs_scenarios_md_is_the_schemas() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/scenarios.md");
    let doc = std::fs::read_to_string(&path).expect("docs/scenarios.md");
    if let Err(e) = compare(&doc) {
        if std::env::var_os("ELLIPSOID_WRITE_DOCS").is_some() {
            std::fs::write(&path, rewritten(&doc).expect(&e)).expect("write docs/scenarios.md");
            return;
        }
        panic!(
            "{e}\n(ELLIPSOID_WRITE_DOCS=1 cargo test -p ellipsoid-core --test schema_docs writes it)"
        );
    }
}

/// A key of the schema missing from the document, a row the schema does not have, or a
/// changed unit is found; the prose around the reference is free.
#[test]
fn a_reference_that_disagrees_with_the_schema_is_found() {
    let good = rewritten(&format!("prose\n{BEGIN}{END}more prose\n")).unwrap();
    assert_eq!(compare(&good), Ok(()));
    let without = good.replace(
        &good
            .lines()
            .find(|l| l.starts_with("| `initial.height`"))
            .map(|l| format!("{l}\n"))
            .unwrap(),
        "",
    );
    assert!(compare(&without).unwrap_err().contains("initial.height"));
    let extra = good.replace(
        END,
        &format!("| `initial.spin` | rad/s | number | 0 | ? |\n{END}"),
    );
    assert!(compare(&extra).is_err());
    let unit = good.replace("| `body.mass` | kg |", "| `body.mass` | g |");
    assert!(compare(&unit).unwrap_err().contains("body.mass"));
    assert!(compare("prose without markers\n").is_err());
    assert_eq!(compare(&good.replace("more prose", "other prose")), Ok(()));
}
