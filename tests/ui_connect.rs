//! The connect screen: lists recent connections, every built-in simulator,
//! the serial ports found and a TCP bridge; builds the connection options
//! from the form (checked before anything is opened); remembers what
//! opened (in a temporary data directory here); and, through the real
//! event loop, opens the console on the connection chosen.

mod panes_support;
mod ui_support;

use std::io;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use axterm::device::{DeviceEvent, LinkState, TrafficRecord};
use axterm::families::find_family;
use axterm::link::ports::{ListedPort, PortInfo, PortKind, UsbIdentity};
use axterm::protocol::Family;
use axterm::session::{AxisFlag, AxisInfo, AxisStatus, LineResult, PollCadence, SessionError};
use axterm::ui::app::{self, App, AppEvent, Connector, Controller, Effect, Pending};
use axterm::ui::axes::AxesPane;
use axterm::ui::command::CommandPane;
use axterm::ui::connect::ConnectPane;
use axterm::ui::connect::recent::{RECENT_FILE, Recents};
use axterm::ui::keymap::Keymap;
use axterm::ui::pane::{Notice, Pane};
use axterm::ui::theme::Theme;
use panes_support::draw;
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers};
use tokio::sync::{broadcast, mpsc, watch};
use ui_support::{key, key_with, snapshot, type_text};

static SCANS: AtomicUsize = AtomicUsize::new(0);

fn two_devices() -> Vec<PortInfo> {
    vec![
        PortInfo {
            path: "/dev/ttyACM0".into(),
            kind: PortKind::Usb(UsbIdentity {
                vid: 0x2a3c,
                pid: 0x0100,
                manufacturer: Some("Trinamic".into()),
                product: Some("StepRocker".into()),
                ..UsbIdentity::default()
            }),
        },
        PortInfo {
            path: "/dev/ttyUSB0".into(),
            kind: PortKind::Other,
        },
    ]
}

fn two_ports() -> io::Result<Vec<ListedPort>> {
    SCANS.fetch_add(1, Ordering::SeqCst);
    Ok(two_devices()
        .into_iter()
        .map(|port| ListedPort {
            port,
            by_id: Vec::new(),
        })
        .collect())
}

/// The same ports, the second with a stable name in /dev/serial/by-id.
fn two_ports_one_by_id() -> io::Result<Vec<ListedPort>> {
    Ok(two_devices()
        .into_iter()
        .map(|port| {
            let by_id = if port.path == "/dev/ttyUSB0" {
                vec!["/dev/serial/by-id/usb-FTDI_FT232R_USB_UART_A50285BI-if00-port0".into()]
            } else {
                Vec::new()
            };
            ListedPort { port, by_id }
        })
        .collect())
}

fn no_sysfs() -> io::Result<Vec<ListedPort>> {
    Err(io::Error::new(io::ErrorKind::NotFound, "no /sys/class/tty"))
}

fn console(data: &Path, lister: axterm::ui::connect::PortLister) -> App {
    let panes: Vec<Box<dyn Pane>> = vec![
        Box::new(CommandPane::new(None)),
        Box::new(AxesPane::new()),
        Box::new(ConnectPane::new(Some(data), lister)),
    ];
    let theme = Theme::builtin("dark").expect("theme");
    let keymap = Keymap::builtin("default").expect("keymap");
    let mut app = App::new(panes, theme, keymap);
    app.focus("connect");
    app
}

fn text(app: &mut App, w: u16, h: u16) -> String {
    draw(app, w, h).0.join("\n")
}

fn connects(effects: &[Effect]) -> Option<Vec<String>> {
    effects.iter().find_map(|e| match e {
        Effect::Connect(args) => Some(args.clone()),
        _ => None,
    })
}

/// Move the selection from the first simulator to the last one: the
/// rows below count from there, whatever simulators are registered.
fn past_the_other_simulators(app: &mut App) {
    for _ in 1..axterm::families::kinds().count() {
        app.handle(key(KeyCode::Down));
    }
}

