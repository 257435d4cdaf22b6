//! The command line's file arguments, checked before a run starts: where the results, the
//! summary and the checkpoint go must be writable, must not be an input of the run or each
//! other, and may only replace a regular file that a run wrote (never a link, device, FIFO,
//! socket or directory), and only one that can be replaced (not immutable, not in a directory
//! that refuses renames).
//!
//! Every path is checked as the write will resolve it
//! ([`sph_output::safety::resolve_for_write`]: `sub/../params.toml` with `sub` missing is
//! `params.toml`, which the write reaches after creating `sub`), and no directory is created
//! here: a refused run leaves the file system as it was. Each refusal is one line naming the
//! argument (a writability probe in the target directory is created and removed at once).

use crate::error::CaseError;
use sph_output::safety::{
    check_destination, check_replaceable, check_results_destination, resolve_for_write, same_file,
    OutputLock, TempFile,
};
use std::path::{Path, PathBuf};

/// The files of one `sph run`.
#[derive(Clone, Debug, Default)]
pub struct RunFiles {
    /// The results, without extension (`.h5`, `.xmf` appended); `None` with `--no-output`.
    pub results: Option<PathBuf>,
    /// `--summary`.
    pub summary: Option<PathBuf>,
    /// What the run reads, with the argument that names it (`--config`, the `sph` program).
    pub inputs: Vec<(String, PathBuf)>,
    /// The checkpoint file (`--checkpoint`), if the run writes checkpoints.
    pub checkpoint: Option<PathBuf>,
    /// A rank other than 0 of a distributed run: it does not probe the results' lock, which
    /// rank 0 takes for the run and may already hold (the probe would then fail at random).
    pub other_rank: bool,
    /// `--format vtu`: the VTU frames and their `.pvd` beside the results.
    pub vtu: bool,
    /// `--log`, appended to: never an input, the results or the summary.
    pub log: Option<PathBuf>,
}

/// `path` as the write will resolve it (the path itself if the current directory is gone).
fn real(path: &Path) -> PathBuf {
    resolve_for_write(path).unwrap_or_else(|| path.to_path_buf())
}

impl RunFiles {
    /// Checks every destination (see the module documentation).
    pub fn check(&self) -> Result<(), CaseError> {
        let mut outputs: Vec<(String, PathBuf)> = Vec::new();
        if let Some(base) = &self.results {
            let real_base = real(base);
            let dir = parent_dir(&real_base);
            check_directory("--out", parent_dir(base).as_path(), &dir)?;
            check_results_destination(&real_base)?;
            let h5 = sph_output::h5_path(&real_base);
            let xmf = sph_output::xmf_path(&real_base);
            for file in [&h5, &xmf] {
                check_replaceable(file)
                    .map_err(|e| CaseError::Config(format!("--out {}", refusal(&e))))?;
            }
            // Fail before building the scene if another run is writing these results (the
            // writer takes the lock for good when the run starts).
            if dir.is_dir() && !self.other_rank {
                drop(OutputLock::acquire(&h5)?);
            }
            let lock = sph_output::safety::lock_path(&h5);
            for out in [h5, xmf, lock] {
                outputs.push(("--out".into(), out));
            }
            if self.vtu {
                sph_output::vtu::check_vtu_destination(&real_base)
                    .map_err(|e| CaseError::Config(format!("--format vtu {}", refusal(&e))))?;
                let pvd = sph_output::vtu::pvd_path(&real_base);
                check_replaceable(&pvd)
                    .map_err(|e| CaseError::Config(format!("--format vtu {}", refusal(&e))))?;
                outputs.push(("--format vtu".into(), pvd));
                outputs.push((
                    "--format vtu".into(),
                    sph_output::vtu::vtu_path(&real_base, 0),
                ));
            }
            for (what, input) in &self.inputs {
                for (_, out) in &outputs {
                    if same_file(out, input) {
                        return Err(CaseError::Config(format!(
                            "--out: the results {} would replace {}, an input of this run ({what})",
                            out.display(),
                            input.display()
                        )));
                    }
                }
            }
        }
        if let Some(path) = &self.summary {
            check_names_a_file("--summary", path)?;
            for (what, other) in self.inputs.iter().chain(&outputs) {
                if same_file(path, other) {
                    let role = if what == "--out" {
                        "the results of this run"
                    } else {
                        "an input of this run"
                    };
                    return Err(CaseError::Config(format!(
                        "--summary {}: is {} ({what}); choose another file",
                        path.display(),
                        role
                    )));
                }
            }
            check_summary(path, &real(path))?;
        }
        if let Some(path) = &self.log {
            check_names_a_file("--log", path)?;
            let roles = self
                .inputs
                .iter()
                .map(|i| (i, "an input"))
                .chain(outputs.iter().map(|o| (o, "an output")));
            for ((what, other), role) in roles {
                if same_file(path, other) {
                    return Err(CaseError::Config(format!(
                        "--log {}: is {role} of this run ({what}); choose another file",
                        path.display()
                    )));
                }
            }
            if [&self.summary, &self.checkpoint]
                .into_iter()
                .flatten()
                .any(|o| same_file(path, o))
            {
                return Err(CaseError::Config(format!(
                    "--log {}: is the --summary or --checkpoint file; choose another file",
                    path.display()
                )));
            }
            check_destination(&real(path))
                .map_err(|e| CaseError::Config(format!("--log {}", refusal_reason(&e))))?;
        }
        if let Some(path) = &self.checkpoint {
            check_checkpoint(
                path,
                self.inputs.iter().chain(&outputs),
                &self.summary,
                self.other_rank,
            )?;
        }
        Ok(())
    }
}

