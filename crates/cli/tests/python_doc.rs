//! docs/python.md against the Python module's sources, so that the page cannot drift: every
//! call the page shows (`` `simulate(scene, t_end=, …)` ``) names a function of its
//! section's module (`## `rollstack.blocks``: `rollstack/blocks.py`) with those keywords
//! and those defaults, and every kind of failure event a run reports is named.
//!
//! The module is not built here: its Python sources are read as text.

use std::collections::BTreeMap;

const DOC: &str = include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/python.md"));
const PACKAGE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../python/python/rollstack");

/// A Python function's parameters, in order, with their default as written (if any).
type Parameters = Vec<(String, Option<String>)>;

/// Every `def name(…)` of a Python source, by name (methods included).
fn definitions(source: &str) -> BTreeMap<String, Parameters> {
    let mut out = BTreeMap::new();
    for (start, _) in source.match_indices("def ") {
        let line_start = source[..start].rfind('\n').map_or(0, |i| i + 1);
        if !source[line_start..start].trim().is_empty() {
            continue; // "def " inside a line, as in a docstring
        }
        let rest = &source[start + 4..];
        let Some(open) = rest.find('(') else { continue };
        let name = rest[..open].trim().to_owned();
        let mut depth = 0;
        let mut end = open;
        for (i, c) in rest[open..].char_indices() {
            match c {
                '(' | '[' => depth += 1,
                ')' | ']' => depth -= 1,
                _ => {}
            }
            if depth == 0 {
                end = open + i;
                break;
            }
        }
        let parameters = split_top_level(&rest[open + 1..end])
            .into_iter()
            .filter_map(|p| {
                let p = p.trim().trim_start_matches('*');
                let (head, default) = match p.split_once('=') {
                    Some((h, d)) => (h, Some(d.trim().to_owned())),
                    None => (p, None),
                };
                let name = head.split(':').next().unwrap_or_default().trim().to_owned();
                (!name.is_empty() && name != "self" && name != "cls").then_some((name, default))
            })
            .collect();
        out.insert(name, parameters);
    }
    out
}

