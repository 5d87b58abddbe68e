//! The one way prisma writes a file: EXR, PNG, statistics, plots, CSV and reports all go
//! through [`Outputs`].
//!
//! - **Checked before any work** ([`check_destination`]): a directory, a path ending in `/`, a
//!   block device, a socket or a dangling symbolic link is refused, and the nearest existing
//!   directory must accept a new file. Commands run these checks before they render, and
//!   [`check_not_inputs`] before they read: no output may be one of the command's inputs (the
//!   scene file, a mesh it loads, a part being merged or resumed), however it is spelled (a
//!   symbolic or hard link to it counts: files are compared by device and inode).
//! - **Staged, then put in place together** ([`Outputs::stage`], [`Outputs::commit`]): each
//!   output is encoded into a hidden temporary file beside its destination
//!   (`.NAME.tmp-PID-N.EXT`); every write, the final flush and an `fsync` are checked. Only when
//!   every output of a command is staged are they renamed over their destinations, so a failure
//!   while encoding or writing any of them (a full disk, an encoder error) leaves no new file
//!   and every old one as it was. A failing rename during the commit (very rare: the staging
//!   proved the directory writable) leaves the outputs renamed before it in place. Missing
//!   directories on the way to an output are created; when the outputs are abandoned after an
//!   error, the directories created for them are removed again.
//! - **A replaced file keeps its permission bits** (a 0600 image stays 0600), and its owner and
//!   group when prisma runs as root (the temporary file is given them before any byte is
//!   written); otherwise the new file belongs to whoever ran prisma, as any new file does. The
//!   replacement is a new file (an inode): **hard links** to the old one keep the old contents.
//! - **Special files are written, never replaced.** Renaming over `/dev/null` as root replaced
//!   the device node with a regular file; a character device or a FIFO is now opened and written
//!   in place (its bytes staged in memory until the commit), through any symbolic link that leads
//!   to it (`/dev/stdout` into a pipe: `/proc/self/fd/1` names `pipe:[N]`, no path).
//! - **Symbolic links are followed as the kernel would follow them.** The file a link points to
//!   is replaced and the link stays, except for a link that Linux's `fs.protected_symlinks`
//!   forbids following: a link in a sticky world-writable directory (`/tmp`) owned by neither the
//!   user running prisma nor the directory's owner. That one is refused (exit code 2) whether or
//!   not the sysctl is on, since prisma resolves the link itself and the kernel cannot see it:
//!   another user's link in `/tmp` must not let them aim root's render at root's files.
//!   Every link from the output's name to its file is checked (links among the directories
//!   above it are followed as the path lookup follows them).
//! - **Interrupted, nothing is left behind.** Temporary files are registered while they exist;
//!   [`abandon_and_exit`] deletes them and exits, and the binary calls it from its Ctrl-C /
//!   SIGTERM handler. (A registry of paths is the one piece of global state here: a
//!   signal handler has no other way to reach them.)

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Cursor, Seek, SeekFrom, Write};
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

use super::OutputError;

/// Temporary files that exist now, for [`abandon_and_exit`].
static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
/// Numbers temporary files within this process.
static NEXT_TEMPORARY: AtomicU64 = AtomicU64::new(0);

/// Deletes every temporary file this process has open for writing and exits with `code` (for
/// a signal handler: the outputs are abandoned). The registry stays locked until the process
/// is gone, so no temporary file can be created meanwhile: the handler runs on a thread of its
/// own, and the render's thread could otherwise stage the next output while the process exits
/// and leave its file behind (seen once in CI, in `interrupt_during_write_leaves_tmp`).
pub fn abandon_and_exit(code: i32) -> ! {
    let paths = registry();
    remove_all(&paths);
    std::process::exit(code)
}

/// Deletes the files `paths`.
fn remove_all(paths: &[PathBuf]) {
    for path in paths {
        let _ = std::fs::remove_file(path);
    }
}

/// A temporary file path that [`abandon_and_exit`] knows about until it is dropped (which
/// removes the file unless [`Temporary::keep`] was called after renaming it).
struct Temporary {
    path: PathBuf,
    owned: bool,
}