/// The checkpoint goes to a writable directory and replaces at most an earlier checkpoint
/// (a file starting with `SPHCKPT`) that can be replaced, never an input, the results, the
/// summary, a link, a device, a FIFO or a socket; no other run holds it.
fn check_checkpoint<'a>(
    path: &Path,
    others: impl Iterator<Item = &'a (String, PathBuf)>,
    summary: &Option<PathBuf>,
    other_rank: bool,
) -> Result<(), CaseError> {
    let refuse = |why: String| CaseError::Config(format!("--checkpoint {}: {why}", path.display()));
    let text = path.to_string_lossy();
    let target = real(path);
    if text.ends_with('/') || target.is_dir() {
        return Err(refuse("names a directory, not a file".into()));
    }
    for (what, other) in others {
        if same_file(path, other) {
            return Err(refuse(format!(
                "is {} ({what}); choose another file",
                other.display()
            )));
        }
    }
    if summary.as_deref().is_some_and(|s| same_file(path, s)) {
        return Err(refuse("is the --summary file; choose another file".into()));
    }
    check_destination(&target)
        .and_then(|()| check_replaceable(&target))
        .map_err(|e| refuse(format!("will not write there: {}", refusal_reason(&e))))?;
    if target.exists() {
        let mut head = [0u8; 7];
        let is_checkpoint = std::fs::File::open(&target)
            .and_then(|mut f| std::io::Read::read_exact(&mut f, &mut head))
            .is_ok()
            && &head == b"SPHCKPT";
        if !is_checkpoint {
            return Err(refuse(
                "exists and is not an sph checkpoint; remove it or choose another file".into(),
            ));
        }
    }
    let dir = parent_dir(&target);
    check_directory("--checkpoint", path, &dir)?;
    // Fail now if another run checkpoints here (the run takes the lock when it starts).
    if dir.is_dir() && !other_rank {
        drop(OutputLock::acquire(&target).map_err(|e| refuse(refusal_reason(&e)))?);
    }
    Ok(())
}

