//! The scanner behind `tests/layering.rs`: which module paths a Rust source file names.
//!
//! It reads source text only (it shares nothing with the crates it checks): comments, string
//! and character literals are blanked first, then every path that starts at `crate::`,
//! `super::` or `self::` is expanded (use groups `{a, b::{c}}` included) and resolved to an
//! absolute module path, with inline `mod name { … }` blocks taken into account, so that
//! `super` inside `mod tests` means the file's module.

/// One path a file names: the line it is on, the path as absolute segments from the crate
/// root, and the path as written (for the message).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Reference {
    /// 1-based line of the path's first segment.
    pub line: usize,
    /// Absolute segments, without a trailing `self`.
    pub path: Vec<String>,
    /// As written, from the root keyword to the last segment.
    pub written: String,
}

/// The module path of a source file given relative to its crate's `src/` folder:
/// `models/cycle/sample/warm.rs` → `[models, cycle, sample, warm]`, `run/mod.rs` → `[run]`,
/// `lib.rs` → `[]`.
pub fn module_of(relative: &str) -> Vec<String> {
    let mut parts: Vec<String> = relative.split('/').map(str::to_string).collect();
    let last = parts.pop().unwrap_or_default();
    let stem = last.strip_suffix(".rs").unwrap_or(&last);
    if stem != "mod" && stem != "lib" && stem != "main" {
        parts.push(stem.to_string());
    }
    parts
}

/// The source with comments, strings and character literals replaced by spaces (newlines
/// kept, so line numbers stay right). Lifetimes (`'a`) are kept as code.
pub fn code_only(src: &str) -> String {
    let c: Vec<char> = src.chars().collect();
    let mut out = String::with_capacity(src.len());
    let blank = |out: &mut String, ch: char| out.push(if ch == '\n' { '\n' } else { ' ' });
    let mut i = 0;
    while i < c.len() {
        let at = |k: usize| c.get(k).copied().unwrap_or('\0');
        let ident_before = i > 0 && (c[i - 1].is_alphanumeric() || c[i - 1] == '_');
        if at(i) == '/' && at(i + 1) == '/' {
            while i < c.len() && c[i] != '\n' {
                blank(&mut out, c[i]);
                i += 1;
            }
        } else if at(i) == '/' && at(i + 1) == '*' {
            // Block comments nest in Rust.
            let mut depth = 0usize;
            while i < c.len() {
                if at(i) == '/' && at(i + 1) == '*' {
                    depth += 1;
                    out.push_str("  ");
                    i += 2;
                } else if at(i) == '*' && at(i + 1) == '/' {
                    depth -= 1;
                    out.push_str("  ");
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    blank(&mut out, c[i]);
                    i += 1;
                }
            }
        } else if !ident_before && (at(i) == 'r' || (at(i) == 'b' && at(i + 1) == 'r')) && {
            let mut k = i + if at(i) == 'b' { 2 } else { 1 };
            while at(k) == '#' {
                k += 1;
            }
            at(k) == '"'
        } {
            // Raw string: r"…", r#"…"#, br"…".
            let mut k = i + if at(i) == 'b' { 2 } else { 1 };
            let mut hashes = 0;
            while at(k) == '#' {
                hashes += 1;
                k += 1;
            }
            k += 1;
            while k < c.len() && !(c[k] == '"' && (1..=hashes).all(|h| at(k + h) == '#')) {
                k += 1;
            }
            let end = (k + 1 + hashes).min(c.len());
            for &ch in &c[i..end] {
                blank(&mut out, ch);
            }
            i = end;
        } else if at(i) == '"' {
            blank(&mut out, c[i]);
            i += 1;
            while i < c.len() && c[i] != '"' {
                if c[i] == '\\' {
                    blank(&mut out, c[i]);
                    i += 1;
                }
                if i < c.len() {
                    blank(&mut out, c[i]);
                    i += 1;
                }
            }
            if i < c.len() {
                blank(&mut out, c[i]);
                i += 1;
            }
        } else if at(i) == '\'' {
            // A character literal ('x', '\n', '\u{7f}') or a lifetime ('a).
            let end = if at(i + 1) == '\\' {
                (i + 2..c.len()).find(|&k| c[k] == '\'').map(|k| k + 1)
            } else if at(i + 2) == '\'' {
                Some(i + 3)
            } else {
                None
            };
            match end {
                Some(end) => {
                    for &ch in &c[i..end] {
                        blank(&mut out, ch);
                    }
                    i = end;
                }
                None => {
                    out.push('\'');
                    i += 1;
                }
            }
        } else {
            out.push(c[i]);
            i += 1;
        }
    }
    out
}

#[derive(Clone, Debug, PartialEq, Eq)]
enum Tok {
    Ident(String),
    PathSep,
    Open,
    Close,
    Comma,
    Star,
    Other(char),
}

fn tokens(code: &str) -> Vec<(Tok, usize)> {
    let c: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    while i < c.len() {
        let ch = c[i];
        if ch == '\n' {
            line += 1;
            i += 1;
        } else if ch.is_whitespace() {
            i += 1;
        } else if ch.is_alphabetic() || ch == '_' {
            let start = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            let word: String = c[start..i].iter().collect();
            out.push((Tok::Ident(word), line));
        } else if ch == ':' && c.get(i + 1) == Some(&':') {
            out.push((Tok::PathSep, line));
            i += 2;
        } else {
            out.push((
                match ch {
                    '{' => Tok::Open,
                    '}' => Tok::Close,
                    ',' => Tok::Comma,
                    '*' => Tok::Star,
                    other => Tok::Other(other),
                },
                line,
            ));
            i += 1;
        }
    }
    out
}

