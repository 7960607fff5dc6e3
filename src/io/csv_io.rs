//! CSV actuations (`t, L_1, .., L_n` per knot) and trajectories, and atomic output files.

use crate::error::{Error, Result};
use crate::integrate::Trajectory;
use std::io::Write;
use std::path::{Path, PathBuf};

fn io_err(path: &Path, e: impl ToString) -> Error {
    Error::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    }
}

/// Reads an input file of at most `limit` bytes. Only regular files (or links to one) are read:
/// a directory, a FIFO or a device (`/dev/zero`, `/dev/stdin`) is refused before it is opened,
/// so that reading can neither block nor go on without end. The error is the reason alone.
pub(crate) fn read_input_file(path: &Path, limit: u64) -> std::result::Result<Vec<u8>, String> {
    use std::io::Read;
    let meta = std::fs::metadata(path).map_err(|e| e.to_string())?;
    check_regular(&meta)?;
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    // Again on the open file: the path may have been replaced in between.
    check_regular(&file.metadata().map_err(|e| e.to_string())?)?;
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| e.to_string())?;
    if bytes.len() as u64 > limit {
        return Err(format!(
            "larger than {} MiB: not an input file of crawlopt",
            limit >> 20
        ));
    }
    Ok(bytes)
}

fn check_regular(meta: &std::fs::Metadata) -> std::result::Result<(), String> {
    if meta.is_dir() {
        Err("is a directory, not a file".into())
    } else if !meta.is_file() {
        Err("is not a regular file (a device, a FIFO or a socket)".into())
    } else {
        Ok(())
    }
}

/// Largest CSV actuation read (bytes): about a million knots.
pub const MAX_CSV_BYTES: u64 = 64 << 20;

/// Reads a piecewise-linear actuation from CSV: one row per knot, columns `t, L_1, .., L_n`
/// (a header row is recognised by a non-numeric first field and skipped). Only a regular file
/// of at most `MAX_CSV_BYTES` is read.
pub fn read_actuation_csv(path: &Path, links: usize) -> Result<(Vec<f64>, Vec<Vec<f64>>)> {
    let bytes = read_input_file(path, MAX_CSV_BYTES)
        .map_err(|e| io_err(path, format!("cannot read actuation CSV: {e}")))?;
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(false)
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .from_reader(bytes.as_slice());
    let (mut times, mut lengths) = (Vec::new(), Vec::new());
    for (i, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(|e| io_err(path, format!("invalid CSV: {e}")))?;
        let row = i + 1;
        if i == 0 && rec.get(0).is_some_and(|f| f.parse::<f64>().is_err()) {
            continue; // header
        }
        if rec.len() != links + 1 {
            return Err(io_err(
                path,
                format!(
                    "row {row}: {} columns, expected {} (t and one length per link)",
                    rec.len(),
                    links + 1
                ),
            ));
        }
        let vals = rec
            .iter()
            .enumerate()
            .map(|(c, f)| {
                f.parse::<f64>().map_err(|_| {
                    io_err(
                        path,
                        format!("row {row}, column {}: not a number: {f:?}", c + 1),
                    )
                })
            })
            .collect::<Result<Vec<f64>>>()?;
        times.push(vals[0]);
        lengths.push(vals[1..].to_vec());
    }
    if times.is_empty() {
        return Err(io_err(path, "the actuation CSV has no data rows"));
    }
    Ok((times, lengths))
}

/// How an output path is written (decided by [`AtomicFile::check`] before anything is written).
#[derive(Debug, Clone, PartialEq, Eq)]
enum Target {
    /// A regular file, new or replaced: written under a temporary name next to it and renamed
    /// over it. The path is the destination itself, or the file a symbolic link resolves to.
    File(PathBuf),
    /// An existing device, FIFO or socket: written straight into (there is nothing to rename,
    /// and what was written cannot be taken back on failure).
    Stream,
    /// This process's standard output (`1`) or error (`2`), e.g. `/dev/stdout`: written through
    /// that descriptor, so that what the program prints there stays in order.
    Std(u8),
}

