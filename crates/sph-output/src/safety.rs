//! What a run may write where: destinations it may replace, unique temporary names created
//! exclusively, and the per-output lock.
//!
//! - **Destinations.** A file is only ever replaced if it is a regular file (never a symbolic
//!   link, directory, FIFO, socket or device), and [`create_writer`](crate::create_writer)
//!   replaces a `.h5` only if it is an sph-solids results file ([`is_results_file`]) and a `.xmf`
//!   only if it is an XDMF file. [`check_destination`] says why not, before anything is written.
//! - **Temporary names.** [`TempFile::beside`] creates `<final>.<pid>-<k>.tmp` with
//!   `O_CREAT | O_EXCL`, so two writers (or two processes) never share one; a writer that dies
//!   leaves its own temporary file and nobody else's.
//! - **Lock.** [`OutputLock::acquire`] takes an exclusive advisory lock (`flock`) on
//!   `<final>.lock` for as long as a writer lives; a second writer of the same results fails at
//!   once with [`OutputError::Locked`] naming the process that holds it. The lock file is removed
//!   by its holder; one left by a killed process holds no lock (the kernel drops it with the
//!   process) and is reused.

use std::fs::{File, OpenOptions};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

use crate::OutputError;

/// What kind of file-system object `meta` describes, in words (`None` for a regular file).
pub(crate) fn non_regular_kind(meta: &std::fs::Metadata) -> Option<&'static str> {
    let t = meta.file_type();
    if t.is_file() {
        return None;
    }
    if t.is_symlink() {
        return Some("a symbolic link");
    }
    if t.is_dir() {
        return Some("a directory");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return Some("a FIFO");
        }
        if t.is_socket() {
            return Some("a socket");
        }
        if t.is_char_device() || t.is_block_device() {
            return Some("a device");
        }
    }
    Some("not a regular file")
}

/// `Ok` if `path` does not exist or is a regular file (not a link to one); otherwise
/// [`OutputError::Refused`] saying what it is. Nothing is written.
pub fn check_destination(path: &Path) -> Result<(), OutputError> {
    match std::fs::symlink_metadata(path) {
        Ok(meta) => match non_regular_kind(&meta) {
            None => Ok(()),
            Some(kind) => Err(OutputError::refused(path, format!("it is {kind}"))),
        },
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotADirectory => Err(OutputError::refused(
            path,
            "a component of its directory is not a directory",
        )),
        Err(e) => Err(OutputError::io(path, "inspect", e)),
    }
}

/// `Ok` if a file at `path` (absent, or a regular file) can be replaced by renaming a new file
/// over it, as every output of a run is: neither the file nor its directory is immutable or
/// append-only, and a sticky directory (such as `/tmp`) lets this user replace it. Checked
/// before a run so a result that could not be put in place is refused before it is computed;
/// the directory's own writability and renames are probed by the caller. Nothing is written.
pub fn check_replaceable(path: &Path) -> Result<(), OutputError> {
    #[cfg(target_os = "linux")]
    {
        let dir = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        if let Some(why) = attribute_refusal(&dir) {
            return Err(OutputError::refused(
                path,
                format!("its directory {} is {why}", dir.display()),
            ));
        }
        let Ok(meta) = std::fs::symlink_metadata(path) else {
            return Ok(());
        };
        if let Some(why) = attribute_refusal(path) {
            return Err(OutputError::refused(
                path,
                format!("it is {why}, so it cannot be replaced"),
            ));
        }
        use std::os::unix::fs::MetadataExt;
        if let Ok(d) = std::fs::metadata(&dir) {
            // SAFETY: geteuid has no preconditions.
            let me = unsafe { libc::geteuid() };
            let sticky = d.mode() & libc::S_ISVTX != 0;
            if sticky && me != 0 && meta.uid() != me && d.uid() != me {
                return Err(OutputError::refused(
                    path,
                    format!(
                        "it belongs to another user in the sticky directory {}, so it cannot \
                         be replaced",
                        dir.display()
                    ),
                ));
            }
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = path;
    Ok(())
}

/// `immutable` or `append-only` if the file or directory `path` carries that attribute
/// (`chattr +i`, `+a`): nothing in it can then be renamed over or removed.
#[cfg(target_os = "linux")]
fn attribute_refusal(path: &Path) -> Option<&'static str> {
    use std::os::unix::fs::OpenOptionsExt;
    const FS_IMMUTABLE_FL: libc::c_int = 0x10;
    const FS_APPEND_FL: libc::c_int = 0x20;
    let file = OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK | libc::O_NOFOLLOW)
        .open(path)
        .ok()?;
    let mut flags: libc::c_int = 0;
    // SAFETY: FS_IOC_GETFLAGS writes one int to the valid, exclusively borrowed `flags`.
    let r = unsafe {
        use std::os::fd::AsRawFd;
        libc::ioctl(file.as_raw_fd(), libc::FS_IOC_GETFLAGS, &mut flags)
    };
    if r != 0 {
        // A file system without these attributes has none of them.
        return None;
    }
    if flags & FS_IMMUTABLE_FL != 0 {
        Some("immutable")
    } else if flags & FS_APPEND_FL != 0 {
        Some("append-only")
    } else {
        None
    }
}

