//! The shape of the code, checked: no source file over 500 lines, no function over 80 lines,
//! and no import cycle between the files of one module (a type two files share lives in a
//! file of its own). Reads the sources as text; see docs/architecture.md.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

mod source_support;
use source_support::rust_files;

/// Longest source file, lines.
const MAX_FILE_LINES: usize = 500;
/// Longest function, lines from its `fn` line to its closing brace.
const MAX_FN_LINES: usize = 80;
/// Parsers whose body is one table of keywords, each arm a line or two; splitting them would
/// scatter the table (the "parsers' tables"). File and function name.
const PARSER_TABLES: &[(&str, &str)] = &[
    ("io/vtk.rs", "columns"),      // the legacy VTK section keywords
    ("io/ply/header.rs", "parse"), // the PLY header keywords
    ("io/bgeo.rs", "header"),      // the BGEO header keys
];

fn src_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

fn sources() -> Vec<(String, String)> {
    let src = src_dir();
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    let rel = |p: &Path| p.strip_prefix(&src).unwrap().display().to_string();
    files
        .iter()
        .map(|p| (rel(p), std::fs::read_to_string(p).unwrap()))
        .collect()
}

/// The code of a line without a trailing `//` comment (string contents are kept; a `//` in
/// a string literal only shortens what is scanned).
fn code(line: &str) -> &str {
    line.find("//").map_or(line, |i| &line[..i])
}

/// The name of the function a line declares, if it does.
fn fn_name(line: &str) -> Option<&str> {
    let t = code(line).trim_start();
    let mut words = t.split_whitespace().peekable();
    while let Some(w) = words.next() {
        match w {
            "fn" => {
                let name = words.next()?;
                let end = name
                    .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                    .unwrap_or(name.len());
                return Some(&name[..end]);
            }
            "pub" | "const" | "async" | "unsafe" | "extern" | "\"C\"" => continue,
            _ if w.starts_with("pub(") => continue,
            _ => return None,
        }
    }
    None
}

/// The index of the line that closes the item starting at `lines[start]` (its braces
/// balanced, comments ignored), or `None` for an item without a body (ends with `;` first).
fn item_end<'a>(lines: impl Iterator<Item = &'a str>) -> Option<usize> {
    let (mut depth, mut opened) = (0i64, false);
    for (j, l) in lines.enumerate() {
        let c = code(l);
        if !opened && c.trim_end().ends_with(';') && !c.contains('{') {
            return None;
        }
        for ch in c.chars() {
            match ch {
                '{' => {
                    depth += 1;
                    opened = true;
                }
                '}' => depth -= 1,
                _ => {}
            }
        }
        if opened && depth <= 0 {
            return Some(j);
        }
    }
    None
}

/// (name, first line, length) of every function with a body in `text`.
fn functions(text: &str) -> Vec<(String, usize, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let Some(name) = fn_name(line) else { continue };
        if let Some(j) = item_end(lines[i..].iter().copied()) {
            out.push((name.to_string(), i + 1, j + 1));
        }
    }
    out
}

#[test]
fn no_source_file_is_over_the_limit() {
    let long: Vec<String> = sources()
        .iter()
        .filter(|(_, t)| t.lines().count() > MAX_FILE_LINES)
        .map(|(f, t)| format!("src/{f}: {} lines", t.lines().count()))
        .collect();
    assert!(
        long.is_empty(),
        "files over {MAX_FILE_LINES} lines:\n{}",
        long.join("\n")
    );
}

#[test]
fn no_function_is_over_the_limit() {
    let mut long = Vec::new();
    let mut seen = 0;
    for (f, t) in sources() {
        for (name, line, len) in functions(&t) {
            seen += 1;
            if len > MAX_FN_LINES && !PARSER_TABLES.contains(&(f.as_str(), name.as_str())) {
                long.push(format!("src/{f}:{line} fn {name}: {len} lines"));
            }
        }
    }
    assert!(
        seen > 500,
        "the scan found too few functions to be meaningful ({seen})"
    );
    assert!(
        long.is_empty(),
        "functions over {MAX_FN_LINES} lines:\n{}",
        long.join("\n")
    );
}

#[test]
fn the_function_scan_measures_what_it_should() {
    let text = "fn a() {\n    let x = 1;\n}\npub(crate) fn b(x: u8) -> u8 {\n    // }\n    x\n}\n\
                trait T {\n    fn c(&self);\n}\n";
    let f = functions(text);
    assert_eq!(
        f,
        vec![("a".to_string(), 1, 3), ("b".to_string(), 4, 4)],
        "trait declarations have no body; comments do not close"
    );
}

