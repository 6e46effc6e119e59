//! `--tcp rfc2217://HOST:PORT` against a real ser2net (4.x, a
//! `telnet(rfc2217)` accepter on loopback) in front of `axterm sim KIND
//! --pty`: polls, downloads with verify, IAC (0xFF) bytes inside TMCL
//! frames both ways, and the baud rate the simulator's pseudo-terminal was
//! set to. Skipped, with the reason printed, where ser2net is not
//! installed (`.ci/run` installs it).

mod served_support;

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use served_support::Served;

/// Only guards against a hung test (ser2net never listening).
const GIVE_UP_AFTER: Duration = Duration::from_secs(20);

/// ser2net serving one pseudo-terminal over RFC 2217 on 127.0.0.1; ended
/// (SIGTERM) when dropped.
struct Ser2net {
    child: Child,
    /// `rfc2217://127.0.0.1:PORT`.
    url: String,
    _dir: tempfile::TempDir,
}

impl Ser2net {
    /// None, with the reason printed, when ser2net is not installed.
    fn start(pty: &str) -> Option<Ser2net> {
        if Command::new("ser2net").arg("-v").output().is_err() {
            println!("skipped: ser2net is not installed (apt-get install ser2net)");
            return None;
        }
        let dir = tempfile::tempdir().expect("a temporary directory");
        // A free port: bound, read, and let go for ser2net to take.
        let port = TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .expect("a free port")
            .port();
        let config = dir.path().join("ser2net.yaml");
        // The line starts at 9600 Bd 8N1; the client's RFC 2217 settings
        // change it. kickolduser: the readiness probe below may still be
        // closing when the test connects.
        std::fs::write(
            &config,
            format!(
                "connection: &sim\n  \
                 accepter: telnet(rfc2217),tcp,127.0.0.1,{port}\n  \
                 connector: serialdev,{pty},9600n81,local\n  \
                 options:\n    kickolduser: true\n"
            ),
        )
        .expect("write the ser2net config");
        let pid_file = dir.path().join("ser2net.pid");
        let mut child = Command::new("ser2net")
            .arg("-n") // stay in the foreground, our child
            .arg("-u") // no UUCP lock files
            .arg("-c")
            .arg(&config)
            .arg("-P")
            .arg(&pid_file)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start ser2net");
        // Ready when it accepts a connection (it prints nothing then).
        let started = Instant::now();
        while TcpStream::connect(("127.0.0.1", port)).is_err() {
            if let Ok(Some(status)) = child.try_wait() {
                let mut err = String::new();
                if let Some(mut stderr) = child.stderr.take() {
                    let _ = stderr.read_to_string(&mut err);
                }
                panic!("ser2net ended ({status}) before listening: {err}");
            }
            assert!(started.elapsed() < GIVE_UP_AFTER, "ser2net never listened");
            std::thread::yield_now();
        }
        Some(Ser2net {
            child,
            url: format!("rfc2217://127.0.0.1:{port}"),
            _dir: dir,
        })
    }
}

