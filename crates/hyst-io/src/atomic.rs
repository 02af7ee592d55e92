//! Atomic file replacement on [`tempfile`]: write a temporary file next to the
//! destination, fsync it, then rename it over the destination.

use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::Path;

use crate::IoError;

/// Writes `bytes` to `path` atomically.
///
/// The bytes go to a hidden temporary file (`.NAME.XXXXXX.tmp`, six random
/// characters) in the same directory as `path`, which is flushed and fsynced
/// and then renamed over `path`; afterwards the directory is fsynced (best
/// effort). Readers therefore see either the complete old file or the complete
/// new one, never a mix.
///
/// If `path` already exists, the new file gets its permissions; otherwise it
/// gets the usual permissions of a newly created file (`0o666` less the umask
/// on Unix). If `path` is a symbolic link, the link itself is replaced by a
/// regular file.
///
/// # Errors
///
/// [`IoError::IsDirectory`] if `path` is a directory, and [`IoError::Write`]
/// (naming the step that failed and the OS error) if the temporary file cannot
/// be created, written, synced or renamed. On any error (and on a panic while
/// writing) the destination is untouched and no temporary file remains. A
/// process killed while writing (e.g. by an unhandled Ctrl-C) may leave the
/// temporary file behind, but never a partial destination.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    write_atomic_with(path, |w| w.write_all(bytes))
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
        Ok(meta) => Some(meta.permissions()),
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

    let mut prefix = std::ffi::OsString::from(".");
    prefix.push(file_name);
    prefix.push(".");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    // tempfile creates 0o600 files; ask for what `File::create` gives instead.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    // Removed on drop (error or panic below) unless persisted.
    let temp = builder.tempfile_in(dir).map_err(write_error(
        path,
        format!("create a temporary file in {:?}", dir.display().to_string()),
    ))?;

    // Through the plain `File`: tempfile's own `Write` would append the
    // temporary path to every error message.
    let file = temp.as_file();
    {
        let mut writer = BufWriter::new(file);
        fill(&mut writer)
            .and_then(|()| writer.flush())
            .map_err(write_error(path, "write the temporary file"))?;
    }
    if let Some(permissions) = existing {
        // After creation, so that the umask does not narrow them.
        file.set_permissions(permissions).map_err(write_error(
            path,
            "give the temporary file the old file's permissions",
        ))?;
    }
    file.sync_all()
        .map_err(write_error(path, "sync the temporary file to disk"))?;

    temp.persist(path).map_err(|e| {
        let action = format!(
            "rename the temporary file {:?} over it",
            e.file.path().display().to_string()
        );
        // Dropping `e.file` removes the temporary file.
        write_error(path, action)(e.error)
    })?;

    sync_dir(dir);
    Ok(())
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
        let parent = path.parent().unwrap().display().to_string();
        let os = io::Error::from_raw_os_error(2).to_string();
        // tempfile appends the temporary path it tried.
        let start = format!(
            "{}: cannot create a temporary file in {parent:?}: {os} at path \"{parent}/.out.csv.",
            path.display()
        );
        assert!(msg.starts_with(&start), "{msg}");
        assert!(msg.ends_with(".tmp\""), "{msg}");
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
}
