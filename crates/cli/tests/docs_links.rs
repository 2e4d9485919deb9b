//! The documentation holds together: every relative link of README.md and docs/*.md names a
//! file of the repository, every page of docs/ is reached from the README or from another
//! page, a link to a section of a page (`page.md#anchor`) names one of its headings, and a
//! paragraph of docs/method.md cited by name (`docs/method.md §8.2, "At rest"`, in code,
//! docs or scripts) is in the section the citation gives.
//!
//! The pages and sources are read as text; nothing is built or run.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// README.md and every page of docs/, as (path relative to the root, text).
fn pages() -> Vec<(String, String)> {
    let mut out = vec![("README.md".to_owned(), read(&root().join("README.md")))];
    let mut docs: Vec<PathBuf> = fs::read_dir(root().join("docs"))
        .expect("docs/ is readable")
        .map(|e| e.expect("a docs/ entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    for p in docs {
        let name = format!("docs/{}", p.file_name().unwrap().to_string_lossy());
        out.push((name, read(&p)));
    }
    out
}

fn read(p: &Path) -> String {
    fs::read_to_string(p).unwrap_or_else(|e| panic!("cannot read {}: {e}", p.display()))
}

/// The targets of the markdown links `[text](target)` of a page, outside code blocks,
/// that are not web addresses.
fn relative_links(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut in_code = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        for (i, _) in line.match_indices("](") {
            let rest = &line[i + 2..];
            let Some(end) = rest.find(')') else { continue };
            let target = &rest[..end];
            if !target.contains("://") && !target.starts_with("mailto:") && !target.is_empty() {
                out.push(target.to_owned());
            }
        }
    }
    out
}

