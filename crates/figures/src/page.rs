//! The tour's page: sections of headline numbers, text, tables, figures and links to
//! data files, rendered as one self-contained `index.html`.

use std::fmt::Write as _;

/// What the page says about itself: the program, when, and how to make it again.
#[derive(Debug, Clone, Default)]
pub struct PageHeader {
    /// The rollstack version.
    pub version: String,
    /// The source commit, when known at build time.
    pub commit: Option<String>,
    /// The date the page was made (UTC, `YYYY-MM-DD`).
    pub date: String,
    /// The command line that makes the page.
    pub command: String,
}

/// What one system shows on the page.
#[derive(Debug, Default)]
pub struct Section {
    /// Heading in the page.
    pub title: String,
    /// HTML blocks (text, commands, images, links), in order. Paths are relative to the tour directory.
    pub blocks: Vec<Block>,
}

/// One piece of a section's page.
#[derive(Debug)]
pub enum Block {
    /// A paragraph of plain text.
    Text(String),
    /// A PNG written into the tour directory, with a caption.
    Image {
        /// File name relative to the tour directory.
        file: String,
        /// Caption under the image.
        caption: String,
    },
    /// A command line and the text it printed.
    Command {
        /// The command line, as a user would type it.
        line: String,
        /// What it printed on stdout.
        output: String,
    },
    /// A link to a data file (CSV) in the tour directory.
    Data {
        /// File name relative to the tour directory.
        file: String,
        /// What it holds.
        description: String,
    },
}

impl Block {
    /// An image with its caption.
    #[must_use]
    pub fn image(file: impl Into<String>, caption: impl Into<String>) -> Self {
        Self::Image {
            file: file.into(),
            caption: caption.into(),
        }
    }

    /// A link to a data file with what it holds.
    #[must_use]
    pub fn data(file: impl Into<String>, description: impl Into<String>) -> Self {
        Self::Data {
            file: file.into(),
            description: description.into(),
        }
    }
}

/// `s` with the characters HTML gives a meaning escaped.
fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The HTML page of `sections` (each with the name of its directory, relative to the
/// page), and a line per failed section.
#[must_use]
pub fn render_html(
    header: &PageHeader,
    sections: &[(String, Section)],
    failures: &[String],
) -> String {
    let mut h = String::from(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>rollstack tour</title>\n\
         <style>body{font-family:sans-serif;max-width:1100px;margin:auto;padding:1em}\
         table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:3px 8px;text-align:right}\
         img{max-width:100%;border:1px solid #ddd}figure{margin:1em 0}</style></head><body>\n\
         <h1>rollstack tour</h1>\n<p>Headline results of every system, computed with built-in \
         defaults. Equation numbers refer to Honein (2024).</p>\n",
    );
    let commit = header
        .commit
        .as_deref()
        .map_or_else(String::new, |c| format!(", commit {}", escape(c)));
    let _ = writeln!(
        h,
        "<p>rollstack {}{commit}, {}. Reproduce this page with <code>{}</code>; one \
         section alone with <code>rollstack tour --only NAME</code>.</p>\n<ul>",
        escape(&header.version),
        escape(&header.date),
        escape(&header.command)
    );
    for (name, s) in sections {
        let _ = write!(h, "<li><a href=\"#{name}\">{}</a></li>", escape(&s.title));
    }
    h.push_str("</ul>\n");
    for f in failures {
        let _ = writeln!(h, "<p style=\"color:#b00\">Failed: {}</p>", escape(f));
    }
    for (name, s) in sections {
        let _ = writeln!(h, "<h2 id=\"{name}\">{}</h2>", escape(&s.title));
        let _ = writeln!(
            h,
            "<p><small>Files in <code>{name}/</code>; this section alone: \
             <code>rollstack tour --only {name}</code></small></p>"
        );
        for b in &s.blocks {
            render_block(&mut h, name, b);
        }
    }
    h.push_str("</body></html>\n");
    h
}

/// One block of a section whose files lie in `dir`.
fn render_block(h: &mut String, dir: &str, block: &Block) {
    match block {
        Block::Text(t) => {
            let _ = writeln!(h, "<p>{}</p>", escape(t));
        }
        Block::Image { file, caption } => {
            let _ = writeln!(
                h,
                "<figure><img src=\"{dir}/{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>",
                escape(file),
                escape(caption),
                escape(caption)
            );
        }
        Block::Command { line, output } => {
            let _ = writeln!(
                h,
                "<pre style=\"background:#f4f4f4;padding:6px\"><b>$ {}</b>\n{}</pre>",
                escape(line),
                escape(output.trim_end())
            );
        }
        Block::Data { file, description } => {
            let _ = writeln!(
                h,
                "<p>Data: <a href=\"{dir}/{}\">{}</a> ({})</p>",
                escape(file),
                escape(file),
                escape(description)
            );
        }
    }
}
