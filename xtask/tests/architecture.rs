//! The shape of the workspace's Rust code, checked on its sources:
//! - no function over 80 lines outside tests (from `fn` to its closing brace);
//! - each effect named (its `Extension` variant, its name, its parameter struct) only in its own
//!   file and the list of effects, per crate and in the synthetic-data generator; another
//!   effect's file may name it in the experiment that tells the two apart;
//! - no import circles: in every crate, at every level of the module tree, the modules of one
//!   parent refer to each other without a cycle (a reference is a `crate::`, `super::` or
//!   `self::` path in a `use` or in the code).
//!
//! Test code (`tests/` folders, `tests.rs` files, `#[cfg(test)]` items, `#[test]` functions)
//! is left out.

mod common;
use common::repo;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use syn::visit::Visit;

const MAX_FN_LINES: usize = 80;

/// Folders that hold no source of ours, or only test code.
const SKIPPED_DIRS: &[&str] = &[
    "target",
    ".git",
    ".venv",
    "third_party",
    "tests",
    "node_modules",
];

/// The crate roots whose module trees are checked for circles.
const CRATE_ROOTS: &[&str] = &[
    "src/lib.rs",
    "crates/mf87/src/lib.rs",
    "crates/tire-gap/src/lib.rs",
    "xtask/src/main.rs",
];

fn parse(path: &Path) -> syn::File {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    syn::parse_file(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Every `.rs` file of the repository outside test code.
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if path.is_dir() {
            if !SKIPPED_DIRS.contains(&name.as_str()) {
                sources(&path, out);
            }
        } else if name.ends_with(".rs") && name != "tests.rs" {
            out.push(path);
        }
    }
}

/// Whether `attrs` hold `#[cfg(...)]` naming `test`, or `#[test]`.
fn is_test(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|attr| {
        attr.path().is_ident("test")
            || matches!(&attr.meta, syn::Meta::List(list) if list.path.is_ident("cfg")
                && list.tokens.to_string()
                    .split(|c: char| !c.is_alphanumeric() && c != '_')
                    .any(|word| word == "test"))
    })
}

/// Functions longer than [`MAX_FN_LINES`]: (lines, name, first line).
#[derive(Default)]
struct LongFunctions(Vec<(usize, String, usize)>);

impl LongFunctions {
    fn check(&mut self, attrs: &[syn::Attribute], sig: &syn::Signature, block: &syn::Block) {
        if is_test(attrs) {
            return;
        }
        let first = sig.fn_token.span.start().line;
        let lines = block.brace_token.span.close().end().line - first + 1;
        if lines > MAX_FN_LINES {
            self.0.push((lines, sig.ident.to_string(), first));
        }
    }
}

impl<'a> Visit<'a> for LongFunctions {
    fn visit_item_mod(&mut self, item: &'a syn::ItemMod) {
        if !is_test(&item.attrs) {
            syn::visit::visit_item_mod(self, item);
        }
    }
    fn visit_item_impl(&mut self, item: &'a syn::ItemImpl) {
        if !is_test(&item.attrs) {
            syn::visit::visit_item_impl(self, item);
        }
    }
    fn visit_item_fn(&mut self, item: &'a syn::ItemFn) {
        self.check(&item.attrs, &item.sig, &item.block);
        if !is_test(&item.attrs) {
            syn::visit::visit_item_fn(self, item);
        }
    }
    fn visit_impl_item_fn(&mut self, item: &'a syn::ImplItemFn) {
        self.check(&item.attrs, &item.sig, &item.block);
        syn::visit::visit_impl_item_fn(self, item);
    }
    fn visit_trait_item_fn(&mut self, item: &'a syn::TraitItemFn) {
        if let Some(block) = &item.default {
            self.check(&item.attrs, &item.sig, block);
        }
        syn::visit::visit_trait_item_fn(self, item);
    }
}