fn args(text: &str) -> Vec<String> {
    text.split_whitespace().map(str::to_string).collect()
}

fn tmcl_connected() -> AppEvent {
    let family = find_family("tmcl").expect("tmcl");
    AppEvent::Connected(snapshot(family.console.axes().to_vec()))
}

#[test]
fn the_screen_lists_simulators_ports_and_tcp_at_80x24_and_large() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = console(dir.path(), two_ports);
    for (w, h) in [(80, 24), (200, 50)] {
        let all = text(&mut app, w, h);
        assert!(all.contains("Connect to a controller"), "{all}");
        assert!(all.contains("Simulators (no hardware needed)"), "{all}");
        assert!(
            all.contains("▶ sim tmcm1110") && all.contains("TMCM-1110 StepRocker"),
            "{all}"
        );
        assert!(
            all.contains("/dev/ttyACM0") && all.contains("usb 2a3c:0100  Trinamic  StepRocker"),
            "{all}"
        );
        assert!(all.contains("/dev/ttyUSB0"), "{all}");
        assert!(all.contains("tcp 127.0.0.1:4001"), "{all}");
        // A simulator is highlighted: no wire time unless asked for.
        assert!(
            all.contains("protocol [tmcl]  baud [none]  address [default]"),
            "{all}"
        );
    }
}

/// Each simulator highlighted, the form shows the protocol it speaks and
/// no baud rate, not the form's values for ports; on a port, the form's
/// again (issue 19, point 9: `protocol [tmcl] baud [9600]` beside sim
/// sixpack2).
#[test]
fn the_form_shows_what_the_highlighted_choice_connects_with() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = console(dir.path(), two_ports);
    for kind in axterm::families::kinds() {
        let family = axterm::families::family_of(kind).expect("a family");
        let all = text(&mut app, 100, 30);
        assert!(all.contains(&format!("▶ sim {}", kind.name)), "{all}");
        assert!(
            all.contains(&format!("protocol [{}]  baud [none]", family.name)),
            "{}: {all}",
            kind.name
        );
        app.handle(key(KeyCode::Down));
    }
    let all = text(&mut app, 100, 30);
    assert!(all.contains("▶ /dev/ttyACM0"), "{all}");
    assert!(all.contains("protocol [tmcl]  baud [9600]"), "{all}");
}

#[test]
fn choosing_the_simulator_connects_remembers_it_and_opens_the_console() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = console(dir.path(), two_ports);
    let effects = app.handle(key(KeyCode::Enter));
    assert_eq!(connects(&effects), Some(args("--sim tmcm1110")));
    assert!(text(&mut app, 80, 24).contains("connecting: --sim tmcm1110"));
    app.handle(tmcl_connected());
    assert_eq!(app.focused(), Some("command"));
    let recents = Recents::load(Some(dir.path()));
    assert_eq!(recents.entries(), [args("--sim tmcm1110")]);
    // Next time it is offered first, under Recent.
    let mut again = console(dir.path(), two_ports);
    let all = text(&mut again, 80, 24);
    assert!(
        all.contains("Recent") && all.contains("▶ --sim tmcm1110"),
        "{all}"
    );
    assert_eq!(
        connects(&again.handle(key(KeyCode::Enter))),
        Some(args("--sim tmcm1110"))
    );
}

#[test]
fn a_port_takes_the_protocol_baud_and_address_of_the_form() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = console(dir.path(), two_ports);
    past_the_other_simulators(&mut app);
    app.handle(key(KeyCode::Down));
    app.handle(key(KeyCode::Down));
    // Tab to the baud field, then the address.
    app.handle(key(KeyCode::Tab));
    app.handle(key(KeyCode::Tab));
    app.handle(key_with(KeyCode::Char('u'), KeyModifiers::CONTROL));
    type_text(&mut app, "115200");
    app.handle(key(KeyCode::Tab));
    type_text(&mut app, "3");
    assert!(text(&mut app, 80, 24).contains("baud [115200]  address [3]"));
    let effects = app.handle(key(KeyCode::Enter));
    assert_eq!(
        connects(&effects),
        Some(args(
            "--port /dev/ttyUSB0 --protocol tmcl --baud 115200 --address 3"
        ))
    );
}

