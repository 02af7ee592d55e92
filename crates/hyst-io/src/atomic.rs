//! Output files: atomic replacement on [`tempfile`] for regular files (write a
//! temporary file next to the destination, fsync it, then rename it over the
//! destination), straight writes for standard output (`-`) and devices, and the
//! list of live temporary files that a signal handler removes
//! ([`remove_temporary_files`]).

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

use crate::error::IoError;

/// The output path that means standard output.
pub const STDOUT: &str = "-";

/// Writes `bytes` to `path`: atomically for a regular file, straight through for
/// standard output and devices.
///
/// - `-` writes to standard output.
/// - A path that exists and is not a regular file or directory (a character
///   device such as `/dev/null`, `/dev/stdout`'s target, a FIFO) is opened and
///   written directly: it cannot be replaced, and must not be.
/// - A symbolic link is followed: its target is written (atomically if it is a
///   regular file, created if the link dangles); the link itself stays.
/// - A regular file (or a new path): the bytes go to a hidden temporary file
///   (`.NAME.XXXXXX.tmp`, six random characters) in the same directory, which
///   is flushed and fsynced and then renamed over the file; afterwards the
///   directory is fsynced (best effort). Readers therefore see either the
///   complete old file or the complete new one, never a mix. If the file
///   already exists, the new file gets its permissions; otherwise it gets the
///   usual permissions of a newly created file (`0o666` less the umask on Unix).
///
/// # Errors
///
/// [`IoError::IsDirectory`] if `path` is a directory, and [`IoError::Write`]
/// (naming the step that failed and the OS error) if the temporary file cannot
/// be created, written, synced or renamed. On any error (and on a panic while
/// writing) the destination is untouched and no temporary file remains. A
/// process killed by a signal it does not handle may leave the temporary file
/// behind (never a partial destination); `hyst` handles SIGINT and SIGTERM by
/// calling [`remove_temporary_files`].
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    write_atomic_with(path, |w| w.write_all(bytes))
}

/// The temporary files being written right now (full paths).
static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn temporaries() -> MutexGuard<'static, Vec<PathBuf>> {
    TEMPORARIES.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Removes every temporary file this process is writing, for a signal handler
/// that is about to end the process.
///
/// The returned guard holds the list locked: while it lives no temporary file
/// is created or renamed over its destination, so keep it until the process
/// exits. A rename that had already happened stands (the destination is then
/// complete).
pub fn remove_temporary_files() -> MutexGuard<'static, Vec<PathBuf>> {
    let mut live = temporaries();
    for path in live.drain(..) {
        let _ = fs::remove_file(path);
    }
    live
}

/// Fails with [`IoError::SameFile`] when `output` is the same file as `input`
/// (same device and inode: the same path, a symbolic or a hard link). A path
/// that does not exist yet is never the same file; `-` (standard output) is not
/// checked.
///
/// # Errors
///
/// [`IoError::SameFile`].
pub fn check_distinct(input: &Path, output: &Path) -> Result<(), IoError> {
    if output.as_os_str() == STDOUT {
        return Ok(());
    }
    if same(input, output) {
        return Err(IoError::SameFile {
            input: input.to_path_buf(),
            output: output.to_path_buf(),
        });
    }
    Ok(())
}

/// Refuses, before anything is read or written, an output that is one of the inputs (as
/// [`check_distinct`]) or the same file as another output (by device and inode, or the same
/// path when neither exists yet): one output would replace another, or the data.
///
/// # Errors
/// [`IoError::SameFile`] naming the output and the input, or the two outputs.
pub fn check_all_distinct(inputs: &[&Path], outputs: &[&Path]) -> Result<(), IoError> {
    for (i, output) in outputs.iter().enumerate() {
        for input in inputs {
            check_distinct(input, output)?;
        }
        if output.as_os_str() == STDOUT {
            continue;
        }
        for other in outputs.iter().take(i) {
            if other.as_os_str() != STDOUT && (same(other, output) || lexically_same(other, output))
            {
                return Err(IoError::SameOutput {
                    first: other.to_path_buf(),
                    second: output.to_path_buf(),
                });
            }
        }
    }
    Ok(())
}