/// Expands the use tree that starts at `t[i]` (after a `::`) under `prefix`; returns the index
/// after it. Leaves go to `out` as segment lists.
fn expand(
    t: &[(Tok, usize)],
    mut i: usize,
    mut prefix: Vec<String>,
    out: &mut Vec<Vec<String>>,
) -> usize {
    loop {
        match t.get(i).map(|x| &x.0) {
            Some(Tok::Ident(s)) => {
                prefix.push(s.clone());
                i += 1;
                if t.get(i).map(|x| &x.0) == Some(&Tok::PathSep) {
                    i += 1;
                    continue;
                }
                out.push(prefix);
                return i;
            }
            Some(Tok::Open) => {
                i += 1;
                let mut depth = 0usize;
                while let Some((tok, _)) = t.get(i) {
                    match tok {
                        Tok::Close if depth == 0 => return i + 1,
                        Tok::Close => {
                            depth -= 1;
                            i += 1;
                        }
                        Tok::Comma => i += 1,
                        Tok::Ident(_) | Tok::Open | Tok::Star if depth == 0 => {
                            i = expand(t, i, prefix.clone(), out);
                            // Skip an alias (`as Name`) up to the next item.
                            while let Some((tok, _)) = t.get(i) {
                                if matches!(tok, Tok::Comma | Tok::Close) {
                                    break;
                                }
                                if *tok == Tok::Open {
                                    depth += 1;
                                }
                                i += 1;
                            }
                        }
                        _ => i += 1,
                    }
                }
                return i;
            }
            _ => {
                // `*`, or the end of the path.
                out.push(prefix);
                return i + usize::from(matches!(t.get(i).map(|x| &x.0), Some(Tok::Star)));
            }
        }
    }
}

/// Every path in `src` that starts at `crate::`, `super::` or `self::`, resolved against the
/// file's module path `module` (see [`module_of`]). `super` past the crate root is dropped
/// (the compiler refuses it anyway); `$crate` in macros is not a path of this file.
pub fn references(src: &str, module: &[String]) -> Vec<Reference> {
    let t = tokens(&code_only(src));
    let mut out = Vec::new();
    // Inline modules: (name, brace depth inside them).
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0usize;
    let mut i = 0;
    while i < t.len() {
        let prev = if i > 0 { Some(&t[i - 1].0) } else { None };
        match &t[i].0 {
            Tok::Open => {
                depth += 1;
                i += 1;
                continue;
            }
            Tok::Close => {
                if inline.last().is_some_and(|(_, d)| *d == depth) {
                    inline.pop();
                }
                depth = depth.saturating_sub(1);
                i += 1;
                continue;
            }
            Tok::Ident(w) if w == "mod" => {
                if let (Some((Tok::Ident(name), _)), Some((Tok::Open, _))) =
                    (t.get(i + 1), t.get(i + 2))
                {
                    inline.push((name.clone(), depth + 1));
                }
                i += 1;
                continue;
            }
            _ => {}
        }
        let root = match &t[i].0 {
            Tok::Ident(w) if w == "crate" || w == "super" || w == "self" => w.clone(),
            _ => {
                i += 1;
                continue;
            }
        };
        let starts_path = !matches!(prev, Some(Tok::PathSep) | Some(Tok::Other('$')))
            && t.get(i + 1).map(|x| &x.0) == Some(&Tok::PathSep);
        if !starts_path {
            i += 1;
            continue;
        }
        let line = t[i].1;
        let mut base: Vec<String> = if root == "crate" {
            Vec::new()
        } else {
            module
                .iter()
                .cloned()
                .chain(inline.iter().map(|(n, _)| n.clone()))
                .collect()
        };
        let mut written = vec![root.clone()];
        let mut k = i + 2;
        let mut valid = true;
        if root == "super" {
            valid = base.pop().is_some();
            while let (Some((Tok::Ident(w), _)), Some((Tok::PathSep, _))) = (t.get(k), t.get(k + 1))
            {
                if w != "super" {
                    break;
                }
                valid &= base.pop().is_some();
                written.push("super".into());
                k += 2;
            }
        }
        let mut leaves = Vec::new();
        let next = expand(&t, k, Vec::new(), &mut leaves);
        if valid {
            for leaf in leaves {
                let mut path = base.clone();
                path.extend(leaf.iter().filter(|s| s.as_str() != "self").cloned());
                let mut w = written.clone();
                w.extend(leaf);
                out.push(Reference {
                    line,
                    path,
                    written: w.join("::"),
                });
            }
        }
        i = next.max(i + 1);
    }
    out
}

/// Lines of `src` (code only) on which the identifier `name` appears, 1-based.
pub fn lines_naming(src: &str, name: &str) -> Vec<usize> {
    tokens(&code_only(src))
        .into_iter()
        .filter(|(t, _)| *t == Tok::Ident(name.to_string()))
        .map(|(_, line)| line)
        .collect()
}