/// The directory a file goes to (`.` for a bare name).
fn parent_dir(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// `dir` (where `arg`'s `target` goes, resolved) is a directory, or does not exist yet and its
/// nearest existing ancestor is one; the directory that exists lets this user create, rename
/// over and remove files (probed with two files of its own, removed at once). Nothing is
/// created but the probes.
fn check_directory(arg: &str, shown: &Path, dir: &Path) -> Result<(), CaseError> {
    let mut existing = dir.to_path_buf();
    loop {
        match std::fs::metadata(&existing) {
            Ok(m) if m.is_dir() => break,
            Ok(_) => {
                return Err(CaseError::Config(format!(
                    "{arg} {}: {} is not a directory",
                    shown.display(),
                    existing.display()
                )))
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                existing = match existing.parent() {
                    Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
                    _ => PathBuf::from("."),
                };
            }
            Err(e) => {
                return Err(CaseError::Config(format!(
                    "{arg} {}: cannot inspect {}: {e}",
                    shown.display(),
                    existing.display()
                )))
            }
        }
    }
    let cannot = |what: &str, e: &sph_output::OutputError| {
        CaseError::Config(format!(
            "{arg} {}: cannot {what} in {}: {}",
            shown.display(),
            existing.display(),
            io_reason(e)
        ))
    };
    // A directory that is append-only or immutable refuses the rename every output ends
    // with (and the removal of the probes): say so before probing.
    check_replaceable(&existing.join(".sph-write-probe"))
        .map_err(|e| cannot("replace files", &e))?;
    let probe = existing.join(".sph-write-probe");
    let a = TempFile::beside(&probe, true).map_err(|e| cannot("write", &e))?;
    let b = TempFile::beside(&probe, true).map_err(|e| cannot("write", &e))?;
    let b_path = b.path().to_path_buf();
    drop(b);
    a.persist(&b_path).map_err(|e| cannot("rename files", &e))?;
    std::fs::remove_file(&b_path).map_err(|e| {
        CaseError::Config(format!(
            "{arg} {}: cannot remove files in {}: {e}",
            shown.display(),
            existing.display()
        ))
    })
}

fn io_reason(e: &sph_output::OutputError) -> String {
    match e {
        sph_output::OutputError::Io { source, .. } => source.to_string(),
        other => refusal_reason(other),
    }
}

/// The path of `flag` (`--summary`, `--log`) names a file, not a directory (`.`, `..`, a
/// trailing `/`, a directory).
fn check_names_a_file(flag: &str, path: &Path) -> Result<(), CaseError> {
    let text = path.to_string_lossy();
    let names_dir = text.ends_with('/')
        || matches!(
            path.file_name().map(|n| n.to_string_lossy()),
            None | Some(std::borrow::Cow::Borrowed("." | ".."))
        );
    if names_dir || real(path).is_dir() {
        return Err(CaseError::Config(format!(
            "{flag} {}: names a directory, not a file",
            path.display()
        )));
    }
    Ok(())
}

/// The summary (`shown`, resolved to `target`) goes to a writable directory and replaces at
/// most an empty file or an earlier summary (a JSON object with `case` and `status`) that can
/// be replaced, never a link, device, FIFO or socket.
fn check_summary(shown: &Path, target: &Path) -> Result<(), CaseError> {
    let refuse = |why: String| {
        CaseError::Config(format!(
            "--summary {}: will not write there: {why}",
            shown.display()
        ))
    };
    check_destination(target)
        .and_then(|()| check_replaceable(target))
        .map_err(|e| refuse(refusal_reason(&e)))?;
    if target.exists() {
        let old = sph_output::input::read_text_input(target).map_err(|_| {
            CaseError::Config(format!(
                "--summary {}: exists and cannot be read, so it is not replaced",
                shown.display()
            ))
        })?;
        let is_summary = old.trim().is_empty()
            || serde_json::from_str::<serde_json::Value>(&old)
                .map(|v| v.get("case").is_some() && v.get("status").is_some())
                .unwrap_or(false);
        if !is_summary {
            return Err(CaseError::Config(format!(
                "--summary {}: exists and is not an sph summary (a JSON object with `case` and \
                 `status`); remove it or choose another file",
                shown.display()
            )));
        }
    }
    check_directory("--summary", shown, &parent_dir(target))
}

fn refusal_reason(e: &sph_output::OutputError) -> String {
    match e {
        sph_output::OutputError::Refused { reason, .. } => reason.clone(),
        other => other.to_string(),
    }
}

/// A refusal with its path: `<path>: <reason>`.
fn refusal(e: &sph_output::OutputError) -> String {
    match e {
        sph_output::OutputError::Refused { path, reason } => {
            format!("{}: {reason}", path.display())
        }
        other => other.to_string(),
    }
}

/// Writes `text` to `path` through a temporary file of its own, renamed into place (the
/// destination was checked by [`RunFiles::check`]).
pub fn write_summary(path: &Path, text: &str) -> Result<(), CaseError> {
    check_destination(path)?;
    let dir = parent_dir(path);
    std::fs::create_dir_all(&dir).map_err(|e| CaseError::Io {
        path: dir.display().to_string(),
        source: e,
    })?;
    let mut tmp = TempFile::beside(path, true)?;
    tmp.write_all(text.as_bytes())?;
    tmp.persist(path)?;
    Ok(())
}
