//! The repository's Markdown documentation: every relative link in `README.md` and `docs/*.md`
//! names a file of the repository and, with `#anchor`, a heading in it; the interface table of
//! `docs/fmu.md` names every variable of `modelDescription.xml`, and only those; every backticked
//! repository path names a file or folder and every backticked Rust path names code.

mod common;
use common::repo;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The lines of `text` outside fenced code blocks, with their line numbers (from 1).
fn prose_lines(text: &str) -> Vec<(usize, &str)> {
    let mut fenced = false;
    let mut lines = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        } else if !fenced {
            lines.push((i + 1, line));
        }
    }
    lines
}

/// `line` without its inline code spans (`...`).
fn without_code(line: &str) -> String {
    let mut out = String::new();
    for (i, part) in line.split('`').enumerate() {
        if i % 2 == 0 {
            out.push_str(part);
        }
    }
    out
}

/// The targets of the inline links and images `[text](target)` of `text`, with line numbers.
fn links(text: &str) -> Vec<(usize, String)> {
    let mut found = Vec::new();
    for (n, line) in prose_lines(text) {
        let line = without_code(line);
        let mut rest = line.as_str();
        while let Some(i) = rest.find("](") {
            let after = &rest[i + 2..];
            let Some(end) = after.find(')') else { break };
            let target = after[..end].split_whitespace().next().unwrap_or("");
            found.push((n, target.to_owned()));
            rest = &after[end..];
        }
    }
    found
}

/// GitHub's anchor of a heading: lower case, without punctuation other than `-` and `_`,
/// spaces as `-`.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, ' ' | '-' | '_'))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The anchors of the headings of a Markdown text (repeated headings get `-1`, `-2`, ...).
fn anchors(text: &str) -> BTreeSet<String> {
    let mut seen = BTreeSet::new();
    for (_, line) in prose_lines(text) {
        let hashes = line.chars().take_while(|&c| c == '#').count();
        if !(1..=6).contains(&hashes) || !line[hashes..].starts_with(' ') {
            continue;
        }
        let base = slug(&line[hashes..]);
        let mut anchor = base.clone();
        let mut k = 0;
        while seen.contains(&anchor) {
            k += 1;
            anchor = format!("{base}-{k}");
        }
        seen.insert(anchor);
    }
    seen
}

/// What is wrong with the relative links of the Markdown file `file` (text `text`) in the
/// repository `root`: one message per broken link.
fn broken_links(root: &Path, file: &Path, text: &str) -> Vec<String> {
    let mut broken = Vec::new();
    let name = file
        .strip_prefix(root)
        .unwrap_or(file)
        .display()
        .to_string();
    for (n, target) in links(text) {
        if target.contains("://") || target.starts_with("mailto:") {
            continue;
        }
        let (path, anchor) = match target.split_once('#') {
            Some((p, a)) => (p, Some(a)),
            None => (target.as_str(), None),
        };
        if path.is_empty() {
            let anchor = anchor.unwrap_or("");
            if !anchors(text).contains(anchor) {
                broken.push(format!("{name}:{n}: {target}: no heading #{anchor} here"));
            }
            continue;
        }
        let Ok(resolved) = file.parent().unwrap().join(path).canonicalize() else {
            broken.push(format!("{name}:{n}: {target}: no such file"));
            continue;
        };
        if !resolved.starts_with(root) {
            broken.push(format!("{name}:{n}: {target}: outside the repository"));
            continue;
        }
        if let Some(anchor) = anchor {
            let ok = resolved.extension().is_some_and(|e| e == "md")
                && std::fs::read_to_string(&resolved).is_ok_and(|t| anchors(&t).contains(anchor));
            if !ok {
                broken.push(format!("{name}:{n}: {target}: no heading #{anchor} there"));
            }
        }
    }
    broken
}

/// `README.md` and every `docs/*.md`.
fn markdown_files(root: &Path) -> Vec<PathBuf> {
    let mut files = vec![root.join("README.md")];
    for entry in std::fs::read_dir(root.join("docs")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "md") {
            files.push(path);
        }
    }
    files.sort();
    files
}

#[test]
fn every_relative_link_resolves() {
    let root = repo();
    let files = markdown_files(&root);
    assert!(files.len() >= 10, "{files:?}");
    let mut broken = Vec::new();
    let mut checked = 0;
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        checked += links(&text).len();
        broken.extend(broken_links(&root, file, &text));
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
    // The README links every page of docs/.
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    for file in files
        .iter()
        .filter(|f| f.parent().unwrap().ends_with("docs"))
    {
        let name = file.file_name().unwrap().to_str().unwrap();
        assert!(
            readme.contains(&format!("(docs/{name})")),
            "README.md does not link docs/{name}"
        );
    }
    assert!(checked > 50, "only {checked} links found");
}

