//! `axterm download`, `upload` and `disasm CONNECTION` as a script sees
//! them, against `axterm sim tmcm1110 --pty`: stdout, stderr, exit codes.

mod cli_support;

use cli_support::{axterm, stderr, stdout};
use std::io::{BufRead, BufReader, Read};
use std::path::Path;
use std::process::{Child, Command, Output, Stdio};

fn example(name: &str) -> String {
    format!("{}/tests/data/programs/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// `axterm sim tmcm1110 --pty …` running, with the path it announced.
struct Served {
    child: Child,
    path: String,
}

impl Served {
    fn start(extra: &[&str]) -> Served {
        let mut args = vec!["sim", "tmcm1110", "--pty"];
        args.extend_from_slice(extra);
        let mut child = Command::new(env!("CARGO_BIN_EXE_axterm"))
            .args(&args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start axterm sim");
        let mut first_line = String::new();
        BufReader::new(child.stdout.take().expect("stdout"))
            .read_line(&mut first_line)
            .expect("read the pty path");
        Served {
            child,
            path: first_line.trim().to_string(),
        }
    }

    /// `axterm ARGS… --port PATH`.
    fn run(&self, args: &[&str]) -> Output {
        let mut all = args.to_vec();
        all.extend_from_slice(&["--port", &self.path]);
        axterm(&all)
    }

    /// End it (SIGTERM) and return what it said on stderr.
    fn finish(mut self) -> String {
        let pid = libc::pid_t::try_from(self.child.id()).expect("pid fits pid_t");
        // SAFETY: sends a signal to our own child process; nothing is shared.
        unsafe { libc::kill(pid, libc::SIGTERM) };
        let mut text = String::new();
        if let Some(mut err) = self.child.stderr.take() {
            let _ = err.read_to_string(&mut text);
        }
        let _ = self.child.wait();
        text
    }
}

impl Drop for Served {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The image `axterm asm` makes of `file`.
fn image_of(file: &str) -> String {
    let out = axterm(&["asm", file]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    stdout(&out)
}

#[test]
fn download_verify_upload_and_disasm_against_a_served_module() {
    let served = Served::start(&[]);
    let source = example("s3_5_6_4_timer_interrupt_symbolic.tmc");
    let out = served.run(&["download", &source]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let summary = stdout(&out);
    assert!(
        summary.starts_with("downloaded 15 words to module 1 and verified them in "),
        "{summary}"
    );
    assert_eq!(stderr(&out), "", "quiet when stderr is not a terminal");

    // Upload as source: it assembles to the image the source makes.
    let dir = tempfile::tempdir().expect("temp dir");
    let uploaded = dir.path().join("uploaded.tmc");
    let uploaded = uploaded.to_str().expect("utf-8 path");
    let out = served.run(&["upload", "-o", uploaded]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "");
    assert_eq!(image_of(uploaded), image_of(&source));

    // `disasm CONNECTION` prints the same source.
    let out = served.run(&["disasm"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(
        stdout(&out),
        std::fs::read_to_string(uploaded).expect("uploaded")
    );

    // And as an image, byte for byte the assembler's.
    let out = served.run(&["upload", "--image"]);
    assert_eq!(stdout(&out), image_of(&source));
}

#[test]
fn a_corrupted_store_fails_at_its_address_and_exits_1() {
    let served = Served::start(&["--fault", "corrupt-store=7"]);
    let source = example("s8_6_host_routines.tmc");
    let out = served.run(&["download", &source]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert_eq!(stdout(&out), "", "never says verified");
    let err = stderr(&out);
    assert!(
        err.starts_with("axterm download: word 6 differs: wrote "),
        "{err}"
    );
    assert!(err.contains("NOT verified"), "{err}");
    // The fault counted once; the next download on the same line is fine.
    let out = served.run(&["download", &source, "--format", "json"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(report["verified"], true);
    assert_eq!(report["words"], 16);
    let sim_said = served.finish();
    assert!(
        sim_said.contains("1 program words stored corrupted"),
        "{sim_said}"
    );
}

#[test]
fn a_failed_download_in_json_names_the_address() {
    let served = Served::start(&["--fault", "corrupt-store=2"]);
    let source = example("s8_6_host_routines.tmc");
    let out = served.run(&["download", &source, "--format", "json"]);
    assert_eq!(out.status.code(), Some(1));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(report["ok"], false);
    assert_eq!(report["verified"], false);
    assert_eq!(report["address"], 1);
    assert!(
        report["error"]
            .as_str()
            .is_some_and(|e| e.starts_with("word 1 differs")),
        "{report}"
    );
}

#[test]
fn run_and_autostart_start_the_verified_program() {
    let served = Served::start(&[]);
    let dir = tempfile::tempdir().expect("temp dir");
    let program = dir.path().join("set.tmc");
    std::fs::write(&program, "SGP 42, 2, 1234\nSTOP\n").expect("write");
    let out = served.run(&[
        "download",
        program.to_str().expect("utf-8"),
        "--run",
        "--autostart",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.contains("autostart on"), "{text}");
    assert!(text.contains("started the program"), "{text}");
    let check = dir.path().join("check.txt");
    std::fs::write(
        &check,
        ":wait-until GGP 42, 2 == 1234 timeout 10s\n:expect GGP 77, 0 == 1\n",
    )
    .expect("write");
    let out = served.run(&["run", check.to_str().expect("utf-8")]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

#[test]
fn an_image_file_downloads_as_is() {
    let served = Served::start(&[]);
    let dir = tempfile::tempdir().expect("temp dir");
    let image = dir.path().join("p.hex");
    let source = example("s3_6_43_djnz_loop.tmc");
    let image_path = image.to_str().expect("utf-8");
    let out = axterm(&["asm", &source, "-o", image_path]);
    assert_eq!(out.status.code(), Some(0));
    let out = served.run(&["download", "--image", image_path]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let out = served.run(&["upload", "--image"]);
    assert_eq!(
        stdout(&out),
        std::fs::read_to_string(Path::new(image_path)).expect("image")
    );
}

#[test]
fn a_program_that_does_not_assemble_sends_nothing() {
    let dir = tempfile::tempdir().expect("temp dir");
    let program = dir.path().join("bad.tmc");
    std::fs::write(&program, "MVP ABS, 0, 1000\nJA Nowhere\n").expect("write");
    // A port that cannot exist: had anything been sent, opening it would
    // have failed with exit 3.
    let out = axterm(&[
        "download",
        "--port",
        "/nonexistent/tty",
        program.to_str().expect("utf-8"),
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert_eq!(stdout(&out), "");
    let err = stderr(&out);
    assert!(
        err.contains("bad.tmc:2:4: JA: undefined label `Nowhere`"),
        "{err}"
    );
    assert!(err.contains("1 error in"), "{err}");
    assert!(err.contains("nothing was sent"), "{err}");
}

#[test]
fn an_image_with_a_control_command_sends_nothing() {
    let dir = tempfile::tempdir().expect("temp dir");
    let image = dir.path().join("p.hex");
    std::fs::write(&image, "1C 00 00 00 00 00 00\n85 00 00 00 00 00 00\n").expect("write");
    let out = axterm(&[
        "download",
        "--port",
        "/nonexistent/tty",
        "--image",
        image.to_str().expect("utf-8"),
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(
        err.contains("word 1 (85 00 00 00 00 00 00) cannot be downloaded"),
        "{err}"
    );
    assert!(err.contains("nothing was sent"), "{err}");
}

#[test]
fn an_unreachable_module_exits_3() {
    let out = axterm(&["upload", "--port", "/nonexistent/tty"]);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    let program = example("s3_6_19_ja_loop.tmc");
    let out = axterm(&["download", "--port", "/nonexistent/tty", &program]);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
}

#[test]
fn a_protected_program_is_not_read() {
    let served = Served::start(&[]);
    let out = served.run(&["exec", "SGP 81, 0, 1"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let out = served.run(&["upload"]);
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(err.contains("cannot read word 0 from module 1"), "{err}");
    assert!(err.contains("GP81"), "{err}");
}

#[test]
fn an_emulated_wire_gets_the_wire_limit_figure() {
    let program = example("s3_6_19_ja_loop.tmc");
    let out = axterm(&[
        "download", "--sim", "tmcm1110", "--baud", "115200", &program,
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stdout(&out).contains("of the wire's limit"),
        "{}",
        stdout(&out)
    );
    let out = axterm(&[
        "download", "--sim", "tmcm1110", "--baud", "115200", &program, "--format", "json",
    ]);
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert!(report["wire_share"].is_number(), "{report}");
    assert!(report["wire_limit_us"].is_number(), "{report}");
}