#[test]
fn no_function_is_longer_than_80_lines_outside_tests() {
    let root = repo();
    let mut files = Vec::new();
    sources(&root, &mut files);
    files.sort();
    assert!(files.len() > 50, "found only {} sources", files.len());
    let mut long = Vec::new();
    for file in &files {
        let mut visitor = LongFunctions::default();
        visitor.visit_file(&parse(file));
        let shown = file.strip_prefix(&root).unwrap().display().to_string();
        for (lines, name, line) in visitor.0 {
            long.push(format!("{shown}:{line} {name}: {lines} lines"));
        }
    }
    assert!(
        long.is_empty(),
        "functions over {MAX_FN_LINES} lines (split them into named steps):\n{}",
        long.join("\n")
    );
}

/// A module of a crate: its path from the crate root and the module paths it refers to.
struct Module {
    path: Vec<String>,
    /// Absolute paths (from the crate root) of the `crate::`, `super::` and `self::` paths in
    /// its own code, without those of its child modules.
    refs: Vec<Vec<String>>,
}

/// Collects the paths a module's own items refer to; child modules are separate modules.
struct References<'m> {
    module: &'m [String],
    refs: Vec<Vec<String>>,
}

impl References<'_> {
    /// `segments` made absolute, if it starts with `crate`, `super` or `self`.
    fn absolute(&self, segments: &[String]) -> Option<Vec<String>> {
        let mut base: Vec<String> = match segments.first()?.as_str() {
            "crate" => Vec::new(),
            "self" | "super" => self.module.to_vec(),
            _ => return None,
        };
        let mut rest = &segments[1..];
        if segments[0] == "super" {
            base.pop();
            while rest.first().is_some_and(|s| s == "super") {
                base.pop();
                rest = &rest[1..];
            }
        }
        base.extend(rest.iter().cloned());
        Some(base)
    }

    fn add(&mut self, segments: &[String]) {
        if let Some(path) = self.absolute(segments) {
            self.refs.push(path);
        }
    }

    fn use_tree(&mut self, prefix: &mut Vec<String>, tree: &syn::UseTree) {
        match tree {
            syn::UseTree::Path(p) => {
                prefix.push(p.ident.to_string());
                self.use_tree(prefix, &p.tree);
                prefix.pop();
            }
            syn::UseTree::Name(n) => {
                prefix.push(n.ident.to_string());
                self.add(prefix);
                prefix.pop();
            }
            syn::UseTree::Rename(r) => {
                prefix.push(r.ident.to_string());
                self.add(prefix);
                prefix.pop();
            }
            syn::UseTree::Glob(_) => self.add(prefix),
            syn::UseTree::Group(g) => {
                for tree in &g.items {
                    self.use_tree(prefix, tree);
                }
            }
        }
    }
}

impl<'a> Visit<'a> for References<'_> {
    fn visit_item_mod(&mut self, _: &'a syn::ItemMod) {}
    fn visit_item_use(&mut self, item: &'a syn::ItemUse) {
        if !is_test(&item.attrs) {
            self.use_tree(&mut Vec::new(), &item.tree);
        }
    }
    fn visit_item_fn(&mut self, item: &'a syn::ItemFn) {
        if !is_test(&item.attrs) {
            syn::visit::visit_item_fn(self, item);
        }
    }
    fn visit_item_impl(&mut self, item: &'a syn::ItemImpl) {
        if !is_test(&item.attrs) {
            syn::visit::visit_item_impl(self, item);
        }
    }
    fn visit_path(&mut self, path: &'a syn::Path) {
        let segments: Vec<String> = path.segments.iter().map(|s| s.ident.to_string()).collect();
        self.add(&segments);
        syn::visit::visit_path(self, path);
    }
}

/// The module tree of the crate whose root file is `root`, test modules left out.
fn modules(root: &Path) -> Vec<Module> {
    let mut out = Vec::new();
    let dir = root.parent().unwrap().to_path_buf();
    load(&parse(root).items, &dir, Vec::new(), &mut out);
    out
}

