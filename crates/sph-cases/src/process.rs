//! A run in a child process with what it cost: CPU time, wall time and peak memory of that
//! process alone (`wait4`), so a ladder of runs (`sph converge`, `validate tradeoff`) measures
//! each level as a user running it would see it.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Instant;

/// How a child process ended and what it cost.
#[derive(Clone, Debug, PartialEq)]
pub struct Costed {
    /// Exit status (128 + the signal when a signal ended it).
    pub exit_code: i32,
    /// User CPU seconds of the child.
    pub user_seconds: f64,
    /// System CPU seconds of the child.
    pub system_seconds: f64,
    /// Wall seconds.
    pub wall_seconds: f64,
    /// Peak resident memory of the child, bytes.
    pub peak_bytes: f64,
    /// What the child wrote on stderr, when the command piped it (else empty).
    pub stderr: String,
}

impl Costed {
    /// User + system CPU seconds.
    pub fn cpu_seconds(&self) -> f64 {
        self.user_seconds + self.system_seconds
    }

    /// The first `error…` line of stderr, else its last line (the diagnostic of a failed run).
    pub fn message(&self) -> String {
        self.stderr
            .lines()
            .find(|l| l.starts_with("error"))
            .or_else(|| self.stderr.lines().last())
            .unwrap_or("")
            .to_string()
    }
}

/// Runs `program` with `args` in `dir` (stdout discarded, stderr kept) and waits for it.
///
/// # Errors
/// The program cannot be started or waited for.
pub fn run_costed(program: &Path, args: &[String], dir: Option<&Path>) -> Result<Costed, String> {
    let mut cmd = Command::new(program);
    cmd.args(args).stdout(Stdio::null()).stderr(Stdio::piped());
    if let Some(d) = dir {
        cmd.current_dir(d);
    }
    measure(&mut cmd).map_err(|e| format!("{}: {e}", program.display()))
}

/// Starts `command` as it is configured and waits for it with `wait4`, which reports that
/// child's own resource usage (its peak resident set in particular, which `RUSAGE_CHILDREN`
/// only gives as a maximum over all children so far). A piped stderr is collected.
///
/// # Errors
/// The command cannot be started or waited for.
pub fn measure(command: &mut Command) -> Result<Costed, String> {
    let started = Instant::now();
    let child = command.spawn().map_err(|e| e.to_string())?;
    let mut c = wait_with_usage(child)?;
    c.wall_seconds = started.elapsed().as_secs_f64();
    Ok(c)
}

/// Waits for `child` with `wait4`: its exit code (128 + signal when killed), CPU seconds, peak
/// resident bytes and piped stderr (wall time left to the caller).
#[cfg(unix)]
// The child is reaped by `wait4`, which clippy cannot see.
#[allow(clippy::zombie_processes)]
fn wait_with_usage(mut child: std::process::Child) -> Result<Costed, String> {
    use std::io::Read;
    // Drain stderr on a thread so a chatty child cannot block on a full pipe.
    let reader = child.stderr.take().map(|mut err| {
        std::thread::spawn(move || {
            let mut s = String::new();
            let _ = err.read_to_string(&mut s);
            s
        })
    });
    let pid = child.id() as libc::pid_t;
    let mut status: libc::c_int = 0;
    // SAFETY: rusage is plain old data, for which all zeros is a valid value.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    loop {
        // SAFETY: wait4 writes into the rusage and the status we own; `pid` is our child, not
        // yet waited for (std's Child::wait is never called on it).
        let r = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
        if r == pid {
            break;
        }
        let e = std::io::Error::last_os_error();
        // A signal handled by this process (SIGINT for the whole group) interrupts the wait.
        if e.kind() != std::io::ErrorKind::Interrupted {
            return Err(format!("wait4: {e}"));
        }
    }
    let exit_code = if libc::WIFEXITED(status) {
        libc::WEXITSTATUS(status)
    } else {
        128 + libc::WTERMSIG(status)
    };
    let secs = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    Ok(Costed {
        exit_code,
        user_seconds: secs(usage.ru_utime),
        system_seconds: secs(usage.ru_stime),
        wall_seconds: 0.0,
        // ru_maxrss is in KiB on Linux.
        peak_bytes: usage.ru_maxrss as f64 * 1024.0,
        stderr: reader.and_then(|r| r.join().ok()).unwrap_or_default(),
    })
}

/// Elsewhere: the exit code and stderr, wall time only (CPU time and memory unknown: NaN).
#[cfg(not(unix))]
fn wait_with_usage(child: std::process::Child) -> Result<Costed, String> {
    let out = child.wait_with_output().map_err(|e| e.to_string())?;
    Ok(Costed {
        exit_code: out.status.code().unwrap_or(-1),
        user_seconds: f64::NAN,
        system_seconds: f64::NAN,
        wall_seconds: 0.0,
        peak_bytes: f64::NAN,
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    })
}