/// Whether `path` is an sph-solids results file (a `.h5` or a `.tmp` a run wrote): an HDF5
/// file whose root attribute `format` is [`crate::FORMAT_NAME`]. Reads only the metadata.
pub fn is_results_file(path: &Path) -> bool {
    let Ok(file) = hdf5_pure::File::open_streaming(path) else {
        return false;
    };
    let Ok(attrs) = file.root().attrs() else {
        return false;
    };
    matches!(
        attrs.get("format"),
        Some(hdf5_pure::AttrValue::String(s) | hdf5_pure::AttrValue::VarLenString(s))
            if s == crate::FORMAT_NAME
    )
}

/// Whether `path` starts like an XDMF file (the sidecar a run writes).
fn is_xdmf_file(path: &Path) -> bool {
    let mut head = [0u8; 512];
    let n = File::open(path)
        .and_then(|mut f| f.read(&mut head))
        .unwrap_or(0);
    String::from_utf8_lossy(&head[..n]).contains("<Xdmf")
}

/// The checks [`create_writer`](crate::create_writer) makes before it writes anything: the
/// `.h5` and `.xmf` of `path_without_ext` are absent or regular files, the `.h5` an sph-solids
/// results file and the `.xmf` an XDMF file (so a run replaces only what a run wrote), and the
/// directory is not a file.
pub fn check_results_destination(path_without_ext: &Path) -> Result<(), OutputError> {
    let h5 = crate::h5_path(path_without_ext);
    let xmf = crate::xmf_path(path_without_ext);
    check_destination(&h5)?;
    check_destination(&xmf)?;
    if h5.exists() && !is_results_file(&h5) {
        return Err(OutputError::refused(
            &h5,
            "it exists and is not an sph-solids results file",
        ));
    }
    if xmf.exists() && !is_xdmf_file(&xmf) {
        return Err(OutputError::refused(
            &xmf,
            "it exists and is not an XDMF file",
        ));
    }
    Ok(())
}

/// A temporary file created exclusively next to its final name, `<final>.<pid>-<k>.tmp`.
#[derive(Debug)]
pub struct TempFile {
    path: PathBuf,
    file: Option<File>,
    remove_on_drop: bool,
}

