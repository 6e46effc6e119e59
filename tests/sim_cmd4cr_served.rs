//! The §4.3 worked sequences of the CMD-4CR manual as `axterm run` files,
//! run against `axterm sim cmd4cr --pty` through the real binary and a
//! real pseudo-terminal, with `:expect` lines asserting the positions and
//! states the manual implies (axis letters restored where the manual lost
//! them, §4.3.4/§4.3.7/§4.3.8; `EX=0` in §4.3.3).
//!
//! The simulator runs on the wall clock here, so the files wait for
//! states with `:wait-until` (polling the controller), never for time.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Output, Stdio};

struct Served {
    child: Child,
    pty: String,
}

impl Served {
    fn start(extra: &[&str]) -> Served {
        let mut child = Command::new(env!("CARGO_BIN_EXE_axterm"))
            .args(["sim", "cmd4cr", "--pty"])
            .args(extra)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start axterm sim cmd4cr");
        let stdout = child.stdout.take().expect("stdout");
        let mut first = String::new();
        BufReader::new(stdout)
            .read_line(&mut first)
            .expect("read the pty path");
        Served {
            child,
            pty: first.trim().to_string(),
        }
    }
}

impl Drop for Served {
    fn drop(&mut self) {
        if let Ok(pid) = libc::pid_t::try_from(self.child.id()) {
            // SAFETY: a signal to our own child process; nothing is shared.
            unsafe {
                libc::kill(pid, libc::SIGTERM);
            }
        }
        let _ = self.child.wait();
    }
}

fn run_file(pty: &str, name: &str, text: &str, extra: &[&str]) -> Output {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join(name);
    std::fs::write(&path, text).expect("write the run file");
    Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(["run", "--port", pty, "--protocol", "cmd4cr"])
        .args(extra)
        .arg(&path)
        .output()
        .expect("run axterm run")
}

/// §4.3 sequences: (name, run file).
const SEQUENCES: &[(&str, &str)] = &[
    (
        "4.3.1 jog",
        "LSPDX=500\nHSPDX=5000\nACCX=200\nDECX=200\nEO1=1\nJX-\n\
         :wait-until MSTX == 4 timeout 10s\n:expect PSX == 5000\n\
         # where it stops depends on when STOPX comes: maybe on the home switch\n\
         STOPX\n:wait-until PSX == 0 timeout 10s\n:expect EO == 1\n",
    ),
    (
        "4.3.2 position",
        "LSPD=500\nHSPD=5000\nACC=200\nDEC=200\nEO=3\nABS\nX-20000\nY15000\n\
         :wait-until MSTX == 0 timeout 30s\n:wait-until MSTY == 0 timeout 30s\n\
         :expect PP == -20000:15000:0:0\n:expect EP == -20000:15000:0:0\n",
    ),
    (
        "4.3.3 counters",
        "X3000\n:wait-until MSTX == 0 timeout 30s\n:expect PX == 3000\n:expect EX == 3000\n\
         PX=0\nEX=0\n:expect PX == 0\n:expect EX == 0\n:expect DX == 0\n",
    ),
    (
        "4.3.4 homing",
        "LSPDY=500\nHSPDY=5000\nACCY=200\nDECY=200\nEO2=1\nPY=777\nHY-1\n\
         # mode 1 ends on the home switch (MST bit 6), zero set there\n\
         :wait-until MSTY == 64 timeout 30s\n:expect PY == 0\n:expect EY == 0\n",
    ),
    (
        "4.3.5 linear interpolation",
        "LSPD=500\nHSPD=5000\nACC=200\nDEC=200\nEO=3\nABS\nEINT=1\nX-20000Y15000\n\
         :wait-until MSTX == 0 timeout 30s\n:expect MSTY == 0\n:expect PP == -20000:15000:0:0\n",
    ),
    (
        "4.3.6 circular interpolation",
        "LSPD=500\nHSPD=5000\nACC=200\nDEC=200\nEO=3\nABS\nEINT=1\n\
         # the sync outputs catch X at 2000 and Y at 1000: right and top of the circle\n\
         SYNCX=1\nSYNPX=2000\nSYNOX\nSYNCY=1\nSYNPY=1000\nSYNOY\n\
         CIRXYP1000:0\n:wait-until MSTX == 0 timeout 30s\n\
         :expect SYNSX == 2\n:expect SYNSY == 2\n:expect DO == 3\n:expect PP == 0:0:0:0\n",
    ),
    (
        "4.3.7 on-the-fly speed change",
        "LSPDX=1000\nHSPDX=50000\nACCX=100\nDECX=100\nJX-\n\
         :wait-until MSTX == 4 timeout 10s\n:expect PSX == 50000\n\
         SSPDMX=2\nSSPDX=70000\n:wait-until PSX == 70000 timeout 10s\n\
         STOPX\n:wait-until PSX == 0 timeout 10s\n",
    ),
    (
        "4.3.8 sync output",
        "LSPDX=100\nHSPDX=1000\nSYNCX=1\nSYNPX=5000\nSYNOX\n:expect SYNSX == 1\nX5000\n\
         :expect DO1 == 0\n:wait-until MSTX == 0 timeout 30s\n:expect PX == 5000\n\
         :expect DO1 == 1\n:expect SYNSX == 2\n",
    ),
    (
        "4.3.9 general-purpose I/O",
        ":expect IO5 == 0\nIO19=0\n:expect IO19 == 0\nIO19=1\n:expect IO19 == 1\n\
         :expect IO == 262144\n",
    ),
];