impl Temporary {
    /// A new file with an unused name beside `target`, created and registered together under the
    /// registry's lock (so that [`abandon_and_exit`] sees every file that exists, and none is
    /// created after it).
    fn create_beside(target: &Path, like: Option<&std::fs::Metadata>) -> std::io::Result<(Self, File)> {
        let stem = target.file_stem().map_or_else(|| "output".into(), |s| s.to_string_lossy().into_owned());
        let ext = target.extension().map(|e| format!(".{}", e.to_string_lossy())).unwrap_or_default();
        let number = NEXT_TEMPORARY.fetch_add(1, Ordering::Relaxed);
        let path = target.with_file_name(format!(".{stem}.tmp-{}-{number}{ext}", std::process::id()));
        let file = registry_update(|paths| {
            let mut options = OpenOptions::new();
            options.write(true).create_new(true);
            #[cfg(unix)]
            if let Some(old) = like {
                use std::os::unix::fs::{OpenOptionsExt, PermissionsExt};
                // Never more open than the file it replaces, even before the chmod below.
                options.mode(old.permissions().mode() & PERMISSION_BITS);
            }
            let file = options.open(&path)?;
            paths.push(path.clone());
            Ok::<_, std::io::Error>(file)
        })?;
        let temporary = Self { path, owned: true };
        if let Some(old) = like {
            take_over_mode(&file, old)?;
        }
        Ok((temporary, file))
    }

    /// The file was renamed away: nothing to remove any more.
    fn keep(mut self) {
        self.owned = false;
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        if self.owned {
            let _ = std::fs::remove_file(&self.path);
        }
        registry_update(|paths| paths.retain(|p| p != &self.path));
    }
}

/// The permission bits a replacement keeps (read, write, execute for owner, group, others; not
/// set-user-ID, set-group-ID or sticky, which an image has no use for).
#[cfg(unix)]
const PERMISSION_BITS: u32 = 0o777;

/// Gives the new file `file` the permission bits of `old` (the umask applied to its creation
/// mode may have removed some), and its owner and group when running as root.
#[cfg(unix)]
fn take_over_mode(file: &File, old: &std::fs::Metadata) -> std::io::Result<()> {
    use std::os::unix::fs::{MetadataExt, PermissionsExt};
    if effective_uid() == 0 {
        std::os::unix::fs::fchown(file, Some(old.uid()), Some(old.gid()))?;
    }
    file.set_permissions(std::fs::Permissions::from_mode(old.mode() & PERMISSION_BITS))
}

#[cfg(not(unix))]
fn take_over_mode(_file: &File, _old: &std::fs::Metadata) -> std::io::Result<()> {
    Ok(())
}

/// The registry of temporary files, locked (a panic elsewhere poisons the lock; the list it
/// guards is still whole).
fn registry() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    TEMPORARIES.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

fn registry_update<R>(change: impl FnOnce(&mut Vec<PathBuf>) -> R) -> R {
    change(&mut registry())
}

/// Where an output goes, once checked.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Destination {
    /// A regular file (existing or not): written beside it, then renamed over it. The path is
    /// the one to replace (a symbolic link's target).
    Replace(PathBuf),
    /// A character device or FIFO (`/dev/null`, `/dev/stdout`, a pipe): written in place.
    Special(PathBuf),
}

impl Destination {
    /// The file that receives the bytes.
    pub fn path(&self) -> &Path {
        match self {
            Destination::Replace(path) | Destination::Special(path) => path,
        }
    }
}

/// Checks that `path` can receive an output, without writing it: see the module doc.
pub fn check_destination(path: &Path) -> Result<Destination, OutputError> {
    let refuse = |problem: &str| OutputError::Destination {
        path: path.display().to_string(),
        problem: problem.into(),
    };
    let text = path.as_os_str().to_string_lossy();
    if text.is_empty() {
        return Err(refuse("an empty path"));
    }
    if text.ends_with('/')
        || matches!(
            path.components().next_back(),
            Some(Component::CurDir | Component::ParentDir | Component::RootDir)
        )
    {
        return Err(refuse("names a directory; give a file name"));
    }
    match std::fs::symlink_metadata(path) {
        Ok(meta) if meta.file_type().is_symlink() => {
            check_link_chain(path).map_err(|problem| refuse(&problem))?;
            // `metadata` follows the link as opening it would; `canonicalize` cannot follow
            // `/proc/self/fd/1` when it names a pipe (`pipe:[N]`), which is still writable.
            let target_meta = std::fs::metadata(path).map_err(|_| refuse("is a dangling symbolic link"))?;
            if target_meta.is_dir() {
                return Err(refuse("is a symbolic link to a directory; give a file name"));
            }
            if !target_meta.is_file() {
                return special_kind(path, &target_meta).map_err(|what| refuse(&what));
            }
            let target = std::fs::canonicalize(path).map_err(|_| refuse("is a dangling symbolic link"))?;
            probe_directory(&target)?;
            Ok(Destination::Replace(target))
        }
        Ok(meta) => {
            let kind = meta.file_type();
            if kind.is_dir() {
                return Err(refuse("is a directory; give a file name"));
            }
            if kind.is_file() {
                probe_directory(path)?;
                return Ok(Destination::Replace(path.to_owned()));
            }
            special_kind(path, &meta).map_err(|what| refuse(&what))
        }
        Err(_) => {
            probe_directory(path)?;
            Ok(Destination::Replace(path.to_owned()))
        }
    }
}