/// The output rules (see [`AtomicFile`]). Nothing is created or opened here.
fn target_of(dest: &Path) -> Result<Target> {
    let link = match std::fs::symlink_metadata(dest) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return new_file(dest),
        Err(e) => return Err(io_err(dest, format!("cannot write: {e}"))),
    };
    let meta = match std::fs::metadata(dest) {
        Ok(m) => m,
        Err(e) => {
            return Err(io_err(
                dest,
                format!("is a symbolic link that does not resolve to a file ({e}); not written"),
            ))
        }
    };
    if let Some(fd) = std_stream_of(&meta) {
        return Ok(Target::Std(fd));
    }
    if meta.is_dir() {
        return Err(io_err(
            dest,
            "is a directory; give the name of a file to write",
        ));
    }
    if !meta.is_file() {
        return Ok(Target::Stream);
    }
    if link.file_type().is_symlink() {
        // Written through: the file the link resolves to is replaced, the link stays.
        let real = std::fs::canonicalize(dest)
            .map_err(|e| io_err(dest, format!("cannot resolve the symbolic link: {e}")))?;
        return Ok(Target::File(real));
    }
    Ok(Target::File(dest.to_path_buf()))
}

/// A file to create: it needs a name and an existing directory.
fn new_file(dest: &Path) -> Result<Target> {
    if dest.file_name().is_none() {
        return Err(io_err(dest, "not a file name"));
    }
    let dir = match dest.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => Ok(Target::File(dest.to_path_buf())),
        Ok(_) => Err(io_err(
            dest,
            format!("cannot write: {} is not a directory", dir.display()),
        )),
        Err(e) => Err(io_err(
            dest,
            format!("cannot write: directory {}: {e}", dir.display()),
        )),
    }
}

/// `Some(1)` or `Some(2)` when `meta` is the file this process's standard output or error
/// writes to.
#[cfg(unix)]
fn std_stream_of(meta: &std::fs::Metadata) -> Option<u8> {
    use std::os::fd::AsFd;
    use std::os::unix::fs::MetadataExt;
    let same = |fd: std::os::fd::BorrowedFd| {
        fd.try_clone_to_owned()
            .ok()
            .and_then(|o| std::fs::File::from(o).metadata().ok())
            .is_some_and(|m| m.dev() == meta.dev() && m.ino() == meta.ino())
    };
    if same(std::io::stdout().as_fd()) {
        Some(1)
    } else if same(std::io::stderr().as_fd()) {
        Some(2)
    } else {
        None
    }
}

#[cfg(not(unix))]
fn std_stream_of(_meta: &std::fs::Metadata) -> Option<u8> {
    None
}

/// A duplicate of standard output (`1`) or error (`2`): it shares the file offset, so that
/// what is written through it and what the program prints stay in order.
#[cfg(unix)]
fn std_stream(fd: u8) -> std::io::Result<std::fs::File> {
    use std::os::fd::AsFd;
    let owned = if fd == 1 {
        std::io::stdout().flush()?;
        std::io::stdout().as_fd().try_clone_to_owned()?
    } else {
        std::io::stderr().as_fd().try_clone_to_owned()?
    };
    Ok(std::fs::File::from(owned))
}

#[cfg(not(unix))]
fn std_stream(_fd: u8) -> std::io::Result<std::fs::File> {
    Err(std::io::Error::other(
        "standard streams are written as files on unix only",
    ))
}

/// An output file, all or nothing: a regular file is written under a temporary name next to
/// it and renamed into place on [`AtomicFile::commit`] (dropped without commit, it leaves
/// nothing behind). The rules, checked before anything is written ([`AtomicFile::check`]):
/// - a directory, or a symbolic link to one, is refused;
/// - a symbolic link to a regular file is written through: the file it resolves to is
///   replaced atomically (its permissions kept) and the link stays; a link that resolves to
///   nothing is refused;
/// - an existing device, FIFO or socket (`/dev/null`, a named pipe) is written straight into,
///   never renamed over; this process's standard output or error (`/dev/stdout`) through its
///   own descriptor;
/// - a new file needs an existing directory.
pub struct AtomicFile {
    /// The path as given (for messages).
    dest: PathBuf,
    /// `(temporary, final)` paths of a regular file; `None` for a stream.
    staged: Option<(PathBuf, PathBuf)>,
    file: Option<std::io::BufWriter<std::fs::File>>,
}

