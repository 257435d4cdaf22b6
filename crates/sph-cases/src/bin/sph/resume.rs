//! `sph resume`: the run a checkpoint records, rebuilt, and what a checkpoint records of a run.

use super::*;

/// `sph resume`: reads and checks the checkpoint (rc 2 on any problem, before any work),
/// rebuilds the run it records and continues it.
pub(super) fn resume(a: ResumeArgs) -> Result<ExitCode, CaseError> {
    // On several ranks each resumes from its own file (rank 0's is the one named).
    let rank = ranks().map_or(0, |c| c.rank());
    let path = sph_driver::checkpoint::rank_path(&a.checkpoint, rank);
    if rank > 0 && !path.exists() {
        return Err(CaseError::Config(format!(
            "{}: no checkpoint for rank {rank} (resume on as many ranks as the run that wrote \
             {} had)",
            path.display(),
            a.checkpoint.display()
        )));
    }
    // Read within the memory the run may use: a checkpoint's state is held whole.
    let checkpoint = budget::scoped(memory_budget(a.max_memory, 1)?, || Checkpoint::load(&path))?;
    // Older checkpoints have no `ranks`: one.
    let written_on = checkpoint
        .run
        .get("ranks")
        .and_then(Json::as_u64)
        .unwrap_or(1);
    let now = ranks().map_or(1, |c| c.size()) as u64;
    if written_on != now {
        return Err(CaseError::Config(format!(
            "checkpoint {}: written by a run on {written_on} rank(s), resumed on {now} (resume \
             on as many ranks as the run had: `mpirun -n {written_on} sph resume …`)",
            a.checkpoint.display()
        )));
    }
    let (job, mut settings) = resume_job(&checkpoint)?;
    if a.threads.is_some() {
        settings.threads = a.threads;
    }
    settings.max_memory = a.max_memory;
    settings.log_every = a.log_every;
    settings.log = a.log;
    execute(job, settings, Some(Arc::new(checkpoint)))
}

/// The run a checkpoint records ([`run_description`]): its case (or scene file, unchanged),
/// method, parameters and files.
pub(super) fn resume_job(c: &Checkpoint) -> Result<(Job, Settings), CaseError> {
    let bad = |what: &str| {
        CaseError::Config(format!(
            "checkpoint {}: its run description has no valid `{what}`",
            c.path.display()
        ))
    };
    let text = |key: &str| {
        c.run
            .get(key)
            .and_then(Json::as_str)
            .ok_or_else(|| bad(key))
    };
    let path = |key: &str| -> Result<Option<PathBuf>, CaseError> {
        match c.run.get(key) {
            Some(Json::Null) => Ok(None),
            Some(Json::String(s)) => Ok(Some(PathBuf::from(s))),
            _ => Err(bad(key)),
        }
    };
    let flag = |key: &str| {
        c.run
            .get(key)
            .and_then(Json::as_bool)
            .ok_or_else(|| bad(key))
    };
    let job = match text("job")? {
        "case" => {
            let case = find_case(text("case")?)?;
            let method = resolve_method(case, Some(text("method")?))?;
            let mut params = case.params_for(method);
            let list = c.run.get("params").and_then(Json::as_array);
            for p in list.ok_or_else(|| bad("params"))? {
                params.apply_assignment(p.as_str().ok_or_else(|| bad("params"))?)?;
            }
            Job::Case {
                case,
                method,
                params,
            }
        }
        "scene" => {
            let file = text("scene")?;
            let bytes = sph_output::input::read_input(
                std::path::Path::new(file),
                sph_output::input::MAX_TEXT_BYTES,
            )
            .map_err(|e| CaseError::Config(format!("the scene file {e}")))?;
            if format!("{:016x}", fnv1a64(&bytes)) != text("scene_checksum")? {
                return Err(CaseError::Config(format!(
                    "checkpoint {}: the scene file {file} has changed since the checkpoint was \
                     written; a resumed run must build the same scene",
                    c.path.display()
                )));
            }
            // The overrides of the run (none in checkpoints written before they existed).
            let overrides = match c.run.get("overrides") {
                None => Vec::new(),
                Some(Json::Array(list)) => list
                    .iter()
                    .map(|o| {
                        o.as_str().ok_or_else(|| bad("overrides")).and_then(|o| {
                            sph_scene::Override::parse(o).map_err(|_| bad("overrides"))
                        })
                    })
                    .collect::<Result<_, _>>()?,
                Some(_) => return Err(bad("overrides")),
            };
            Scene::from_file_with(file, &overrides)
                .map(|s| Job::Scene(Box::new(s), PathBuf::from(file)))
                .map_err(|e| CaseError::Config(e.to_string()))?
        }
        _ => return Err(bad("job")),
    };
    let settings = Settings {
        out: path("out")?.ok_or_else(|| bad("out"))?,
        no_output: flag("no_output")?,
        summary: path("summary")?,
        // Absent from checkpoints written before the option existed: off.
        per_rank_output: c
            .run
            .get("per_rank_output")
            .and_then(Json::as_bool)
            .unwrap_or(false),
        backend: text("backend")?.to_string(),
        compress: match c.run.get("compress") {
            Some(Json::Null) => None,
            Some(v) => Some(
                v.as_u64()
                    .and_then(|l| u8::try_from(l).ok())
                    .ok_or_else(|| bad("compress"))?,
            ),
            None => return Err(bad("compress")),
        },
        threads: c
            .run
            .get("threads")
            .and_then(Json::as_u64)
            .map(|n| n as usize),
        max_memory: None,
        allow_long_run: flag("allow_long_run")?,
        dry_run: false,
        log_every: 10.0,
        log: None,
        // Absent from checkpoints written before the option existed: off.
        vtu: c.run.get("vtu").and_then(Json::as_bool).unwrap_or(false),
        checkpoint_every: Some(text("checkpoint_every")?.to_string()),
        checkpoint: path("checkpoint")?,
        config: None,
    };
    Ok((job, settings))
}

