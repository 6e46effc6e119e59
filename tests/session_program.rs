//! Program download, verification and upload through the session, against
//! the in-process TMCM-1110 simulator on tokio's paused clock.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use axterm::cli::asm::SourceFiles;
use axterm::families::find_kind;
use axterm::link::LinkSpec;
use axterm::protocol::program::{
    DownloadOptions, FactValue, FailureKind, Phase, Progress, TransferFailure, TransferReport,
    UploadExtent,
};
use axterm::protocol::tmcl::asm::{NoIncludes, ProgramWord, assemble, disassemble, parse_image};
use axterm::protocol::tmcl::plan::{DownloadPlan, UploadPlan};
use axterm::session::{Cancel, PollCadence, ReplyValue, Session, SessionError, SessionOptions};
use axterm::sim::SimOptions;
use axterm::sim::faults::FaultPlan;

/// Virtual time: only guards against a hung test.
const GIVE_UP_AFTER: Duration = Duration::from_secs(600);

async fn connect_with(faults: FaultPlan, baud: Option<u32>) -> Session {
    let kind = find_kind("tmcm1110").expect("registered");
    let spec = LinkSpec::Sim {
        kind: kind.name.into(),
        sim: Arc::new(Mutex::new((kind.build)(&SimOptions::default()))),
        baud,
        faults,
    };
    let family = axterm::families::family_of(kind).expect("family");
    Session::connect(spec, family, SessionOptions::default())
        .await
        .expect("the simulator link opens")
}

async fn connect() -> Session {
    connect_with(FaultPlan::none(), None).await
}

fn program(source: &str) -> Vec<ProgramWord> {
    match assemble("test.tmc", source, &NoIncludes) {
        Ok(p) => p.words,
        Err(e) => panic!("{e:?}"),
    }
}

fn example(name: &str) -> Vec<ProgramWord> {
    let path = format!("{}/tests/data/programs/{name}", env!("CARGO_MANIFEST_DIR"));
    let source = std::fs::read_to_string(&path).expect("example file");
    match assemble(&path, &source, &SourceFiles) {
        Ok(p) => p.words,
        Err(e) => panic!("{e:?}"),
    }
}

/// A program of `n` words: moves and waits, STOP last.
fn long_program(n: usize) -> Vec<ProgramWord> {
    let mut source = String::new();
    for i in 0..n - 1 {
        source.push_str(&format!("MVP ABS, 0, {}\n", i * 10));
    }
    source.push_str("STOP\n");
    program(&source)
}

async fn value(session: &Session, line: &str) -> ReplyValue {
    session
        .execute_line(line)
        .await
        .unwrap_or_else(|e| panic!("{line}: {e}"))
        .value
}

/// TMCL's download plan for `words`, driven by the session's runner.
async fn download_program(
    session: &Session,
    words: &[ProgramWord],
    options: DownloadOptions,
    cancel: &Cancel,
    progress: &mut (dyn FnMut(Progress) + Send),
) -> Result<TransferReport, TransferFailure> {
    let plan = DownloadPlan::new(words, session.address(), options)?;
    session.transfer(Box::new(plan), cancel, progress).await
}

/// TMCL's upload plan driven by the session's runner: the words read back
/// (from the image it reports) and the report.
async fn upload_program(
    session: &Session,
    extent: UploadExtent,
    cancel: &Cancel,
    progress: &mut (dyn FnMut(Progress) + Send),
) -> Result<(Vec<ProgramWord>, TransferReport), TransferFailure> {
    let plan = UploadPlan::new(session.address(), extent);
    let report = session.transfer(Box::new(plan), cancel, progress).await?;
    let image = report
        .program
        .as_ref()
        .and_then(|p| p.image.clone())
        .unwrap_or_default();
    let words = parse_image(&image).unwrap_or_else(|e| panic!("{e:?}"));
    Ok((words, report))
}

async fn download(
    session: &Session,
    words: &[ProgramWord],
    options: DownloadOptions,
) -> Result<TransferReport, TransferFailure> {
    download_program(session, words, options, &Cancel::new(), &mut |_| {}).await
}

async fn upload(session: &Session, extent: UploadExtent) -> Vec<ProgramWord> {
    upload_program(session, extent, &Cancel::new(), &mut |_| {})
        .await
        .expect("upload")
        .0
}

