//! Reading the docs for `tests/docs_commands.rs`: the markdown files, their fenced blocks, the
//! shell commands in the ```sh blocks, their links and the repository paths they name.
#![allow(dead_code)]

pub mod table;

use std::path::{Path, PathBuf};

/// The repository's folder.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// README.md, then docs/*.md sorted by name, as (path relative to the root, text).
pub fn documents() -> Vec<(String, String)> {
    let mut names: Vec<String> = std::fs::read_dir(root().join("docs"))
        .expect("docs/ exists")
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".md"))
        .map(|n| format!("docs/{n}"))
        .collect();
    names.sort();
    names.insert(0, "README.md".to_string());
    names
        .into_iter()
        .map(|n| {
            let text = std::fs::read_to_string(root().join(&n)).unwrap();
            (n, text)
        })
        .collect()
}

/// A fenced code block: its language tag ("" when none), first line number (1-based) and body.
pub struct Block {
    pub lang: String,
    pub line: usize,
    pub body: Vec<String>,
}

/// Every fenced block (```lang ... ```) of a markdown text.
pub fn blocks(text: &str) -> Vec<Block> {
    let mut out = Vec::new();
    let mut open: Option<Block> = None;
    for (i, line) in text.lines().enumerate() {
        // A fence's info string holds no backtick (```` ```sh ```` in a sentence is no fence).
        let fence = line
            .trim_start()
            .strip_prefix("```")
            .filter(|info| !info.contains('`'));
        match (&mut open, fence) {
            (None, Some(lang)) => {
                open = Some(Block {
                    lang: lang.trim().to_string(),
                    line: i + 1,
                    body: Vec::new(),
                })
            }
            (Some(_), Some(_)) => out.push(open.take().unwrap()),
            (Some(b), None) => b.body.push(line.to_string()),
            (None, None) => {}
        }
    }
    assert!(open.is_none(), "a fenced block is never closed");
    out
}

/// The commands of a ```sh block: continuation lines (`\`) joined, comment lines (`#...`,
/// including `#!` and `#SBATCH`) and trailing comments (` # ...` outside quotes) dropped,
/// whitespace collapsed to single spaces.
pub fn commands(block: &Block) -> Vec<String> {
    let mut out = Vec::new();
    let mut pending = String::new();
    for line in &block.body {
        if let Some(head) = line.trim_end().strip_suffix('\\') {
            pending.push_str(head);
            pending.push(' ');
            continue;
        }
        let whole = std::mem::take(&mut pending) + line;
        let command = without_comment(whole.trim());
        if !command.is_empty() {
            out.push(command.split_whitespace().collect::<Vec<_>>().join(" "));
        }
    }
    out
}

/// A shell line without its comment: from a `#` at the start or after a space, outside quotes.
fn without_comment(line: &str) -> String {
    let mut quote = None;
    let mut prev = ' ';
    for (i, c) in line.char_indices() {
        match quote {
            Some(q) if c == q => quote = None,
            Some(_) => {}
            None if c == '\'' || c == '"' => quote = Some(c),
            None if c == '#' && prev == ' ' => return line[..i].trim_end().to_string(),
            None => {}
        }
        prev = c;
    }
    line.to_string()
}

/// The targets of markdown links and images, `[text](target)` and `![alt](target)`.
pub fn link_targets(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find("](") {
        let after = &rest[i + 2..];
        match after.find(')') {
            Some(j) => {
                out.push(after[..j].trim().to_string());
                rest = &after[j..];
            }
            None => break,
        }
    }
    out
}

/// Folders of the repository whose paths the docs name in backticks (`src/io/ply/...`).
pub const REPO_FOLDERS: &[&str] = &[
    "src/", "tests/", "samples/", "benches/", "python/", "docs/", "fuzz/", "tools/", ".ci/",
];

/// Words inside `backticks` that name a repository path (start with one of [`REPO_FOLDERS`])
/// and are not patterns (`{:04}`, `*`, `NAME`, `<frame>`).
pub fn repo_paths(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (k, span) in text.split('`').enumerate() {
        if k % 2 == 0 {
            continue;
        }
        for word in span.split_whitespace() {
            let word = word.trim_end_matches([',', '.', ';', ':', ')', '\'', '"']);
            let word = word.trim_start_matches(['(', '\'', '"']);
            let is_pattern = word.contains(['{', '*', '<', '$']) || word.contains("NAME");
            if REPO_FOLDERS.iter().any(|f| word.starts_with(f)) && !is_pattern {
                out.push(word.to_string());
            }
        }
    }
    out
}

/// Whether `target` (a link target relative to `doc`, or a path relative to the root) exists,
/// and, for a markdown file with `#anchor`, whether that file has a heading of that anchor.
pub fn exists(doc: &str, target: &str) -> bool {
    let (path, anchor) = target.split_once('#').unwrap_or((target, ""));
    let base = Path::new(doc).parent().unwrap_or(Path::new(""));
    let file = if path.is_empty() {
        root().join(doc)
    } else {
        root().join(base).join(path)
    };
    if !file.exists() {
        return false;
    }
    if anchor.is_empty() || file.extension().is_none_or(|e| e != "md") {
        return true;
    }
    let text = std::fs::read_to_string(&file).unwrap_or_default();
    text.lines()
        .filter_map(|l| l.strip_prefix('#'))
        .any(|h| slug(h.trim_start_matches('#')) == anchor)
}

/// GitHub's anchor of a heading: lower case, punctuation but `-` and `_` dropped, spaces to `-`.
pub fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, ' ' | '-' | '_'))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}
