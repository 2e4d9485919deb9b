//! The documentation holds together: every relative link of README.md and docs/*.md names a
//! file of the repository, every page of docs/ is reached from the README or from another
//! page, and a link to a section of a page (`page.md#anchor`) names one of its headings.
//!
//! The pages are read as text; nothing is built or run.

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

#[test]
fn anchors_follow_githubs_rule() {
    assert_eq!(anchor("## 7. Linear algebra"), "7-linear-algebra");
    assert_eq!(anchor("# Adding a system"), "adding-a-system");
}