impl TempFile {
    /// Creates `<final>.<pid>-<k>.tmp` (the first `k` whose name is free) with
    /// `O_CREAT | O_EXCL`. `remove_on_drop`: delete it if dropped before [`TempFile::persist`]
    /// (false keeps it, e.g. the partial results of a crashed run).
    pub fn beside(final_path: &Path, remove_on_drop: bool) -> Result<Self, OutputError> {
        let pid = std::process::id();
        for k in 0u32.. {
            let path = crate::with_suffix(final_path, &format!(".{pid}-{k}.tmp"));
            match OpenOptions::new().write(true).create_new(true).open(&path) {
                Ok(file) => {
                    return Ok(Self {
                        path,
                        file: Some(file),
                        remove_on_drop,
                    })
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && k < 1000 => continue,
                Err(e) => return Err(OutputError::io(&path, "create", e)),
            }
        }
        unreachable!("the loop returns")
    }

    /// The temporary name.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Writes `bytes` to the file (from its start) and syncs it.
    pub fn write_all(&mut self, bytes: &[u8]) -> Result<(), OutputError> {
        let file = self.file.as_mut().expect("open until persisted");
        file.write_all(bytes)
            .and_then(|_| file.sync_all())
            .map_err(|e| OutputError::io(&self.path, "write", e))
    }

    /// Closes the file and renames it to `final_path` (atomically replacing a regular file
    /// there). The caller checked `final_path` with [`check_destination`].
    pub fn persist(mut self, final_path: &Path) -> Result<(), OutputError> {
        drop(self.file.take());
        std::fs::rename(&self.path, final_path)
            .map_err(|e| OutputError::io(&self.path, "rename into place", e))?;
        self.remove_on_drop = false;
        Ok(())
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if self.remove_on_drop {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// The lock file of the output `final_path`: `<final>.lock`.
pub fn lock_path(final_path: &Path) -> PathBuf {
    crate::with_suffix(final_path, ".lock")
}

/// An exclusive lock on the output `<final>.lock`, held while a writer lives.
#[derive(Debug)]
pub struct OutputLock {
    path: PathBuf,
    file: File,
}

impl OutputLock {
    /// Takes the lock of `final_path` (file `<final>.lock`, created if absent), or fails at once
    /// with [`OutputError::Locked`] if another process (or another writer here) holds it.
    pub fn acquire(final_path: &Path) -> Result<Self, OutputError> {
        let path = lock_path(final_path);
        check_destination(&path)?;
        // A holder removes the file before it unlocks; if we locked a file that was removed
        // meanwhile, the next opener would lock a new one: check and retry.
        for _ in 0..100 {
            let mut options = OpenOptions::new();
            options.read(true).write(true).create(true).truncate(false);
            #[cfg(unix)]
            {
                use std::os::unix::fs::OpenOptionsExt;
                options.custom_flags(libc::O_NOFOLLOW);
            }
            let mut file = options
                .open(&path)
                .map_err(|e| OutputError::io(&path, "open the lock file", e))?;
            match file.try_lock() {
                Ok(()) => {}
                Err(std::fs::TryLockError::WouldBlock) => {
                    let mut text = String::new();
                    let _ = file.read_to_string(&mut text);
                    return Err(OutputError::Locked {
                        path: final_path.to_path_buf(),
                        holder: text.trim().parse().ok(),
                    });
                }
                Err(std::fs::TryLockError::Error(e)) => {
                    return Err(OutputError::io(&path, "lock", e))
                }
            }
            if same_inode(&file, &path) {
                let pid = std::process::id().to_string();
                file.set_len(0)
                    .and_then(|_| file.write_all(pid.as_bytes()))
                    .map_err(|e| OutputError::io(&path, "write the lock file", e))?;
                return Ok(Self { path, file });
            }
        }
        Err(OutputError::io(
            &path,
            "lock",
            std::io::Error::other("the lock file keeps being replaced"),
        ))
    }

    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // Remove while still locked, so nobody can lock this inode and believe it current.
        let _ = std::fs::remove_file(&self.path);
        let _ = self.file.unlock();
    }
}

#[cfg(unix)]
fn same_inode(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::symlink_metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_inode(_file: &File, path: &Path) -> bool {
    path.exists()
}

/// Bytes free for an unprivileged writer on the file system that holds `path` (or, if `path`
/// does not exist yet, its nearest existing ancestor); `None` where it cannot be read.
pub fn free_space(path: &Path) -> Option<u64> {
    let mut p = std::path::absolute(path).ok()?;
    while !p.exists() {
        p = p.parent()?.to_path_buf();
    }
    statvfs_available(&p)
}

#[cfg(unix)]
fn statvfs_available(path: &Path) -> Option<u64> {
    use std::os::unix::ffi::OsStrExt;
    let c = std::ffi::CString::new(path.as_os_str().as_bytes()).ok()?;
    // SAFETY: `statvfs` is plain old data, for which all zeros is a valid value.
    let mut s: libc::statvfs = unsafe { std::mem::zeroed() };
    // SAFETY: `c` is a NUL-terminated path and `s` a valid, exclusively borrowed out-pointer.
    let r = unsafe { libc::statvfs(c.as_ptr(), &mut s) };
    #[allow(clippy::unnecessary_cast)] // the field types differ between platforms
    (r == 0).then(|| (s.f_bavail as u64).saturating_mul(s.f_frsize as u64))
}

#[cfg(not(unix))]
fn statvfs_available(_path: &Path) -> Option<u64> {
    None
}

/// Whether `a` and `b` name the same file once written: the same device and inode when both
/// exist, else the same path as [`resolve_for_write`] resolves them.
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let (x, y) = (resolve_for_write(a), resolve_for_write(b));
        if let (Ok(x), Ok(y)) = (
            x.as_deref().map_or(std::fs::metadata(a), std::fs::metadata),
            y.as_deref().map_or(std::fs::metadata(b), std::fs::metadata),
        ) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
    }
    match (resolve_for_write(a), resolve_for_write(b)) {
        (Some(x), Some(y)) => x == y,
        _ => false,
    }
}

/// The file `path` names once its missing directories are created, as a write will resolve
/// it: its directory component by component, an existing prefix resolved by the file system
/// (symbolic links, and `..` from where they lead), a missing one as the directory that will
/// be created (so `sub/../params.toml`, `sub` missing, is `params.toml`: creating `sub` makes
/// it so); the file name itself as written. `None` if the current directory cannot be read.
pub fn resolve_for_write(path: &Path) -> Option<PathBuf> {
    // The last component stays as written: a write renames over it (a symbolic link there is
    // replaced, or refused, not followed).
    let abs = std::path::absolute(path).ok()?;
    match abs.file_name() {
        Some(name) => Some(resolve_dirs(abs.parent()?)?.join(name)),
        None => resolve_dirs(&abs),
    }
}

/// `dir` resolved as [`resolve_for_write`] resolves directories, every component.
fn resolve_dirs(abs: &Path) -> Option<PathBuf> {
    use std::path::Component;
    let mut out = PathBuf::new();
    let mut exists = true;
    for c in abs.components() {
        match c {
            Component::Prefix(_) | Component::RootDir => out.push(c.as_os_str()),
            Component::CurDir => {}
            Component::ParentDir => {
                if exists {
                    out = out.canonicalize().ok()?;
                }
                out.pop();
                exists = out.exists();
            }
            Component::Normal(name) => {
                out.push(name);
                if exists {
                    match out.canonicalize() {
                        Ok(real) => out = real,
                        Err(_) => exists = false,
                    }
                }
            }
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("sph-safety-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn only_absent_or_regular_destinations_pass() {
        let d = scratch("dest");
        assert!(check_destination(&d.join("absent")).is_ok());
        std::fs::write(d.join("file"), "x").unwrap();
        assert!(check_destination(&d.join("file")).is_ok());
        let e = check_destination(&d).unwrap_err().to_string();
        assert!(e.contains("a directory"), "{e}");
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(d.join("file"), d.join("link")).unwrap();
            let e = check_destination(&d.join("link")).unwrap_err().to_string();
            assert!(e.contains("symbolic link"), "{e}");
            let e = check_destination(Path::new("/dev/null"))
                .unwrap_err()
                .to_string();
            assert!(e.contains("device"), "{e}");
        }
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn temp_names_are_unique_and_exclusive() {
        let d = scratch("temp");
        let target = d.join("s.json");
        let a = TempFile::beside(&target, true).unwrap();
        let b = TempFile::beside(&target, true).unwrap();
        assert_ne!(a.path(), b.path());
        let (pa, pb) = (a.path().to_path_buf(), b.path().to_path_buf());
        let mut b = b;
        b.write_all(b"{}").unwrap();
        b.persist(&target).unwrap();
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "{}");
        assert!(!pb.exists());
        drop(a);
        assert!(!pa.exists(), "a dropped temporary file is removed");
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_second_lock_of_the_same_output_fails_and_names_the_holder() {
        let d = scratch("lock");
        let target = d.join("r.h5");
        let lock = OutputLock::acquire(&target).unwrap();
        let e = OutputLock::acquire(&target).unwrap_err();
        match &e {
            OutputError::Locked { holder, .. } => assert_eq!(*holder, Some(std::process::id())),
            other => panic!("{other:?}"),
        }
        let lock_path = lock.path().to_path_buf();
        drop(lock);
        assert!(!lock_path.exists(), "the holder removes its lock file");
        let again = OutputLock::acquire(&target).unwrap();
        drop(again);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn free_space_is_read_for_new_paths_too() {
        let d = scratch("free");
        let here = free_space(&d).expect("statvfs works here");
        assert!(here > 0);
        let deeper = free_space(&d.join("not/yet/created.h5")).unwrap();
        // Same file system; other writers may change it a little in between.
        assert!(
            deeper.abs_diff(here) < here / 2 + (1 << 30),
            "{here} vs {deeper}"
        );
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn same_file_sees_through_dots_and_links() {
        let d = scratch("same");
        std::fs::create_dir_all(d.join("a")).unwrap();
        std::fs::write(d.join("x.toml"), "").unwrap();
        assert!(same_file(&d.join("a/../x.toml"), &d.join("x.toml")));
        assert!(same_file(&d.join("a/../new.json"), &d.join("new.json")));
        assert!(!same_file(&d.join("a/new.json"), &d.join("new.json")));
        // Through a directory that does not exist yet: the write creates it, then climbs out.
        assert!(same_file(&d.join("missing/../x.toml"), &d.join("x.toml")));
        assert!(same_file(
            &d.join("m/n/../../a/./../x.toml"),
            &d.join("x.toml")
        ));
        assert!(!same_file(&d.join("missing/x.toml"), &d.join("x.toml")));
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(d.join("x.toml"), d.join("l.toml")).unwrap();
            assert!(same_file(&d.join("l.toml"), &d.join("x.toml")));
            // `..` after a link to a directory leaves from where the link leads.
            std::fs::create_dir_all(d.join("deep/inner")).unwrap();
            std::fs::write(d.join("deep/y.toml"), "").unwrap();
            std::os::unix::fs::symlink(d.join("deep/inner"), d.join("link")).unwrap();
            assert!(same_file(&d.join("link/../y.toml"), &d.join("deep/y.toml")));
            assert!(same_file(
                &d.join("link/new/../../y.toml"),
                &d.join("deep/y.toml")
            ));
        }
        std::fs::remove_dir_all(&d).unwrap();
    }
}
