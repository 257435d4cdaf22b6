//! The command line's file arguments, checked before a run starts: where the results and the
//! summary go must be writable, must not be an input of the run or each other, and may only
//! replace a regular file that a run wrote (never a link, device, FIFO, socket or directory).
//! Each refusal is one line naming the argument; nothing is written (a writability probe in
//! the target directory is created and removed at once).

use crate::error::CaseError;
use sph_output::safety::{
    check_destination, check_results_destination, same_file, OutputLock, TempFile,
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
}

impl RunFiles {
    /// Checks every destination (see the module documentation).
    pub fn check(&self) -> Result<(), CaseError> {
        let mut outputs: Vec<(String, PathBuf)> = Vec::new();
        if let Some(base) = &self.results {
            let dir = parent_dir(base);
            check_directory("--out", base, &dir)?;
            check_results_destination(base)?;
            // Fail before building the scene if another run is writing these results (the
            // writer takes the lock for good when the run starts).
            if dir.is_dir() && !self.other_rank {
                drop(OutputLock::acquire(&sph_output::h5_path(base))?);
            }
            outputs.push(("--out".into(), sph_output::h5_path(base)));
            outputs.push(("--out".into(), sph_output::xmf_path(base)));
            outputs.push((
                "--out".into(),
                sph_output::safety::lock_path(&sph_output::h5_path(base)),
            ));
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
            check_names_a_file(path)?;
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
            check_summary(path)?;
        }
        if let Some(path) = &self.checkpoint {
            check_checkpoint(path, self.inputs.iter().chain(&outputs), &self.summary)?;
        }
        Ok(())
    }
}

/// The checkpoint goes to a writable directory and replaces at most an earlier checkpoint
/// (a file starting with `SPHCKPT`), never an input, the results, the summary, a link, a
/// device, a FIFO or a socket.
fn check_checkpoint<'a>(
    path: &Path,
    others: impl Iterator<Item = &'a (String, PathBuf)>,
    summary: &Option<PathBuf>,
) -> Result<(), CaseError> {
    let refuse = |why: String| CaseError::Config(format!("--checkpoint {}: {why}", path.display()));
    let text = path.to_string_lossy();
    if text.ends_with('/') || path.is_dir() {
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
    check_destination(path)
        .map_err(|e| refuse(format!("will not write there: {}", refusal_reason(&e))))?;
    if path.exists() {
        let mut head = [0u8; 7];
        let is_checkpoint = std::fs::File::open(path)
            .and_then(|mut f| std::io::Read::read_exact(&mut f, &mut head))
            .is_ok()
            && &head == b"SPHCKPT";
        if !is_checkpoint {
            return Err(refuse(
                "exists and is not an sph checkpoint; remove it or choose another file".into(),
            ));
        }
    }
    check_directory("--checkpoint", path, &parent_dir(path))
}

/// The directory a file goes to (`.` for a bare name).
fn parent_dir(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// `dir` (where `arg`'s `target` goes) is a directory, or does not exist yet and its nearest
/// existing ancestor is one; the directory that exists is writable (probed by creating and
/// removing a file there).
fn check_directory(arg: &str, target: &Path, dir: &Path) -> Result<(), CaseError> {
    let shown = if arg == "--out" { dir } else { target };
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
    TempFile::beside(&existing.join(".sph-write-probe"), true)
        .map(drop)
        .map_err(|e| {
            CaseError::Config(format!(
                "{arg} {}: cannot write in {}: {}",
                shown.display(),
                existing.display(),
                io_reason(&e)
            ))
        })
}

fn io_reason(e: &sph_output::OutputError) -> String {
    match e {
        sph_output::OutputError::Io { source, .. } => source.to_string(),
        other => other.to_string(),
    }
}

/// The summary path names a file, not a directory (`.`, `..`, a trailing `/`, a directory).
fn check_names_a_file(path: &Path) -> Result<(), CaseError> {
    let text = path.to_string_lossy();
    let names_dir = text.ends_with('/')
        || matches!(
            path.file_name().map(|n| n.to_string_lossy()),
            None | Some(std::borrow::Cow::Borrowed("." | ".."))
        );
    if names_dir || path.is_dir() {
        return Err(CaseError::Config(format!(
            "--summary {}: names a directory, not a file",
            path.display()
        )));
    }
    Ok(())
}

/// The summary goes to a writable directory and replaces at most an empty file or an earlier
/// summary (a JSON object with `case` and `status`), never a link, device, FIFO or socket.
fn check_summary(path: &Path) -> Result<(), CaseError> {
    check_destination(path).map_err(|e| {
        CaseError::Config(format!(
            "--summary {}: will not write there: {}",
            path.display(),
            refusal_reason(&e)
        ))
    })?;
    if let Ok(old) = std::fs::read_to_string(path) {
        let is_summary = old.trim().is_empty()
            || serde_json::from_str::<serde_json::Value>(&old)
                .map(|v| v.get("case").is_some() && v.get("status").is_some())
                .unwrap_or(false);
        if !is_summary {
            return Err(CaseError::Config(format!(
                "--summary {}: exists and is not an sph summary (a JSON object with `case` and \
                 `status`); remove it or choose another file",
                path.display()
            )));
        }
    } else if path.exists() {
        return Err(CaseError::Config(format!(
            "--summary {}: exists and cannot be read, so it is not replaced",
            path.display()
        )));
    }
    check_directory("--summary", path, &parent_dir(path))
}

fn refusal_reason(e: &sph_output::OutputError) -> String {
    match e {
        sph_output::OutputError::Refused { reason, .. } => reason.clone(),
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
