//! The files axterm reads and writes for the user, and the only way it
//! reads or writes them.
//!
//! Reading: every file a user names (program source and its `#include`s,
//! batch files, parameter files, themes and keymaps, A-Script, program
//! images, a simulator's memory file, the editor's and console's own
//! files) is read whole into memory, so a read must end and must stay
//! small. [`read_text`] and [`read_bytes`] take only a regular file
//! (after following symbolic links: a FIFO would hang the read, a device
//! such as `/dev/zero` never ends) of at most [`MAX_FILE_BYTES`], the same
//! cap [`read_stdin_text`] puts on standard input. Text must be UTF-8
//! without control bytes other than tab, line feed, carriage return and
//! form feed, so a binary file is refused as a whole instead of having its
//! first "line" quoted back in an error.
//!
//! Writing: [`write_atomically`] replaces a file in one step (a temporary
//! file with a name no other writer uses, in the same directory, synced,
//! renamed over the old one, the directory synced), so a crash or a
//! second writer never leaves half a file behind. A record that grows
//! line by line (a session recording) is started with [`create_new`] and
//! grown with [`append_synced`]: each piece is on the disk when the call
//! returns, so a crash loses nothing already recorded.
//!
//! A file written because the user named it (an export, an upload, a
//! plot, a log, a recording) goes through [`save`], [`start_growing`] or
//! [`open_growing`] under one rule ([`Existing`]): an existing file is
//! refused unless `--force` was given, and a folder that is not there is
//! the user's mistake, not the device's ([`WriteError::is_usage`]).

use std::fs::{File, Metadata, OpenOptions};
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// The largest file axterm reads: far above any real program, batch,
/// parameter, theme or memory file (a full TMCL program memory as source
/// is well under a megabyte), far below what would strain memory.
pub const MAX_FILE_BYTES: u64 = 16 * 1024 * 1024;

/// Why a file could not be read. The message says why, not which file:
/// callers say "cannot read FILE: …".
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    #[error("no such file")]
    NotFound,
    #[error("permission denied")]
    PermissionDenied,
    /// A directory, FIFO, device or socket: `kind` says which.
    #[error("it is {kind}, not a regular file")]
    NotRegular { kind: &'static str },
    #[error(
        "it is larger than {} MiB ({}): no file axterm reads is that big",
        MAX_FILE_BYTES / (1024 * 1024),
        describe_size(*.size)
    )]
    TooLarge {
        /// The size, when the file system says it; `None` for a stream
        /// (standard input) cut off at the cap.
        size: Option<u64>,
    },
    #[error("not a text file: byte {offset} is not UTF-8 text (a binary file?)")]
    NotUtf8 { offset: usize },
    #[error("not a text file: byte {offset} is the control byte 0x{byte:02X} (a binary file?)")]
    ControlByte { offset: usize, byte: u8 },
    #[error("{0}")]
    Io(io::Error),
}

fn describe_size(size: Option<u64>) -> String {
    match size {
        Some(bytes) => format!("{bytes} bytes"),
        None => "more came".to_string(),
    }
}

impl ReadError {
    /// Whether there is simply no file (often fine: nothing saved yet).
    pub fn is_not_found(&self) -> bool {
        matches!(self, ReadError::NotFound)
    }

    fn from_io(error: io::Error) -> ReadError {
        match error.kind() {
            io::ErrorKind::NotFound => ReadError::NotFound,
            io::ErrorKind::PermissionDenied => ReadError::PermissionDenied,
            _ => ReadError::Io(error),
        }
    }
}

/// The whole text of the regular file at `path` (see the module notes).
pub fn read_text(path: impl AsRef<Path>) -> Result<String, ReadError> {
    text_from(read_bytes(path)?)
}