/// Follows the chain of symbolic links that starts at `path` (itself a link) and refuses a link
/// that Linux's `fs.protected_symlinks` would not follow: see the module doc.
fn check_link_chain(path: &Path) -> Result<(), String> {
    // The kernel's own limit on links followed in one lookup.
    const MAX_LINKS: usize = 40;
    let mut link = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        let meta = match std::fs::symlink_metadata(&link) {
            Ok(meta) if meta.file_type().is_symlink() => meta,
            _ => return Ok(()),
        };
        let directory = link.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
        if let Some(problem) = protected_link(&meta, directory) {
            return Err(if link == path {
                problem
            } else {
                format!("leads to {}, which {problem}", link.display())
            });
        }
        let Ok(next) = std::fs::read_link(&link) else { return Ok(()) };
        link = directory.join(next);
    }
    Err(format!("leads through more than {MAX_LINKS} symbolic links"))
}

/// Why the kernel (`fs.protected_symlinks`, `may_follow_link` in fs/namei.c) would refuse to
/// follow a symbolic link (metadata `meta`) in `directory` for this process: a link in
/// a sticky world-writable directory may be followed only by its owner, or when the directory's
/// owner owns it too.
#[cfg(unix)]
fn protected_link(meta: &std::fs::Metadata, directory: &Path) -> Option<String> {
    use std::os::unix::fs::MetadataExt;
    const STICKY_WORLD_WRITABLE: u32 = 0o1002;
    let dir = std::fs::metadata(directory).ok()?;
    let follower = effective_uid();
    if meta.uid() == follower
        || dir.mode() & STICKY_WORLD_WRITABLE != STICKY_WORLD_WRITABLE
        || meta.uid() == dir.uid()
    {
        return None;
    }
    Some(format!(
        "is a symbolic link owned by another user (uid {}) in the sticky world-writable directory {}: \
         refused, as the kernel's fs.protected_symlinks refuses to follow it (remove the link or write elsewhere)",
        meta.uid(),
        directory.display()
    ))
}

#[cfg(not(unix))]
fn protected_link(_meta: &std::fs::Metadata, _directory: &Path) -> Option<String> {
    None
}

/// The effective user id of this process.
#[cfg(unix)]
fn effective_uid() -> u32 {
    // SAFETY: geteuid has no preconditions and cannot fail.
    unsafe { libc::geteuid() }
}

#[cfg(unix)]
fn special_kind(path: &Path, meta: &std::fs::Metadata) -> Result<Destination, String> {
    use std::os::unix::fs::FileTypeExt;
    let kind = meta.file_type();
    if kind.is_char_device() || kind.is_fifo() {
        Ok(Destination::Special(path.to_owned()))
    } else if kind.is_block_device() {
        Err("is a block device; prisma writes regular files, character devices and FIFOs only".into())
    } else {
        Err("is a socket or other special file; prisma writes regular files, character devices and FIFOs only".into())
    }
}

#[cfg(not(unix))]
fn special_kind(_path: &Path, _meta: &std::fs::Metadata) -> Result<Destination, String> {
    Err("is not a regular file".into())
}

