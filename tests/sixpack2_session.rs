//! The SIXpack 2 end to end in one process: the family's console lines
//! through the unchanged session and device task to the real simulator
//! (`--sim sixpack2`), on tokio's paused clock with the wire time of
//! 19200 Bd. A ramp is sent, unanswered, and read back with `$20` until
//! the motor is inactive at its target; a `$28` with a wait mask waits
//! while the polls go on and answers once its motor is idle, and the
//! emergency stop does not wait for it.

mod session_support;

use std::sync::{Arc, Mutex};
use std::time::Duration;

use axterm::families::find_family;
use axterm::link::LinkSpec;
use axterm::session::{PollCadence, ReplyValue, Session, SessionOptions};
use axterm::sim::faults::FaultPlan;
use axterm::sim::{SimOptions, sixpack2};
use session_support::wait_for;

async fn connect() -> Session {
    let controller = (sixpack2::KIND.build)(&SimOptions {
        address: None,
        eeprom_file: None,
    });
    let spec = LinkSpec::Sim {
        kind: "sixpack2".into(),
        sim: Arc::new(Mutex::new(controller)),
        baud: Some(19200),
        faults: FaultPlan::none(),
    };
    let family = find_family("sixpack2").expect("registered");
    Session::connect(spec, family, SessionOptions::default())
        .await
        .expect("the link opens")
}

async fn read(session: &Session, line: &str) -> String {
    match session.execute_line(line).await {
        Ok(result) => result.value.to_string(),
        Err(e) => panic!("{line}: {e}"),
    }
}

#[tokio::test(start_paused = true)]
async fn a_ramp_is_sent_unanswered_and_read_back_until_the_motor_is_inactive_at_its_target() {
    let session = connect().await;
    let sent = session
        .execute_line("StartRamp 0 10000")
        .await
        .expect("written");
    assert_eq!(sent.value, ReplyValue::Text("sent".into()));
    assert!(sent.reply.is_empty(), "a ramp is never acknowledged (§7)");
    assert_eq!(
        read(&session, "GetPositionAndActivity 0")
            .await
            .split(' ')
            .nth(1),
        Some("action=ramp")
    );
    let mut reads = 0;
    let last = loop {
        let value = read(&session, "GetPositionAndActivity 0").await;
        if value.contains("action=inactive") {
            break value;
        }
        reads += 1;
        assert!(reads < 10_000, "the ramp never ended: {value}");
        tokio::time::sleep(Duration::from_millis(20)).await;
    };
    assert_eq!(last, "posact=10000 action=inactive stop=0");
    assert!(
        reads > 10,
        "a ramp of 10000 µsteps takes a while: {reads} reads"
    );
}

#[tokio::test(start_paused = true)]
async fn a_waited_28_lets_the_polls_go_on_and_answers_once_its_motor_is_idle() {
    let session = connect().await;
    session.start_polling(PollCadence::default());
    session
        .execute_line("StartRamp 1 40000")
        .await
        .expect("written");
    let waiting = {
        let session = session.clone();
        tokio::spawn(async move { session.execute_line("GetAllActivities 0 1").await })
    };
    // Meanwhile the polls read motor 1 on its way.
    let axes = wait_for(&session, |axes| {
        axes[1].position.is_some_and(|p| p > 1000 && p < 40_000)
    })
    .await;
    assert!(!waiting.is_finished(), "{:?}", axes[1]);
    let answer = waiting.await.expect("joined").expect("answered");
    assert_eq!(
        answer.value.to_string(),
        "m0=inactive m1=inactive m2=inactive m3=inactive m4=inactive m5=inactive"
    );
    assert_eq!(answer.reply.first(), Some(&0x28));
    assert_eq!(
        read(&session, "GetPositionAndActivity 1").await,
        "posact=40000 action=inactive stop=0"
    );
}