/// The whole content of the regular file at `path`, at most
/// [`MAX_FILE_BYTES`].
pub fn read_bytes(path: impl AsRef<Path>) -> Result<Vec<u8>, ReadError> {
    let path = path.as_ref();
    // Checked before opening: opening a FIFO for reading blocks until a
    // writer comes, and opening a device may act on it.
    let metadata = std::fs::metadata(path).map_err(ReadError::from_io)?;
    check_regular(&metadata)?;
    let file = open_for_reading(path)?;
    // Checked again on what was opened, in case the path changed between.
    let metadata = file.metadata().map_err(ReadError::from_io)?;
    check_regular(&metadata)?;
    // A file that grows while it is read is still cut off at the cap.
    read_capped(file)
}

/// All of standard input as text, at most [`MAX_FILE_BYTES`] (`axterm run
/// -`, `axterm asm -`): `/dev/zero` or an endless pipe is refused at the
/// cap instead of filling memory.
pub fn read_stdin_text() -> Result<String, ReadError> {
    text_from(read_capped(io::stdin().lock())?)
}

fn check_regular(metadata: &Metadata) -> Result<(), ReadError> {
    if metadata.is_file() {
        if metadata.len() > MAX_FILE_BYTES {
            return Err(ReadError::TooLarge {
                size: Some(metadata.len()),
            });
        }
        return Ok(());
    }
    Err(ReadError::NotRegular {
        kind: kind_of(metadata),
    })
}

/// What a file that is not a regular one is, in a technician's words.
fn kind_of(metadata: &Metadata) -> &'static str {
    if metadata.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let kind = metadata.file_type();
        if kind.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if kind.is_char_device() {
            return "a character device";
        }
        if kind.is_block_device() {
            return "a block device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    "a special file"
}

/// Open without blocking: should a FIFO have taken the checked file's
/// place, the open returns at once (and the second check refuses it).
fn open_for_reading(path: &Path) -> Result<File, ReadError> {
    let mut options = OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    options.open(path).map_err(ReadError::from_io)
}

fn read_capped(reader: impl Read) -> Result<Vec<u8>, ReadError> {
    let mut bytes = Vec::new();
    reader
        .take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(ReadError::from_io)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(ReadError::TooLarge { size: None });
    }
    Ok(bytes)
}

/// `bytes` as text, refused when they are not what a text file holds.
fn text_from(bytes: Vec<u8>) -> Result<String, ReadError> {
    let text = String::from_utf8(bytes).map_err(|e| ReadError::NotUtf8 {
        offset: e.utf8_error().valid_up_to(),
    })?;
    let control = text
        .bytes()
        .enumerate()
        .find(|&(_, b)| b < 0x20 && !matches!(b, b'\t' | b'\n' | b'\r' | 0x0C));
    if let Some((offset, byte)) = control {
        return Err(ReadError::ControlByte { offset, byte });
    }
    Ok(text)
}

/// Replace (or create) the file at `path` with `bytes` in one step: the
/// bytes go to a temporary file beside it under a name no other writer
/// uses (two simulators on one memory file, two consoles saving history),
/// are synced to the disk, and the temporary file is renamed over `path`,
/// then the directory is synced so the rename itself survives a power
/// cut. Readers see the old file or the new one, never a mix.
///
/// A symbolic link is followed (the file it points at is replaced, the
/// link stays). Something at `path` that is not a regular file (a
/// terminal, `/dev/stdout`, a FIFO) is written to directly: there is
/// nothing to replace. A directory is refused.
pub fn write_atomically(path: impl AsRef<Path>, bytes: &[u8]) -> io::Result<()> {
    let path = path.as_ref();
    let target = match std::fs::metadata(path) {
        Ok(metadata) if metadata.is_dir() => {
            return Err(io::Error::new(
                io::ErrorKind::IsADirectory,
                "it is a directory",
            ));
        }
        Ok(metadata) if !metadata.is_file() => {
            let mut out = OpenOptions::new().write(true).open(path)?;
            return out.write_all(bytes).and_then(|()| out.flush());
        }
        Ok(_) => std::fs::canonicalize(path)?,
        Err(e) if e.kind() == io::ErrorKind::NotFound => path.to_path_buf(),
        Err(e) => return Err(e),
    };
    let dir = match target.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let (temporary, mut file) = create_temporary(&dir, &target)?;
    let written = (|| {
        // A replaced file keeps its permissions.
        if let Ok(old) = std::fs::metadata(&target) {
            file.set_permissions(old.permissions())?;
        }
        file.write_all(bytes)?;
        file.sync_all()?;
        drop(file);
        std::fs::rename(&temporary, &target)
    })();
    if let Err(e) = written {
        let _ = std::fs::remove_file(&temporary);
        return Err(e);
    }
    sync_directory(&dir)
}