#[test]
fn every_worked_sequence_of_4_3_runs_against_the_served_simulator() {
    let handles: Vec<_> = SEQUENCES
        .iter()
        .map(|&(name, text)| {
            std::thread::spawn(move || {
                let served = Served::start(&[]);
                let out = run_file(&served.pty, "sequence.txt", text, &[]);
                (name, out)
            })
        })
        .collect();
    for handle in handles {
        let (name, out) = handle.join().expect("sequence thread");
        assert_eq!(
            out.status.code(),
            Some(0),
            "{name}:\n{}\n{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

#[test]
fn the_served_simulator_keeps_its_id_and_flash() {
    let dir = tempfile::tempdir().expect("temp dir");
    let flash = dir.path().join("flash.json");
    let flash = flash.to_string_lossy().into_owned();
    {
        let served = Served::start(&["--address", "7", "--eeprom", &flash]);
        let out = run_file(
            &served.pty,
            "store.txt",
            "POLX=5\nSTORE\n:expect POLX == 5\n",
            &["--address", "7"],
        );
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let served = Served::start(&["--address", "7", "--eeprom", &flash]);
    let out = run_file(
        &served.pty,
        "read.txt",
        ":expect POLX == 5\n",
        &["--address", "7"],
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_program_given_with_program_runs_when_started_over_the_wire() {
    // §5.4.1, loaded by the simulator-side option and started with SACTRL.
    let dir = tempfile::tempdir().expect("temp dir");
    let program = dir.path().join("example1.txt");
    std::fs::write(
        &program,
        "PRG 0\n    HSPD=20000\n    LSPD=1000\n    ACC=300\n    EO=1\n    X1000\n    WAITX\n    X0\n    WAITX\nEND\n",
    )
    .expect("write the program");
    let served = Served::start(&["--program", &program.to_string_lossy()]);
    let out = run_file(
        &served.pty,
        "start.txt",
        ":expect SASTAT0 == 0\nSYNCX=1\nSYNPX=1000\nSYNOX\nSACTRL0=1\n\
         :wait-until SASTAT0 == 0 timeout 30s\n:expect SYNSX == 2\n:expect PX == 0\n:expect HSPD == 20000\n",
        &[],
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_program_that_does_not_compile_is_refused_before_serving() {
    let dir = tempfile::tempdir().expect("temp dir");
    let program = dir.path().join("bad.txt");
    std::fs::write(&program, "PRG 0\n    V200=1\nEND\n").expect("write");
    let out = Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(["sim", "cmd4cr", "--pty", "--program"])
        .arg(&program)
        .output()
        .expect("run axterm sim");
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty(), "nothing served");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.txt") && err.contains("Var Range Error"),
        "{err}"
    );
    let out = Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(["sim", "tmcm1110", "--pty", "--program"])
        .arg(&program)
        .output()
        .expect("run axterm sim");
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("runs no A-Script"));
}