/// Adds the module at `path` whose items are `items`; `dir` holds its child modules' files.
fn load(items: &[syn::Item], dir: &Path, path: Vec<String>, out: &mut Vec<Module>) {
    let mut refs = References {
        module: &path,
        refs: Vec::new(),
    };
    for item in items {
        refs.visit_item(item);
    }
    let refs = refs.refs;
    for item in items {
        let syn::Item::Mod(m) = item else { continue };
        if is_test(&m.attrs) {
            continue;
        }
        let name = m.ident.to_string();
        let mut child = path.clone();
        child.push(name.clone());
        match &m.content {
            Some((_, inner)) => load(inner, &dir.join(&name), child, out),
            None => {
                let flat = dir.join(format!("{name}.rs"));
                let file = if flat.exists() {
                    flat
                } else {
                    dir.join(&name).join("mod.rs")
                };
                load(&parse(&file).items, &dir.join(&name), child, out);
            }
        }
    }
    out.push(Module { path, refs });
}

/// Sibling -> sibling it refers to -> an example: which module refers to which path.
type Edges = BTreeMap<String, BTreeMap<String, String>>;

/// Whether `to` can be reached from `from` along `edges`.
fn reaches(edges: &Edges, from: &str, to: &str) -> bool {
    let mut seen = BTreeSet::new();
    let mut todo = vec![from.to_string()];
    while let Some(node) = todo.pop() {
        if node == to {
            return true;
        }
        if seen.insert(node.clone()) {
            todo.extend(edges.get(&node).into_iter().flat_map(|e| e.keys().cloned()));
        }
    }
    false
}

/// The edges that lie on a cycle, as `a -> b (example)`.
fn circular(edges: &Edges) -> Vec<String> {
    let mut found = Vec::new();
    for (from, targets) in edges {
        for (to, example) in targets {
            if reaches(edges, to, from) {
                found.push(format!("{from} -> {to} ({example})"));
            }
        }
    }
    found
}

/// For every module with children, the references between its children: child -> children it
/// refers to, through any module inside it.
fn sibling_edges(modules: &[Module]) -> BTreeMap<Vec<String>, Edges> {
    let paths: BTreeSet<&Vec<String>> = modules.iter().map(|m| &m.path).collect();
    let mut levels: BTreeMap<Vec<String>, Edges> = BTreeMap::new();
    for module in modules {
        for depth in 0..module.path.len() {
            let parent = &module.path[..depth];
            let from = &module.path[depth];
            for target in &module.refs {
                let Some(to) = target.get(depth) else {
                    continue;
                };
                let mut child = parent.to_vec();
                child.push(to.clone());
                if target.starts_with(parent) && to != from && paths.contains(&child) {
                    levels
                        .entry(parent.to_vec())
                        .or_default()
                        .entry(from.clone())
                        .or_default()
                        .entry(to.clone())
                        .or_insert_with(|| {
                            format!(
                                "{} uses crate::{}",
                                module.path.join("::"),
                                target.join("::")
                            )
                        });
                }
            }
        }
    }
    levels
}

#[test]
fn modules_refer_to_each_other_without_circles() {
    let root = repo();
    let mut circles = Vec::new();
    for crate_root in CRATE_ROOTS {
        let modules = modules(&root.join(crate_root));
        assert!(
            modules.len() > 3,
            "{crate_root}: found {} modules",
            modules.len()
        );
        for (parent, edges) in sibling_edges(&modules) {
            let parent = if parent.is_empty() {
                "crate".into()
            } else {
                parent.join("::")
            };
            for edge in circular(&edges) {
                circles.push(format!("{crate_root}, in {parent}: {edge}"));
            }
        }
    }
    assert!(
        circles.is_empty(),
        "import circles:\n{}",
        circles.join("\n")
    );
}

