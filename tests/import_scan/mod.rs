//! Which top-level crate modules a source file names, found by reading its tokens: every
//! `crate::x` path (also in `pub use`, grouped and multi-line `use crate::{a::X, b::{c, d}}`,
//! and inline paths without `use`), and every `super::` chain that climbs to the crate root
//! (counting inline `mod name { .. }` blocks). Comments, strings and character literals are
//! skipped, so doc links and messages may name any module.

/// One token of Rust source, with the line (from 1) it starts on.
#[derive(Debug, Clone, PartialEq)]
struct Token {
    text: String,
    line: usize,
}

/// The tokens of `src` that matter for paths: identifiers, `::` and single punctuation
/// characters. Comments, string, byte-string, raw-string and character literals are dropped.
fn tokens(src: &str) -> Vec<Token> {
    let c: Vec<char> = src.chars().collect();
    let (mut i, mut line, mut out) = (0, 1, Vec::new());
    while i < c.len() {
        let start_line = line;
        let ch = c[i];
        if ch == '\n' {
            line += 1;
            i += 1;
        } else if ch.is_whitespace() {
            i += 1;
        } else if ch == '/' && c.get(i + 1) == Some(&'/') {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if ch == '/' && c.get(i + 1) == Some(&'*') {
            i = skip_block_comment(&c, i, &mut line);
        } else if ch == '"' {
            i = skip_string(&c, i + 1, 0, &mut line);
        } else if ch == '\'' {
            i = skip_char_or_lifetime(&c, i);
        } else if ch.is_alphanumeric() || ch == '_' {
            let s = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            let word: String = c[s..i].iter().collect();
            if matches!(word.as_str(), "r" | "br" | "b" | "c" | "cr")
                && matches!(c.get(i), Some('"') | Some('#'))
            {
                let mut hashes = 0;
                while c.get(i + hashes) == Some(&'#') {
                    hashes += 1;
                }
                if c.get(i + hashes) == Some(&'"') {
                    i = skip_string(&c, i + hashes + 1, hashes, &mut line);
                    continue;
                }
            }
            if word == "b" && c.get(i) == Some(&'\'') {
                i = skip_char_or_lifetime(&c, i);
                continue;
            }
            out.push(Token {
                text: word,
                line: start_line,
            });
        } else if ch == ':' && c.get(i + 1) == Some(&':') {
            out.push(Token {
                text: "::".into(),
                line,
            });
            i += 2;
        } else {
            out.push(Token {
                text: ch.to_string(),
                line,
            });
            i += 1;
        }
    }
    out
}

/// Index after the (possibly nested) block comment opening at `i`.
fn skip_block_comment(c: &[char], mut i: usize, line: &mut usize) -> usize {
    let mut depth = 0;
    while i < c.len() {
        if c[i] == '/' && c.get(i + 1) == Some(&'*') {
            depth += 1;
            i += 2;
        } else if c[i] == '*' && c.get(i + 1) == Some(&'/') {
            depth -= 1;
            i += 2;
            if depth == 0 {
                return i;
            }
        } else {
            *line += usize::from(c[i] == '\n');
            i += 1;
        }
    }
    i
}

/// Index after a string whose contents start at `i`, closed by `"` and `hashes` `#`s (escapes
/// count only when `hashes` is 0 and the string is not raw: a raw string never has `\"`, so
/// treating `\` as an escape there could only skip a closing quote written as `\"#`, which a
/// raw string with hashes closes anyway).
fn skip_string(c: &[char], mut i: usize, hashes: usize, line: &mut usize) -> usize {
    while i < c.len() {
        match c[i] {
            '\\' if hashes == 0 => i += 2,
            '"' if (1..=hashes).all(|k| c.get(i + k) == Some(&'#')) => return i + 1 + hashes,
            ch => {
                *line += usize::from(ch == '\n');
                i += 1;
            }
        }
    }
    i
}

/// Index after the character literal or lifetime whose `'` is at `i`.
fn skip_char_or_lifetime(c: &[char], i: usize) -> usize {
    if c.get(i + 1) == Some(&'\\') {
        let mut j = i + 2;
        while j < c.len() && c[j] != '\'' {
            j += 1;
        }
        j + 1
    } else if c.get(i + 2) == Some(&'\'') {
        i + 3
    } else {
        i + 1 // a lifetime or label: its name follows as an identifier
    }
}

/// Every top-level module named by a path in `src`, a file whose module path below the crate
/// root is `module_path` (e.g. `["render", "camera"]` for `src/render/camera.rs`), with the
/// line it is named on. What reaches the root names a module or a root item (`Error`); the
/// caller keeps the names in its module list.
pub fn crate_modules_used(src: &str, module_path: &[&str]) -> Vec<(usize, String)> {
    let t = tokens(src);
    let mut out = Vec::new();
    // Inline modules open at the given brace depth.
    let (mut inline, mut depth): (Vec<usize>, usize) = (Vec::new(), 0);
    let mut i = 0;
    while i < t.len() {
        match t[i].text.as_str() {
            "{" => depth += 1,
            "}" => {
                if inline.last() == Some(&depth) {
                    inline.pop();
                }
                depth = depth.saturating_sub(1);
            }
            "mod" if t.get(i + 2).is_some_and(|b| b.text == "{") => inline.push(depth + 1),
            "crate" if is_sep(&t, i + 1) && !prev_is(&t, i, "::") => {
                heads(&t, i + 2, &mut out);
            }
            "super" if is_sep(&t, i + 1) && !prev_is(&t, i, "::") => {
                let mut ups = 1;
                let mut j = i + 2;
                while t.get(j).is_some_and(|x| x.text == "super") && is_sep(&t, j + 1) {
                    ups += 1;
                    j += 2;
                }
                if ups == module_path.len() + inline.len() {
                    heads(&t, j, &mut out);
                }
                i = j;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    out
}

fn is_sep(t: &[Token], i: usize) -> bool {
    t.get(i).is_some_and(|x| x.text == "::")
}

fn prev_is(t: &[Token], i: usize, s: &str) -> bool {
    i > 0 && t[i - 1].text == s
}

/// The first segment of the path at `i` (just after `crate::`), or of each item of the group
/// `{ .. }` there, pushed with its line.
fn heads(t: &[Token], i: usize, out: &mut Vec<(usize, String)>) {
    let Some(first) = t.get(i) else { return };
    if first.text != "{" {
        out.push((first.line, first.text.clone()));
        return;
    }
    let (mut depth, mut at_item) = (1, true);
    for x in &t[i + 1..] {
        match x.text.as_str() {
            "{" => depth += 1,
            "}" => {
                depth -= 1;
                if depth == 0 {
                    return;
                }
            }
            "," if depth == 1 => at_item = true,
            _ if at_item && depth == 1 => {
                out.push((x.line, x.text.clone()));
                at_item = false;
            }
            _ => {}
        }
    }
}
