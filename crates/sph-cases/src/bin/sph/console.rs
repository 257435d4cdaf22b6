//! What `sph` writes to the terminal, under one rule for every subcommand:
//!
//! - **stderr** (errors, progress lines): written line by line, and a failed write (a full
//!   disk, a closed terminal after SIGHUP, `2>/dev/full`) is ignored. Logging never ends or
//!   changes a run; its exit status stays the documented 0/1/2.
//! - **stdout** (the list, a template, a run's figures): a reader that closed the pipe early
//!   (`sph list | head -1`) has what it wanted, which is not an error; any other failed write is
//!   one line on stderr and exit status 1, after the run's files are complete.
//! - **bad arguments**: one line, like every other error (clap's usage text goes to `--help`).

use std::io::Write;
use std::path::Path;
use std::process::ExitCode;
use std::sync::Mutex;

/// The `--log` file, when one was given: every line [`say`] writes, the progress lines and
/// the figures also go there. Failed writes are ignored, as on stderr.
static LOG: Mutex<Option<std::fs::File>> = Mutex::new(None);

/// Opens `path` for appending as the log file (created if absent).
pub(super) fn open_log(path: &Path) -> Result<(), sph_cases::CaseError> {
    let file = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .map_err(|e| sph_cases::CaseError::Io {
            path: format!("--log {}", path.display()),
            source: e,
        })?;
    if let Ok(mut log) = LOG.lock() {
        *log = Some(file);
    }
    Ok(())
}

/// Writes `text` and a newline to the log file only (the progress lines behind a terminal's
/// progress bar, the figures printed on stdout).
pub(super) fn log_only(text: &str) {
    if let Ok(mut log) = LOG.lock() {
        if let Some(f) = log.as_mut() {
            let _ = writeln!(f, "{text}").and_then(|_| f.flush());
        }
    }
}

/// Writes `line` and a newline to stderr (and the log file); a failure to write is ignored
/// (see the module documentation).
pub(super) fn say(line: &str) {
    let mut err = std::io::stderr().lock();
    let _ = writeln!(err, "{line}").and_then(|_| err.flush());
    log_only(line);
}

/// Writes `text` to stdout. A closed pipe is not an error.
pub(super) fn print_out(text: &str) -> std::io::Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|_| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        r => r,
    }
}

/// Prints `text` to stdout for a command that would otherwise end with `code`: a failed write
/// is reported and turns a success into exit status 1 (a failure keeps its own status).
pub(super) fn print_or_fail(text: &str, code: ExitCode) -> ExitCode {
    match print_out(text) {
        Ok(()) => code,
        Err(e) => {
            say(&format!("error: writing to stdout: {e}"));
            if code == ExitCode::SUCCESS {
                ExitCode::from(1)
            } else {
                code
            }
        }
    }
}

/// A command-line parsing error as one line (exit status 2), or the help or version text clap
/// prints on request (exit status 0).
pub(super) fn argument_error(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            let text = e.render().to_string();
            print_or_fail(&text, ExitCode::SUCCESS)
        }
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand | ErrorKind::MissingSubcommand => {
            say("error: a subcommand is needed: list, run or resume (see `sph --help`)");
            ExitCode::from(2)
        }
        _ => {
            say(&one_line(&e.render().to_string()));
            ExitCode::from(2)
        }
    }
}

/// The first line of a clap error, with a pointer to `--help` in place of its usage text.
fn one_line(rendered: &str) -> String {
    let mut lines = rendered.lines().map(str::trim).skip_while(|l| l.is_empty());
    let first = lines.next().unwrap_or("error: invalid arguments");
    // A first line that ends in a colon lists what it is about on the lines after it (the
    // missing required arguments): those join it.
    let first = match first.strip_suffix(':') {
        Some(head) => {
            let list: Vec<&str> = lines.take_while(|l| !l.is_empty()).collect();
            format!("{head}: {}", list.join(", "))
        }
        None => first.to_string(),
    };
    let first = first.trim_end_matches('.');
    let first = if first.starts_with("error:") {
        first.to_string()
    } else {
        format!("error: {first}")
    };
    format!("{first} (see `sph --help`)")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clap_errors_become_one_line() {
        let text = "error: invalid value '-1' for '--threads <THREADS>': invalid digit found in \
                    string\n\nFor more information, try '--help'.\n";
        assert_eq!(
            one_line(text),
            "error: invalid value '-1' for '--threads <THREADS>': invalid digit found in string \
             (see `sph --help`)"
        );
        assert_eq!(
            one_line(
                "error: the following required arguments were not provided:\n  --tolerance \
                 <TOLERANCE>\n  --quantity <QUANTITY>\n\nUsage: sph converge\n"
            ),
            "error: the following required arguments were not provided: --tolerance \
             <TOLERANCE>, --quantity <QUANTITY> (see `sph --help`)"
        );
        assert_eq!(
            one_line("\n  unexpected argument\n\nUsage: sph run\n"),
            "error: unexpected argument (see `sph --help`)"
        );
    }
}