#[test]
fn the_checks_see_long_functions_and_circles() {
    let long =
        syn::parse_file(&format!("fn long() {{\n{}}}\n", "let _ = 1;\n".repeat(80))).unwrap();
    let mut visitor = LongFunctions::default();
    visitor.visit_file(&long);
    assert_eq!(visitor.0, vec![(82, "long".to_string(), 1)]);
    let mut short = LongFunctions::default();
    short.visit_file(
        &syn::parse_file(&format!(
            "#[test]\nfn t() {{\n{}}}\n",
            "let _ = 1;\n".repeat(90)
        ))
        .unwrap(),
    );
    assert!(short.0.is_empty());

    let module = |path: &[&str], refs: &[&[&str]]| Module {
        path: path.iter().map(|s| s.to_string()).collect(),
        refs: refs
            .iter()
            .map(|r| r.iter().map(|s| s.to_string()).collect())
            .collect(),
    };
    let modules = [
        module(&[], &[]),
        module(&["a"], &[&["b", "f"]]),
        module(&["b"], &[]),
        module(&["b", "inner"], &[&["a", "g"]]),
    ];
    let levels = sibling_edges(&modules);
    assert_eq!(
        circular(&levels[&Vec::new()]),
        [
            "a -> b (a uses crate::b::f)",
            "b -> a (b::inner uses crate::a::g)"
        ]
    );
    let acyclic = [
        module(&[], &[]),
        module(&["a"], &[&["b"]]),
        module(&["b"], &[]),
    ];
    assert!(circular(&sibling_edges(&acyclic)[&Vec::new()]).is_empty());

    let refs = References {
        module: &["x".to_string(), "y".to_string()],
        refs: Vec::new(),
    };
    let seg = |s: &[&str]| s.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    assert_eq!(
        refs.absolute(&seg(&["super", "z", "f"])),
        Some(seg(&["x", "z", "f"]))
    );
    assert_eq!(refs.absolute(&seg(&["crate", "q"])), Some(seg(&["q"])));
    assert_eq!(refs.absolute(&seg(&["std", "fmt"])), None);
}

/// Where the effects may be named: a crate's (or the generator's) source folder, its list of
/// effects (which names them all) and the folder of its one file per effect.
struct EffectHome {
    dir: &'static str,
    /// Sub-folders of `dir` that are a unit of their own.
    apart: &'static [&'static str],
    list: &'static str,
    files: &'static str,
}

const EFFECT_HOMES: &[EffectHome] = &[
    EffectHome {
        dir: "src",
        apart: &[],
        list: "",
        files: "",
    },
    EffectHome {
        dir: "crates/mf87/src",
        apart: &[],
        list: "extensions/mod.rs",
        files: "extensions",
    },
    EffectHome {
        dir: "crates/tire-gap/src",
        apart: &["synth"],
        list: "method/fit/effects/mod.rs",
        files: "method/fit/effects",
    },
    EffectHome {
        dir: "crates/tire-gap/src/synth",
        apart: &[],
        list: "effects/mod.rs",
        files: "effects",
    },
];

/// Every identifier in the non-test items of `file`, and every `Extension::<Variant>` path as
/// one string.
fn identifiers(file: &syn::File) -> BTreeSet<String> {
    fn walk(tokens: proc_macro2::TokenStream, out: &mut BTreeSet<String>) {
        // The last three tokens, to see `Extension :: Variant`.
        let mut last: Vec<String> = Vec::new();
        for tree in tokens {
            let text = match &tree {
                proc_macro2::TokenTree::Ident(ident) => {
                    let ident = ident.to_string();
                    if last.len() >= 3 && last[last.len() - 3..] == ["Extension", ":", ":"] {
                        out.insert(format!("Extension::{ident}"));
                    }
                    out.insert(ident.clone());
                    ident
                }
                proc_macro2::TokenTree::Group(group) => {
                    walk(group.stream(), out);
                    String::new()
                }
                proc_macro2::TokenTree::Punct(p) => p.as_char().to_string(),
                proc_macro2::TokenTree::Literal(_) => String::new(),
            };
            last.push(text);
        }
    }
    let mut out = BTreeSet::new();
    for item in &file.items {
        let attrs: &[syn::Attribute] = match item {
            syn::Item::Mod(m) => &m.attrs,
            syn::Item::Fn(f) => &f.attrs,
            syn::Item::Impl(i) => &i.attrs,
            syn::Item::Use(u) => &u.attrs,
            syn::Item::Const(c) => &c.attrs,
            _ => &[],
        };
        if !is_test(attrs) {
            walk(quote::ToTokens::to_token_stream(item), &mut out);
        }
    }
    out
}