impl Drop for Ser2net {
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

fn axterm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(args)
        .output()
        .expect("axterm runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The line settings the simulator noted so far (`axterm sim line: the
/// client set it to …`). It checks its pseudo-terminal's settings before
/// it reads the client's next bytes, so a rate set before a request was
/// answered has been noted by then; a BREAK typed now is answered after
/// every note already given.
fn line_notices(served: &mut Served) -> Vec<String> {
    let stdin_answer = "axterm sim: a BREAK on the line";
    let mut notices = Vec::new();
    served.type_line("BREAK");
    loop {
        let line = served
            .next_stderr_line()
            .expect("axterm sim ended without answering");
        if line == stdin_answer {
            return notices;
        }
        if let Some(settings) = line.strip_prefix("axterm sim line: the client set it to ") {
            notices.push(settings.to_string());
        }
    }
}

#[test]
fn a_tmcl_poll_through_ser2net_sets_the_simulators_baud_rate() {
    let mut served = Served::start_driven("tmcm1110", &[]);
    let Some(bridge) = Ser2net::start(&served.pty) else {
        return;
    };
    let out = axterm(&[
        "exec",
        "--tcp",
        &bridge.url,
        "--protocol",
        "tmcl",
        "--baud",
        "57600",
        "GAP 1, 0",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout), "0\n");
    // ser2net opened the pty at 9600 Bd; RFC 2217 set it to 57600.
    let notices = line_notices(&mut served);
    assert!(notices.contains(&"57600 Bd 8N1".to_string()), "{notices:?}");
}

#[test]
fn iac_bytes_inside_tmcl_frames_survive_both_ways() {
    // The frames this test is about: a request whose checksum is 0xFF, a
    // request and a reply whose value holds 0xFF, a reply whose checksum
    // is 0xFF (2 + 1 + 100 + 6 + 146 = 255).
    let encoded = axterm(&["encode", "tmcl", "SAP 4, 0, 245"]);
    assert_eq!(text(&encoded.stdout).trim(), "01 05 04 00 00 00 00 F5 FF");
    let encoded = axterm(&["encode", "tmcl", "SAP 4, 0, 255"]);
    assert_eq!(text(&encoded.stdout).trim(), "01 05 04 00 00 00 00 FF 09");

    let served = Served::start("tmcm1110", &[]);
    let Some(bridge) = Ser2net::start(&served.pty) else {
        return;
    };
    let out = axterm(&[
        "exec",
        "--tcp",
        &bridge.url,
        "--protocol",
        "tmcl",
        "SAP 4, 0, 245",
        "GAP 4, 0",
        "SAP 4, 0, 255",
        "GAP 4, 0",
        "SAP 4, 0, 146",
        "GAP 4, 0",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout), "ok\n245\nok\n255\nok\n146\n");
}

#[test]
fn a_tmcl_download_through_ser2net_is_verified() {
    let served = Served::start("tmcm1110", &[]);
    let Some(bridge) = Ser2net::start(&served.pty) else {
        return;
    };
    let source = format!(
        "{}/tests/data/programs/s2_4_first_program.tmc",
        env!("CARGO_MANIFEST_DIR")
    );
    let out = axterm(&[
        "download",
        "--tcp",
        &bridge.url,
        "--protocol",
        "tmcl",
        "--baud",
        "115200",
        &source,
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains("verified"),
        "{}",
        text(&out.stdout)
    );
}

// 19200 Bd, not 38400: a Linux pseudo-terminal starts at 38400 Bd 8N1, so
// a client asking for 38400 leaves the settings the simulator first saw
// unchanged whenever it does not look during the moment ser2net has the
// line at its configured 9600 (the notice says changes only).
#[test]
fn mccl_polls_and_downloads_through_ser2net_at_the_baud_asked() {
    let mut served = Served::start_driven("mccl", &[]);
    let Some(bridge) = Ser2net::start(&served.pty) else {
        return;
    };
    let link = [
        "--tcp",
        bridge.url.as_str(),
        "--protocol",
        "mccl",
        "--baud",
        "19200",
    ];
    let mut args = vec!["exec"];
    args.extend(link);
    args.push("1TP");
    let out = axterm(&args);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout), "0\n");

    let dir = tempfile::tempdir().expect("a temporary directory");
    let file = dir.path().join("cycle.mfx1");
    std::fs::write(
        &file,
        "2MN\nMD10,2MR500,WS.1,MR-500,WS.1\nMD11,AL@100,AA5,AR100\n",
    )
    .expect("write");
    let mut args = vec!["download"];
    args.extend(link);
    args.push(file.to_str().expect("a path"));
    let out = axterm(&args);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains("2 macro(s) read back with TM and verified"),
        "{}",
        text(&out.stdout)
    );
    let notices = line_notices(&mut served);
    assert!(notices.contains(&"19200 Bd 8N1".to_string()), "{notices:?}");
}

/// A Telnet server that refuses COM-PORT-OPTION (no ser2net needed): the
/// connection fails, exit 3, and the message says so.
#[test]
fn a_server_refusing_com_port_option_is_named() {
    let listener = TcpListener::bind("127.0.0.1:0").expect("bind");
    let address = listener.local_addr().expect("address");
    let server = std::thread::spawn(move || {
        let (mut client, _) = listener.accept().expect("accept");
        // IAC DONT COM-PORT-OPTION, then wait for the client to leave.
        client.write_all(&[255, 254, 44]).expect("refuse");
        let mut rest = Vec::new();
        let _ = client.read_to_end(&mut rest);
    });
    let url = format!("rfc2217://{address}");
    let out = axterm(&["exec", "--tcp", &url, "--protocol", "tmcl", "GAP 1, 0"]);
    assert_eq!(out.status.code(), Some(3), "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains(&format!(
            "cannot open {url} at 9600 Bd: the server refused COM-PORT-OPTION"
        )),
        "{}",
        text(&out.stderr)
    );
    server.join().expect("the server thread");
}

// ------------------------------------------- the link against a scripted server

mod scripted {
    use std::time::Duration;

    use axterm::link::{Link, LinkInput, LinkSpec};
    use tokio::io::{AsyncReadExt, AsyncWriteExt};
    use tokio::net::{TcpListener, TcpStream};

    const GIVE_UP_AFTER: Duration = Duration::from_secs(10);
    const IAC: u8 = 255;

    /// What an RFC 2217 client sends first: WILL COM-PORT-OPTION, WILL
    /// BINARY, DO BINARY, DO SUPPRESS-GO-AHEAD.
    const OPENING: [u8; 12] = [IAC, 251, 44, IAC, 251, 0, IAC, 253, 0, IAC, 253, 3];

    /// The four settings at 57600 Bd 8N1 (RFC 2217 SET-BAUDRATE, -DATASIZE,
    /// -PARITY, -STOPSIZE).
    const SETTINGS: [u8; 31] = [
        IAC, 250, 44, 1, 0, 0, 0xE1, 0x00, IAC, 240, //
        IAC, 250, 44, 2, 8, IAC, 240, //
        IAC, 250, 44, 3, 1, IAC, 240, //
        IAC, 250, 44, 4, 1, IAC, 240,
    ];