#[test]
fn a_port_with_a_by_id_name_shows_it_and_is_opened_by_it() {
    // The by-id name stays when the adapter comes back as another ttyUSB:
    // the connection (and the recent one remembered) uses it.
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = console(dir.path(), two_ports_one_by_id);
    let all = text(&mut app, 120, 30);
    assert!(
        all.contains("/dev/ttyUSB0") && all.contains("by-id usb-FTDI_FT232R_USB_UART_A50285BI"),
        "{all}"
    );
    past_the_other_simulators(&mut app);
    app.handle(key(KeyCode::Down));
    app.handle(key(KeyCode::Down));
    let effects = app.handle(key(KeyCode::Enter));
    assert_eq!(
        connects(&effects),
        Some(args(
            "--port /dev/serial/by-id/usb-FTDI_FT232R_USB_UART_A50285BI-if00-port0 --protocol tmcl --baud 9600"
        ))
    );
}

#[test]
fn a_bad_address_or_baud_opens_nothing() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = console(dir.path(), two_ports);
    past_the_other_simulators(&mut app);
    app.handle(key(KeyCode::Down));
    for _ in 0..3 {
        app.handle(key(KeyCode::Tab));
    }
    type_text(&mut app, "300");
    assert_eq!(connects(&app.handle(key(KeyCode::Enter))), None);
    assert!(
        text(&mut app, 100, 24)
            .contains("address 300: give a number from 0 to 255; nothing opened")
    );
    app.handle(key(KeyCode::Esc));
    app.handle(key(KeyCode::Tab));
    app.handle(key(KeyCode::Tab));
    app.handle(key_with(KeyCode::Char('u'), KeyModifiers::CONTROL));
    type_text(&mut app, "fast");
    assert_eq!(connects(&app.handle(key(KeyCode::Enter))), None);
    assert!(text(&mut app, 100, 24).contains("baud fast"));
}

#[test]
fn the_baud_rate_follows_the_familys_factory_rate_unless_typed() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = console(dir.path(), two_ports);
    past_the_other_simulators(&mut app);
    app.handle(key(KeyCode::Down));
    app.handle(key(KeyCode::Tab));
    // tmcl, cmd4cr, sixpack2.
    app.handle(key(KeyCode::Right));
    app.handle(key(KeyCode::Right));
    assert!(
        text(&mut app, 80, 24).contains("protocol [sixpack2]  baud [19200]"),
        "SIXpack 2: 19200 Bd with no jumpers (§6.1.1)"
    );
    assert_eq!(
        connects(&app.handle(key(KeyCode::Enter))),
        Some(args("--port /dev/ttyACM0 --protocol sixpack2 --baud 19200"))
    );
    // From the protocol to the baud field.
    app.handle(key(KeyCode::Tab));
    app.handle(key_with(KeyCode::Char('u'), KeyModifiers::CONTROL));
    type_text(&mut app, "57600");
    app.handle(key(KeyCode::Esc));
    app.handle(key(KeyCode::Tab));
    app.handle(key(KeyCode::Left));
    assert!(
        text(&mut app, 80, 24).contains("protocol [cmd4cr]  baud [57600]"),
        "a rate typed stays"
    );
}