/// Checks, before a long computation, that `path` can be written as [`write_atomic`] will write
/// it: standard output and an existing device or FIFO pass (nothing is opened: a FIFO would
/// block); a directory is refused; otherwise a temporary file is created in the destination's
/// directory and removed again, so a missing or read-only directory is found now rather than
/// after the work.
///
/// # Errors
/// [`IoError::IsDirectory`], or [`IoError::Write`] naming the step that failed.
pub fn check_writable(path: &Path) -> Result<(), IoError> {
    if path.as_os_str() == STDOUT {
        return Ok(());
    }
    match fs::metadata(path) {
        Ok(meta) if meta.is_dir() => Err(IoError::IsDirectory {
            path: path.to_path_buf(),
        }),
        Ok(meta) if !meta.is_file() => Ok(()),
        _ => Output::create(path).map(drop),
    }
}

/// Checks, before a long computation, that files can be written into the directory `dir`
/// (created later if it does not exist yet): an existing `dir` must be a writable directory;
/// otherwise its nearest existing ancestor must be one (nothing is created: a command that then
/// fails leaves no empty directory behind).
///
/// # Errors
/// [`IoError::Write`] naming the directory and the step that failed.
pub fn check_writable_dir(dir: &Path) -> Result<(), IoError> {
    let mut existing = dir;
    while !existing.as_os_str().is_empty() && fs::symlink_metadata(existing).is_err() {
        match existing.parent() {
            Some(parent) => existing = parent,
            None => break,
        }
    }
    let probe = if existing.as_os_str().is_empty() {
        Path::new(".")
    } else {
        existing
    };
    let action = if probe == dir {
        "write into the directory".to_string()
    } else {
        format!("create the directory in {:?}", probe.display().to_string())
    };
    match fs::metadata(probe) {
        Ok(meta) if meta.is_dir() => tempfile::tempfile_in(probe)
            .map(drop)
            .map_err(|e| write_error(dir, action)(e)),
        Ok(_) => Err(write_error(dir, action)(io::Error::new(
            io::ErrorKind::NotADirectory,
            format!("{} is not a directory", probe.display()),
        ))),
        Err(e) => Err(write_error(dir, action)(e)),
    }
}

/// Whether two paths name the same existing file, by device and inode from their metadata
/// (through symbolic links). Nothing is opened: opening a FIFO would block until a writer
/// comes.
#[cfg(unix)]
fn same(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino(),
        _ => false,
    }
}

/// Whether two paths name the same existing file.
#[cfg(not(unix))]
fn same(a: &Path, b: &Path) -> bool {
    same_file::is_same_file(a, b).unwrap_or(false)
}

/// The same path once `.` components and repeated separators are left out (for files that do
/// not exist yet).
fn lexically_same(a: &Path, b: &Path) -> bool {
    a.components().eq(b.components())
}

/// Builds a [`IoError::Write`] for `path`.
fn write_error(path: &Path, action: impl Into<String>) -> impl FnOnce(io::Error) -> IoError + '_ {
    let action = action.into();
    move |source| IoError::Write {
        path: path.to_path_buf(),
        action,
        source,
    }
}

/// Writes whatever `fill` writes to `path`, as [`write_atomic`] describes.
///
/// Same guarantees as [`write_atomic`]; an error returned by `fill` is reported
/// as [`IoError::Write`] and leaves the destination untouched (standard output
/// and devices excepted: what was written there stays written).
pub(crate) fn write_atomic_with<F>(path: &Path, fill: F) -> Result<(), IoError>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    let mut output = Output::create(path)?;
    fill(&mut output).map_err(|e| output.error(e))?;
    output.finish()
}

