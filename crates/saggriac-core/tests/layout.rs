//! The shape of the code, checked: no import cycle among the core's modules, the configuration a
//! leaf, and no source file (tests included) over 500 lines, in both crates.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};

const MAX_LINES: usize = 500;

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// Module path of a file under src/ ("low_level::ssa_reacher"); None for lib.rs.
fn module_of(rel: &Path) -> Option<String> {
    let mut parts: Vec<String> = rel.iter().map(|s| s.to_string_lossy().into_owned()).collect();
    let last = parts.pop()?.trim_end_matches(".rs").to_string();
    if last != "mod" && last != "lib" {
        parts.push(last);
    }
    (!parts.is_empty()).then(|| parts.join("::"))
}

/// The modules each module's non-test code names through `crate::` paths.
fn imports() -> BTreeMap<String, Vec<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut code = BTreeMap::new();
    for f in &files {
        let rel = f.strip_prefix(&src).unwrap();
        if rel.file_name().is_some_and(|n| n == "tests.rs") {
            continue;
        }
        if let Some(m) = module_of(rel) {
            let text = fs::read_to_string(f).unwrap();
            // Inline unit tests sit at the end of a file, after `#[cfg(test)]`.
            let body = text.split("#[cfg(test)]").next().unwrap().to_string();
            code.insert(m, body);
        }
    }
    let known: Vec<String> = code.keys().cloned().collect();
    let mut graph = BTreeMap::new();
    for (m, body) in &code {
        let mut deps = Vec::new();
        for line in body.lines().filter(|l| !l.trim_start().starts_with("//")) {
            for (i, _) in line.match_indices("crate::") {
                let path: String = line[i + 7..].chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_' || *c == ':').collect();
                let segs: Vec<&str> = path.split("::").filter(|s| !s.is_empty()).collect();
                // The longest prefix that is a module: `crate::config::low_level::X` is config::low_level.
                let target = (1..=segs.len()).rev().map(|n| segs[..n].join("::")).find(|p| known.contains(p));
                if let Some(t) = target {
                    if &t != m && !deps.contains(&t) {
                        deps.push(t);
                    }
                }
            }
        }
        graph.insert(m.clone(), deps);
    }
    graph
}

#[test]
fn no_import_cycle_among_the_core_modules() {
    let graph = imports();
    // Depth-first search; a back edge to a module on the stack is a cycle.
    fn visit(m: &str, g: &BTreeMap<String, Vec<String>>, state: &mut BTreeMap<String, u8>, stack: &mut Vec<String>) {
        match state.get(m) {
            Some(2) => return,
            Some(1) => {
                let at = stack.iter().position(|s| s == m).unwrap();
                panic!("import cycle: {} -> {m}", stack[at..].join(" -> "));
            }
            _ => {}
        }
        state.insert(m.to_string(), 1);
        stack.push(m.to_string());
        for d in &g[m] {
            visit(d, g, state, stack);
        }
        stack.pop();
        state.insert(m.to_string(), 2);
    }
    let mut state = BTreeMap::new();
    for m in graph.keys() {
        visit(m, &graph, &mut state, &mut Vec::new());
    }
    // The check sees the imports (a test that cannot fail is a defect).
    assert!(graph["run_loop"].contains(&"low_level".to_string()) && graph["low_level::ssa_reacher"].contains(&"parts".to_string()));
}

#[test]
fn the_configuration_imports_no_component() {
    let graph = imports();
    let leafish = |d: &str| d == "error" || d == "task_space" || d == "config" || d.starts_with("config::");
    for (m, deps) in graph.iter().filter(|(m, _)| *m == "config" || m.starts_with("config::")) {
        let bad: Vec<&String> = deps.iter().filter(|d| !leafish(d)).collect();
        assert!(bad.is_empty(), "{m} imports {bad:?}");
    }
}

#[test]
fn no_source_file_over_500_lines() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in ["src", "tests", "benches", "examples", "../saggriac-py/src"] {
        rust_files(&root.join(dir), &mut files);
    }
    assert!(files.len() > 40);
    let long: Vec<String> = files
        .iter()
        .filter_map(|f| {
            let n = fs::read_to_string(f).unwrap().lines().count();
            (n > MAX_LINES).then(|| format!("{} ({n} lines)", f.display()))
        })
        .collect();
    assert!(long.is_empty(), "over {MAX_LINES} lines: {long:?}");
}