/// What a checkpoint records to rebuild the run (absolute paths: `sph resume` may run
/// elsewhere). Parameters as `key=value` assignments, every one of them (exact: floats print
/// in the shortest form that reads back to the same value).
pub(super) fn run_description(
    job: &Job,
    s: &Settings,
    checkpoint: &std::path::Path,
    threads: usize,
) -> Result<Json, CaseError> {
    let abs = |p: &std::path::Path| -> Result<String, CaseError> {
        std::path::absolute(p)
            .map(|p| p.to_string_lossy().into_owned())
            .map_err(|e| CaseError::Io {
                path: p.display().to_string(),
                source: e,
            })
    };
    let mut d = serde_json::json!({
        "out": abs(&s.out)?,
        "no_output": s.no_output,
        "per_rank_output": s.per_rank_output,
        "summary": s.summary.as_deref().map(abs).transpose()?,
        "backend": s.backend,
        "compress": s.compress,
        "threads": threads,
        "allow_long_run": s.allow_long_run,
        "checkpoint_every": s.checkpoint_every,
        "checkpoint": abs(checkpoint)?,
        "vtu": s.vtu,
        "ranks": ranks().map_or(1, |c| c.size()),
    });
    let m = d.as_object_mut().expect("an object");
    match job {
        Job::Case {
            case,
            method,
            params,
        } => {
            let assignments: Vec<String> = params
                .specs()
                .iter()
                .filter_map(|p| params.value(p.key).map(|v| format!("{}={v}", p.key)))
                .collect();
            m.insert("job".into(), "case".into());
            m.insert("case".into(), case.info().name.into());
            m.insert("method".into(), (*method).into());
            m.insert("params".into(), assignments.into());
        }
        Job::Scene(scene, file) => {
            let bytes = sph_output::input::read_input(file, sph_output::input::MAX_TEXT_BYTES)
                .map_err(|e| CaseError::Config(format!("the scene file {e}")))?;
            let overrides: Vec<String> = scene
                .overrides()
                .iter()
                .map(|o| format!("{}={}", o.key, o.value))
                .collect();
            m.insert("overrides".into(), overrides.into());
            m.insert("job".into(), "scene".into());
            m.insert("scene".into(), abs(file)?.into());
            m.insert(
                "scene_checksum".into(),
                format!("{:016x}", fnv1a64(&bytes)).into(),
            );
        }
    }
    Ok(d)
}
