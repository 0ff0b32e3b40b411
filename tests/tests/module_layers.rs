//! The modules of the core (`rust-core`) and of the simulator (`sim-data`)
//! import each other without cycles, and the core's folders follow the
//! pipeline: a folder uses only the folders above it in the table of its
//! `lib.rs`.
//!
//! The test reads the sources: every `crate::a::b` path and every
//! `super::x` path outside comments is an edge from the module whose file
//! holds it to the deepest module the path names. An edge between a module
//! and its own ancestor (a folder's `mod.rs` and its files) is not a
//! dependency between ideas and is left out; every other edge is lifted to
//! the two sibling modules under the lowest common ancestor, and the
//! graph of siblings must have no cycle.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The core's folders in pipeline order, as its `lib.rs` lists them.
const LAYERS: [&str; 7] = [
    "arkit",
    "geometry",
    "io",
    "session",
    "capture",
    "personalize",
    "avatar",
];

/// Module path of a source file: `src/personalize/ebfr.rs` →
/// `["personalize", "ebfr"]`, `src/session/mod.rs` → `["session"]`.
fn module_of(src: &Path, file: &Path) -> Vec<String> {
    let relative = file.strip_prefix(src).expect("under src");
    let mut parts: Vec<String> = relative
        .iter()
        .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    if parts.last().is_some_and(|p| p == "mod" || p == "lib") {
        parts.pop();
    }
    parts
}

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("readable source folder") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The identifier paths that follow each `crate::` or `super::` in `code`,
/// e.g. `crate::session::file::read` → `["session", "file", "read"]`
/// resolved against `module` (for `super::`).
fn referenced_paths(code: &str, module: &[String]) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    for (start, _) in code
        .match_indices("crate::")
        .chain(code.match_indices("super::"))
    {
        let before = code[..start].chars().last();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
            continue;
        }
        let rest = &code[start..];
        let mut segments: Vec<&str> = Vec::new();
        for segment in rest.split("::") {
            let ident: String = segment
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if ident.is_empty() {
                break;
            }
            let complete = ident.len() == segment.len();
            segments.push(&segment[..ident.len()]);
            if !complete {
                break;
            }
        }
        let mut path: Vec<String> = if segments.first() == Some(&"crate") {
            Vec::new()
        } else {
            // `super` of module `a::b` is `a`, whether its file is
            // `a/b.rs` or `a/b/mod.rs`.
            module[..module.len().saturating_sub(1)].to_vec()
        };
        let mut rest_segments = segments.iter().skip(1).peekable();
        while rest_segments.peek() == Some(&&"super") {
            rest_segments.next();
            path.pop();
        }
        path.extend(rest_segments.map(|s| s.to_string()));
        out.push(path);
    }
    out
}