#[test]
fn a_familys_link_option_is_chosen_on_the_form() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = console(dir.path(), two_ports);
    assert!(
        !text(&mut app, 100, 24).contains("link ["),
        "tmcm1110 has no link option"
    );
    let sixpack2 = axterm::families::kinds()
        .position(|k| k.name == "sixpack2")
        .expect("a sixpack2 simulator");
    for _ in 0..sixpack2 {
        app.handle(key(KeyCode::Down));
    }
    let shown = text(&mut app, 100, 24);
    assert!(shown.contains("link [framing=auto]"), "{shown}");
    assert_eq!(
        connects(&app.handle(key(KeyCode::Enter))),
        Some(args("--sim sixpack2"))
    );
    // Protocol, baud, address, tcp, link.
    for _ in 0..5 {
        app.handle(key(KeyCode::Tab));
    }
    app.handle(key(KeyCode::Right));
    let shown = text(&mut app, 100, 24);
    assert!(
        shown.contains("link [framing=cmd8]") && shown.contains("8 bytes CMD P0..P6"),
        "{shown}"
    );
    app.handle(key(KeyCode::Tab));
    assert_eq!(
        connects(&app.handle(key(KeyCode::Enter))),
        Some(args("--sim sixpack2 --link-option framing=cmd8"))
    );
}

#[test]
fn tcp_takes_the_host_typed() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = console(dir.path(), two_ports);
    // sim, ACM0, USB0, rescan, tcp.
    past_the_other_simulators(&mut app);
    for _ in 0..4 {
        app.handle(key(KeyCode::Down));
    }
    for _ in 0..4 {
        app.handle(key(KeyCode::Tab));
    }
    app.handle(key_with(KeyCode::Char('u'), KeyModifiers::CONTROL));
    app.handle(key(KeyCode::End));
    app.handle(key_with(KeyCode::Char('u'), KeyModifiers::CONTROL));
    type_text(&mut app, "rig.local:4001");
    assert_eq!(
        connects(&app.handle(key(KeyCode::Enter))),
        Some(args("--tcp rig.local:4001 --protocol tmcl --baud 9600"))
    );
}

#[test]
fn a_failed_connection_is_shown_and_not_remembered() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = console(dir.path(), two_ports);
    past_the_other_simulators(&mut app);
    app.handle(key(KeyCode::Down));
    app.handle(key(KeyCode::Enter));
    // The reason and its advice, as a failed opening gives them.
    app.handle(AppEvent::Notice(Notice::error(
        ":connect: cannot open /dev/ttyACM0 at 9600 Bd: permission denied\n  \
         crw-rw---- root dialout /dev/ttyACM0   (`ls -l /dev/ttyACM0`)\n  \
         you (alice) are not in group dialout, which may read and write it\n  \
         fix: `sudo usermod -aG dialout $USER`, then log out and in again",
    )));
    let all = text(&mut app, 100, 24);
    assert!(all.contains("permission denied"), "{all}");
    // Each line of the advice on a line of its own.
    for line in [
        "  crw-rw---- root dialout /dev/ttyACM0   (`ls -l /dev/ttyACM0`)",
        "  you (alice) are not in group dialout, which may read and write it",
        "  fix: `sudo usermod -aG dialout $USER`, then log out and in again",
    ] {
        assert!(all.contains(&format!("│{line}")), "{line}: {all}");
    }
    assert_eq!(app.focused(), Some("connect"));
    assert!(!dir.path().join(RECENT_FILE).exists());
}

#[test]
fn ports_are_looked_for_again_on_request_and_a_listing_failure_is_said() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = console(dir.path(), two_ports);
    text(&mut app, 80, 24);
    let before = SCANS.load(Ordering::SeqCst);
    past_the_other_simulators(&mut app);
    for _ in 0..3 {
        app.handle(key(KeyCode::Down));
    }
    assert!(text(&mut app, 80, 24).contains("▶ ↻ look for serial ports again"));
    app.handle(key(KeyCode::Enter));
    assert!(SCANS.load(Ordering::SeqCst) > before);
    assert!(text(&mut app, 80, 24).contains("2 serial port(s) found"));
    let mut broken = console(dir.path(), no_sysfs);
    let all = text(&mut broken, 80, 24);
    assert!(
        all.contains("cannot list serial ports: no /sys/class/tty"),
        "{all}"
    );
    assert!(all.contains("sim tmcm1110"), "{all}");
}

