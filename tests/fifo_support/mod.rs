//! A FIFO (named pipe) with a writer standing ready, for tests that an
//! input file which is a FIFO is refused without being opened: were it
//! read, the writer's text would come and the read would succeed, so a
//! test sees the difference without waiting for anything.
#![allow(dead_code)]

use std::ffi::CString;
use std::os::unix::ffi::OsStrExt;
use std::os::unix::fs::OpenOptionsExt;
use std::path::PathBuf;

/// A FIFO at `path`, and a thread waiting to write `text` into it (it
/// waits until a reader opens it).
pub struct Fifo {
    pub path: PathBuf,
    writer: Option<std::thread::JoinHandle<()>>,
}

impl Fifo {
    pub fn new(path: PathBuf, text: &'static str) -> Fifo {
        let name = CString::new(path.as_os_str().as_bytes()).expect("no NUL");
        // SAFETY: `name` is a valid NUL-terminated path for the call.
        assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0, "mkfifo");
        let target = path.clone();
        let writer = std::thread::spawn(move || {
            let _ = std::fs::write(&target, text);
        });
        Fifo {
            path,
            writer: Some(writer),
        }
    }
}

impl Drop for Fifo {
    fn drop(&mut self) {
        // Had axterm opened it, the writer is done; if not, a reader
        // opened here (without waiting) lets the writer's open return. The
        // reader stays open until the writer has finished: the writer
        // thread may not have reached its open yet, and a reader closed
        // before that would leave it waiting for a partner forever.
        let reader = std::fs::OpenOptions::new()
            .read(true)
            .custom_flags(libc::O_NONBLOCK)
            .open(&self.path);
        if let Some(writer) = self.writer.take() {
            let _ = writer.join();
        }
        drop(reader);
    }
}