/// Code without `//` comments (doc links are documentation, not imports).
fn without_comments(text: &str) -> String {
    text.lines()
        .map(|line| match line.find("//") {
            Some(i) => &line[..i],
            None => line,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The longest prefix of `path` that is a module.
fn deepest_module(modules: &BTreeSet<Vec<String>>, path: &[String]) -> Vec<String> {
    (0..=path.len())
        .rev()
        .map(|k| path[..k].to_vec())
        .find(|p| modules.contains(p))
        .unwrap_or_default()
}

/// The `src` folder of the workspace crate in folder `krate`.
fn src_of(krate: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(krate)
        .join("src")
}

/// Edges between sibling modules of the crate whose sources are in `src`:
/// `(parent, from child, to child)`.
fn sibling_edges(src: &Path) -> BTreeSet<(Vec<String>, String, String)> {
    let mut files = Vec::new();
    sources(src, &mut files);
    let modules: BTreeSet<Vec<String>> = files.iter().map(|f| module_of(src, f)).collect();
    let mut edges = BTreeSet::new();
    for file in &files {
        let module = module_of(src, file);
        let text = std::fs::read_to_string(file).expect("readable source");
        for path in referenced_paths(&without_comments(&text), &module) {
            let target = deepest_module(&modules, &path);
            let common = module
                .iter()
                .zip(&target)
                .take_while(|(a, b)| a == b)
                .count();
            if common == module.len() || common == target.len() {
                continue; // an ancestor or a descendant
            }
            if module[0] == "test_support" || target[0] == "test_support" {
                continue; // fixtures of the unit tests, a dev-dependency in all but name
            }
            edges.insert((
                module[..common].to_vec(),
                module[common].clone(),
                target[common].clone(),
            ));
        }
    }
    edges
}

/// Panics naming the first cycle among sibling modules of the crate in
/// `src`.
fn assert_no_cycle(src: &Path) {
    let edges = sibling_edges(src);
    let mut graph: BTreeMap<(Vec<String>, String), Vec<String>> = BTreeMap::new();
    for (parent, from, to) in &edges {
        graph
            .entry((parent.clone(), from.clone()))
            .or_default()
            .push(to.clone());
    }
    // Depth-first search for a back edge.
    fn visit(
        graph: &BTreeMap<(Vec<String>, String), Vec<String>>,
        parent: &[String],
        node: &str,
        stack: &mut Vec<String>,
        done: &mut BTreeSet<(Vec<String>, String)>,
    ) -> Option<Vec<String>> {
        if let Some(at) = stack.iter().position(|n| n == node) {
            let mut cycle = stack[at..].to_vec();
            cycle.push(node.to_string());
            return Some(cycle);
        }
        if done.contains(&(parent.to_vec(), node.to_string())) {
            return None;
        }
        stack.push(node.to_string());
        for next in graph
            .get(&(parent.to_vec(), node.to_string()))
            .into_iter()
            .flatten()
        {
            if let Some(cycle) = visit(graph, parent, next, stack, done) {
                return Some(cycle);
            }
        }
        stack.pop();
        done.insert((parent.to_vec(), node.to_string()));
        None
    }
    let mut done = BTreeSet::new();
    for (parent, node) in graph.keys() {
        let mut stack = Vec::new();
        if let Some(cycle) = visit(&graph, parent, node, &mut stack, &mut done) {
            panic!(
                "{}: import cycle under `crate::{}`: {}",
                src.display(),
                parent.join("::"),
                cycle.join(" → ")
            );
        }
    }
}

#[test]
fn the_core_has_no_import_cycle() {
    assert_no_cycle(&src_of("rust-core"));
}

#[test]
fn the_simulator_has_no_import_cycle() {
    assert_no_cycle(&src_of("sim-data"));
}

#[test]
fn core_folders_use_only_the_folders_above_them() {
    for (parent, from, to) in sibling_edges(&src_of("rust-core")) {
        if !parent.is_empty() {
            continue;
        }
        let rank = |m: &str| LAYERS.iter().position(|l| *l == m);
        match (rank(&from), rank(&to)) {
            (Some(a), Some(b)) => assert!(
                b < a,
                "`{from}` uses `{to}`, which comes after it in the pipeline"
            ),
            _ => panic!("`{from}` → `{to}`: a top-level module missing from LAYERS"),
        }
    }
}

#[test]
fn the_checker_reads_paths_and_finds_the_real_edges() {
    // The parser on a made-up pair of files: `a` and `b` under `x`.
    let a = vec!["x".to_string(), "a".to_string()];
    let code = without_comments(
        "use super::b::Thing; // crate::y::z is a comment\nfn f() { crate::x::c::g(); }",
    );
    assert_eq!(
        referenced_paths(&code, &a),
        vec![
            vec!["x".to_string(), "c".to_string(), "g".to_string()],
            vec!["x".to_string(), "b".to_string(), "Thing".to_string()],
        ]
    );
    // And on the real tree it finds the edges it should.
    let edges = sibling_edges(&src_of("rust-core"));
    let has = |from: &str, to: &str| {
        edges
            .iter()
            .any(|(p, f, t)| p.is_empty() && f == from && t == to)
    };
    assert!(has("personalize", "geometry"), "{edges:?}");
    assert!(has("session", "arkit"));
    assert!(!has("geometry", "session"));
}