/// An output being written, as [`write_atomic`] describes: standard output, a device written
/// straight through, or a temporary file next to the destination that [`Output::finish`]
/// renames over it. Dropped unfinished (an error, a panic), it removes the temporary file and
/// leaves the destination as it was.
pub(crate) struct Output {
    /// The path the user gave (named in errors).
    path: PathBuf,
    /// Where the bytes go.
    sink: Sink,
}

/// Where an [`Output`]'s bytes go.
enum Sink {
    /// Standard output.
    Stdout(BufWriter<io::StdoutLock<'static>>),
    /// An existing non-regular file (a device, a FIFO), written directly.
    Device(BufWriter<File>),
    /// A temporary file, renamed over `target` when finished.
    Temporary {
        /// The temporary file, written through the plain `File`: tempfile's own `Write`
        /// would append the temporary path to every error message.
        writer: BufWriter<File>,
        /// Its path; removes the file when dropped unless persisted.
        temp: tempfile::TempPath,
        /// Its entry on the list of [`remove_temporary_files`].
        listed: Listed,
        /// The regular file to replace (the target of a symbolic link the user named).
        target: PathBuf,
        /// The directory of both.
        dir: PathBuf,
        /// The permissions of the file being replaced, if it exists.
        existing: Option<fs::Permissions>,
    },
}

/// The buffer of an [`Output`]: large enough that writing 10 M short rows costs no more than
/// the rows themselves.
const BUFFER: usize = 64 * 1024;

impl Output {
    /// Opens the output for `path`: standard output for `-`, the device itself for an existing
    /// non-regular file, otherwise a new temporary file in the destination's directory (the
    /// target of a symbolic link is the destination).
    ///
    /// # Errors
    /// [`IoError::IsDirectory`], or [`IoError::Write`] naming the step that failed.
    pub(crate) fn create(path: &Path) -> Result<Output, IoError> {
        let sink = if path.as_os_str() == STDOUT {
            Sink::Stdout(BufWriter::with_capacity(BUFFER, io::stdout().lock()))
        } else {
            // `metadata` follows symbolic links, the kernel's "magic" ones too (/dev/stdout ->
            // /proc/self/fd/1 -> a pipe), so a device or FIFO is recognised through any link.
            let followed = fs::metadata(path);
            match &followed {
                Ok(meta) if meta.is_dir() => {
                    return Err(IoError::IsDirectory {
                        path: path.to_path_buf(),
                    })
                }
                Ok(meta) if !meta.is_file() => {
                    let file = OpenOptions::new()
                        .write(true)
                        .open(path)
                        .map_err(write_error(path, "open"))?;
                    Sink::Device(BufWriter::with_capacity(BUFFER, file))
                }
                _ => {
                    let mut target = path.to_path_buf();
                    if fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink()) {
                        target = resolve_link(path)
                            .map_err(write_error(path, "follow the symbolic link"))?;
                    }
                    temporary(path, target, followed.ok().map(|m| m.permissions()))?
                }
            }
        };
        Ok(Output {
            path: path.to_path_buf(),
            sink,
        })
    }

    /// The [`IoError::Write`] for an error while writing the bytes.
    pub(crate) fn error(&self, source: io::Error) -> IoError {
        let action = match self.sink {
            Sink::Stdout(_) => "write to standard output",
            Sink::Device(_) => "write",
            Sink::Temporary { .. } => "write the temporary file",
        };
        write_error(&self.path, action)(source)
    }

    /// Writes `bytes`.
    ///
    /// # Errors
    /// [`IoError::Write`].
    pub(crate) fn write_bytes(&mut self, bytes: &[u8]) -> Result<(), IoError> {
        self.write_all(bytes).map_err(|e| self.error(e))
    }

