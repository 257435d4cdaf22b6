//! Reading what a run reads (a scene or parameter file, a particle file, a checkpoint) without
//! hanging or filling memory on a file that is not one: only regular files are read (a FIFO,
//! device such as `/dev/zero`, socket or directory is refused at once, and opening never waits
//! for a FIFO's writer), and never more than a stated size.

use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};

/// Largest scene or parameter file read, bytes: text written by hand or by a script, far above
/// any real one and far below what would strain memory.
pub const MAX_TEXT_BYTES: u64 = 16 << 20;

/// Why an input was not read: the file and the reason, one line.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}: {reason}", path.display())]
pub struct InputError {
    /// The file.
    pub path: PathBuf,
    /// What is wrong with it.
    pub reason: String,
}

impl InputError {
    fn new(path: &Path, reason: impl Into<String>) -> Self {
        Self {
            path: path.to_path_buf(),
            reason: reason.into(),
        }
    }
}

/// Opens `path` for reading if it is a regular file of at most `max_bytes`, returning the file
/// and its size. Opening does not block on a FIFO (`O_NONBLOCK`), and what is opened is
/// checked (`fstat`), not the name, so nothing can be swapped in between.
///
/// # Errors
/// The file cannot be opened, is not a regular file, or is larger than `max_bytes`.
pub fn open_input(path: &Path, max_bytes: u64) -> Result<(File, u64), InputError> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options
        .open(path)
        .map_err(|e| InputError::new(path, format!("cannot read it: {e}")))?;
    let meta = file
        .metadata()
        .map_err(|e| InputError::new(path, format!("cannot inspect it: {e}")))?;
    if !meta.is_file() {
        let kind = crate::safety::non_regular_kind(&meta).unwrap_or("not a regular file");
        return Err(InputError::new(
            path,
            format!("it is {kind}; an input must be a regular file"),
        ));
    }
    let size = meta.len();
    if size > max_bytes {
        return Err(InputError::new(
            path,
            format!(
                "it has {size} bytes, more than the {max_bytes} an input of this kind may have"
            ),
        ));
    }
    Ok((file, size))
}

/// The whole of `path` (see [`open_input`]), at most `max_bytes`, even if the file grows while
/// it is read.
///
/// # Errors
/// As [`open_input`]; a read error.
pub fn read_input(path: &Path, max_bytes: u64) -> Result<Vec<u8>, InputError> {
    let (file, size) = open_input(path, max_bytes)?;
    let mut bytes = Vec::with_capacity(size as usize);
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| InputError::new(path, format!("cannot read it: {e}")))?;
    if bytes.len() as u64 > max_bytes {
        return Err(InputError::new(
            path,
            format!("it grew beyond {max_bytes} bytes while being read"),
        ));
    }
    Ok(bytes)
}

/// A text input (a scene or parameter file): [`read_input`] with [`MAX_TEXT_BYTES`], as UTF-8.
///
/// # Errors
/// As [`read_input`]; text that is not UTF-8.
pub fn read_text_input(path: &Path) -> Result<String, InputError> {
    String::from_utf8(read_input(path, MAX_TEXT_BYTES)?)
        .map_err(|_| InputError::new(path, "it is not UTF-8 text"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("sph-input-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn regular_files_within_the_cap_are_read_and_others_refused() {
        let d = scratch("kinds");
        std::fs::write(d.join("a.toml"), "x = 1\n").unwrap();
        assert_eq!(read_text_input(&d.join("a.toml")).unwrap(), "x = 1\n");
        let e = read_input(&d.join("a.toml"), 3).unwrap_err().to_string();
        assert!(e.contains("6 bytes, more than the 3"), "{e}");
        let e = read_input(&d, 100).unwrap_err().to_string();
        assert!(e.contains("it is a directory"), "{e}");
        let e = read_input(&d.join("missing"), 100).unwrap_err().to_string();
        assert!(e.contains("cannot read it"), "{e}");
        std::fs::write(d.join("bin"), [0xff, 0xfe]).unwrap();
        let e = read_text_input(&d.join("bin")).unwrap_err().to_string();
        assert!(e.contains("not UTF-8"), "{e}");
        #[cfg(unix)]
        {
            let e = read_input(Path::new("/dev/zero"), 100)
                .unwrap_err()
                .to_string();
            assert!(e.contains("it is a device"), "{e}");
            // A FIFO without a writer: refused at once (a plain open would wait forever).
            let fifo = d.join("fifo");
            let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
            // SAFETY: a NUL-terminated path.
            assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
            let e = read_input(&fifo, 100).unwrap_err().to_string();
            assert!(e.contains("it is a FIFO"), "{e}");
        }
        std::fs::remove_dir_all(&d).unwrap();
    }
}