    /// The server's confirmations: the client's codes plus 100, with `baud`.
    fn confirmations(baud: u32) -> Vec<u8> {
        let b = baud.to_be_bytes();
        vec![
            IAC, 250, 44, 101, b[0], b[1], b[2], b[3], IAC, 240, //
            IAC, 250, 44, 102, 8, IAC, 240, //
            IAC, 250, 44, 103, 1, IAC, 240, //
            IAC, 250, 44, 104, 1, IAC, 240,
        ]
    }

    /// Open an RFC 2217 link at 57600 Bd while `server` plays the bridge.
    async fn open_against<F, Fut>(server: F) -> Result<Link, String>
    where
        F: FnOnce(TcpStream) -> Fut + Send + 'static,
        Fut: std::future::Future<Output = ()> + Send,
    {
        let listener = TcpListener::bind("127.0.0.1:0").await.expect("bind");
        let address = listener.local_addr().expect("address").to_string();
        let serving = tokio::spawn(async move {
            let (stream, _) = listener.accept().await.expect("accept");
            server(stream).await;
        });
        let spec = LinkSpec::Rfc2217 {
            address,
            baud: 57600,
        };
        let link = tokio::time::timeout(GIVE_UP_AFTER, spec.open())
            .await
            .expect("opens or fails within the guard time");
        if link.is_err() {
            serving.abort();
        }
        link.map_err(|e| e.to_string())
    }

    async fn read_exactly(stream: &mut TcpStream, n: usize) -> Vec<u8> {
        let mut buf = vec![0; n];
        tokio::time::timeout(GIVE_UP_AFTER, stream.read_exact(&mut buf))
            .await
            .expect("the client writes within the guard time")
            .expect("read");
        buf
    }

    async fn device_bytes(link: &mut Link, n: usize) -> Vec<u8> {
        let mut got = Vec::new();
        while got.len() < n {
            match tokio::time::timeout(GIVE_UP_AFTER, link.incoming.recv()).await {
                Ok(Some(LinkInput::Bytes(bytes))) => got.extend(bytes),
                other => panic!("expected bytes, got {other:?}"),
            }
        }
        got
    }

    #[tokio::test]
    async fn settings_are_sent_once_accepted_and_telnet_never_reaches_the_device_task() {
        let (to_test, mut from_server) = tokio::sync::mpsc::unbounded_channel();
        let mut link = open_against(move |mut bridge| async move {
            assert_eq!(read_exactly(&mut bridge, OPENING.len()).await, OPENING);
            bridge
                .write_all(&[IAC, 253, 44])
                .await
                .expect("DO COM-PORT");
            assert_eq!(read_exactly(&mut bridge, SETTINGS.len()).await, SETTINGS);
            bridge
                .write_all(&confirmations(57600))
                .await
                .expect("confirm");
            // Device bytes with IAC doubled, an offer of ECHO in between,
            // sent in pieces that cut both sequences.
            for piece in [&[1, IAC][..], &[IAC, 2, IAC], &[251], &[1, 3]] {
                bridge.write_all(piece).await.expect("write");
                bridge.flush().await.expect("flush");
            }
            // The client refuses ECHO, then sends a frame holding 0xFF.
            assert_eq!(read_exactly(&mut bridge, 3).await, [IAC, 254, 1]);
            let _ = to_test.send(read_exactly(&mut bridge, 4).await);
        })
        .await
        .expect("opens");
        assert!(
            link.name.starts_with("rfc2217://127.0.0.1:"),
            "{}",
            link.name
        );
        assert_eq!(device_bytes(&mut link, 4).await, [1, IAC, 2, 3]);
        link.outgoing.send(&[7, IAC, 8]).expect("send");
        let sent = tokio::time::timeout(GIVE_UP_AFTER, from_server.recv())
            .await
            .expect("the server reports");
        assert_eq!(sent, Some(vec![7, IAC, IAC, 8]), "IAC doubled on the wire");
    }

    #[tokio::test]
    async fn a_server_setting_another_rate_fails_the_opening() {
        let error = open_against(|mut bridge| async move {
            read_exactly(&mut bridge, OPENING.len()).await;
            bridge
                .write_all(&[IAC, 253, 44])
                .await
                .expect("DO COM-PORT");
            read_exactly(&mut bridge, SETTINGS.len()).await;
            bridge
                .write_all(&confirmations(9600))
                .await
                .expect("confirm");
            let mut rest = Vec::new();
            let _ = bridge.read_to_end(&mut rest).await;
        })
        .await
        .expect_err("refused");
        assert!(
            error.ends_with(
                "at 57600 Bd: the server set its port to 9600 Bd, not the 57600 Bd asked for"
            ),
            "{error}"
        );
    }

    #[tokio::test]
    async fn a_server_closing_during_the_opening_is_named() {
        let error = open_against(|mut bridge| async move {
            read_exactly(&mut bridge, OPENING.len()).await;
        })
        .await
        .expect_err("fails");
        assert!(
            error.ends_with("the server closed the connection during the RFC 2217 opening"),
            "{error}"
        );
    }
}