/// The word at `address` as the console reads it.
async fn readmem(session: &Session, address: usize) -> String {
    value(session, &format!("READMEM {address}"))
        .await
        .to_string()
}

#[tokio::test(start_paused = true)]
async fn a_download_is_stored_verified_and_reads_back() {
    let session = connect().await;
    let words = example("s8_6_host_routines.tmc");
    let mut seen: Vec<Progress> = Vec::new();
    let report = download_program(
        &session,
        &words,
        DownloadOptions::default(),
        &Cancel::new(),
        &mut |p| seen.push(p),
    )
    .await
    .expect("downloaded and verified");
    assert_eq!(report.count, words.len());
    assert_eq!(report.module, 1);
    assert_eq!(report.fact("stopped_program"), Some(&FactValue::Absent));
    assert_eq!(report.fact("leftover_from"), Some(&FactValue::Absent));
    // GP128, 131, 132, the words, 133, the read-backs, the word after.
    assert_eq!(report.transactions, 2 * words.len() as u64 + 5);
    let storing = seen.iter().filter(|p| p.phase == Phase::Storing).count();
    let verifying = seen.iter().filter(|p| p.phase == Phase::Verifying).count();
    assert_eq!((storing, verifying), (words.len() + 1, words.len() + 1));
    assert_eq!(
        seen.last(),
        Some(&Progress {
            phase: Phase::Verifying,
            done: words.len(),
            total: Some(words.len())
        })
    );
    assert_eq!(value(&session, "GGP 129, 0").await, ReplyValue::Number(0));
    assert_eq!(readmem(&session, 3).await, "MVP ABS, 0, 1000");
    assert_eq!(upload(&session, UploadExtent::UntilBlank).await, words);
}

#[tokio::test(start_paused = true)]
async fn a_word_stored_corrupted_fails_verification_at_its_address() {
    let faults = FaultPlan::parse("corrupt-store=5").expect("parses");
    let session = connect_with(faults.clone(), None).await;
    let words = long_program(12);
    let error = download(&session, &words, DownloadOptions::default())
        .await
        .expect_err("a corrupted word is never verified");
    assert_eq!(error.kind, FailureKind::Failed, "{error}");
    assert_eq!(
        error.address(),
        Some(4),
        "the fifth word stored is at address 4"
    );
    assert!(
        error.to_string().starts_with(
            "word 4 differs: wrote MVP ABS, 0, 40 (04 00 00 00 00 00 28), read MVP ABS, 0, 41"
        ),
        "{error}"
    );
    assert_eq!(faults.counts().corrupted_stores, 1);
    // Nothing was run or left in download mode.
    assert_eq!(value(&session, "GGP 129, 0").await, ReplyValue::Number(0));
}

#[tokio::test(start_paused = true)]
async fn the_corruption_is_caught_at_a_throttled_baud_rate_too() {
    let faults = FaultPlan::parse("corrupt-store=1").expect("parses");
    let session = connect_with(faults, Some(115_200)).await;
    let error = download(&session, &long_program(3), DownloadOptions::default())
        .await
        .unwrap_err();
    assert_eq!(error.address(), Some(0), "{error}");
}

#[tokio::test(start_paused = true)]
async fn cancelling_midway_leaves_download_mode_with_the_words_so_far() {
    let session = connect().await;
    let words = long_program(10);
    let cancel = Cancel::new();
    let canceller = cancel.clone();
    let error = download_program(
        &session,
        &words,
        DownloadOptions::default(),
        &cancel,
        &mut |p| {
            if p.phase == Phase::Storing && p.done == 3 {
                canceller.cancel();
            }
        },
    )
    .await
    .expect_err("cancelled");
    assert_eq!(
        error.cancelled(),
        Some(Progress {
            phase: Phase::Storing,
            done: 3,
            total: Some(10)
        })
    );
    assert!(
        error.to_string().contains("download mode was left"),
        "{error}"
    );
    assert_eq!(value(&session, "GGP 129, 0").await, ReplyValue::Number(0));
    assert_eq!(readmem(&session, 2).await, "MVP ABS, 0, 20");
    assert_eq!(
        readmem(&session, 3).await,
        "0 0 0 0",
        "word 3 was never sent"
    );
    // The session is free for the next transfer and for the user.
    assert_eq!(value(&session, "SAP 4, 0, 100").await, ReplyValue::None);
    download(&session, &words, DownloadOptions::default())
        .await
        .expect("a second download");
}