#[test]
fn a_connection_typed_as_connect_is_remembered_too() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = console(dir.path(), two_ports);
    app.focus("command");
    type_text(&mut app, ":connect --sim tmcm1110 --address 2");
    let effects = app.handle(key(KeyCode::Enter));
    assert_eq!(connects(&effects), Some(args("--sim tmcm1110 --address 2")));
    app.handle(tmcl_connected());
    assert_eq!(
        Recents::load(Some(dir.path())).entries(),
        [args("--sim tmcm1110 --address 2")]
    );
    // Connected, the screen says so and offers to switch.
    app.focus("connect");
    assert!(text(&mut app, 100, 24).contains("Connected to sim tmcm1110 #1"));
}

/// Just enough of a controller for the loop to open the console on it.
struct Quiet {
    status: watch::Sender<Vec<AxisStatus>>,
    link: watch::Sender<LinkState>,
    identity: watch::Sender<Option<String>>,
}

impl Controller for Quiet {
    fn family(&self) -> &'static Family {
        find_family("tmcl").expect("tmcl")
    }
    fn address(&self) -> u8 {
        1
    }
    fn axes(&self) -> Vec<AxisInfo> {
        self.family().console.axes().to_vec()
    }
    fn link_name(&self) -> String {
        "sim tmcm1110".into()
    }
    fn status(&self) -> watch::Receiver<Vec<AxisStatus>> {
        self.status.subscribe()
    }
    fn link_state(&self) -> watch::Receiver<LinkState> {
        self.link.subscribe()
    }
    fn identity(&self) -> watch::Receiver<Option<String>> {
        self.identity.subscribe()
    }
    fn traffic(&self) -> Option<broadcast::Receiver<TrafficRecord>> {
        None
    }
    fn events(&self) -> Option<broadcast::Receiver<DeviceEvent>> {
        None
    }
    fn execute(&self, line: String) -> Pending<Result<LineResult, SessionError>> {
        Box::pin(async move {
            Err(SessionError::Refused {
                line,
                message: "quiet".into(),
            })
        })
    }
    fn emergency_stop(&self) -> Pending<Vec<Result<LineResult, SessionError>>> {
        Box::pin(async { Vec::new() })
    }
    fn set_polling(&self, _cadence: Option<PollCadence>) {}
    fn acknowledge_errors(&self, _axis: usize, _seen: &[AxisFlag]) {}
    fn with_address(&self, _address: u8) -> Arc<dyn Controller> {
        quiet()
    }
}

fn quiet() -> Arc<dyn Controller> {
    Arc::new(Quiet {
        status: watch::channel(vec![AxisStatus::default()]).0,
        link: watch::channel(LinkState::Connected {
            link: "sim tmcm1110".into(),
        })
        .0,
        identity: watch::channel(None).0,
    })
}

#[tokio::test(start_paused = true)]
async fn through_the_event_loop_the_chosen_connection_opens_the_console() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = console(dir.path(), two_ports);
    let asked = Arc::new(Mutex::new(Vec::new()));
    let seen = Arc::clone(&asked);
    let connector: Connector = Box::new(move |args: Vec<String>| {
        if let Ok(mut seen) = seen.lock() {
            seen.push(args);
        }
        Box::pin(async { Ok(quiet()) })
    });
    let (keys, input) = mpsc::unbounded_channel();
    let (drawn_tx, mut drawn) = mpsc::unbounded_channel::<String>();
    let mut terminal = Terminal::new(TestBackend::new(100, 30)).expect("test backend");
    let mut draw = move |app: &mut App| -> io::Result<()> {
        let Ok(_) = terminal.draw(|f| app.render(f));
        let buffer = terminal.backend().buffer();
        let text: Vec<String> = (0..30)
            .map(|y| {
                (0..100)
                    .map(|x| buffer[(x, y)].symbol().to_string())
                    .collect()
            })
            .collect();
        let _ = drawn_tx.send(text.join("\n"));
        Ok(())
    };
    let driver = async move {
        let until = async |drawn: &mut mpsc::UnboundedReceiver<String>, needle: &str| {
            let found = tokio::time::timeout(Duration::from_secs(600), async {
                while let Some(frame) = drawn.recv().await {
                    if frame.contains(needle) {
                        return frame;
                    }
                }
                String::new()
            })
            .await;
            found.unwrap_or_else(|_| panic!("never showed {needle}"))
        };
        until(&mut drawn, "Connect to a controller").await;
        let _ = keys.send(Event::Key(KeyEvent::new(
            KeyCode::Enter,
            KeyModifiers::NONE,
        )));
        let frame = until(&mut drawn, "sim tmcm1110 #1 connected").await;
        assert!(frame.contains("┌ 1 Command │"), "{frame}");
        let _ = keys.send(Event::Key(KeyEvent::new(
            KeyCode::F(10),
            KeyModifiers::NONE,
        )));
    };
    let looping = app::run(&mut app, None, connector, input, None, &mut draw);
    let (result, ()) = tokio::join!(looping, driver);
    result.expect("the loop ends cleanly");
    assert_eq!(app.focused(), Some("command"));
    assert_eq!(
        asked.lock().map(|a| a.clone()).unwrap_or_default(),
        [args("--sim tmcm1110")]
    );
    assert_eq!(
        Recents::load(Some(dir.path())).entries(),
        [args("--sim tmcm1110")]
    );
}