#[test]
fn the_link_check_finds_broken_links() {
    let root = repo();
    let file = root.join("docs/fmu.md");
    let text = "\
# Top heading
## Sign conventions: `iso` (ISO 8855)
[ok](errata.md) [ok](#top-heading) [ok](#sign-conventions-iso-iso-8855)
![ok](demo.png) [web](https://example.org/x.md) `[code](missing.md)`
[gone](missing.md) [no heading](errata.md#nowhere) [outside](../..) [here](#nowhere)
```
[fenced](missing-too.md)
```
";
    let broken = broken_links(&root, &file, text);
    assert_eq!(broken.len(), 4, "{broken:#?}");
    assert!(
        broken[0].ends_with("missing.md: no such file"),
        "{}",
        broken[0]
    );
    assert!(
        broken[1].contains("errata.md#nowhere: no heading"),
        "{}",
        broken[1]
    );
    assert!(
        broken[2].ends_with("../..: outside the repository"),
        "{}",
        broken[2]
    );
    assert!(
        broken[3].ends_with("#nowhere: no heading #nowhere here"),
        "{}",
        broken[3]
    );
    assert_eq!(slug("Model Exchange"), "model-exchange");
    assert_eq!(slug(" 1. Fy row: a8 "), "1-fy-row-a8");
    let twice = anchors("## A\ntext\n## A\n");
    assert!(twice.contains("a") && twice.contains("a-1"), "{twice:?}");
}

/// The variable names in the first column of the table under `## Interface` of `docs/fmu.md`;
/// a cell "`X_a1` .. `X_aN`" stands for X_a1 to X_aN.
fn documented_variables(text: &str) -> BTreeSet<String> {
    let start = text
        .find("\n## Interface\n")
        .expect("docs/fmu.md has no Interface section");
    let mut names = BTreeSet::new();
    for line in text[start..].lines().skip(2) {
        if line.starts_with("## ") {
            break;
        }
        let Some(cell) = line.strip_prefix('|').and_then(|l| l.split('|').next()) else {
            continue;
        };
        let spans: Vec<&str> = cell.split('`').skip(1).step_by(2).collect();
        if let [.., first, last] = spans[..]
            && cell.contains("` .. `")
        {
            let (prefix, from) = first.rsplit_once("_a").unwrap();
            let to = last
                .strip_prefix(prefix)
                .unwrap()
                .strip_prefix("_a")
                .unwrap();
            let (from, to): (u32, u32) = (from.parse().unwrap(), to.parse().unwrap());
            names.extend((from..=to).map(|k| format!("{prefix}_a{k}")));
            names.extend(spans[..spans.len() - 2].iter().map(|s| s.to_string()));
        } else {
            names.extend(spans.iter().map(|s| s.to_string()));
        }
    }
    names
}

#[test]
fn the_interface_table_names_every_variable() {
    let root = repo();
    let xml = std::fs::read_to_string(root.join("modelDescription/modelDescription.xml")).unwrap();
    let doc = roxmltree::Document::parse(&xml).unwrap();
    let declared: BTreeSet<String> = doc
        .descendants()
        .filter(|n| n.has_tag_name("ScalarVariable"))
        .map(|n| n.attribute("name").unwrap().to_owned())
        .collect();
    let text = std::fs::read_to_string(root.join("docs/fmu.md")).unwrap();
    let documented = documented_variables(&text);
    let missing: Vec<_> = declared.difference(&documented).collect();
    let unknown: Vec<_> = documented.difference(&declared).collect();
    assert!(
        missing.is_empty() && unknown.is_empty(),
        "docs/fmu.md's interface table lacks {missing:?} and names {unknown:?}, \
         which modelDescription.xml does not declare"
    );
    assert!(declared.len() > 50, "{declared:?}");
}

#[test]
fn interface_cells_expand_coefficient_ranges() {
    let text = "x\n## Interface\n\n| variable | c |\n|---|---|\n\
                | `Fz` | input |\n| `Fy_C`, `Fy_a1` .. `Fy_a3` | parameter |\n\
                | `lag_Fx`, `lag_Fy` | local |\n\n## Next\n| `not_this` | x |\n";
    let names: Vec<_> = documented_variables(text).into_iter().collect();
    assert_eq!(
        names,
        ["Fy_C", "Fy_a1", "Fy_a2", "Fy_a3", "Fz", "lag_Fx", "lag_Fy"]
    );
}

/// The inline code spans (`...`) of the prose of `text`, with line numbers.
fn code_spans(text: &str) -> Vec<(usize, String)> {
    let mut found = Vec::new();
    for (n, line) in prose_lines(text) {
        for (i, part) in line.split('`').enumerate() {
            if i % 2 == 1 {
                found.push((n, part.to_owned()));
            }
        }
    }
    found
}

/// Whether a code span is a placeholder or pattern rather than one name: `<name>.rs`,
/// `docs/*.md`, `file:///C:/...`, a command with arguments.
fn is_pattern(span: &str) -> bool {
    span.contains(['<', '*', '{', ' ', '$']) || span.contains("...") || span.contains("://")
}

/// The folders of the repository a backticked path may start from: the root and each crate
/// (a page about tire-gap names its files from the crate's `src/`).
fn path_roots(root: &Path) -> Vec<PathBuf> {
    let mut roots = vec![root.to_path_buf()];
    for entry in std::fs::read_dir(root.join("crates")).unwrap() {
        roots.push(entry.unwrap().path());
    }
    roots
}

/// The names every Rust file of the repository defines (functions, types, constants, traits,
/// macros, modules, enum variants and fields are not told apart) and its module names (file
/// and folder names).
fn rust_names(root: &Path) -> BTreeSet<String> {
    fn walk(dir: &Path, names: &mut BTreeSet<String>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            let file = path.file_name().unwrap().to_string_lossy().into_owned();
            if path.is_dir() {
                if !matches!(file.as_str(), "target" | ".git" | ".venv" | "node_modules") {
                    names.insert(file.replace('-', "_"));
                    walk(&path, names);
                }
            } else if let Some(stem) = file.strip_suffix(".rs") {
                names.insert(stem.to_owned());
                let text = std::fs::read_to_string(&path).unwrap();
                for word in text.split(|c: char| !(c.is_alphanumeric() || c == '_')) {
                    if !word.is_empty() {
                        names.insert(word.to_owned());
                    }
                }
            }
        }
    }
    let mut names = BTreeSet::new();
    walk(root, &mut names);
    names
}

/// What is stale among the backticked names of the Markdown file `file` (text `text`): a
/// repository path (starting with one of the repository's top-level folders) that names no
/// file or folder, from the root or a crate; a Rust path (`a::b`) one of whose segments is no
/// name of the repository's code, the standard library's or a dependency's that it uses.
fn stale_names(root: &Path, file: &Path, text: &str, names: &BTreeSet<String>) -> Vec<String> {
    let name = file
        .strip_prefix(root)
        .unwrap_or(file)
        .display()
        .to_string();
    let top: BTreeSet<String> = std::fs::read_dir(root)
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.path().is_dir())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|f| f != "target") // build outputs, made by the commands the docs describe
        .collect();
    let roots = path_roots(root);
    let mut stale = Vec::new();
    for (n, span) in code_spans(text) {
        if is_pattern(&span) {
            continue;
        }
        let first = span.split('/').next().unwrap_or("");
        if span.contains('/') && top.contains(first) {
            let path = span.trim_end_matches('/');
            if !roots.iter().any(|r| r.join(path).exists()) {
                stale.push(format!("{name}:{n}: `{span}`: no such file or folder"));
            }
        } else if span.contains("::") {
            let item = span.trim_end_matches("()").trim_end_matches('!');
            let unknown: Vec<&str> = item
                .split("::")
                .filter(|s| !s.is_empty() && !names.contains(*s))
                .collect();
            if !unknown.is_empty() {
                stale.push(format!(
                    "{name}:{n}: `{span}`: no {} in the code",
                    unknown.join(", ")
                ));
            }
        }
    }
    stale
}

