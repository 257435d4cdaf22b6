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

/// A scene file, with `--method` and `--set` as overrides of its keys or parameters
/// (`--method M` is `--set method=M`, applied first). `--config` is a case's parameter file
/// and does not apply.
fn scene_job(a: &RunArgs) -> Result<Job, CaseError> {
    if a.config.is_some() {
        return Err(CaseError::Config(format!(
            "--config reads a case's parameter file; {} is a scene file: give its keys or \
             parameters with --set KEY=VALUE",
            a.case
        )));
    }
    let mut overrides = Vec::new();
    if let Some(m) = &a.method {
        overrides.push(sph_scene::Override {
            key: "method".into(),
            value: m.clone(),
        });
    }
    for s in &a.set {
        overrides.push(
            sph_scene::Override::parse(s).map_err(|e| CaseError::Config(format!("--set {e}")))?,
        );
    }
    Scene::from_file_with(&a.case, &overrides)
        .map(|s| Job::Scene(Box::new(s), PathBuf::from(&a.case)))
        .map_err(|e| CaseError::Config(e.to_string()))
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