impl AtomicFile {
    /// Refuses, without writing anything, a destination that [`AtomicFile::create`] would
    /// refuse (a directory, a dangling symbolic link, a file in a missing directory): so that
    /// a command can say so before it computes what to write.
    pub fn check(dest: &Path) -> Result<()> {
        target_of(dest).map(|_| ())
    }

    /// The destination opened for writing when, by the rules above, it is written straight
    /// into (a device, FIFO or socket, or this process's standard output or error); `None`
    /// for a regular file or a new one (nothing is opened then). For outputs that append to a
    /// regular file instead of replacing it (a sweep's table).
    pub fn open_stream(dest: &Path) -> Result<Option<std::fs::File>> {
        let cannot = |e: std::io::Error| io_err(dest, format!("cannot write: {e}"));
        match target_of(dest)? {
            Target::File(_) => Ok(None),
            Target::Stream => std::fs::OpenOptions::new()
                .write(true)
                .open(dest)
                .map(Some)
                .map_err(cannot),
            Target::Std(fd) => std_stream(fd).map(Some).map_err(cannot),
        }
    }

    /// Opens the destination by the rules above: a temporary file next to a regular file, or
    /// the stream itself.
    pub fn create(dest: &Path) -> Result<Self> {
        let cannot = |e: std::io::Error| io_err(dest, format!("cannot write: {e}"));
        let (staged, file) = match target_of(dest)? {
            Target::File(real) => {
                let (tmp, file) = create_temporary(&real).map_err(cannot)?;
                (Some((tmp, real)), file)
            }
            Target::Stream => (
                None,
                std::fs::OpenOptions::new()
                    .write(true)
                    .open(dest)
                    .map_err(cannot)?,
            ),
            Target::Std(fd) => (None, std_stream(fd).map_err(cannot)?),
        };
        Ok(AtomicFile {
            dest: dest.to_path_buf(),
            staged,
            file: Some(std::io::BufWriter::new(file)),
        })
    }

    /// The writer.
    pub fn writer(&mut self) -> &mut std::io::BufWriter<std::fs::File> {
        // `file` is only taken by `commit`, which consumes `self`.
        self.file.as_mut().expect("file open until commit")
    }

    /// Flushes, and renames a regular file into place (keeping the permissions of the file it
    /// replaces). On failure the temporary file is removed.
    pub fn commit(mut self) -> Result<()> {
        // See `writer`.
        let f = self.file.take().expect("file open until commit");
        let result = (|| {
            let file = f.into_inner().map_err(|e| e.into_error())?;
            if let Some((tmp, real)) = &self.staged {
                if let Ok(old) = std::fs::metadata(real) {
                    if old.is_file() {
                        file.set_permissions(old.permissions())?;
                    }
                }
                drop(file);
                // Under the registry's lock: a signal's clean-up waits for the rename, or has
                // removed the file (the rename then fails, and the process is ending anyway).
                let mut reg = staged();
                if reg.1 {
                    return Err(std::io::Error::other("the process is ending (interrupted)"));
                }
                std::fs::rename(tmp, real)?;
                reg.0.retain(|p| p != tmp);
            }
            Ok(())
        })();
        result.map_err(|e: std::io::Error| {
            if let Some((tmp, _)) = &self.staged {
                let _ = std::fs::remove_file(tmp);
                unstage(tmp);
            }
            io_err(&self.dest, format!("cannot write: {e}"))
        })
    }
}