/// Whether a file the user asked axterm to write may replace one that is
/// already there. One rule for every such file (`params export`, `upload
/// -o`, `asm -o`, `:plot csv`, `:log`, `:record`, the traffic and
/// parameter panes' saves): an existing file is refused unless the user
/// said `--force` (on the command line and in the console alike).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Existing {
    /// An existing file is left as it is and the write refused.
    Refuse,
    /// An existing file is replaced (`--force`).
    Replace,
}

impl Existing {
    /// `--force` given or not.
    pub fn from_force(force: bool) -> Existing {
        if force {
            Existing::Replace
        } else {
            Existing::Refuse
        }
    }
}

/// The word that lets a write replace an existing file, on the command
/// line and in the console (`:log --force FILE`), as `:run
/// --no-stop-on-failure FILE` takes its option.
pub const FORCE_FLAG: &str = "--force";

/// `--force` at the start of a console command's arguments: whether it
/// is there, and the rest (the file name).
pub fn force_option(rest: &str) -> (Existing, &str) {
    let rest = rest.trim();
    match rest.strip_prefix(FORCE_FLAG) {
        Some(after) if after.is_empty() || after.starts_with(char::is_whitespace) => {
            (Existing::Replace, after.trim_start())
        }
        _ => (Existing::Refuse, rest),
    }
}

/// Why a file the user named cannot be written. The message says why, not
/// which file: callers say "cannot write FILE: …".
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// A file is there and `--force` was not given.
    #[error("it exists: give --force to replace it (nothing was overwritten)")]
    Exists,
    /// The folder it would go in does not exist.
    #[error("there is no folder {0}")]
    NoFolder(String),
    /// The place it would go in is not a folder.
    #[error("{0} is not a folder")]
    NotAFolder(String),
    #[error("it is a directory")]
    IsDirectory,
    #[error("{0}")]
    Io(io::Error),
}

impl WriteError {
    /// A mistake in what was asked (exit code 2): the file exists, or the
    /// place for it does not; not a failure of the disk.
    pub fn is_usage(&self) -> bool {
        !matches!(self, WriteError::Io(_))
    }
}

impl From<io::Error> for WriteError {
    fn from(error: io::Error) -> WriteError {
        match error.kind() {
            io::ErrorKind::AlreadyExists => WriteError::Exists,
            io::ErrorKind::IsADirectory => WriteError::IsDirectory,
            _ => WriteError::Io(error),
        }
    }
}

/// The folder a file at `path` goes in.
fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Whether a file the user named can be written at `path` under
/// `existing`, checked before any work (before a link is opened): its
/// folder is there, it is not a directory, and an existing file is
/// refused without `--force`. A device or FIFO (`/dev/stdout`) is
/// written to, never replaced, and is no existing file here.
pub fn check_destination(path: impl AsRef<Path>, existing: Existing) -> Result<(), WriteError> {
    let path = path.as_ref();
    let folder = folder_of(path);
    match std::fs::metadata(&folder) {
        Ok(metadata) if metadata.is_dir() => {}
        Ok(_) => return Err(WriteError::NotAFolder(folder.display().to_string())),
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            return Err(WriteError::NoFolder(folder.display().to_string()));
        }
        Err(e) => return Err(WriteError::Io(e)),
    }
    match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(WriteError::Io(e)),
        Ok(_) => match std::fs::metadata(path) {
            Ok(metadata) if metadata.is_dir() => Err(WriteError::IsDirectory),
            Ok(metadata) if !metadata.is_file() => Ok(()),
            // A file, or a link to one or to nothing.
            _ if existing == Existing::Refuse => Err(WriteError::Exists),
            _ => Ok(()),
        },
    }
}