/// The nearest existing ancestor directory of `path` accepts a new file (created and removed
/// at once), so that a missing permission shows before a long render, not after it.
fn probe_directory(path: &Path) -> Result<(), OutputError> {
    let refuse = |problem: String| OutputError::Destination { path: path.display().to_string(), problem };
    let mut ancestor = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    loop {
        match std::fs::metadata(ancestor) {
            Ok(meta) if meta.is_dir() => break,
            Ok(_) => return Err(refuse(format!("{} is not a directory", ancestor.display()))),
            Err(_) => match ancestor.parent().filter(|p| !p.as_os_str().is_empty()) {
                Some(parent) => ancestor = parent,
                None => {
                    ancestor = Path::new(".");
                    if std::fs::metadata(ancestor).is_err() {
                        return Err(refuse("the working directory cannot be read".into()));
                    }
                    break;
                }
            },
        }
    }
    let (probe, file) = Temporary::create_beside(&ancestor.join("probe"), None)
        .map_err(|e| refuse(format!("cannot create a file in {}: {e}", ancestor.display())))?;
    drop(file);
    drop(probe);
    Ok(())
}

/// The bytes of one output as its encoder writes them: a buffered temporary file or memory
/// (for a special file). Seekable, as the EXR encoder needs.
pub enum Sink {
    /// Into a temporary file.
    File(BufWriter<File>),
    /// Into memory.
    Memory(Cursor<Vec<u8>>),
}

impl Write for Sink {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        match self {
            Sink::File(file) => file.write(bytes),
            Sink::Memory(memory) => memory.write(bytes),
        }
    }
    fn flush(&mut self) -> std::io::Result<()> {
        match self {
            Sink::File(file) => file.flush(),
            Sink::Memory(memory) => memory.flush(),
        }
    }
}

impl Seek for Sink {
    fn seek(&mut self, position: SeekFrom) -> std::io::Result<u64> {
        match self {
            Sink::File(file) => file.seek(position),
            Sink::Memory(memory) => memory.seek(position),
        }
    }
}

/// One staged output.
enum Staged {
    /// Complete in a temporary file, to be renamed over `target`.
    Renamed { temporary: Temporary, target: PathBuf },
    /// Complete in memory, to be written into the special file `target`.
    Written { bytes: Vec<u8>, target: PathBuf },
}

/// The outputs of one command: staged one by one, put in place together by [`Outputs::commit`].
/// Dropped without a commit, it removes what it staged.
#[derive(Default)]
pub struct Outputs {
    staged: Vec<Staged>,
    /// Directories created for the outputs, parents first: removed again (when still empty)
    /// unless the commit succeeds.
    created: Vec<PathBuf>,
}

impl Outputs {
    /// No outputs yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Encodes one output for `path`: `encode` writes the file's bytes into the sink. Errors name
    /// `path`; on error nothing of this output remains.
    pub fn stage(
        &mut self,
        path: &Path,
        encode: impl FnOnce(&mut Sink) -> Result<(), OutputError>,
    ) -> Result<(), OutputError> {
        let io = |source| OutputError::Io { path: path.display().to_string(), source };
        match check_destination(path)? {
            Destination::Special(target) => {
                let mut sink = Sink::Memory(Cursor::new(Vec::new()));
                encode(&mut sink)?;
                let Sink::Memory(memory) = sink else { unreachable!("a memory sink stays one") };
                self.staged.push(Staged::Written { bytes: memory.into_inner(), target });
            }
            Destination::Replace(target) => {
                if let Some(dir) = target.parent().filter(|d| !d.as_os_str().is_empty()) {
                    create_directories(dir, &mut self.created).map_err(io)?;
                }
                let old = std::fs::metadata(&target).ok().filter(std::fs::Metadata::is_file);
                let (temporary, file) = Temporary::create_beside(&target, old.as_ref()).map_err(io)?;
                let mut sink = Sink::File(BufWriter::new(file));
                encode(&mut sink)?;
                let Sink::File(buffered) = sink else { unreachable!("a file sink stays one") };
                // `into_inner` flushes and reports a failed final write; `sync_all` reports what
                // the file system defers (a full disk shows there on some of them).
                let file = buffered.into_inner().map_err(|e| io(e.into_error()))?;
                file.sync_all().map_err(io)?;
                self.staged.push(Staged::Renamed { temporary, target });
            }
        }
        Ok(())
    }

