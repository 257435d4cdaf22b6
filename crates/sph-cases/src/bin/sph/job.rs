//! What `sph run` runs: a case with its parameters, or a scene file, and which of the two
//! the argument names.

use super::*;

/// What `sph run` runs: a built-in case with its parameters, or a scene file.
pub(super) enum Job {
    Case {
        case: &'static dyn sph_cases::Case,
        method: &'static str,
        params: sph_cases::Params,
    },
    /// A scene and its file.
    Scene(Box<Scene>, PathBuf),
}

/// The job `sph run ARG` names: a case by its name, or a scene file (a path that exists or
/// ends in `.toml`). A case name that is also a file here is refused as ambiguous (a file
/// named like a case must not take its place silently, nor hide it).
pub(super) fn job(a: &RunArgs) -> Result<Job, CaseError> {
    let path = std::path::Path::new(&a.case);
    let exists = std::fs::symlink_metadata(path).is_ok();
    match find_case(&a.case) {
        Ok(_) if exists => Err(CaseError::Config(format!(
            "`{0}` is both a case and a file here: write `./{0}` to run the file as a scene, \
             or run the case from another directory",
            a.case
        ))),
        Ok(_) => case_job(a),
        Err(_) if exists || a.case.ends_with(".toml") => scene_job(a),
        Err(e) => Err(e),
    }
}

/// A scene file: `--method`, `--set` and `--config` do not apply (the file holds everything).
fn scene_job(a: &RunArgs) -> Result<Job, CaseError> {
    for (flag, given) in [
        ("--method", a.method.is_some()),
        ("--set", !a.set.is_empty()),
        ("--config", a.config.is_some()),
    ] {
        if given {
            return Err(CaseError::Config(format!(
                "{flag} does not apply to a scene file ({}): edit the file",
                a.case
            )));
        }
    }
    Scene::from_file(&a.case)
        .map(|s| Job::Scene(Box::new(s), PathBuf::from(&a.case)))
        .map_err(|e| match parameter_file_case(&a.case) {
            Some(case) => CaseError::Config(format!(
                "{0} is a parameter file of case `{case}` (as `sph list --toml` writes), not a \
                 scene: run it with `sph run {case} --config {0}`",
                a.case
            )),
            None => CaseError::Config(e.to_string()),
        })
}

/// The case a parameter file names (`case = "…"`, no `[[body]]`), if the file is one.
fn parameter_file_case(file: &str) -> Option<String> {
    let text = sph_output::input::read_text_input(std::path::Path::new(file)).ok()?;
    let table: toml::Table = text.parse().ok()?;
    if table.contains_key("body") || table.contains_key("dimension") {
        return None;
    }
    table.get("case")?.as_str().map(str::to_string)
}

fn case_job(a: &RunArgs) -> Result<Job, CaseError> {
    let case = find_case(&a.case)?;
    let mut method = a.method.clone();
    // The method decides the defaults (`Case::params_for`), so it is resolved before the
    // configuration file and the assignments are applied on top of its defaults.
    let toml = match &a.config {
        Some(path) => {
            let text = sph_output::input::read_text_input(path)
                .map_err(|e| CaseError::Config(format!("--config {e}")))?;
            let extras = case
                .params()
                .apply_toml(&text, &path.display().to_string())?;
            if let Some(c) = extras.case {
                if c != a.case {
                    return Err(CaseError::Config(format!(
                        "{}: names case `{c}` but `{}` was asked for",
                        path.display(),
                        a.case
                    )));
                }
            }
            match (&method, extras.method) {
                (Some(m), Some(t)) if *m != t => {
                    return Err(CaseError::Config(format!(
                        "{}: method = \"{t}\" contradicts --method {m}; drop one of them",
                        path.display()
                    )))
                }
                (None, t) => method = t,
                _ => {}
            }
            Some((text, path.display().to_string()))
        }
        None => None,
    };
    let method = resolve_method(case, method.as_deref())?;
    let mut params = case.params_for(method);
    if let Some((text, name)) = &toml {
        params.apply_toml(text, name)?;
    }
    for s in &a.set {
        params.apply_assignment(s)?;
    }
    params.check_method(method)?;
    Ok(Job::Case {
        case,
        method,
        params,
    })
}
