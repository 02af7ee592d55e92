//! Atomic file replacement: write a temporary file next to the destination,
//! fsync it, then rename it over the destination.

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::IoError;

/// Writes `bytes` to `path` atomically.
///
/// The bytes go to a hidden temporary file (`.NAME.PID.N.tmp`) in the same
/// directory as `path`, which is flushed and fsynced and then renamed over
/// `path`; afterwards the directory is fsynced (best effort). Readers therefore
/// see either the complete old file or the complete new one, never a mix.
///
/// If `path` already exists, the new file gets its permissions; otherwise it
/// gets the usual permissions of a newly created file. If `path` is a symbolic
/// link, the link itself is replaced by a regular file.
///
/// # Errors
///
/// [`IoError::IsDirectory`] if `path` is a directory, and [`IoError::Write`]
/// (naming the step that failed and the OS error) if the temporary file cannot
/// be created, written, synced or renamed. On any error the destination is
/// untouched and no temporary file remains.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    write_atomic_with(path, |w| w.write_all(bytes))
}

/// Counter that makes temporary names unique within this process.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// A temporary file that is removed when dropped, unless it was renamed.
struct TempGuard {
    /// Where the temporary file lives.
    path: PathBuf,
    /// Set once the file has been renamed into place.
    persisted: bool,
}

impl Drop for TempGuard {
    fn drop(&mut self) {
        if !self.persisted {
            // Nothing sensible to do if this fails; the error that got us here
            // is the one worth reporting.
            let _ = fs::remove_file(&self.path);
        }
    }
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

/// Writes atomically whatever `fill` writes into the (buffered) temporary file.
///
/// Same guarantees as [`write_atomic`]; an error returned by `fill` is reported
/// as [`IoError::Write`] and leaves the destination untouched.
pub(crate) fn write_atomic_with<F>(path: &Path, fill: F) -> Result<(), IoError>
where
    F: FnOnce(&mut BufWriter<&File>) -> io::Result<()>,
{
    let existing = match fs::metadata(path) {
        Ok(meta) if meta.is_dir() => {
            return Err(IoError::IsDirectory {
                path: path.to_path_buf(),
            })
        }
        Ok(meta) => Some(meta),
        Err(_) => None,
    };
    let file_name = path.file_name().ok_or_else(|| IoError::Write {
        path: path.to_path_buf(),
        action: "write".into(),
        source: io::Error::new(io::ErrorKind::InvalidInput, "the path has no file name"),
    })?;
    let dir = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };

    let (file, mut guard) = create_temp(dir, &file_name.to_string_lossy()).map_err(write_error(
        path,
        format!("create a temporary file in {:?}", dir.display().to_string()),
    ))?;

    {
        let mut writer = BufWriter::new(&file);
        fill(&mut writer)
            .and_then(|()| writer.flush())
            .map_err(write_error(path, "write the temporary file"))?;
    }
    if let Some(meta) = existing {
        file.set_permissions(meta.permissions())
            .map_err(write_error(
                path,
                "give the temporary file the old file's permissions",
            ))?;
    }
    file.sync_all()
        .map_err(write_error(path, "sync the temporary file to disk"))?;
    drop(file);

    fs::rename(&guard.path, path).map_err(write_error(
        path,
        format!(
            "rename the temporary file {:?} over it",
            guard.path.display().to_string()
        ),
    ))?;
    guard.persisted = true;

    sync_dir(dir);
    Ok(())
}

/// Creates a new, empty, uniquely named temporary file in `dir`.
fn create_temp(dir: &Path, name: &str) -> io::Result<(File, TempGuard)> {
    let pid = std::process::id();
    let mut attempts = 0;
    loop {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let path = dir.join(format!(".{name}.{pid}.{n}.tmp"));
        match OpenOptions::new().write(true).create_new(true).open(&path) {
            Ok(file) => {
                let guard = TempGuard {
                    path,
                    persisted: false,
                };
                return Ok((file, guard));
            }
            // A stale file from an earlier process with the same id; try the next name.
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists && attempts < 1000 => {
                attempts += 1;
            }
            Err(e) => return Err(e),
        }
    }
}

/// Makes the rename durable by syncing the directory (Unix only).
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
        fs::set_permissions(&path, fs::Permissions::from_mode(0o750)).unwrap();
        write_atomic(&path, b"new").unwrap();
        let mode = fs::metadata(&path).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o750);
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
        let dir_shown = format!("{:?}", path.parent().unwrap().display().to_string());
        let os = io::Error::from_raw_os_error(2).to_string();
        assert_eq!(
            msg,
            format!(
                "{}: cannot create a temporary file in {dir_shown}: {os}",
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
        let err = write_atomic_with(&path, |w| {
            w.write_all(b"x\n2\n")?;
            w.flush()?;
            Err(io::Error::other("disk on fire"))
        })
        .unwrap_err();
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
}