    /// Puts every staged output in place: first the special files are written (a write there
    /// cannot be undone, but when it fails no regular file has been replaced yet), then the
    /// temporary files are renamed over their destinations in the order staged.
    pub fn commit(mut self) -> Result<(), OutputError> {
        let (special, regular): (Vec<Staged>, Vec<Staged>) =
            std::mem::take(&mut self.staged).into_iter().partition(|s| matches!(s, Staged::Written { .. }));
        let mut directories: Vec<PathBuf> = Vec::new();
        for staged in special.into_iter().chain(regular) {
            match staged {
                Staged::Written { bytes, target } => {
                    let io = |source| OutputError::Io { path: target.display().to_string(), source };
                    let mut file = OpenOptions::new().write(true).open(&target).map_err(io)?;
                    file.write_all(&bytes).and_then(|()| file.flush()).map_err(io)?;
                }
                Staged::Renamed { temporary, target } => {
                    std::fs::rename(&temporary.path, &target)
                        .map_err(|source| OutputError::Io { path: target.display().to_string(), source })?;
                    temporary.keep();
                    let dir = target.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
                    if !directories.iter().any(|d| d == dir) {
                        directories.push(dir.to_owned());
                    }
                }
            }
        }
        self.created.clear();
        // Best effort: makes the renames durable; some file systems refuse fsync on directories.
        for dir in directories {
            if let Ok(dir) = File::open(dir) {
                let _ = dir.sync_all();
            }
        }
        Ok(())
    }
}

impl Drop for Outputs {
    /// Abandoned: the staged temporary files go first, then the directories created for them
    /// (innermost first; one that holds anything else stays).
    fn drop(&mut self) {
        self.staged.clear();
        for dir in self.created.iter().rev() {
            let _ = std::fs::remove_dir(dir);
        }
    }
}

/// Creates `dir` and its missing ancestors, adding each one created to `created` (parents first).
fn create_directories(dir: &Path, created: &mut Vec<PathBuf>) -> std::io::Result<()> {
    let mut missing = Vec::new();
    let mut ancestor = Some(dir);
    while let Some(path) = ancestor.filter(|p| !p.as_os_str().is_empty()) {
        if std::fs::metadata(path).is_ok() {
            break;
        }
        missing.push(path.to_path_buf());
        ancestor = path.parent();
    }
    for path in missing.into_iter().rev() {
        match std::fs::create_dir(&path) {
            Ok(()) => created.push(path),
            // Made meanwhile by someone else: theirs, not to be removed.
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

/// Writes a single output (see [`Outputs`]).
pub fn write_file(
    path: &Path,
    encode: impl FnOnce(&mut Sink) -> Result<(), OutputError>,
) -> Result<(), OutputError> {
    let mut outputs = Outputs::new();
    outputs.stage(path, encode)?;
    outputs.commit()
}

/// Writes `text` to `path` (see [`Outputs`]).
pub fn write_text(path: &Path, text: &str) -> Result<(), OutputError> {
    write_file(path, |sink| text_into(sink, path, text))
}

/// Writes `text` into a sink, errors naming `path`.
pub fn text_into(sink: &mut Sink, path: &Path, text: &str) -> Result<(), OutputError> {
    sink.write_all(text.as_bytes())
        .map_err(|source| OutputError::Io { path: path.display().to_string(), source })
}

/// Whether two paths name the same file: the same device and inode where both exist (so a
/// symbolic or hard link to a file is that file), else the same absolute path once symbolic
/// links in their existing ancestors are resolved.
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(a), Ok(b)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return (a.dev(), a.ino()) == (b.dev(), b.ino());
        }
    }
    identity(a) == identity(b)
}

/// Refuses an output that is one of the command's inputs, before any work: `outputs` are
/// (the flag that names it, its path), `inputs` are (its path, what it is: "the scene file",
/// "the part being merged"). The error reads `-o a.exr: is the part being merged; …`. A special
/// file among the outputs (`/dev/null`, a pipe) is written in place and replaces nothing, so it
/// is not compared.
pub fn check_not_inputs<'a>(
    outputs: impl IntoIterator<Item = (&'a str, &'a Path)>,
    inputs: &[(&Path, &str)],
) -> Result<(), OutputError> {
    for (flag, output) in outputs {
        if std::fs::metadata(output).is_ok_and(|meta| !meta.is_file()) {
            continue;
        }
        if let Some((_, what)) = inputs.iter().find(|(input, _)| same_file(output, input)) {
            return Err(OutputError::Destination {
                path: format!("{flag} {}", output.display()),
                problem: format!("is {what}; an output never replaces an input, so give another name"),
            });
        }
    }
    Ok(())
}