/// GitHub's anchor of a heading: lower case, spaces to hyphens, punctuation dropped.
fn anchor(heading: &str) -> String {
    heading
        .trim_start_matches('#')
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

fn anchors(text: &str) -> BTreeSet<String> {
    text.lines()
        .filter(|l| l.starts_with('#'))
        .map(anchor)
        .collect()
}

#[test]
fn every_relative_link_names_a_file_and_every_anchor_a_heading() {
    let mut broken = Vec::new();
    for (page, text) in pages() {
        let dir = root().join(&page).parent().unwrap().to_path_buf();
        for link in relative_links(&text) {
            let (file, section) = link.split_once('#').unwrap_or((link.as_str(), ""));
            let target = if file.is_empty() {
                root().join(&page)
            } else {
                dir.join(file)
            };
            if !target.exists() {
                broken.push(format!("{page}: ({link}) names no file"));
                continue;
            }
            let is_page = target.extension().is_some_and(|e| e == "md");
            if !section.is_empty() && is_page && !anchors(&read(&target)).contains(section) {
                broken.push(format!("{page}: ({link}) names no heading of {file}"));
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn every_page_of_docs_is_reached_from_the_readme_or_another_page() {
    let pages = pages();
    let mut linked = BTreeSet::new();
    for (page, text) in &pages {
        let dir = Path::new(page).parent().unwrap();
        for link in relative_links(text) {
            let file = link.split('#').next().unwrap_or_default();
            if !file.is_empty() {
                let joined = dir.join(file);
                let normal = joined.to_string_lossy().replace("docs/../", "");
                if normal != *page {
                    linked.insert(normal);
                }
            }
        }
    }
    let orphans: Vec<&String> = pages
        .iter()
        .map(|(p, _)| p)
        .filter(|p| p.starts_with("docs/") && !linked.contains(*p))
        .collect();
    assert!(
        orphans.is_empty(),
        "pages no other page links to: {orphans:?}"
    );
}

/// The files that may cite docs/method.md: the sources of crates/ (src, tests, benches,
/// examples), docs/*.md and scripts/, as (path relative to the root, text).
fn citing_files() -> Vec<(String, String)> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = fs::read_dir(dir) else {
            return;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                if p.file_name().is_some_and(|n| n != "target" && n != ".venv") {
                    walk(&p, out);
                }
            } else if p
                .extension()
                .is_some_and(|e| e == "rs" || e == "md" || e == "py")
            {
                out.push(p);
            }
        }
    }
    let mut paths = Vec::new();
    for dir in ["crates", "docs", "scripts"] {
        walk(&root().join(dir), &mut paths);
    }
    paths.sort();
    paths
        .into_iter()
        .map(|p| {
            let name = p
                .strip_prefix(root())
                .unwrap()
                .to_string_lossy()
                .into_owned();
            (name, read(&p))
        })
        .collect()
}

/// `text` with its line breaks, and the comment markers that start the next line, made
/// single spaces: a citation wrapped over two comment lines reads as one.
fn joined(text: &str) -> String {
    text.lines()
        .map(|l| {
            let l = l.trim_start();
            ["//!", "///", "//", "#"]
                .iter()
                .find_map(|m| l.strip_prefix(m))
                .unwrap_or(l)
                .trim()
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// The citations `§N, "Name"` (or `§N "Name"`) of `text`, as (N, Name); with `page` only
/// those that follow the name of that page (`method.md §N, "Name"`, `[method.md](method.md)
/// §N, "Name"`).
fn citations(text: &str, page: Option<&str>) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for (i, _) in text.match_indices('§') {
        if let Some(page) = page {
            let before = text[..i].trim_end().trim_end_matches(')');
            let before = before.strip_suffix(&format!("]({page}")).unwrap_or(before);
            if !before.ends_with(page) {
                continue;
            }
        }
        let rest = &text[i + '§'.len_utf8()..];
        let number: String = rest
            .chars()
            .take_while(|c| c.is_ascii_digit() || *c == '.')
            .collect();
        let number = number.trim_end_matches('.').to_owned();
        let rest = rest[number.len()..].trim_start_matches('.');
        let rest = rest.strip_prefix(',').unwrap_or(rest).trim_start();
        let Some(rest) = rest.strip_prefix('"') else {
            continue;
        };
        let Some(end) = rest.find('"') else { continue };
        if !number.is_empty() {
            out.push((number, rest[..end].to_owned()));
        }
    }
    out
}

/// The text of section `number` of a page (`## 3.`, `### 8.2`), to the next heading of
/// its level or above.
fn section<'a>(page: &'a str, number: &str) -> Option<&'a str> {
    let heading = |l: &str| {
        let level = l.len() - l.trim_start_matches('#').len();
        let n = l[level..].split_whitespace().next()?.trim_end_matches('.');
        (level > 0).then(|| (level, n.to_owned()))
    };
    let mut start = None;
    let mut offset = 0;
    for line in page.split_inclusive('\n') {
        if let Some((level, n)) = heading(line) {
            match start {
                Some((at, l)) if level <= l => return Some(&page[at..offset]),
                None if n == number => start = Some((offset, level)),
                _ => {}
            }
        }
        offset += line.len();
    }
    start.map(|(at, _)| &page[at..])
}

#[test]
fn every_cited_paragraph_of_the_method_is_in_its_section() {
    let method = read(&root().join("docs/method.md"));
    let mut broken = Vec::new();
    for (file, text) in citing_files() {
        let own = file == "docs/method.md";
        let page = (!own).then_some("method.md");
        for (number, name) in citations(&joined(&text), page) {
            let found = section(&method, &number).is_some_and(|s| {
                s.lines()
                    .any(|l| l.starts_with('#') && l.contains(name.as_str()))
                    || joined(s).contains(&format!("**{name}"))
            });
            if !found {
                broken.push(format!("{file}: §{number}, \"{name}\""));
            }
        }
    }
    assert!(
        broken.is_empty(),
        "cited paragraphs of docs/method.md that are not in their section (a heading or a \
         bold paragraph title):\n{}",
        broken.join("\n")
    );
}

#[test]
fn a_citation_is_read_across_a_wrapped_comment() {
    let text = "/// as in docs/method.md\n/// §8.2, \"At rest\", and §7 \"Pruned matrices\"";
    assert_eq!(
        citations(&joined(text), Some("method.md")),
        [("8.2".to_owned(), "At rest".to_owned())]
    );
    assert_eq!(citations(&joined(text), None).len(), 2);
    let page = "## 7. A\nx\n### 7.1 B\ny\n## 8. C\nz\n";
    assert_eq!(section(page, "7"), Some("## 7. A\nx\n### 7.1 B\ny\n"));
    assert_eq!(section(page, "7.1"), Some("### 7.1 B\ny\n"));
    assert_eq!(section(page, "8"), Some("## 8. C\nz\n"));
}

#[test]
fn anchors_follow_githubs_rule() {
    assert_eq!(anchor("## 7. Linear algebra"), "7-linear-algebra");
    assert_eq!(anchor("# Adding a system"), "adding-a-system");
}