#[tokio::test(start_paused = true)]
async fn the_emergency_stop_does_not_wait_for_a_waited_28() {
    let session = connect().await;
    session
        .execute_line("ConstantRotation 2 300")
        .await
        .expect("written");
    let waiting = {
        let session = session.clone();
        tokio::spawn(async move { session.execute_line("GetAllActivities 0 2").await })
    };
    tokio::time::sleep(Duration::from_millis(500)).await;
    assert!(!waiting.is_finished(), "a rotation never ends by itself");
    let results = session.emergency_stop_lines().await;
    assert_eq!(results.len(), 18);
    assert!(results.iter().all(Result::is_ok));
    let answer = waiting
        .await
        .expect("joined")
        .expect("answered after the stop");
    assert!(
        answer
            .value
            .to_string()
            .starts_with("m0=inactive m1=inactive m2=inactive"),
        "{}",
        answer.value
    );
}

#[tokio::test(start_paused = true)]
async fn settings_written_are_kept_until_the_unit_reports_a_reset() {
    use axterm::protocol::parameters::Scope;
    use axterm::protocol::settings::KnownSetting;
    let session = connect().await;
    // Power-on: the reset flag is set; reading it clears it (§7.4).
    assert!(session.identify().await.expect("$43").contains("reset=1"));
    let settings = session.settings();
    session
        .execute_line("SetAMaxVMax 0 100 300")
        .await
        .expect("written");
    session
        .execute_line("SetPeakCurrent 2 200")
        .await
        .expect("written");
    {
        let cache = settings.borrow();
        assert_eq!(cache.value(Scope::Axis(0), 0x1401), Some(100));
        assert_eq!(cache.value(Scope::Axis(0), 0x1402), Some(300));
        assert_eq!(
            cache.value(Scope::Axis(3), 0x1001),
            Some(200),
            "the pair's current (§7.1)"
        );
    }
    assert!(session.identify().await.expect("$43").contains("reset=0"));
    assert_eq!(settings.borrow().value(Scope::Axis(0), 0x1402), Some(300));
    session
        .execute_line("HardwareReset")
        .await
        .expect("written");
    assert_eq!(
        settings.borrow().get(Scope::Axis(0), 0x1402),
        Some(&KnownSetting::Stale {
            was: 300,
            why: "HardwareReset was sent (§7.4)".into()
        })
    );
    // The unit is deaf for a second, then comes back with its flag set.
    tokio::time::sleep(Duration::from_millis(1500)).await;
    session
        .execute_line("SetAMaxVMax 1 50 200")
        .await
        .expect("written");
    assert!(session.identify().await.expect("$43").contains("reset=1"));
    assert_eq!(
        settings.borrow().get(Scope::Axis(1), 0x1402),
        Some(&KnownSetting::Stale {
            was: 200,
            why: "the unit reported a reset ($43 reset flag, §7.4)".into()
        }),
        "a reset flag says a reset came after the flag was last read"
    );
}

#[tokio::test(start_paused = true)]
async fn the_reference_lamp_follows_the_null_positive_flag_written() {
    let session = connect().await;
    let home = |session: &Session| session.status().borrow()[0].home_switch;
    // Power-on: the carriage stands off its opener switch, whose closed
    // contact pulls the input low; "the reference inputs are inverted"
    // (§7.3), so the bit reads 1: active for the factory NullPositive = 0
    // (§6.4.2).
    session
        .execute_line("GetInputValues 0")
        .await
        .expect("read");
    assert_eq!(home(&session), Some(true));
    // With NullPositive set the switch is active high (§5.5.2.3): the same
    // level is the inactive state, on the gauge as in the unit.
    session
        .execute_line("SetMotorParameters 0 10000 NullLeft,NullPositive")
        .await
        .expect("written");
    session
        .execute_line("GetInputValues 0")
        .await
        .expect("read");
    assert_eq!(home(&session), Some(false));
    // Forgotten at a reset: the factory reading again.
    session
        .execute_line("HardwareReset")
        .await
        .expect("written");
    tokio::time::sleep(Duration::from_millis(1500)).await;
    session
        .execute_line("GetInputValues 0")
        .await
        .expect("read");
    assert_eq!(home(&session), Some(true));
}