#[tokio::test(start_paused = true)]
async fn cancelling_the_verification_never_says_verified() {
    let session = connect().await;
    let cancel = Cancel::new();
    let canceller = cancel.clone();
    let error = download_program(
        &session,
        &long_program(6),
        DownloadOptions::default(),
        &cancel,
        &mut |p| {
            if p.phase == Phase::Verifying && p.done == 2 {
                canceller.cancel();
            }
        },
    )
    .await
    .unwrap_err();
    assert!(matches!(
        error.cancelled(),
        Some(Progress {
            phase: Phase::Verifying,
            done: 2,
            ..
        })
    ));
    assert!(error.to_string().contains("not verified"), "{error}");
}

#[tokio::test(start_paused = true)]
async fn a_dropped_download_still_leaves_download_mode() {
    let session = connect().await;
    let words = long_program(10);
    let (reached, at_word_3) = tokio::sync::oneshot::channel();
    let mut reached = Some(reached);
    let cancel = Cancel::new();
    let mut progress = |p: Progress| {
        if p.phase == Phase::Storing
            && p.done == 3
            && let Some(reached) = reached.take()
        {
            let _ = reached.send(());
        }
    };
    let transfer = download_program(
        &session,
        &words,
        DownloadOptions::default(),
        &cancel,
        &mut progress,
    );
    tokio::select! {
        _ = transfer => panic!("the download finished before word 3"),
        _ = at_word_3 => {}
    }
    // The future is gone; a task of its own sends 133. Until then, lines
    // the module would store are refused.
    let left = async {
        loop {
            match session.execute_line("GGP 129, 0").await {
                Ok(result) => break result.value,
                Err(SessionError::Refused { message, .. }) => {
                    assert!(message.contains("download mode"), "{message}");
                    tokio::time::sleep(Duration::from_millis(1)).await;
                }
                Err(e) => panic!("{e}"),
            }
        }
    };
    let mode = tokio::time::timeout(GIVE_UP_AFTER, left)
        .await
        .expect("left");
    assert_eq!(mode, ReplyValue::Number(0));
}

#[tokio::test(start_paused = true)]
async fn polling_is_paused_so_that_no_poll_is_stored_as_a_word() {
    let session = connect_with(FaultPlan::none(), Some(115_200)).await;
    // Always due: without the pause, the device task would send a poll
    // whenever the next word is not queued yet, and the module would store
    // it among the words.
    let cadence = PollCadence {
        fast: Duration::from_millis(1),
        slow: Duration::from_millis(1),
    };
    session.start_polling(cadence);
    let mut status = session.status();
    status.changed().await.expect("polling runs");
    let words = long_program(50);
    download(&session, &words, DownloadOptions::default())
        .await
        .expect("verified");
    assert_eq!(session.poll_cadence(), Some(cadence));
    let polls_before = session.device().counters().borrow().polls;
    tokio::time::sleep(Duration::from_millis(10)).await;
    assert!(
        session.device().counters().borrow().polls > polls_before,
        "polling resumed"
    );
}

#[tokio::test(start_paused = true)]
async fn user_lines_the_module_would_store_are_refused_during_a_download() {
    let session = connect().await;
    let (go, signal) = tokio::sync::oneshot::channel::<()>();
    let user = session.clone();
    let attempt = tokio::spawn(async move {
        let _ = signal.await;
        let store = user.execute_line("SAP 4, 0, 100").await;
        let read = user.execute_line("APPSTATUS").await;
        (store, read)
    });
    let mut go = Some(go);
    let words = long_program(10);
    download_with_progress(&session, &words, |p| {
        if p.phase == Phase::Storing
            && p.done == 2
            && let Some(go) = go.take()
        {
            let _ = go.send(());
        }
    })
    .await
    .expect("verified: the refused line never reached the module");
    let (store, read) = attempt.await.expect("the user task");
    let error = store.expect_err("refused");
    assert!(error.nothing_sent(), "{error}");
    assert!(error.to_string().contains("download mode"), "{error}");
    read.expect("135 is executed even in download mode");
}