/// Write a file the user asked for: [`check_destination`], then in one
/// step as [`write_atomically`]. Without `--force` the new file is put in
/// place only if the name is still free when it is (a hard link, which
/// never replaces), so a file that appeared meanwhile is not overwritten
/// either.
pub fn save(path: impl AsRef<Path>, bytes: &[u8], existing: Existing) -> Result<(), WriteError> {
    let path = path.as_ref();
    check_destination(path, existing)?;
    let free =
        matches!(std::fs::symlink_metadata(path), Err(e) if e.kind() == io::ErrorKind::NotFound);
    if existing == Existing::Replace || !free {
        // Replacing, or a device or FIFO written to directly.
        return write_atomically(path, bytes).map_err(WriteError::from);
    }
    let folder = folder_of(path);
    let (temporary, mut file) = create_temporary(&folder, path)?;
    let written = (|| {
        file.write_all(bytes)?;
        file.sync_all()?;
        drop(file);
        match std::fs::hard_link(&temporary, path) {
            Ok(()) => Ok(()),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => Err(e),
            // A file system without hard links (FAT, some shares): the
            // check above is all there is.
            Err(_) => std::fs::rename(&temporary, path),
        }
    })();
    let _ = std::fs::remove_file(&temporary);
    written?;
    sync_directory(&folder).map_err(WriteError::from)
}

/// Start a file that grows line by line (a session recording, a traffic
/// log) with `bytes`: a new file, or with `--force` an existing one
/// replaced. It is then grown with [`append_synced`] or opened for
/// appending.
pub fn start_growing(
    path: impl AsRef<Path>,
    bytes: &[u8],
    existing: Existing,
) -> Result<(), WriteError> {
    let path = path.as_ref();
    check_destination(path, existing)?;
    match existing {
        Existing::Refuse => create_new(path, bytes).map_err(WriteError::from),
        Existing::Replace => write_atomically(path, bytes).map_err(WriteError::from),
    }
}

/// Open a file that grows as it is written (a traffic log): a new file,
/// or with `--force` an existing one emptied first. A device or FIFO
/// (`/dev/stdout`) is written to as it is.
pub fn open_growing(path: impl AsRef<Path>, existing: Existing) -> Result<File, WriteError> {
    let path = path.as_ref();
    check_destination(path, existing)?;
    let mut options = OpenOptions::new();
    match std::fs::metadata(path) {
        Ok(metadata) if !metadata.is_file() => options.append(true),
        _ if existing == Existing::Refuse => options.write(true).create_new(true),
        _ => options.write(true).create(true).truncate(true),
    };
    options.open(path).map_err(WriteError::from)
}

/// Create `path` with `bytes` in it, synced, refusing a file that already
/// exists (nothing is overwritten).
pub fn create_new(path: impl AsRef<Path>, bytes: &[u8]) -> io::Result<()> {
    let path = path.as_ref();
    let mut file = OpenOptions::new().write(true).create_new(true).open(path)?;
    file.write_all(bytes)?;
    file.sync_all()?;
    let dir = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.to_path_buf(),
        _ => PathBuf::from("."),
    };
    sync_directory(&dir)
}

/// Add `bytes` at the end of the existing file `path` in one write
/// (`O_APPEND`: another writer's pieces never land inside this one) and
/// sync it, so that what the call wrote survives a crash of axterm or of
/// the machine.
pub fn append_synced(path: impl AsRef<Path>, bytes: &[u8]) -> io::Result<()> {
    let mut file = OpenOptions::new().append(true).open(path)?;
    file.write_all(bytes)?;
    file.sync_data()
}

/// Distinguishes the temporary files of one process; the process id
/// distinguishes processes.
static TEMPORARY_COUNT: AtomicU64 = AtomicU64::new(0);