#[test]
fn every_backticked_path_and_item_exists() {
    let root = repo();
    let names = rust_names(&root);
    let mut stale = Vec::new();
    for file in markdown_files(&root) {
        let text = std::fs::read_to_string(&file).unwrap();
        stale.extend(stale_names(&root, &file, &text, &names));
    }
    assert!(
        stale.is_empty(),
        "stale names in the docs:\n{}",
        stale.join("\n")
    );
}

#[test]
fn the_name_check_finds_stale_paths_and_items() {
    let root = repo();
    let names = rust_names(&root);
    let file = root.join("docs/development.md");
    // The missing item's name is made here, so that this file does not define it.
    let missing = ["no", "such", "item"].join("_");
    let text = format!(
        "\
`crates/mf87/src/units.rs` `src/instance.rs` `crates/tire-gap/src/data.rs` `src/data.rs`
`crates/mf87/src/extensions/<name>.rs` `docs/*.md` `m/s` `Params::paper_table`
`crates/tire-gap/src/sanity.rs` `src/nowhere.rs` `Params::{missing}`
```
`crates/fenced/path.rs`
```
"
    );
    let stale = stale_names(&root, &file, &text, &names);
    assert_eq!(stale.len(), 3, "{stale:#?}");
    assert!(stale[0].contains("`crates/tire-gap/src/sanity.rs`: no such file"));
    assert!(stale[1].contains("`src/nowhere.rs`: no such file"));
    assert!(stale[2].contains(&format!("no {missing} in the code")));
}