async fn download_with_progress(
    session: &Session,
    words: &[ProgramWord],
    mut progress: impl FnMut(Progress) + Send,
) -> Result<TransferReport, TransferFailure> {
    download_program(
        session,
        words,
        DownloadOptions::default(),
        &Cancel::new(),
        &mut progress,
    )
    .await
}

#[tokio::test(start_paused = true)]
async fn an_emergency_stop_cancels_a_download_and_is_never_stored() {
    let session = connect().await;
    assert_eq!(value(&session, "ROR 0, 500").await, ReplyValue::None);
    let (go, signal) = tokio::sync::oneshot::channel::<()>();
    let stopper = session.clone();
    let stop = tokio::spawn(async move {
        let _ = signal.await;
        stopper.emergency_stop().await
    });
    let mut go = Some(go);
    let words = long_program(20);
    let error = download_with_progress(&session, &words, |p| {
        if p.phase == Phase::Storing
            && p.done == 4
            && let Some(go) = go.take()
        {
            let _ = go.send(());
        }
    })
    .await
    .expect_err("the stop cancels it");
    assert!(
        matches!(
            error.cancelled(),
            Some(Progress {
                phase: Phase::Storing,
                ..
            })
        ),
        "{error}"
    );
    stop.await.expect("the stop task").expect("stopped");
    assert_eq!(value(&session, "GGP 129, 0").await, ReplyValue::Number(0));
    assert_eq!(
        value(&session, "GAP 2, 0").await,
        ReplyValue::Number(0),
        "MST executed"
    );
    for address in 0..words.len() {
        let word = readmem(&session, address).await;
        assert!(!word.starts_with("MST"), "MST stored at {address}");
    }
}

#[tokio::test(start_paused = true)]
async fn run_starts_the_verified_program() {
    let session = connect().await;
    let words = program("SGP 42, 2, 1234\nSTOP\n");
    let report = download(
        &session,
        &words,
        DownloadOptions {
            run: true,
            autostart: false,
        },
    )
    .await
    .expect("verified");
    assert_eq!(report.fact("started"), Some(&FactValue::Flag(true)));
    let set = async {
        loop {
            if value(&session, "GGP 42, 2").await == ReplyValue::Number(1234) {
                break;
            }
            tokio::time::sleep(Duration::from_millis(1)).await;
        }
    };
    tokio::time::timeout(GIVE_UP_AFTER, set)
        .await
        .expect("the program set the variable");
}

#[tokio::test(start_paused = true)]
async fn without_run_the_program_does_not_start() {
    let session = connect().await;
    download(
        &session,
        &program("SGP 42, 2, 1234\nSTOP\n"),
        DownloadOptions::default(),
    )
    .await
    .expect("verified");
    tokio::time::sleep(Duration::from_millis(50)).await;
    assert_eq!(value(&session, "GGP 42, 2").await, ReplyValue::Number(0));
    assert_eq!(value(&session, "GGP 77, 0").await, ReplyValue::Number(0));
}

#[tokio::test(start_paused = true)]
async fn autostart_sets_gp77() {
    let session = connect().await;
    let report = download(
        &session,
        &program("STOP\n"),
        DownloadOptions {
            run: false,
            autostart: true,
        },
    )
    .await
    .expect("verified");
    assert_eq!(report.fact("autostart"), Some(&FactValue::Flag(true)));
    assert_eq!(value(&session, "GGP 77, 0").await, ReplyValue::Number(1));
}

#[tokio::test(start_paused = true)]
async fn a_running_program_is_stopped_and_reset_first() {
    let session = connect().await;
    download(
        &session,
        &program("Loop: WAIT TICKS, 0, 1\nJA Loop\n"),
        DownloadOptions::default(),
    )
    .await
    .expect("verified");
    value(&session, "RUNAPP").await;
    tokio::time::sleep(Duration::from_millis(5)).await;
    assert_eq!(value(&session, "GGP 128, 0").await, ReplyValue::Number(1));
    let report = download(&session, &program("STOP\n"), DownloadOptions::default())
        .await
        .expect("verified");
    assert_eq!(
        report.fact("stopped_program"),
        Some(&FactValue::Text("running".into()))
    );
    assert_ne!(value(&session, "GGP 128, 0").await, ReplyValue::Number(1));
    assert_eq!(
        value(&session, "GGP 130, 0").await,
        ReplyValue::Number(0),
        "PC reset"
    );
}