/// The temporary files of this process's uncommitted [`AtomicFile`]s, and whether
/// [`remove_staged_files`] has run (no temporary file is created after it).
static STAGED: std::sync::Mutex<(Vec<PathBuf>, bool)> = std::sync::Mutex::new((Vec::new(), false));

/// The registry of temporary files, also when a thread panicked holding it (a list of paths
/// cannot be left inconsistent).
fn staged() -> std::sync::MutexGuard<'static, (Vec<PathBuf>, bool)> {
    STAGED
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Removes the temporary files of every [`AtomicFile`] not yet committed, and makes any later
/// [`AtomicFile::create`] of a regular file fail: for a process about to end on a signal
/// (Ctrl-C, SIGTERM), whose destructors will not run. A commit in progress either renames
/// its whole file into place first, or finds its temporary file gone. Returns how many files
/// were removed. Call it from a normal thread (e.g. a signal-handling thread), not from inside
/// a signal handler: it locks and allocates.
pub fn remove_staged_files() -> usize {
    let mut reg = staged();
    reg.1 = true;
    let files = std::mem::take(&mut reg.0);
    files
        .iter()
        .filter(|tmp| std::fs::remove_file(tmp).is_ok())
        .count()
}

/// Takes `tmp` off the registry of temporary files.
fn unstage(tmp: &Path) {
    staged().0.retain(|p| p != tmp);
}

/// A new temporary file `.NAME.tmpPID` (or `.NAME.tmpPID.I`) next to `real`, created
/// exclusively (never through an existing path), and registered for [`remove_staged_files`].
fn create_temporary(real: &Path) -> std::io::Result<(PathBuf, std::fs::File)> {
    let mut reg = staged();
    if reg.1 {
        return Err(std::io::Error::other("the process is ending (interrupted)"));
    }
    let (tmp, file) = create_temporary_file(real)?;
    reg.0.push(tmp.clone());
    Ok((tmp, file))
}

fn create_temporary_file(real: &Path) -> std::io::Result<(PathBuf, std::fs::File)> {
    let name = real
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let pid = std::process::id();
    let mut last = None;
    for i in 0..100 {
        let suffix = if i == 0 {
            String::new()
        } else {
            format!(".{i}")
        };
        let tmp = real.with_file_name(format!(".{name}.tmp{pid}{suffix}"));
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
        {
            Ok(f) => return Ok((tmp, f)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last = Some(e),
            Err(e) => return Err(e),
        }
    }
    Err(last.unwrap_or_else(|| std::io::Error::other("no temporary name left")))
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.file.take().is_some() {
            if let Some((tmp, _)) = &self.staged {
                let _ = std::fs::remove_file(tmp);
                unstage(tmp);
            }
        }
    }
}

/// Writes a trajectory as CSV: `t, x_1..x_n, X_1..X_N, y, slip_1..slip_N` (1-based names).
pub fn write_trajectory_csv(path: &Path, traj: &Trajectory) -> Result<()> {
    let mut out = AtomicFile::create(path)?;
    let n = traj.x.first().map_or(0, Vec::len);
    let nb = traj.positions.first().map_or(0, Vec::len);
    {
        let mut w = csv::Writer::from_writer(out.writer());
        let mut header = vec!["t".to_string()];
        header.extend((1..=n).map(|l| format!("x_{l}")));
        header.extend((1..=nb).map(|b| format!("X_{b}")));
        header.push("y".into());
        header.extend((1..=nb).map(|b| format!("slip_{b}")));
        w.write_record(&header).map_err(|e| io_err(path, e))?;
        for i in 0..traj.t.len() {
            let mut row = vec![format!("{}", traj.t[i])];
            row.extend(traj.x[i].iter().map(|v| format!("{v}")));
            row.extend(traj.positions[i].iter().map(|v| format!("{v}")));
            row.push(format!("{}", traj.barycentre[i]));
            row.extend(traj.slip[i].iter().map(|v| v.to_string()));
            w.write_record(&row).map_err(|e| io_err(path, e))?;
        }
        w.flush().map_err(|e| io_err(path, e))?;
    }
    out.commit()
}
