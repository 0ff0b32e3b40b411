//! Every exported call that computes from data returns `Result`, so the
//! generated Swift can `try` it instead of `try!` (which crashes the app on
//! an error or a panic caught at the boundary). A call that only hands back
//! a value stored or fixed at build time may stay infallible; those are
//! listed here, so a new infallible export is a decision, not an accident.

use std::collections::BTreeSet;

/// The exports that may not fail, and why.
const INFALLIBLE: [(&str, &str); 8] = [
    ("arkit_names", "a fixed list"),
    ("arkit_keys", "a fixed list"),
    ("core_version", "a constant"),
    ("methods", "a fixed list"),
    ("default_method", "a constant"),
    ("method", "PersonalizedFace: a stored name"),
    ("shapes_found", "AvatarPreview: a stored count"),
    ("recorded_frame_count", "SessionHandle: a stored length"),
];

/// The exported functions of `source` and whether each returns `Result`:
/// every `pub fn` inside an `impl` block marked `#[uniffi::export]`, and
/// every `pub fn` marked so itself.
fn exports(source: &str) -> Vec<(String, bool)> {
    let mut out = Vec::new();
    let mut lines = source.lines().peekable();
    let mut in_export_impl = false;
    let mut marked = false;
    while let Some(line) = lines.next() {
        let trimmed = line.trim_start();
        if line.starts_with("#[uniffi::export") {
            marked = true;
            continue;
        }
        if marked && line.starts_with("impl ") {
            in_export_impl = true;
            marked = false;
            continue;
        }
        if line == "}" {
            in_export_impl = false;
        }
        let top_level_fn = marked && line.starts_with("pub fn ");
        if (in_export_impl && trimmed.starts_with("pub fn ")) || top_level_fn {
            marked = false;
            let name: String = trimmed["pub fn ".len()..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            // The signature runs to the line that opens the body.
            let mut signature = line.to_string();
            while !signature.trim_end().ends_with('{') {
                match lines.next() {
                    Some(next) => signature.push_str(next),
                    None => break,
                }
            }
            let returns = signature.split("->").nth(1).unwrap_or("").trim_start();
            out.push((name, returns.starts_with("Result<")));
        }
    }
    out
}

#[test]
fn every_export_that_computes_returns_a_result() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/src");
    let mut found = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "rs") {
            found.extend(exports(&std::fs::read_to_string(&path).unwrap()));
        }
    }
    assert!(found.len() > 25, "the exports were found: {found:?}");
    let allowed: BTreeSet<&str> = INFALLIBLE.iter().map(|(name, _)| *name).collect();
    let infallible: BTreeSet<&str> = found
        .iter()
        .filter(|(_, result)| !result)
        .map(|(name, _)| name.as_str())
        .collect();
    assert_eq!(
        infallible, allowed,
        "an export that computes from data returns Result; one that only hands back \
         a stored value may be listed in INFALLIBLE"
    );
}

#[test]
fn the_reader_tells_fallible_from_infallible_exports() {
    let source = "#[uniffi::export]\nimpl A {\n    pub fn a(&self) -> u32 {\n    }\n    \
                  pub fn b(\n        &self,\n    ) -> Result<u32, E> {\n    }\n}\n\
                  pub fn helper() -> u32 {\n}\n#[uniffi::export]\npub fn c() -> Vec<u8> {\n}\n";
    assert_eq!(
        exports(source),
        [
            ("a".to_string(), false),
            ("b".to_string(), true),
            ("c".to_string(), false)
        ]
    );
}