#[tokio::test(start_paused = true)]
async fn an_older_longer_program_leaves_its_tail_and_the_report_says_so() {
    let session = connect().await;
    download(&session, &long_program(8), DownloadOptions::default())
        .await
        .expect("verified");
    let report = download(&session, &long_program(3), DownloadOptions::default())
        .await
        .expect("verified");
    assert_eq!(report.fact("leftover_from"), Some(&FactValue::Number(3)));
    // The upload reads until the first blank word, tail included; a given
    // length reads the new program alone.
    assert_eq!(upload(&session, UploadExtent::UntilBlank).await.len(), 8);
    assert_eq!(
        upload(&session, UploadExtent::Units(3)).await,
        long_program(3)
    );
}

#[tokio::test(start_paused = true)]
async fn upload_all_reads_the_whole_memory_and_drops_the_blank_tail() {
    let session = connect().await;
    let words = long_program(5);
    download(&session, &words, DownloadOptions::default())
        .await
        .expect("verified");
    let mut last = None;
    let (read, report) = upload_program(&session, UploadExtent::All, &Cancel::new(), &mut |p| {
        last = Some(p)
    })
    .await
    .expect("upload");
    assert_eq!(read, words);
    assert_eq!(report.transactions, 2048);
    assert_eq!(
        last,
        Some(Progress {
            phase: Phase::Reading,
            done: 2048,
            total: Some(2048)
        })
    );
    assert!(upload(&session, UploadExtent::Units(0)).await.is_empty());
}

#[tokio::test(start_paused = true)]
async fn an_uploaded_program_disassembles_to_source_that_reassembles_to_it() {
    let session = connect().await;
    for name in [
        "s3_5_6_4_timer_interrupt_symbolic.tmc",
        "s8_6_host_routines.tmc",
        "s3_6_43_djnz_loop.tmc",
    ] {
        let words = example(name);
        download(&session, &words, DownloadOptions::default())
            .await
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let uploaded = upload(&session, UploadExtent::Units(words.len())).await;
        assert_eq!(uploaded, words, "{name}");
        let source = disassemble(&uploaded);
        assert_eq!(program(&source), uploaded, "{name}:\n{source}");
    }
}

#[tokio::test(start_paused = true)]
async fn protected_programs_are_refused_with_the_reason() {
    let session = connect().await;
    download(&session, &long_program(2), DownloadOptions::default())
        .await
        .expect("verified");
    value(&session, "SGP 81, 0, 2").await;
    let error = download(&session, &long_program(2), DownloadOptions::default())
        .await
        .unwrap_err();
    let message = error.to_string();
    assert!(
        message.starts_with("cannot enter download mode (132)"),
        "{message}"
    );
    assert!(message.contains("status 5"), "{message}");
    assert!(message.contains("GP81"), "{message}");
    // Not left in download mode: the user's lines go through.
    assert_eq!(value(&session, "SAP 4, 0, 100").await, ReplyValue::None);

    value(&session, "SGP 81, 0, 3").await;
    let error = upload_program(
        &session,
        UploadExtent::UntilBlank,
        &Cancel::new(),
        &mut |_| {},
    )
    .await
    .unwrap_err();
    assert_eq!(error.address(), Some(0));
    assert!(error.to_string().contains("GP81"), "{error}");
}

#[tokio::test(start_paused = true)]
async fn an_image_with_a_control_command_sends_nothing() {
    let session = connect().await;
    let mut words = long_program(3);
    words.insert(
        1,
        ProgramWord {
            opcode: 133,
            kind: 0,
            motor_bank: 0,
            value: 0,
        },
    );
    let error = download(&session, &words, DownloadOptions::default())
        .await
        .unwrap_err();
    assert!(error.nothing_sent());
    assert_eq!(error.address(), Some(1));
    assert!(error.to_string().ends_with("nothing was sent"), "{error}");
    assert_eq!(session.device().counters().borrow().transactions, 0);
}

