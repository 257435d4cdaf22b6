//! Issue 42: every library crate can be packaged for crates.io and depended on by a user's
//! crate. What `cargo package` needs of a manifest is checked here, quickly, for every crate;
//! `.ci/run` then packages them (`cargo package --workspace --no-verify`) and builds
//! `tests/external-crate`, which depends on the individual crates by path and version.

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn manifest(dir: &Path) -> toml::Table {
    let text = std::fs::read_to_string(dir.join("Cargo.toml")).unwrap();
    text.parse().unwrap()
}

/// The published crates: the facade and every crate under `crates/`.
fn library_crates() -> Vec<PathBuf> {
    let mut dirs = vec![root()];
    for entry in std::fs::read_dir(root().join("crates")).unwrap() {
        let dir = entry.unwrap().path();
        if dir.join("Cargo.toml").is_file() {
            dirs.push(dir);
        }
    }
    dirs
}

#[test]
fn every_library_crate_has_the_metadata_crates_io_needs() {
    let crates = library_crates();
    assert!(crates.len() >= 10, "{crates:?}");
    for dir in &crates {
        let m = manifest(dir);
        let package = m["package"].as_table().unwrap();
        let name = package["name"].as_str().unwrap();
        assert_ne!(
            package.get("publish").and_then(|p| p.as_bool()),
            Some(false),
            "{name}: publish = false"
        );
        for key in [
            "description",
            "license",
            "readme",
            "documentation",
            "keywords",
            "categories",
            "rust-version",
        ] {
            assert!(package.contains_key(key), "{name}: no `{key}`");
        }
        assert!(
            !package.contains_key("repository"),
            "{name}: a repository address (add it only when it is real)"
        );
        let readme = package["readme"].as_str().unwrap();
        assert!(dir.join(readme).is_file(), "{name}: no {readme}");
        for license in ["LICENSE-MIT", "LICENSE-APACHE"] {
            let text = std::fs::read_to_string(dir.join(license))
                .unwrap_or_else(|e| panic!("{name}: {license}: {e}"));
            assert!(text.len() > 1000, "{name}: {license} is not a licence text");
        }
        assert_eq!(
            package["documentation"].as_str(),
            Some(format!("https://docs.rs/{name}").as_str())
        );
    }
}

#[test]
fn every_path_dependency_also_names_a_version() {
    // Workspace dependencies: `cargo package` drops the path and keeps the version.
    let ws = manifest(&root());
    let deps = ws["workspace"]["dependencies"].as_table().unwrap();
    let mut paths = 0;
    for (name, spec) in deps {
        if let Some(t) = spec.as_table().filter(|t| t.contains_key("path")) {
            paths += 1;
            assert!(
                t.contains_key("version"),
                "workspace dependency {name}: no version"
            );
        }
    }
    assert!(paths >= 9, "{paths} path dependencies");
    // And no crate names a path of its own.
    for dir in library_crates() {
        let m = manifest(&dir);
        for section in ["dependencies", "dev-dependencies"] {
            for (name, spec) in m
                .get(section)
                .and_then(|d| d.as_table())
                .into_iter()
                .flatten()
            {
                if let Some(t) = spec.as_table() {
                    assert!(
                        !t.contains_key("path") || t.contains_key("version"),
                        "{}: {section}.{name}: a path without a version",
                        dir.display()
                    );
                }
            }
        }
    }
}

#[test]
fn no_library_source_reads_a_file_outside_its_crate_at_compile_time() {
    // A packaged crate holds only its own directory: `include_str!("../../x")` from `src/`
    // would not build.
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|e| e == "rs") {
                out.push(p);
            }
        }
    }
    /// `path` without `.` and `..` components (lexically).
    fn normal(path: &Path) -> PathBuf {
        let mut out = PathBuf::new();
        for c in path.components() {
            match c {
                std::path::Component::ParentDir => {
                    out.pop();
                }
                std::path::Component::CurDir => {}
                c => out.push(c),
            }
        }
        out
    }
    let mut checked = 0;
    for dir in library_crates() {
        let mut files = Vec::new();
        walk(&dir.join("src"), &mut files);
        for f in files {
            let text = std::fs::read_to_string(&f).unwrap();
            for macro_name in ["include_str!(\"", "include_bytes!(\""] {
                for (at, _) in text.match_indices(macro_name) {
                    let rest = &text[at + macro_name.len()..];
                    let target = &rest[..rest.find('"').unwrap()];
                    let resolved = normal(&f.parent().unwrap().join(target));
                    assert!(
                        resolved.starts_with(normal(&dir)),
                        "{}: {macro_name}{target}\" reads outside its crate",
                        f.display()
                    );
                    checked += 1;
                }
            }
        }
    }
    let _ = checked;
}

#[test]
fn the_facade_re_exports_every_library_crate_a_program_builds_with() {
    let m = manifest(&root());
    let deps = m["dependencies"].as_table().unwrap();
    let lib = std::fs::read_to_string(root().join("src/lib.rs")).unwrap();
    for name in [
        "sph-core",
        "sph-geometry",
        "sph-materials",
        "sph-tl",
        "sph-ul",
        "sph-mps",
        "sph-driver",
        "sph-output",
        "sph-scene",
    ] {
        assert!(
            deps.contains_key(name),
            "the facade does not depend on {name}"
        );
        let module = name.replace('-', "_");
        assert!(
            lib.contains(&format!("pub use {module} as ")),
            "src/lib.rs does not re-export {module}"
        );
    }
}
