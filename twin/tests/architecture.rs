//! The direction of the data, checked on the source: twin's stages import
//! only the stages before them (source → st → scene → program, plant →
//! run → output), and no production file of either crate takes part in an
//! import circle, a parent and its child included (ARCHITECTURE.md).
//!
//! A reference is a `crate::a::b`, `super::a`, `self::a` or `child::a`
//! path in a source file's production part (comments and everything from
//! its first `#[cfg(test)]` on are left out); it names the longest module
//! path that is a file of the crate.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Module path (`program::bind`) → file, for every `.rs` file under `src`
/// except test files.
fn modules(src: &Path) -> BTreeMap<String, PathBuf> {
    let mut out = BTreeMap::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("source folder") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            let name = path.file_name().and_then(|n| n.to_str()).unwrap_or_default();
            if !name.ends_with(".rs") || name == "tests.rs" {
                continue;
            }
            let rel = path.strip_prefix(src).expect("under src").with_extension("");
            let mut parts: Vec<String> = rel.iter().map(|p| p.to_string_lossy().into_owned()).collect();
            if matches!(parts.last().map(String::as_str), Some("mod" | "lib" | "main")) {
                parts.pop();
            }
            out.insert(parts.join("::"), path);
        }
    }
    out
}

/// The production part of a file, without comments.
fn production(path: &Path) -> String {
    let text = std::fs::read_to_string(path).expect("readable");
    let text = text.split("#[cfg(test)]").next().unwrap_or_default();
    text.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The identifiers of a `::`-separated path starting at `at` in `text`.
fn path_at(text: &str, at: usize) -> Vec<&str> {
    let rest = &text[at..];
    let end = rest
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == ':'))
        .unwrap_or(rest.len());
    rest[..end].split("::").filter(|s| !s.is_empty()).collect()
}

/// The modules `module` refers to (other than itself): by `crate::` or
/// `super::` paths, and by paths that start with one of its own child
/// modules (`use child::Item;`). A parent and its child are files like
/// any other: a child that reaches up into its parent's items while the
/// parent uses the child is an import circle.
fn references(module: &str, text: &str, all: &BTreeMap<String, PathBuf>) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let own: Vec<&str> = module.split("::").filter(|s| !s.is_empty()).collect();
    let parent = &own[..own.len().saturating_sub(1)];
    let children: Vec<&str> = all
        .keys()
        .filter_map(|m| {
            let rest = if module.is_empty() {
                m.as_str()
            } else {
                m.strip_prefix(module)?.strip_prefix("::")?
            };
            (!rest.is_empty() && !rest.contains("::")).then_some(rest)
        })
        .collect();
    let mut prefixes: Vec<(String, Vec<&str>)> = vec![
        ("crate::".to_owned(), Vec::new()),
        ("super::".to_owned(), parent.to_vec()),
        ("self::".to_owned(), own.clone()),
    ];
    for child in &children {
        let mut base = own.clone();
        base.push(child);
        prefixes.push((format!("{child}::"), base));
    }
    let inline = inline_modules(text);
    for (prefix, base) in &prefixes {
        for (at, _) in text.match_indices(prefix.as_str()) {
            let preceded = text[..at].chars().next_back();
            // `pub(in crate::a)` restricts visibility: it imports nothing.
            if preceded.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_' || c == ':')
                || text[..at].ends_with("in ")
            {
                continue;
            }
            // In an inline `mod x { … }`, `super::` is the file's module.
            let base = if prefix == "super::" && inline.iter().any(|r| r.contains(&at)) {
                &own
            } else {
                base
            };
            let mut path = base.clone();
            let mut rest = path_at(text, at + prefix.len());
            // `super::super::x`: one level up per `super`.
            while prefix == "super::" && rest.first() == Some(&"super") {
                rest.remove(0);
                path.pop();
            }
            path.extend(rest);
            let target = (1..=path.len())
                .rev()
                .map(|k| path[..k].join("::"))
                .find(|m| all.contains_key(m));
            if let Some(target) = target
                && target != module
                && !target.is_empty()
            {
                out.insert(target);
            }
        }
    }
    out
}

/// The byte ranges of the inline modules (`mod x { … }`) of a file.
fn inline_modules(text: &str) -> Vec<std::ops::Range<usize>> {
    let mut out = Vec::new();
    for (at, _) in text.match_indices("mod ") {
        if text[..at]
            .chars()
            .next_back()
            .is_some_and(|c| c.is_ascii_alphanumeric() || c == '_')
        {
            continue;
        }
        let rest = &text[at + 4..];
        let name_end = rest
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(rest.len());
        if name_end == 0 || !rest[name_end..].trim_start().starts_with('{') {
            continue;
        }
        let open = at + 4 + name_end + rest[name_end..].find('{').unwrap_or(0);
        let mut depth = 0usize;
        for (i, c) in text[open..].char_indices() {
            match c {
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        out.push(open..open + i);
                        break;
                    }
                }
                _ => {}
            }
        }
    }
    out
}

fn graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let all = modules(src);
    all.iter()
        .map(|(m, path)| (m.clone(), references(m, &production(path), &all)))
        .collect()
}