/// A new file `.NAME.PID.N.tmp` in `dir`, created exclusively: a name
/// taken (a leftover of a crashed writer) is skipped, never reused.
fn create_temporary(dir: &Path, target: &Path) -> io::Result<(PathBuf, File)> {
    let name = target
        .file_name()
        .map_or_else(|| "file".into(), |n| n.to_string_lossy().into_owned());
    loop {
        let count = TEMPORARY_COUNT.fetch_add(1, Ordering::Relaxed);
        let temporary = dir.join(format!(".{name}.{}.{count}.tmp", std::process::id()));
        match OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temporary)
        {
            Ok(file) => return Ok((temporary, file)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {}
            Err(e) => return Err(e),
        }
    }
}

/// Make a rename in `dir` durable. File systems that cannot sync a
/// directory (they say "invalid argument") have nothing to sync.
fn sync_directory(dir: &Path) -> io::Result<()> {
    #[cfg(unix)]
    {
        match File::open(dir).and_then(|d| d.sync_all()) {
            Err(e) if e.kind() != io::ErrorKind::InvalidInput => return Err(e),
            _ => {}
        }
    }
    #[cfg(not(unix))]
    let _ = dir;
    Ok(())
}

/// Source files from the file system, for a program's `#include` (the
/// command line and the editor read them alike).
#[derive(Debug, Clone, Copy, Default)]
pub struct SourceFiles;

impl crate::protocol::program::SourceLoader for SourceFiles {
    fn load(&self, path: &str) -> Result<String, crate::protocol::program::LoadError> {
        use crate::protocol::program::LoadError;
        read_text(path).map_err(|e| match e {
            ReadError::NotFound => LoadError::NotFound,
            other => LoadError::Unreadable(Box::new(other)),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_record_is_created_once_and_grows_by_appending() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("session.txt");
        create_new(&path, b"# header\n").expect("created");
        append_synced(&path, b"SAP 4, 0, 1000\n").expect("appended");
        append_synced(&path, b":expect GAP 4, 0 == 1000\n").expect("appended");
        assert_eq!(
            std::fs::read_to_string(&path).expect("read"),
            "# header\nSAP 4, 0, 1000\n:expect GAP 4, 0 == 1000\n"
        );
        let again = create_new(&path, b"other").expect_err("exists");
        assert_eq!(again.kind(), io::ErrorKind::AlreadyExists);
        assert!(
            append_synced(dir.path().join("gone.txt"), b"x").is_err(),
            "no file to grow"
        );
    }

    #[test]
    fn a_text_file_is_read_whole() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("a.txt");
        std::fs::write(&path, "SAP 4, 0, 1000\r\n\tGAP 4, 0\x0C\n").expect("write");
        assert_eq!(
            read_text(&path).expect("read"),
            "SAP 4, 0, 1000\r\n\tGAP 4, 0\x0C\n"
        );
        assert!(read_text(dir.path().join("none")).is_err_and(|e| e.is_not_found()));
    }

    #[test]
    fn a_symbolic_link_is_followed() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("a.txt");
        std::fs::write(&path, "x").expect("write");
        let link = dir.path().join("link.txt");
        std::os::unix::fs::symlink(&path, &link).expect("symlink");
        assert_eq!(read_text(&link).expect("read"), "x");
        // The link to a device is refused like the device.
        let zero = dir.path().join("zero");
        std::os::unix::fs::symlink("/dev/zero", &zero).expect("symlink");
        let error = read_bytes(&zero).expect_err("device");
        assert_eq!(
            error.to_string(),
            "it is a character device, not a regular file"
        );
    }

    #[test]
    fn directories_and_devices_are_refused_without_reading() {
        let dir = tempfile::tempdir().expect("temp dir");
        let error = read_text(dir.path()).expect_err("directory");
        assert_eq!(error.to_string(), "it is a directory, not a regular file");
        let error = read_text("/dev/zero").expect_err("device");
        assert!(matches!(error, ReadError::NotRegular { .. }), "{error}");
    }