    /// Flushes the bytes, and for a regular file gives the temporary file the old file's
    /// permissions, syncs it to disk and renames it over the destination (then syncs the
    /// directory, best effort).
    ///
    /// # Errors
    /// [`IoError::Write`] naming the step that failed; the destination is then untouched and
    /// the temporary file removed.
    pub(crate) fn finish(mut self) -> Result<(), IoError> {
        self.flush().map_err(|e| self.error(e))?;
        let path = self.path;
        let Sink::Temporary {
            writer,
            temp,
            listed,
            target,
            dir,
            existing,
        } = self.sink
        else {
            return Ok(());
        };
        let file = writer
            .into_inner()
            .map_err(|e| write_error(&path, "write the temporary file")(e.into_error()))?;
        if let Some(permissions) = existing {
            // After creation, so that the umask does not narrow them.
            file.set_permissions(permissions).map_err(write_error(
                &path,
                "give the temporary file the old file's permissions",
            ))?;
        }
        file.sync_all()
            .map_err(write_error(&path, "sync the temporary file to disk"))?;
        drop(file);

        // Renamed and unlisted under the lock: a signal handler either removes the
        // temporary file first (and the process ends before the rename) or finds
        // the rename done.
        let persisted = {
            let mut live = temporaries();
            let persisted = temp.persist(&target);
            live.retain(|p| p != &listed.0);
            std::mem::forget(listed);
            persisted
        };
        persisted.map_err(|e| {
            let action = format!(
                "rename the temporary file {:?} over it",
                e.path.display().to_string()
            );
            // Dropping `e.path` removes the temporary file.
            write_error(&path, action)(e.error)
        })?;

        sync_dir(&dir);
        Ok(())
    }
}

impl Write for Output {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        match &mut self.sink {
            Sink::Stdout(w) => w.write(bytes),
            Sink::Device(w) => w.write(bytes),
            Sink::Temporary { writer, .. } => writer.write(bytes),
        }
    }

    fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
        match &mut self.sink {
            Sink::Stdout(w) => w.write_all(bytes),
            Sink::Device(w) => w.write_all(bytes),
            Sink::Temporary { writer, .. } => writer.write_all(bytes),
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        match &mut self.sink {
            Sink::Stdout(w) => w.flush(),
            Sink::Device(w) => w.flush(),
            Sink::Temporary { writer, .. } => writer.flush(),
        }
    }
}

/// The final target of the symbolic link `link`: its canonical path, or for a
/// dangling link the (last) target it names, relative to the link's directory.
fn resolve_link(link: &Path) -> io::Result<PathBuf> {
    if let Ok(resolved) = fs::canonicalize(link) {
        return Ok(resolved);
    }
    let mut current = link.to_path_buf();
    for _ in 0..40 {
        match fs::read_link(&current) {
            Ok(next) => {
                current = match current.parent() {
                    Some(dir) => dir.join(next),
                    None => next,
                };
            }
            Err(_) => return Ok(current),
        }
    }
    Err(io::Error::other("too many levels of symbolic links"))
}

/// The OS error under an error of `tempfile`, which appends the temporary path it tried ("No
/// such file or directory (os error 2) at path \"dir/.o.toml.rLQshm.tmp\""): that path names
/// a file the user never asked for, so it is dropped. tempfile keeps the OS error only in its
/// message (its error's `source` is the OS error's own, none), so the code is read back from it.
fn os_error(e: io::Error) -> io::Error {
    let message = e.to_string();
    let Some(at) = message.rfind(" at path \"") else {
        return e;
    };
    let head = &message[..at];
    let code = head
        .strip_suffix(')')
        .and_then(|h| h.rsplit_once("(os error "))
        .and_then(|(_, code)| code.parse::<i32>().ok());
    match code {
        Some(code) => io::Error::from_raw_os_error(code),
        None => io::Error::new(e.kind(), head.to_string()),
    }
}