/// The import circles: strongly connected groups of more than one file.
fn circles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    // Kosaraju: finish order on the graph, then components on its reverse.
    fn visit(v: &str, g: &BTreeMap<String, BTreeSet<String>>, seen: &mut BTreeSet<String>, order: &mut Vec<String>) {
        if !seen.insert(v.to_owned()) {
            return;
        }
        for w in g.get(v).into_iter().flatten() {
            visit(w, g, seen, order);
        }
        order.push(v.to_owned());
    }
    let mut reverse: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (v, ws) in graph {
        for w in ws {
            reverse.entry(w.clone()).or_default().insert(v.clone());
        }
    }
    let (mut seen, mut order) = (BTreeSet::new(), Vec::new());
    for v in graph.keys() {
        visit(v, graph, &mut seen, &mut order);
    }
    let mut assigned = BTreeSet::new();
    let mut out = Vec::new();
    for v in order.iter().rev() {
        let mut component = Vec::new();
        visit(v, &reverse, &mut assigned, &mut component);
        if component.len() > 1 {
            component.sort();
            out.push(component);
        }
    }
    out
}

fn crate_src(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(name).join("src")
}

#[test]
fn no_production_file_is_in_an_import_circle() {
    for name in ["planner", "twin"] {
        let graph = graph(&crate_src(name));
        assert!(graph.len() > 20, "{name}: {} files found", graph.len());
        let edges: Vec<String> = circles(&graph)
            .iter()
            .flat_map(|c| {
                let graph = &graph;
                c.iter().flat_map(move |a| {
                    graph[a]
                        .iter()
                        .filter(|b| c.contains(b))
                        .map(move |b| format!("{a} → {b}"))
                })
            })
            .collect();
        assert!(edges.is_empty(), "{name}: imports in circles:\n{}", edges.join("\n"));
    }
}

#[test]
fn twin_stages_import_only_the_stages_before_them() {
    // Stage → the stages it may import.
    let allowed: BTreeMap<&str, &[&str]> = BTreeMap::from([
        ("source", &[][..]),
        ("st", &["source"][..]),
        ("l5x", &["source"][..]),
        ("scene", &["source", "st", "l5x"][..]),
        ("program", &["source", "st", "l5x", "scene"][..]),
        ("plant", &["source", "st", "l5x", "scene"][..]),
        ("run", &["source", "st", "l5x", "scene", "program", "plant"][..]),
        ("output", &["source", "st", "l5x", "scene", "program", "plant", "run"][..]),
    ]);
    let stage = |module: &str| module.split("::").next().unwrap_or_default().to_owned();
    let mut wrong = Vec::new();
    for (module, targets) in graph(&crate_src("twin")) {
        let from = stage(&module);
        let Some(may) = allowed.get(from.as_str()) else {
            continue; // lib.rs, main.rs: they put the stages together.
        };
        for target in targets {
            let to = stage(&target);
            if to != from && !may.contains(&to.as_str()) {
                wrong.push(format!("{module} imports {target}"));
            }
        }
    }
    assert!(wrong.is_empty(), "{wrong:#?}");
}

#[test]
fn the_interpreter_does_not_import_the_compiler() {
    // What runs each scan (the interpreter, the task engine, the steps)
    // works on the compiled form alone.
    let graph = graph(&crate_src("twin"));
    let runtime = |m: &str| m.starts_with("program::exec") || m == "program::controller" || m == "program::steps";
    let wrong: Vec<String> = graph
        .iter()
        .filter(|(m, _)| runtime(m))
        .flat_map(|(m, targets)| {
            targets
                .iter()
                .filter(|t| t.starts_with("program::compile"))
                .map(move |t| format!("{m} imports {t}"))
        })
        .collect();
    assert!(graph.keys().any(|m| m == "program::exec"), "the interpreter is found");
    assert!(wrong.is_empty(), "{wrong:#?}");
}

#[test]
fn the_checker_sees_a_circle_and_a_backward_import() {
    let all: BTreeMap<String, PathBuf> = ["scene", "scene::raw", "program", "program::bind", "program::coord"]
        .iter()
        .map(|m| ((*m).to_owned(), PathBuf::new()))
        .collect();
    let bind = references(
        "program::bind",
        "use super::coord::bind; use crate::scene::raw::X;",
        &all,
    );
    assert_eq!(
        bind,
        BTreeSet::from(["program::coord".to_owned(), "scene::raw".to_owned()])
    );
    let graph = BTreeMap::from([
        ("program::bind".to_owned(), bind),
        (
            "program::coord".to_owned(),
            references("program::coord", "use super::bind::Bind;", &all),
        ),
    ]);
    assert_eq!(
        circles(&graph),
        vec![vec!["program::bind".to_owned(), "program::coord".to_owned()]]
    );
    // `super::` in an inline module is the file's own module; `super::super`
    // goes up twice.
    let inline = references(
        "program::bind",
        "mod exerr {\n    use super::Thing;\n}\nuse super::super::scene::raw::Y;",
        &all,
    );
    assert_eq!(inline, BTreeSet::from(["scene::raw".to_owned()]));
    // A parent using its child while the child uses the parent's items.
    let parent = references("program", "mod bind;\nuse bind::Bindings;", &all);
    assert_eq!(parent, BTreeSet::from(["program::bind".to_owned()]));
    let child = references("program::bind", "use super::Program;", &all);
    assert_eq!(child, BTreeSet::from(["program".to_owned()]));
    let graph = BTreeMap::from([("program".to_owned(), parent), ("program::bind".to_owned(), child)]);
    assert_eq!(
        circles(&graph),
        vec![vec!["program".to_owned(), "program::bind".to_owned()]]
    );
}