/// The files of one module folder as nodes: `src/render/transport.rs` is `transport`;
/// a sub-folder `src/geometry/mls/` is `mls`. `mod.rs` is the module itself, not a node.
fn module_nodes(dir: &Path) -> BTreeMap<String, Vec<PathBuf>> {
    let mut nodes = BTreeMap::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        let stem = p.file_stem().unwrap().to_string_lossy().to_string();
        if p.is_dir() {
            let mut files = Vec::new();
            rust_files(&p, &mut files);
            nodes.insert(stem, files);
        } else if p.extension().is_some_and(|x| x == "rs") && stem != "mod" {
            nodes.insert(stem, vec![p]);
        }
    }
    nodes
}

/// Names that `mod.rs` re-exports (`pub use file::{A, B}`) → the node defining them.
fn reexports(dir: &Path, nodes: &BTreeMap<String, Vec<PathBuf>>) -> BTreeMap<String, String> {
    let mut map = BTreeMap::new();
    let Ok(text) = std::fs::read_to_string(dir.join("mod.rs")) else {
        return map;
    };
    for stmt in use_statements(&text) {
        let Some(rest) = stmt
            .strip_prefix("pub use ")
            .or(stmt.strip_prefix("pub(crate) use "))
        else {
            continue;
        };
        let rest = rest.strip_prefix("self::").unwrap_or(rest);
        let Some((node, names)) = rest.split_once("::") else {
            continue;
        };
        if !nodes.contains_key(node) {
            continue;
        }
        for n in top_names(names) {
            map.insert(n, node.to_string());
        }
    }
    map
}

/// Every `use ...;` statement, whitespace folded, comments dropped.
fn use_statements(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur: Option<String> = None;
    for line in text.lines() {
        let c = code(line).trim();
        if cur.is_none()
            && (c.starts_with("use ")
                || c.starts_with("pub use ")
                || c.starts_with("pub(crate) use "))
        {
            cur = Some(String::new());
        }
        if let Some(s) = cur.as_mut() {
            s.push_str(c);
            s.push(' ');
            if c.ends_with(';') {
                out.push(
                    s.split_whitespace()
                        .collect::<Vec<_>>()
                        .join(" ")
                        .replace(":: ", "::")
                        .replace(" ::", "::"),
                );
                cur = None;
            }
        }
    }
    out
}

/// The first path segment of each item of `a`, `{a, b::c, d as e}`.
fn top_names(items: &str) -> Vec<String> {
    let items = items.trim().trim_end_matches(';').trim();
    let inner = items.strip_prefix('{').and_then(|s| s.strip_suffix('}'));
    let Some(inner) = inner else {
        return vec![
            items
                .split("::")
                .next()
                .unwrap()
                .split(' ')
                .next()
                .unwrap()
                .to_string(),
        ];
    };
    let (mut depth, mut start, mut out) = (0, 0, Vec::new());
    let bytes: Vec<char> = inner.chars().collect();
    for (i, ch) in bytes.iter().enumerate() {
        match ch {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                out.push(bytes[start..i].iter().collect::<String>());
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(bytes[start..].iter().collect::<String>());
    out.iter()
        .map(|s| {
            s.trim()
                .split("::")
                .next()
                .unwrap()
                .split(' ')
                .next()
                .unwrap()
                .to_string()
        })
        .filter(|s| !s.is_empty() && s != "self")
        .collect()
}

/// The sibling nodes a file of `node` refers to: through `super::x`, `crate::module::x`, or a
/// name `mod.rs` re-exports from `x`.
fn references(
    module: &str,
    text: &str,
    nodes: &BTreeMap<String, Vec<PathBuf>>,
    names: &BTreeMap<String, String>,
) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let prefixes = ["super::".to_string(), format!("crate::{module}::")];
    let mut add = |first: &str| {
        if nodes.contains_key(first) {
            out.insert(first.to_string());
        } else if let Some(n) = names.get(first) {
            out.insert(n.clone());
        }
    };
    for stmt in use_statements(text) {
        for p in &prefixes {
            if let Some(pos) = stmt.find(p.as_str()) {
                for n in top_names(&stmt[pos + p.len()..]) {
                    add(&n);
                }
            }
        }
    }
    for line in text.lines() {
        let c = code(line);
        if c.trim_start().starts_with("use ") || c.trim_start().starts_with("pub use ") {
            continue;
        }
        for p in &prefixes {
            let mut rest = c;
            while let Some(pos) = rest.find(p.as_str()) {
                rest = &rest[pos + p.len()..];
                let first: String = rest
                    .chars()
                    .take_while(|ch| ch.is_alphanumeric() || *ch == '_')
                    .collect();
                add(&first);
            }
        }
    }
    out
}

/// Every set of nodes that reach each other (a strongly connected component of more than one
/// node), each sorted: the import cycles of `graph`.
fn cycles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    let reach = |from: &str| {
        let mut seen = BTreeSet::new();
        let mut todo = vec![from.to_string()];
        while let Some(n) = todo.pop() {
            for m in graph.get(&n).into_iter().flatten() {
                if seen.insert(m.clone()) {
                    todo.push(m.clone());
                }
            }
        }
        seen
    };
    let reached: BTreeMap<&String, BTreeSet<String>> =
        graph.keys().map(|n| (n, reach(n))).collect();
    let mut out: Vec<Vec<String>> = Vec::new();
    for n in graph.keys() {
        let scc: Vec<String> = graph
            .keys()
            .filter(|m| *m == n || (reached[n].contains(*m) && reached[*m].contains(n)))
            .cloned()
            .collect();
        if scc.len() > 1 && !out.contains(&scc) {
            out.push(scc);
        }
    }
    out
}