/// A new temporary file (`.NAME.XXXXXX.tmp`) next to `target`, on the list of
/// [`remove_temporary_files`]; errors name `path`, the path the user gave.
fn temporary(
    path: &Path,
    target: PathBuf,
    existing: Option<fs::Permissions>,
) -> Result<Sink, IoError> {
    let file_name = target.file_name().ok_or_else(|| IoError::Write {
        path: path.to_path_buf(),
        action: "write".into(),
        source: io::Error::new(io::ErrorKind::InvalidInput, "the path has no file name"),
    })?;
    let dir = match target.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.to_path_buf(),
        _ => PathBuf::from("."),
    };

    let mut prefix = std::ffi::OsString::from(".");
    prefix.push(file_name);
    prefix.push(".");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    // tempfile creates 0o600 files; ask for what `File::create` gives instead.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    // Created and listed under the lock, so a signal handler's cleanup sees it.
    let (file, temp) = {
        let mut live = temporaries();
        let temp = builder.tempfile_in(&dir).map_err(|e| {
            // The directory is named only when it is not the one of the path the user gave (a
            // symbolic link's target); the OS error is given without the temporary path.
            let action = if target == path {
                "create a file in its directory".to_string()
            } else {
                format!(
                    "create a file in {:?}, the directory of its link target",
                    dir.display().to_string()
                )
            };
            write_error(path, action)(os_error(e))
        })?;
        live.push(temp.path().to_path_buf());
        temp.into_parts()
    };
    let listed = Listed(temp.to_path_buf());
    Ok(Sink::Temporary {
        writer: BufWriter::with_capacity(BUFFER, file),
        temp,
        listed,
        target,
        dir,
        existing,
    })
}

/// A temporary file on the list of [`remove_temporary_files`]; dropping it
/// (on an error or a panic) takes it off.
struct Listed(PathBuf);

impl Drop for Listed {
    fn drop(&mut self) {
        temporaries().retain(|p| p != &self.0);
    }
}