/// The identifiers that name an effect: `Extension::<Variant>`, and its own name and type
/// name where these are not also ordinary words of the code (`temperature` is also the
/// operating condition).
fn effect_names(effect: &str) -> Vec<String> {
    let variant = camel(effect);
    let mut names = vec![format!("Extension::{variant}")];
    if effect.contains('_') {
        names.extend([effect.to_string(), variant]);
    }
    names
}

/// `combined_slip` -> `CombinedSlip`.
fn camel(snake: &str) -> String {
    snake
        .split('_')
        .map(|w| w[..1].to_uppercase() + &w[1..])
        .collect()
}

#[test]
fn each_effect_is_named_in_one_file_per_crate_besides_the_list() {
    let root = repo();
    let mut spread = Vec::new();
    for home in EFFECT_HOMES {
        let dir = root.join(home.dir);
        let mut files = Vec::new();
        sources(&dir, &mut files);
        files.retain(|f| !home.apart.iter().any(|a| f.starts_with(dir.join(a))));
        let named: Vec<(String, BTreeSet<String>)> = files
            .iter()
            .map(|f| {
                let shown = f.strip_prefix(&dir).unwrap().display().to_string();
                (shown, identifiers(&parse(f)))
            })
            .collect();
        for effect in mf87::Extension::NAMES {
            let names = effect_names(effect);
            let in_files: Vec<&str> = named
                .iter()
                .filter(|(shown, ids)| shown != home.list && names.iter().any(|n| ids.contains(n)))
                .map(|(shown, _)| shown.as_str())
                .collect();
            // Besides its own file, another effect's file may name it: the experiment that
            // tells the two apart is written in one of the pair's files.
            let own = format!("{}/{effect}.rs", home.files);
            let in_effect_files =
                |f: &&str| !home.files.is_empty() && f.starts_with(&format!("{}/", home.files));
            let outside: Vec<&str> = in_files
                .iter()
                .copied()
                .filter(|f| !in_effect_files(f))
                .collect();
            let missing_own =
                !home.files.is_empty() && !in_files.is_empty() && !in_files.contains(&own.as_str());
            if !outside.is_empty() || missing_own {
                spread.push(format!("{}: {effect} in {}", home.dir, in_files.join(", ")));
            }
        }
    }
    assert!(
        spread.is_empty(),
        "effects named outside their own file and the list:\n{}",
        spread.join("\n")
    );
}

/// Layers that must not refer to others: (crate root, module path, module paths it must not
/// use). The method reports to an observer of its own (`method::observer`), not to the
/// terminal (`progress`) or a front end; the readers only read: cleaning the rows read and
/// cutting a programme into blocks are the method's preparation, which the front calls.
const LAYERS: &[(&str, &str, &[&str])] = &[
    (
        "crates/tire-gap/src/lib.rs",
        "method",
        &["io", "cli", "synth", "progress", "profile", "front"],
    ),
    (
        "crates/tire-gap/src/lib.rs",
        "io::input",
        &["method", "cli", "synth", "progress", "profile", "front"],
    ),
];

/// Whether the module path `path` lies in `prefix` (a path such as `io::input`).
fn within(path: &[String], prefix: &str) -> bool {
    let prefix: Vec<&str> = prefix.split("::").collect();
    path.len() >= prefix.len() && path.iter().zip(&prefix).all(|(a, b)| a == b)
}

#[test]
fn the_method_and_the_readers_use_no_layer_above_them() {
    let root = repo();
    let mut crossings = Vec::new();
    for (crate_root, layer, forbidden) in LAYERS {
        for module in modules(&root.join(crate_root)) {
            if !within(&module.path, layer) {
                continue;
            }
            for target in &module.refs {
                if forbidden.iter().any(|f| within(target, f)) {
                    crossings.push(format!(
                        "{crate_root}: {} uses crate::{}",
                        module.path.join("::"),
                        target.join("::")
                    ));
                }
            }
        }
    }
    assert!(
        crossings.is_empty(),
        "layer crossings:\n{}",
        crossings.join("\n")
    );
}