/// `text` without its `#[cfg(test)]` items: a test module may use any file of its module.
fn without_tests(text: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = String::new();
    let mut i = 0;
    while i < lines.len() {
        if lines[i].trim() == "#[cfg(test)]" {
            // Skip the attribute and the item it marks (a body, or up to its `;`).
            let rest = &lines[i + 1..];
            let end = item_end(rest.iter().copied())
                .or_else(|| rest.iter().position(|l| code(l).trim_end().ends_with(';')))
                .unwrap_or(rest.len());
            i += end + 2;
            continue;
        }
        out.push_str(lines[i]);
        out.push('\n');
        i += 1;
    }
    out
}

fn module_graph(dir: &Path, module: &str) -> BTreeMap<String, BTreeSet<String>> {
    let nodes = module_nodes(dir);
    let names = reexports(dir, &nodes);
    let mut graph = BTreeMap::new();
    for (node, files) in &nodes {
        let mut refs = BTreeSet::new();
        for f in files {
            let text = without_tests(&std::fs::read_to_string(f).unwrap());
            refs.extend(references(module, &text, &nodes, &names));
        }
        refs.remove(node);
        graph.insert(node.clone(), refs);
    }
    graph
}

#[test]
fn no_import_cycle_between_the_files_of_a_module() {
    let src = src_dir();
    let mut found = Vec::new();
    let mut edges = 0;
    for e in std::fs::read_dir(&src).unwrap() {
        let dir = e.unwrap().path();
        if !dir.is_dir() {
            continue;
        }
        let module = dir.file_name().unwrap().to_string_lossy().to_string();
        let graph = module_graph(&dir, &module);
        edges += graph.values().map(BTreeSet::len).sum::<usize>();
        for c in cycles(&graph) {
            found.push(format!("src/{module}/: {} import each other", c.join(", ")));
        }
    }
    assert!(
        edges > 30,
        "the scan found too few imports to be meaningful ({edges})"
    );
    assert!(
        found.is_empty(),
        "import cycles inside modules:\n{}",
        found.join("\n")
    );
}

#[test]
fn the_cycle_scan_finds_a_planted_cycle() {
    let g: BTreeMap<String, BTreeSet<String>> = [
        ("a", vec!["b"]),
        ("b", vec!["c"]),
        ("c", vec!["a"]),
        ("d", vec!["a"]),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v.into_iter().map(String::from).collect()))
    .collect();
    assert_eq!(
        cycles(&g),
        vec![vec!["a".to_string(), "b".into(), "c".into()]]
    );
    assert_eq!(top_names("{a, b::{c, d}, e as f};"), vec!["a", "b", "e"]);
    let text = "use super::a;\n#[cfg(test)]\nmod tests {\n    use super::b;\n}\nfn f() {}\n";
    assert_eq!(without_tests(text), "use super::a;\nfn f() {}\n");
}