/// Makes the rename durable by syncing the directory (Unix only); tempfile's
/// `persist` only renames.
///
/// Best effort: by the time this runs the destination has already been replaced,
/// so failing here would misreport the outcome.
fn sync_dir(dir: &Path) {
    #[cfg(unix)]
    {
        if let Ok(d) = File::open(dir) {
            let _ = d.sync_all();
        }
    }
    #[cfg(not(unix))]
    {
        let _ = dir;
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::*;

    /// The names of all entries in `dir`, sorted.
    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn creates_a_new_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.json");
        write_atomic(&path, b"{}\n").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"{}\n");
        assert_eq!(entries(dir.path()), ["out.json"]);
    }

    #[test]
    fn replaces_an_existing_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.svg");
        fs::write(&path, b"old contents that are longer").unwrap();
        write_atomic(&path, b"new").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"new");
        assert_eq!(entries(dir.path()), ["out.svg"]);
        write_atomic(&path, b"").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"");
    }

    #[cfg(unix)]
    #[test]
    fn keeps_the_permissions_of_the_old_file() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("run.sh");
        fs::write(&path, b"old").unwrap();
        // Group and other write bits, which a usual umask (0o022) would strip.
        fs::set_permissions(&path, fs::Permissions::from_mode(0o646)).unwrap();
        write_atomic(&path, b"new").unwrap();
        let mode = fs::metadata(&path).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o646);
    }

    #[cfg(unix)]
    #[test]
    fn a_new_file_gets_the_permissions_file_create_gives() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("new.csv");
        write_atomic(&path, b"x\n").unwrap();
        let reference = dir.path().join("reference");
        File::create(&reference).unwrap();
        let mode = |p: &Path| fs::metadata(p).unwrap().permissions().mode() & 0o777;
        // Not tempfile's private 0o600 (unless the umask itself is 0o177).
        assert_eq!(mode(&path), mode(&reference));
    }

    #[test]
    fn writes_into_a_subdirectory() {
        let dir = tempfile::tempdir().unwrap();
        let sub = dir.path().join("sub");
        fs::create_dir(&sub).unwrap();
        let target = sub.join("f.bin");
        write_atomic(&target, &[0, 1, 2, 255]).unwrap();
        assert_eq!(fs::read(&target).unwrap(), [0, 1, 2, 255]);
        assert_eq!(entries(&sub), ["f.bin"]);
    }

    #[test]
    fn missing_directory_is_an_error_naming_path_and_step() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("no-such-dir").join("out.csv");
        let err = write_atomic(&path, b"x").unwrap_err();
        assert!(matches!(err, IoError::Write { .. }), "{err:?}");
        let msg = err.to_string();
        let os = io::Error::from_raw_os_error(2).to_string();
        // The path once, the OS error without tempfile's temporary path.
        assert_eq!(
            msg,
            format!(
                "{}: cannot create a file in its directory: {os}",
                path.display()
            )
        );
        assert!(msg.contains("No such file or directory"), "{msg}");
        assert_eq!(entries(dir.path()), Vec::<String>::new());
    }

    #[test]
    fn directory_destination_is_an_error_and_leaves_it_alone() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("results");
        fs::create_dir(&target).unwrap();
        fs::write(target.join("keep.txt"), b"keep").unwrap();
        let err = write_atomic(&target, b"x").unwrap_err();
        assert!(matches!(err, IoError::IsDirectory { .. }), "{err:?}");
        assert_eq!(
            err.to_string(),
            format!("{}: is a directory, not a file", target.display())
        );
        assert_eq!(entries(dir.path()), ["results"]);
        assert_eq!(entries(&target), ["keep.txt"]);
    }

    #[test]
    fn failure_while_writing_keeps_old_file_and_removes_temp() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("data.csv");
        fs::write(&path, b"x\n1\n").unwrap();
        let mut seen_while_writing = Vec::new();
        let err = write_atomic_with(&path, |w| {
            w.write_all(b"x\n2\n")?;
            w.flush()?;
            seen_while_writing = entries(dir.path());
            assert_eq!(fs::read(&path).unwrap(), b"x\n1\n");
            Err(io::Error::other("disk on fire"))
        })
        .unwrap_err();
        // The temporary file lived next to the target, under a hidden name.
        assert_eq!(seen_while_writing.len(), 2, "{seen_while_writing:?}");
        let temp = &seen_while_writing[0];
        assert!(
            temp.starts_with(".data.csv.") && temp.ends_with(".tmp"),
            "{temp}"
        );
        assert_eq!(temp.len(), ".data.csv.".len() + 6 + ".tmp".len(), "{temp}");
        assert_eq!(
            err.to_string(),
            format!(
                "{}: cannot write the temporary file: disk on fire",
                path.display()
            )
        );
        assert_eq!(fs::read(&path).unwrap(), b"x\n1\n");
        assert_eq!(entries(dir.path()), ["data.csv"]);
    }

    #[test]
    fn failed_rename_leaves_no_temp_and_keeps_what_is_at_the_target() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("data.csv");
        fs::write(&path, b"old").unwrap();
        // While the file is being written, something replaces the target by a
        // non-empty directory, so the final rename fails.
        let err = write_atomic_with(&path, |w| {
            w.write_all(b"new")?;
            fs::remove_file(&path)?;
            fs::create_dir(&path)?;
            fs::write(path.join("keep.txt"), b"keep")
        })
        .unwrap_err();
        let msg = err.to_string();
        let start = format!(
            "{}: cannot rename the temporary file \"{}/.data.csv.",
            path.display(),
            dir.path().display()
        );
        assert!(msg.starts_with(&start), "{msg}");
        assert!(msg.contains(".tmp\" over it: "), "{msg}");
        assert_eq!(entries(dir.path()), ["data.csv"]);
        assert_eq!(entries(&path), ["keep.txt"]);
        assert_eq!(fs::read(path.join("keep.txt")).unwrap(), b"keep");
    }

    #[test]
    fn panic_while_writing_keeps_old_file_and_removes_temp() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("data.csv");
        fs::write(&path, b"old").unwrap();
        let result = std::panic::catch_unwind(|| {
            let _ = write_atomic_with(&path, |w| {
                w.write_all(b"half")?;
                panic!("bug in the caller");
            });
        });
        assert!(result.is_err());
        assert_eq!(fs::read(&path).unwrap(), b"old");
        assert_eq!(entries(dir.path()), ["data.csv"]);
    }

    #[test]
    fn path_without_file_name_is_an_error() {
        let err = write_atomic(Path::new(".."), b"x").unwrap_err();
        // ".." is a directory, which is reported first.
        assert!(matches!(err, IoError::IsDirectory { .. }), "{err:?}");
        let dir = tempfile::tempdir().unwrap();
        let err = write_atomic(&dir.path().join("missing").join(".."), b"x").unwrap_err();
        assert!(
            err.to_string()
                .ends_with("cannot write: the path has no file name"),
            "{err}"
        );
    }

    #[cfg(unix)]
    #[test]
    fn a_symbolic_link_is_written_through_and_stays_a_link() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("real.csv");
        fs::write(&target, b"old").unwrap();
        let link = dir.path().join("link.csv");
        std::os::unix::fs::symlink("real.csv", &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(fs::read(&target).unwrap(), b"new");
        assert_eq!(entries(dir.path()), ["link.csv", "real.csv"]);
        // A dangling link: its target is created, the link stays.
        let dangling = dir.path().join("dangling.csv");
        std::os::unix::fs::symlink("made.csv", &dangling).unwrap();
        write_atomic(&dangling, b"made").unwrap();
        assert!(fs::symlink_metadata(&dangling)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(fs::read(dir.path().join("made.csv")).unwrap(), b"made");
    }

    #[cfg(unix)]
    #[test]
    fn a_device_is_written_not_replaced() {
        write_atomic(Path::new("/dev/null"), b"discarded").unwrap();
        assert!(!fs::metadata("/dev/null").unwrap().is_file());
        // Through a symbolic link to the device too.
        let dir = tempfile::tempdir().unwrap();
        let link = dir.path().join("null");
        std::os::unix::fs::symlink("/dev/null", &link).unwrap();
        write_atomic(&link, b"discarded").unwrap();
        assert!(fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert!(!fs::metadata("/dev/null").unwrap().is_file());
        assert_eq!(entries(dir.path()), ["null"]);
    }

    #[cfg(unix)]
    #[test]
    fn same_file_is_detected_through_links() {
        let dir = tempfile::tempdir().unwrap();
        let data = dir.path().join("d.csv");
        fs::write(&data, b"x\n1\n").unwrap();
        let soft = dir.path().join("soft.csv");
        std::os::unix::fs::symlink(&data, &soft).unwrap();
        let hard = dir.path().join("hard.csv");
        fs::hard_link(&data, &hard).unwrap();
        for out in [&data, &soft, &hard] {
            let err = check_distinct(&data, out).unwrap_err();
            assert!(matches!(err, IoError::SameFile { .. }), "{err:?}");
            assert_eq!(
                err.to_string(),
                format!(
                    "{}: is the same file as the input {} (the input would be overwritten); \
                     choose another output",
                    out.display(),
                    data.display()
                )
            );
        }
        check_distinct(&data, &dir.path().join("new.csv")).unwrap();
        let copy = dir.path().join("copy.csv");
        fs::write(&copy, b"x\n1\n").unwrap();
        check_distinct(&data, &copy).unwrap();
        check_distinct(&data, Path::new(STDOUT)).unwrap();
    }

    #[test]
    fn live_temporary_files_are_listed_until_renamed() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.csv");
        let mut listed = Vec::new();
        write_atomic_with(&path, |w| {
            listed = temporaries().clone();
            w.write_all(b"x")
        })
        .unwrap();
        let temp: Vec<_> = listed
            .iter()
            .filter(|p| p.parent() == Some(dir.path()))
            .collect();
        assert_eq!(temp.len(), 1, "{listed:?}");
        assert!(!temp[0].exists());
        assert!(!temporaries().iter().any(|p| p.parent() == Some(dir.path())));
    }
}