    #[test]
    fn a_fifo_is_refused_before_it_is_opened() {
        use std::os::unix::ffi::OsStrExt;
        let dir = tempfile::tempdir().expect("temp dir");
        let fifo = dir.path().join("fifo");
        let name = std::ffi::CString::new(fifo.as_os_str().as_bytes()).expect("no NUL");
        // SAFETY: `name` is a valid NUL-terminated path for the call.
        assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0);
        // Opening it for reading would wait for a writer that never comes.
        let error = read_text(&fifo).expect_err("a FIFO");
        assert_eq!(
            error.to_string(),
            "it is a FIFO (named pipe), not a regular file"
        );
    }

    #[test]
    fn a_file_over_the_cap_is_refused_with_its_size() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("big.tmc");
        // Sparse: nothing is written to the disk.
        let file = File::create(&path).expect("create");
        file.set_len(MAX_FILE_BYTES + 1).expect("grow");
        let error = read_bytes(&path).expect_err("too large");
        assert_eq!(
            error.to_string(),
            "it is larger than 16 MiB (16777217 bytes): no file axterm reads is that big"
        );
        file.set_len(MAX_FILE_BYTES).expect("shrink");
        assert_eq!(
            read_bytes(&path).expect("at the cap").len() as u64,
            MAX_FILE_BYTES
        );
    }

    #[test]
    fn a_stream_is_cut_off_at_the_cap() {
        let endless = io::repeat(b'x');
        let error = read_capped(endless).expect_err("endless");
        assert!(
            matches!(error, ReadError::TooLarge { size: None }),
            "{error}"
        );
        assert!(error.to_string().contains("more came"), "{error}");
    }

    #[test]
    fn binary_content_is_not_text_and_is_not_quoted() {
        let error = text_from(b"GAP 1, 0\n\x00\x00".to_vec()).expect_err("NUL");
        assert_eq!(
            error.to_string(),
            "not a text file: byte 9 is the control byte 0x00 (a binary file?)"
        );
        let error = text_from(b"ab\xFF\xFEcd".to_vec()).expect_err("not UTF-8");
        assert_eq!(
            error.to_string(),
            "not a text file: byte 2 is not UTF-8 text (a binary file?)"
        );
        assert_eq!(text_from("é ✓\n".into()).expect("UTF-8"), "é ✓\n");
    }

    #[test]
    fn a_write_replaces_the_file_and_leaves_no_temporary() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("out.json");
        write_atomically(&path, b"first").expect("create");
        write_atomically(&path, b"second").expect("replace");
        assert_eq!(std::fs::read(&path).expect("read"), b"second");
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .expect("list")
            .map(|e| e.expect("entry").file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("out.json")]);
    }

    #[test]
    fn a_write_keeps_permissions_and_links() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("real.txt");
        std::fs::write(&path, "old").expect("write");
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o600)).expect("chmod");
        let link = dir.path().join("link.txt");
        std::os::unix::fs::symlink(&path, &link).expect("symlink");
        write_atomically(&link, b"new").expect("write through the link");
        assert!(
            std::fs::symlink_metadata(&link)
                .expect("link")
                .file_type()
                .is_symlink()
        );
        assert_eq!(std::fs::read(&path).expect("read"), b"new");
        let mode = std::fs::metadata(&path).expect("meta").permissions().mode();
        assert_eq!(mode & 0o777, 0o600);
    }

    #[test]
    fn temporary_names_are_never_reused() {
        let dir = tempfile::tempdir().expect("temp dir");
        let target = dir.path().join("eeprom.json");
        let (first, _a) = create_temporary(dir.path(), &target).expect("first");
        let (second, _b) = create_temporary(dir.path(), &target).expect("second");
        assert_ne!(first, second);
        // Leftovers with the next names (a crashed writer's) are stepped
        // over, not overwritten.
        let next = TEMPORARY_COUNT.load(Ordering::Relaxed);
        let leftovers: Vec<PathBuf> = (next..next + 64)
            .map(|n| {
                dir.path()
                    .join(format!(".eeprom.json.{}.{n}.tmp", std::process::id()))
            })
            .collect();
        for leftover in &leftovers {
            std::fs::write(leftover, "leftover").expect("write");
        }
        let (third, _c) = create_temporary(dir.path(), &target).expect("third");
        assert!(!leftovers.contains(&third));
        for leftover in &leftovers {
            assert_eq!(std::fs::read(leftover).expect("read"), b"leftover");
        }
    }

    #[test]
    fn a_file_the_user_named_is_not_overwritten_without_force() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("params.toml");
        save(&path, b"first", Existing::Refuse).expect("a new file");
        let refused = save(&path, b"second", Existing::Refuse).expect_err("exists");
        assert!(matches!(refused, WriteError::Exists), "{refused}");
        assert!(refused.is_usage());
        assert_eq!(
            refused.to_string(),
            "it exists: give --force to replace it (nothing was overwritten)"
        );
        assert_eq!(std::fs::read(&path).expect("read"), b"first");
        save(&path, b"third", Existing::Replace).expect("forced");
        assert_eq!(std::fs::read(&path).expect("read"), b"third");
        // No temporary is left behind by either way.
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .expect("list")
            .map(|e| e.expect("entry").file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("params.toml")]);
        // A link to nothing is a name taken too.
        let dangling = dir.path().join("dangling");
        std::os::unix::fs::symlink(dir.path().join("nowhere"), &dangling).expect("symlink");
        assert!(matches!(
            save(&dangling, b"x", Existing::Refuse),
            Err(WriteError::Exists)
        ));
    }

    #[test]
    fn a_missing_folder_or_a_directory_is_a_usage_error_even_with_force() {
        let dir = tempfile::tempdir().expect("temp dir");
        let missing = dir.path().join("no-such-folder").join("x.toml");
        for existing in [Existing::Refuse, Existing::Replace] {
            let error = check_destination(&missing, existing).expect_err("no folder");
            assert!(matches!(error, WriteError::NoFolder(_)), "{error}");
            assert!(error.is_usage());
            assert!(
                error.to_string().starts_with("there is no folder "),
                "{error}"
            );
            let error = save(dir.path(), b"x", existing).expect_err("a directory");
            assert!(matches!(error, WriteError::IsDirectory), "{error}");
        }
        let file = dir.path().join("file");
        std::fs::write(&file, "x").expect("write");
        let error = check_destination(file.join("x.toml"), Existing::Replace).expect_err("file");
        assert!(matches!(error, WriteError::NotAFolder(_)), "{error}");
        // A device is written to, not replaced: no --force needed.
        save("/dev/null", b"nothing", Existing::Refuse).expect("a device");
    }

    #[test]
    fn a_growing_file_starts_new_or_forced() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("session.txt");
        start_growing(&path, b"# one\n", Existing::Refuse).expect("new");
        assert!(matches!(
            start_growing(&path, b"# two\n", Existing::Refuse),
            Err(WriteError::Exists)
        ));
        start_growing(&path, b"# three\n", Existing::Replace).expect("forced");
        assert_eq!(std::fs::read(&path).expect("read"), b"# three\n");
    }

    #[test]
    fn force_is_an_option_before_the_file_name() {
        assert_eq!(force_option("--force a.csv"), (Existing::Replace, "a.csv"));
        assert_eq!(force_option("  --force  "), (Existing::Replace, ""));
        assert_eq!(force_option("a.csv"), (Existing::Refuse, "a.csv"));
        assert_eq!(
            force_option("--forced.csv"),
            (Existing::Refuse, "--forced.csv")
        );
    }

    #[test]
    fn a_directory_is_not_replaced_and_a_device_is_written_to() {
        use std::os::unix::fs::FileTypeExt;
        let dir = tempfile::tempdir().expect("temp dir");
        assert!(write_atomically(dir.path(), b"x").is_err());
        write_atomically("/dev/null", b"nothing").expect("a device is written to");
        let null = std::fs::metadata("/dev/null").expect("still there");
        assert!(null.file_type().is_char_device());
    }
}