/// Refuses an input that is not a regular file (a FIFO would block the read until someone
/// writes to it; a device may never end), before reading it: the one-line error reads `PATH:
/// the part being merged is a FIFO, not a regular file`, with `what` naming the input. A
/// missing file passes: reading it reports that.
pub fn check_regular_input(path: &Path, what: &str) -> Result<(), String> {
    match std::fs::metadata(path) {
        Ok(meta) if !meta.is_file() => {
            Err(format!("{}: {what} is {}, not a regular file", path.display(), kind_name(&meta)))
        }
        _ => Ok(()),
    }
}

/// A name for the kind of a file that is not a regular one.
fn kind_name(meta: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let kind = meta.file_type();
        if kind.is_fifo() {
            return "a FIFO";
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
    if meta.is_dir() {
        "a directory"
    } else {
        "a special file"
    }
}

fn identity(path: &Path) -> PathBuf {
    if let Ok(real) = std::fs::canonicalize(path) {
        return real;
    }
    let mut rest = Vec::new();
    let mut ancestor = path.to_path_buf();
    loop {
        if let Ok(real) = std::fs::canonicalize(&ancestor) {
            return rest.iter().rev().fold(real, |p: PathBuf, c: &std::ffi::OsString| p.join(c));
        }
        match (ancestor.file_name().map(|n| n.to_owned()), ancestor.parent()) {
            (Some(name), Some(parent)) => {
                rest.push(name);
                ancestor = if parent.as_os_str().is_empty() { PathBuf::from(".") } else { parent.to_owned() };
            }
            _ => return path.to_owned(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn io_error(message: &str) -> OutputError {
        OutputError::Io { path: "x".into(), source: std::io::Error::other(message.to_owned()) }
    }

    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn failed_write_leaves_no_file_and_the_old_one_intact() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("image.exr");
        std::fs::write(&target, b"previous").unwrap();
        let result = write_file(&target, |sink| {
            sink.write_all(b"partial").unwrap();
            Err(io_error("simulated encoder failure"))
        });
        assert!(result.is_err());
        assert_eq!(entries(dir.path()), ["image.exr"]);
        assert_eq!(std::fs::read(&target).unwrap(), b"previous");
    }

    /// A write error inside the encoder (here the sink of a full disk is simulated by an
    /// encoder that fails after writing) must not leave the temporary file, and a later output's
    /// failure must leave none of the earlier staged ones either.
    #[test]
    fn png_enospc_reports_success_fails_the_whole_set() {
        let dir = tempfile::tempdir().unwrap();
        let mut outputs = Outputs::new();
        outputs.stage(&dir.path().join("a.exr"), |sink| text_into(sink, Path::new("a"), "exr")).unwrap();
        let failed = outputs.stage(&dir.path().join("a.png"), |sink| {
            sink.write_all(b"\x89PNG").unwrap();
            Err(OutputError::Io {
                path: "a.png".into(),
                source: std::io::Error::from_raw_os_error(28), // ENOSPC
            })
        });
        assert!(failed.is_err());
        drop(outputs);
        assert!(entries(dir.path()).is_empty(), "{:?}", entries(dir.path()));
    }

    #[test]
    fn staged_outputs_land_together_under_their_names() {
        let dir = tempfile::tempdir().unwrap();
        let mut outputs = Outputs::new();
        for name in ["sub/a.exr", "sub/a.png"] {
            outputs.stage(&dir.path().join(name), |sink| text_into(sink, Path::new(name), name)).unwrap();
        }
        assert!(!dir.path().join("sub/a.exr").exists(), "nothing lands before the commit");
        outputs.commit().unwrap();
        assert_eq!(entries(&dir.path().join("sub")), ["a.exr", "a.png"]);
        assert_eq!(std::fs::read_to_string(dir.path().join("sub/a.png")).unwrap(), "sub/a.png");
    }

    #[test]
    fn interrupt_during_write_leaves_tmp_is_cleaned_by_the_registry() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("big.exr");
        let _ = write_file(&target, |sink| {
            sink.write_all(b"half an image").unwrap();
            sink.flush().unwrap();
            assert_eq!(entries(dir.path()).len(), 1, "the temporary file exists while writing");
            // What the Ctrl-C handler does before exiting (`abandon_and_exit`, which then keeps
            // the registry locked; `interrupt_during_write_leaves_tmp` tests the whole of it):
            registry_update(|paths| remove_all(paths));
            assert!(entries(dir.path()).is_empty(), "the handler removed it");
            Err(io_error("interrupted"))
        });
        assert!(entries(dir.path()).is_empty());
    }

    #[test]
    fn directories_and_empty_paths_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        for path in [
            dir.path().to_path_buf(),
            PathBuf::from("."),
            PathBuf::from(".."),
            PathBuf::from("out/"),
            PathBuf::new(),
        ] {
            let error = check_destination(&path).expect_err("not a file");
            assert!(matches!(error, OutputError::Destination { .. }), "{path:?}: {error}");
        }
        let file = dir.path().join("f");
        std::fs::write(&file, "x").unwrap();
        assert!(check_destination(&file.join("under_a_file.exr")).is_err());
    }

    #[cfg(unix)]
    #[test]
    fn output_to_device_replaces_it_no_more() {
        // /dev/null is a character device: written in place, never renamed over.
        assert_eq!(
            check_destination(Path::new("/dev/null")).unwrap(),
            Destination::Special("/dev/null".into())
        );
        write_text(Path::new("/dev/null"), "discarded").unwrap();
        let meta = std::fs::metadata("/dev/null").unwrap();
        assert!(!meta.is_file(), "/dev/null is still a device");
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn a_full_device_fails_the_write() {
        // /dev/full refuses every write with ENOSPC: the error must surface at the commit.
        let error = write_text(Path::new("/dev/full"), "x").expect_err("ENOSPC");
        assert!(error.to_string().contains("/dev/full"), "{error}");
    }

    #[cfg(unix)]
    #[test]
    fn a_symbolic_link_is_followed_and_kept() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.exr");
        std::fs::write(&real, "old").unwrap();
        let link = dir.path().join("link.exr");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        write_text(&link, "new").unwrap();
        assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "new");
    }

    #[cfg(unix)]
    #[test]
    fn a_replaced_file_keeps_its_permission_bits() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("private.exr");
        std::fs::write(&target, "old").unwrap();
        std::fs::set_permissions(&target, std::fs::Permissions::from_mode(0o600)).unwrap();
        write_text(&target, "new").unwrap();
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "new");
        assert_eq!(std::fs::metadata(&target).unwrap().permissions().mode() & 0o7777, 0o600);
    }

    #[test]
    fn abandoned_outputs_remove_the_directories_they_made() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("kept")).unwrap();
        let result = write_file(&dir.path().join("kept/new/deeper/a.json"), |sink| {
            sink.write_all(b"{").unwrap();
            Err(io_error("disk full"))
        });
        assert!(result.is_err());
        assert_eq!(entries(dir.path()), ["kept"], "the directory that was there stays");
        assert!(entries(&dir.path().join("kept")).is_empty(), "new/deeper are gone");
    }

    #[cfg(unix)]
    #[test]
    fn an_output_linked_to_an_input_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let scene = dir.path().join("scene.toml");
        std::fs::write(&scene, "x").unwrap();
        let hard = dir.path().join("hard.json");
        std::fs::hard_link(&scene, &hard).unwrap();
        let soft = dir.path().join("soft.json");
        std::os::unix::fs::symlink(&scene, &soft).unwrap();
        let inputs = [(scene.as_path(), "the scene file")];
        for output in [&scene, &hard, &soft] {
            let error = check_not_inputs([("--stats", output.as_path())], &inputs).expect_err("an input");
            assert!(error.to_string().starts_with("--stats "), "{error}");
            assert!(error.to_string().contains("is the scene file"), "{error}");
        }
        let other = dir.path().join("other.json");
        assert!(check_not_inputs([("--stats", other.as_path())], &inputs).is_ok());
        // A device is written in place, never replaced: no input can be lost through it.
        let null = [(Path::new("/dev/null"), "the scene file")];
        assert!(check_not_inputs([("-o", Path::new("/dev/null"))], &null).is_ok());
        assert!(check_regular_input(Path::new("/dev/null"), "the part being merged")
            .is_err_and(|e| e.contains("a character device")));
    }

    #[test]
    fn same_file_sees_through_spellings() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("x.exr");
        let b = dir.path().join("sub/../x.exr");
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        assert!(same_file(&a, &b));
        assert!(!same_file(&a, &dir.path().join("x.png")));
    }
}