#[tokio::test(start_paused = true)]
async fn one_transfer_at_a_time() {
    let session = connect().await;
    let (go, signal) = tokio::sync::oneshot::channel::<()>();
    let other = session.clone();
    let second = tokio::spawn(async move {
        let _ = signal.await;
        upload_program(&other, UploadExtent::Units(1), &Cancel::new(), &mut |_| {})
            .await
            .map(|(words, _)| words)
    });
    let mut go = Some(go);
    download_with_progress(&session, &long_program(5), |p| {
        if p.done == 1
            && let Some(go) = go.take()
        {
            let _ = go.send(());
        }
    })
    .await
    .expect("verified");
    let error = second.await.expect("task").unwrap_err();
    assert_eq!(error, TransferFailure::busy());
}

/// A download whose 133 is lost with the link: the session stays marked
/// as in download mode once the link is back.
async fn stranded() -> Session {
    let words = long_program(3);
    // GP128, 131, 132 and the words get through; the link is cut at 133.
    let faults =
        FaultPlan::parse(&format!("disconnect-after={}", 3 + words.len())).expect("parses");
    let session = connect_with(faults, None).await;
    let error = download(&session, &words, DownloadOptions::default())
        .await
        .expect_err("133 was lost");
    let message = error.to_string();
    assert!(
        message.starts_with("cannot leave download mode (133)"),
        "{message}"
    );
    assert!(message.contains("send ENDDOWNLOAD"), "{message}");
    // 135 is executed in download mode: it is let through, and answers
    // once the link is back.
    let back = async {
        while session.execute_line("APPSTATUS").await.is_err() {
            tokio::time::sleep(Duration::from_millis(10)).await;
        }
    };
    tokio::time::timeout(GIVE_UP_AFTER, back)
        .await
        .expect("reconnected");
    let refused = session.execute_line("SAP 4, 0, 100").await.unwrap_err();
    assert!(refused.nothing_sent(), "{refused}");
    session
}

#[tokio::test(start_paused = true)]
async fn enddownload_by_hand_ends_a_stranded_download_mode() {
    let session = stranded().await;
    assert_eq!(value(&session, "ENDDOWNLOAD").await, ReplyValue::None);
    assert_eq!(value(&session, "SAP 4, 0, 100").await, ReplyValue::None);
    assert_eq!(value(&session, "GAP 4, 0").await, ReplyValue::Number(100));
}

#[tokio::test(start_paused = true)]
async fn the_emergency_stop_leaves_a_stranded_download_mode_first() {
    let session = stranded().await;
    let results = session.emergency_stop_lines().await;
    let sent: Vec<String> = results
        .iter()
        .map(|r| r.as_ref().expect("sent").line.clone())
        .collect();
    // Download mode was left before the MST: it was executed, not stored.
    assert_eq!(sent, ["ENDDOWNLOAD", "MST 0", "STOPAPP", "MST 0"]);
    // The sixth request of this connection, the last before the fault
    // cuts it again.
    assert_eq!(value(&session, "SAP 4, 0, 100").await, ReplyValue::None);
}

/// The manual's first program (§2.4) downloaded with `run`: the motor
/// turns left (ROL), then travels between ±512000; the session's polled
/// status sees both, through the device task like the console's gauges.
#[tokio::test(start_paused = true)]
async fn the_first_program_of_the_manual_moves_the_motor_seen_by_polling() {
    let session = connect().await;
    let words = example("s2_4_first_program.tmc");
    let report = download(
        &session,
        &words,
        DownloadOptions {
            run: true,
            autostart: false,
        },
    )
    .await
    .expect("verified");
    assert_eq!(report.fact("started"), Some(&FactValue::Flag(true)));
    session.start_polling(PollCadence::default());
    let status = session.status();
    let position_seen = |wanted: fn(i64) -> bool| {
        let mut status = status.clone();
        async move {
            loop {
                let position = status.borrow_and_update().first().and_then(|a| a.position);
                if position.is_some_and(wanted) {
                    return;
                }
                status.changed().await.expect("the session lives");
            }
        }
    };
    tokio::time::timeout(GIVE_UP_AFTER, position_seen(|p| p < -1000))
        .await
        .expect("ROL 0, 1000 turns the motor left");
    tokio::time::timeout(GIVE_UP_AFTER, position_seen(|p| p > 100_000))
        .await
        .expect("MVP ABS, 0, 512000 moves it right");
}