/// A parameter list split at its top-level commas.
fn split_top_level(text: &str) -> Vec<&str> {
    let (mut depth, mut start, mut out) = (0, 0, Vec::new());
    for (i, c) in text.char_indices() {
        match c {
            '(' | '[' | '{' => depth += 1,
            ')' | ']' | '}' => depth -= 1,
            ',' if depth == 0 => {
                out.push(&text[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(&text[start..]);
    out
}

/// Whether two defaults say the same: equal numbers, or equal text.
fn same_default(doc: &str, source: &str) -> bool {
    match (doc.parse::<f64>(), source.parse::<f64>()) {
        (Ok(a), Ok(b)) => a == b,
        _ => doc == source,
    }
}

/// The calls the page shows, `(module, name, arguments)`, by section.
fn documented_calls() -> Vec<(String, String, String)> {
    let mut out = Vec::new();
    let mut module = None;
    for paragraph in DOC.split("\n\n") {
        for line in paragraph.lines().filter(|l| l.starts_with("## ")) {
            module = line
                .strip_prefix("## `rollstack.")
                .and_then(|rest| rest.split('`').next())
                .map(str::to_owned);
        }
        let Some(module) = &module else { continue };
        let text = paragraph.replace('\n', " ");
        for span in text.split('`').skip(1).step_by(2) {
            let Some(open) = span.find('(') else { continue };
            let name = span[..open].rsplit('.').next().unwrap_or_default();
            let plain_name =
                !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
            if plain_name && span.ends_with(')') && name != "help" {
                let arguments = span[open + 1..span.len() - 1].to_owned();
                out.push((module.clone(), name.to_owned(), arguments));
            }
        }
    }
    out
}

#[test]
fn every_call_on_the_page_is_a_function_of_its_module() {
    let calls = documented_calls();
    assert!(calls.len() > 20, "the page's calls are read: {calls:?}");
    let mut failures = Vec::new();
    for (module, name, arguments) in &calls {
        let path = format!("{PACKAGE}/{module}.py");
        let source = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
        let defs = definitions(&source);
        let class = [format!("class {name}("), format!("class {name}:")];
        if class.iter().any(|c| source.contains(c.as_str())) {
            continue; // a class: `Scene(**tables)`
        }
        let Some(parameters) = defs.get(name) else {
            failures.push(format!("rollstack.{module} has no function {name}"));
            continue;
        };
        for argument in split_top_level(arguments) {
            for alternative in argument.split(" or ") {
                let a = alternative.trim().trim_start_matches('*');
                let (key, default) = match a.split_once('=') {
                    Some((k, d)) => (k.trim(), Some(d.trim())),
                    None => (a, None),
                };
                let plain =
                    !key.is_empty() && key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
                if !plain {
                    continue; // `...`, `*`, or an example value such as a dict
                }
                match parameters.iter().find(|(p, _)| p == key) {
                    None => failures.push(format!(
                        "{module}.{name}({arguments}): no parameter {key} (it has {:?})",
                        parameters.iter().map(|(p, _)| p).collect::<Vec<_>>()
                    )),
                    Some((_, source_default)) => {
                        if let (Some(d), Some(s)) =
                            (default.filter(|d| !d.is_empty()), source_default)
                        {
                            let comparable =
                                d.parse::<f64>().is_ok() || d.starts_with('"') || d == "None";
                            if comparable && !same_default(d, s) {
                                failures.push(format!(
                                    "{module}.{name}: the page says {key}={d}, the source {key}={s}"
                                ));
                            }
                        }
                    }
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "docs/python.md disagrees with the module:\n  {}",
        failures.join("\n  ")
    );
}

/// The names of a Python module's `__all__`.
fn exported(source: &str) -> Vec<String> {
    let start = source.find("__all__ = [").expect("the module has __all__") + 11;
    let end = start + source[start..].find(']').expect("__all__ is closed");
    source[start..end]
        .split(',')
        .map(|n| n.trim().trim_matches('"').to_owned())
        .filter(|n| !n.is_empty())
        .collect()
}

/// The text of each `## `rollstack.MODULE`` section of the page, by module.
fn sections() -> BTreeMap<String, String> {
    DOC.split("\n## ")
        .filter_map(|section| {
            let module = section.strip_prefix("`rollstack.")?.split('`').next()?;
            Some((module.to_owned(), section.replace('\n', " ")))
        })
        .collect()
}

#[test]
fn every_public_name_of_a_module_is_on_its_section() {
    let sections = sections();
    assert_eq!(sections.len(), 5, "{:?}", sections.keys());
    let mut missing = Vec::new();
    for (module, text) in &sections {
        let source = std::fs::read_to_string(format!("{PACKAGE}/{module}.py")).unwrap();
        for name in exported(&source) {
            let shown = text.split('`').skip(1).step_by(2).any(|span| {
                let head = span.split('(').next().unwrap_or_default();
                head.rsplit('.').next() == Some(name.as_str())
            });
            if !shown {
                missing.push(format!("rollstack.{module}.{name}"));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "docs/python.md does not show: {}",
        missing.join(", ")
    );
}

#[test]
fn every_failure_event_kind_is_named() {
    use blockstack::events::EventKind;
    let blocks_py = std::fs::read_to_string(format!("{PACKAGE}/blocks.py")).unwrap();
    for kind in [
        EventKind::SupportLost,
        EventKind::Tipped,
        EventKind::HeightDropped,
        EventKind::TouchedFloor,
    ] {
        let name = serde_json::to_value(kind).unwrap();
        let name = name.as_str().unwrap();
        assert!(
            DOC.contains(&format!("`{name}`")),
            "docs/python.md does not name {name}"
        );
        assert!(
            blocks_py.contains(&format!("\"{name}\"")),
            "blocks.py's simulate does not name {name}"
        );
    }
}

#[test]
fn the_source_reader_reads_what_it_should() {
    let defs = definitions("def f(a: int, *, b: float = 1.0, c: Dict[str, int] = {}) -> None:\n    pass\n    def g(self, x=\"y\"):\n");
    assert_eq!(
        defs["f"]
            .iter()
            .map(|(p, _)| p.as_str())
            .collect::<Vec<_>>(),
        ["a", "b", "c"]
    );
    assert_eq!(defs["f"][1].1.as_deref(), Some("1.0"));
    assert_eq!(defs["g"], [("x".to_owned(), Some("\"y\"".to_owned()))]);
    assert!(same_default("1", "1.0") && !same_default("2e-3", "0.02"));
}