#[test]
fn connection_options_name_their_protocol_family() {
    use axterm::ui::connect::family_of_args;
    let name = |text: &str| family_of_args(&args(text)).map(|f| f.name);
    assert_eq!(name("--sim tmcm1110"), Some("tmcl"));
    assert_eq!(name("--sim=tmcm1110 --address 3"), Some("tmcl"));
    assert_eq!(name("--port /dev/ttyUSB0 --protocol tmcl"), Some("tmcl"));
    assert_eq!(name("--tcp 127.0.0.1:4001 --protocol=TMCL"), Some("tmcl"));
    // As on the command line: no protocol and no simulator is TMCL.
    assert_eq!(name("--port /dev/ttyUSB0"), Some("tmcl"));
    assert_eq!(name("--port /dev/ttyUSB0 --protocol klingon"), None);
    assert_eq!(name("--sim nosuch"), None);
}

/// The connect screen tells the other panes (the command line's help and
/// completion) which family its choice connects with, when a key changes
/// it, once.
#[test]
fn the_family_of_the_choice_is_told_when_it_changes() {
    use axterm::ui::pane::{Input, Outcome, Request, View};
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(
        dir.path().join(RECENT_FILE),
        "[[connection]]\nargs = [\"--port\", \"/dev/ttyUSB0\", \"--protocol\", \"tmcl\"]\n",
    )
    .expect("recent file");
    assert_eq!(
        axterm::ui::connect::initial_family(Some(dir.path())).map(|f| f.name),
        Some("tmcl")
    );
    let mut pane = ConnectPane::new(Some(dir.path()), two_ports);
    assert_eq!(pane.chosen_family().map(|f| f.name), Some("tmcl"));
    let theme = Theme::builtin("dark").expect("theme");
    let keymap = Keymap::builtin("default").expect("keymap");
    let view = View {
        theme: &theme,
        keymap: &keymap,
        session: None,
        modules: &[],
        module: 0,
        focused: true,
        shown: true,
    };
    let down = Input::Key(KeyEvent::new(KeyCode::Down, KeyModifiers::NONE));
    let up = Input::Key(KeyEvent::new(KeyCode::Up, KeyModifiers::NONE));
    let told = |outcome: Outcome| match outcome {
        Outcome::Handled(requests) => requests
            .into_iter()
            .filter(|r| matches!(r, Request::ChooseFamily(_)))
            .collect::<Vec<_>>(),
        Outcome::Ignored => Vec::new(),
    };
    // From the recent port to the simulator: told once.
    assert_eq!(
        told(pane.handle_input(&down, &view)),
        [Request::ChooseFamily("tmcl")]
    );
    // Back to the recent port, the same family: nothing to tell (the row
    // below the first simulator is another simulator, of any family).
    assert_eq!(told(pane.handle_input(&up, &view)), []);
}
