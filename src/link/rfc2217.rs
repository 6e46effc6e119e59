//! The client side of Telnet (RFC 854/855) with the COM-PORT-OPTION of
//! RFC 2217, as a pure state machine: bytes from the server in, the
//! device's own bytes, the answers to send back and the server's COM-PORT
//! answers out. No I/O here; `tcp.rs` owns the socket.
//!
//! Why each piece is here:
//! - IAC (255) is Telnet's escape: a data byte 255 travels as IAC IAC both
//!   ways (RFC 854, "IAC ... Data Byte 255"). TMCL frames carry any byte,
//!   so a checksum or value of 255 must be doubled going out and undoubled
//!   coming in.
//! - The server's option negotiation (IAC WILL/WONT/DO/DONT x) and
//!   subnegotiation (IAC SB ... IAC SE) are no device bytes: they are
//!   stripped, even when a TCP read ends in the middle of one.
//! - Options we did not ask for are refused (RFC 854: WONT for DO, DONT for
//!   WILL); we ask for BINARY both ways (RFC 856) so that a CR is not
//!   followed by an inserted NUL, and for SUPPRESS-GO-AHEAD (RFC 858).
//! - RFC 2217: the client sends IAC WILL COM-PORT-OPTION; the server
//!   answers DO (it will take commands) or DONT (refused). Server-to-client
//!   subnegotiation codes are the client's codes plus 100.

/// Telnet command bytes (RFC 854).
pub const IAC: u8 = 255;
pub const DONT: u8 = 254;
pub const DO: u8 = 253;
pub const WONT: u8 = 252;
pub const WILL: u8 = 251;
pub const SB: u8 = 250;
pub const SE: u8 = 240;

/// Telnet options we speak.
pub const BINARY: u8 = 0;
pub const SUPPRESS_GO_AHEAD: u8 = 3;
pub const COM_PORT_OPTION: u8 = 44;

/// RFC 2217 client-to-server command codes (server answers add 100).
pub const SET_BAUDRATE: u8 = 1;
pub const SET_DATASIZE: u8 = 2;
pub const SET_PARITY: u8 = 3;
pub const SET_STOPSIZE: u8 = 4;
/// Offset of a server's answer code over the client's command code.
pub const SERVER_OFFSET: u8 = 100;

/// A subnegotiation longer than this is no RFC 2217 answer (the longest,
/// a signature, is text); the rest is dropped up to its IAC SE.
const MAX_SUBNEGOTIATION: usize = 256;

/// Parity as RFC 2217 numbers it (SET-PARITY values).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ComParity {
    None = 1,
    Odd = 2,
    Even = 3,
    Mark = 4,
    Space = 5,
}

/// Stop bits as RFC 2217 numbers them (SET-STOPSIZE values).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ComStopBits {
    One = 1,
    Two = 2,
    OneAndHalf = 3,
}

/// What the server told us that the link must act on.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ServerNews {
    /// DO COM-PORT-OPTION: it takes our port settings.
    ComPortAccepted,
    /// DONT COM-PORT-OPTION: it will not.
    ComPortRefused,
    /// An answer to SET-BAUDRATE (code 101): the rate now in force.
    Baud(u32),
    /// An answer to SET-DATASIZE (102).
    DataSize(u8),
    /// An answer to SET-PARITY (103), RFC 2217 numbering.
    Parity(u8),
    /// An answer to SET-STOPSIZE (104), RFC 2217 numbering.
    StopSize(u8),
}

/// The result of feeding received bytes.
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub struct Received {
    /// The device's bytes, unescaped, negotiation stripped.
    pub data: Vec<u8>,
    /// Telnet answers to send back to the server as they are (not escaped).
    pub answer: Vec<u8>,
    /// What the server said about the COM port, in order.
    pub news: Vec<ServerNews>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum State {
    Data,
    /// After an IAC.
    Command,
    /// After IAC WILL/WONT/DO/DONT: the option byte comes next.
    Option(u8),
    /// Inside IAC SB ...
    Sub,
    /// An IAC inside a subnegotiation: IAC (data 255) or SE (end) follows.
    SubIac,
}

/// Our side and the server's side of one option (a short form of the
/// RFC 1143 "Q method": enough to never answer an answer).
#[derive(Debug, Clone, Copy, Default)]
struct OptionState {
    enabled: bool,
    requested: bool,
}

/// The Telnet client's state across reads.
#[derive(Debug, Clone)]
pub struct TelnetClient {
    state: State,
    sub: Vec<u8>,
    sub_overflow: bool,
    /// Options we (the client) perform: BINARY, COM-PORT-OPTION.
    ours: [OptionState; 256],
    /// Options the server performs: BINARY, SUPPRESS-GO-AHEAD.
    theirs: [OptionState; 256],
}

impl Default for TelnetClient {
    fn default() -> Self {
        TelnetClient::new()
    }
}

/// Options we agree to perform when asked.
fn we_perform(option: u8) -> bool {
    matches!(option, BINARY | COM_PORT_OPTION)
}

/// Options we agree to let the server perform.
fn they_perform(option: u8) -> bool {
    matches!(option, BINARY | SUPPRESS_GO_AHEAD)
}

impl TelnetClient {
    pub fn new() -> TelnetClient {
        TelnetClient {
            state: State::Data,
            sub: Vec::new(),
            sub_overflow: false,
            ours: [OptionState::default(); 256],
            theirs: [OptionState::default(); 256],
        }
    }

    /// The opening requests: WILL COM-PORT-OPTION, BINARY both ways,
    /// DO SUPPRESS-GO-AHEAD. Send these first, as they are.
    pub fn start(&mut self) -> Vec<u8> {
        let mut out = Vec::new();
        for option in [COM_PORT_OPTION, BINARY] {
            if let Some(o) = self.ours.get_mut(usize::from(option)) {
                o.requested = true;
            }
            out.extend([IAC, WILL, option]);
        }
        for option in [BINARY, SUPPRESS_GO_AHEAD] {
            if let Some(o) = self.theirs.get_mut(usize::from(option)) {
                o.requested = true;
            }
            out.extend([IAC, DO, option]);
        }
        out
    }

    /// Whether the server agreed to COM-PORT-OPTION.
    pub fn com_port_accepted(&self) -> bool {
        self.ours
            .get(usize::from(COM_PORT_OPTION))
            .is_some_and(|o| o.enabled)
    }

    /// Feed bytes received from the server, split anywhere.
    pub fn receive(&mut self, bytes: &[u8]) -> Received {
        let mut out = Received::default();
        for &byte in bytes {
            self.state = match (self.state, byte) {
                (State::Data, IAC) => State::Command,
                (State::Data, _) => {
                    out.data.push(byte);
                    State::Data
                }
                (State::Command, IAC) => {
                    out.data.push(IAC);
                    State::Data
                }
                (State::Command, WILL | WONT | DO | DONT) => State::Option(byte),
                (State::Command, SB) => {
                    self.sub.clear();
                    self.sub_overflow = false;
                    State::Sub
                }
                // NOP, GA, DM, BRK and the like carry nothing for us.
                (State::Command, _) => State::Data,
                (State::Option(verb), option) => {
                    self.negotiate(verb, option, &mut out);
                    State::Data
                }
                (State::Sub, IAC) => State::SubIac,
                (State::Sub, _) => {
                    self.sub_push(byte);
                    State::Sub
                }
                (State::SubIac, IAC) => {
                    self.sub_push(IAC);
                    State::Sub
                }
                (State::SubIac, SE) => {
                    self.subnegotiation(&mut out);
                    State::Data
                }
                // IAC then anything else inside SB is a protocol error
                // (RFC 855); end the subnegotiation there, as others do.
                (State::SubIac, _) => {
                    self.subnegotiation(&mut out);
                    State::Data
                }
            };
        }
        out
    }

    fn sub_push(&mut self, byte: u8) {
        if self.sub.len() < MAX_SUBNEGOTIATION {
            self.sub.push(byte);
        } else {
            self.sub_overflow = true;
        }
    }

    fn negotiate(&mut self, verb: u8, option: u8, out: &mut Received) {
        let index = usize::from(option);
        match verb {
            DO | DONT => {
                let Some(ours) = self.ours.get_mut(index) else {
                    return;
                };
                let agree = verb == DO && we_perform(option);
                let was_requested = ours.requested;
                ours.requested = false;
                if agree {
                    if !ours.enabled {
                        ours.enabled = true;
                        if !was_requested {
                            out.answer.extend([IAC, WILL, option]);
                        }
                    }
                    if option == COM_PORT_OPTION {
                        out.news.push(ServerNews::ComPortAccepted);
                    }
                } else {
                    // DONT, or DO for something we do not do.
                    let changed = ours.enabled;
                    ours.enabled = false;
                    if verb == DO || (changed && !was_requested) {
                        out.answer.extend([IAC, WONT, option]);
                    }
                    if option == COM_PORT_OPTION && (changed || was_requested) {
                        out.news.push(ServerNews::ComPortRefused);
                    }
                }
            }
            WILL | WONT => {
                let Some(theirs) = self.theirs.get_mut(index) else {
                    return;
                };
                let agree = verb == WILL && they_perform(option);
                let was_requested = theirs.requested;
                theirs.requested = false;
                if agree {
                    if !theirs.enabled {
                        theirs.enabled = true;
                        if !was_requested {
                            out.answer.extend([IAC, DO, option]);
                        }
                    }
                } else {
                    let changed = theirs.enabled;
                    theirs.enabled = false;
                    if verb == WILL || (changed && !was_requested) {
                        out.answer.extend([IAC, DONT, option]);
                    }
                }
            }
            _ => {}
        }
    }

    fn subnegotiation(&mut self, out: &mut Received) {
        let sub = std::mem::take(&mut self.sub);
        if self.sub_overflow {
            return;
        }
        let [COM_PORT_OPTION, code, value @ ..] = sub.as_slice() else {
            return;
        };
        let news = match (code.checked_sub(SERVER_OFFSET), value) {
            (Some(SET_BAUDRATE), [a, b, c, d]) => {
                ServerNews::Baud(u32::from_be_bytes([*a, *b, *c, *d]))
            }
            (Some(SET_DATASIZE), [v]) => ServerNews::DataSize(*v),
            (Some(SET_PARITY), [v]) => ServerNews::Parity(*v),
            (Some(SET_STOPSIZE), [v]) => ServerNews::StopSize(*v),
            // Signature, line and modem state, flow control: nothing the
            // link acts on.
            _ => return,
        };
        out.news.push(news);
    }
}

/// Data bytes to send: IAC doubled (RFC 854).
pub fn escape(data: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(data.len() + 2);
    for &byte in data {
        out.push(byte);
        if byte == IAC {
            out.push(IAC);
        }
    }
    out
}

/// IAC SB COM-PORT-OPTION code value... IAC SE, IACs in the value doubled.
fn com_port_command(code: u8, value: &[u8]) -> Vec<u8> {
    let mut out = vec![IAC, SB, COM_PORT_OPTION, code];
    out.extend(escape(value));
    out.extend([IAC, SE]);
    out
}

/// SET-BAUDRATE (RFC 2217: four bytes, network order).
pub fn set_baudrate(baud: u32) -> Vec<u8> {
    com_port_command(SET_BAUDRATE, &baud.to_be_bytes())
}

/// SET-DATASIZE (5 to 8 bits).
pub fn set_datasize(bits: u8) -> Vec<u8> {
    com_port_command(SET_DATASIZE, &[bits])
}

pub fn set_parity(parity: ComParity) -> Vec<u8> {
    com_port_command(SET_PARITY, &[parity as u8])
}

pub fn set_stopsize(stop: ComStopBits) -> Vec<u8> {
    com_port_command(SET_STOPSIZE, &[stop as u8])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn data_of(client: &mut TelnetClient, chunks: &[&[u8]]) -> Vec<u8> {
        chunks
            .iter()
            .flat_map(|chunk| client.receive(chunk).data)
            .collect()
    }

    #[test]
    fn iac_is_doubled_on_send() {
        assert_eq!(
            escape(&[1, 0xFF, 2, 0xFF, 0xFF]),
            [1, 0xFF, 0xFF, 2, 0xFF, 0xFF, 0xFF, 0xFF]
        );
        assert_eq!(escape(b"plain"), b"plain");
    }

    #[test]
    fn doubled_iac_is_one_data_byte_on_receive_even_split() {
        let mut client = TelnetClient::new();
        assert_eq!(client.receive(&[1, 0xFF, 0xFF, 2]).data, [1, 0xFF, 2]);
        assert_eq!(
            data_of(&mut client, &[&[3, 0xFF], &[0xFF, 4]]),
            [3, 0xFF, 4]
        );
    }

    #[test]
    fn negotiation_is_stripped_and_answered() {
        let mut client = TelnetClient::new();
        // The server offers ECHO (1), asks for TERMINAL-TYPE (24): refused.
        let got = client.receive(&[b'a', IAC, WILL, 1, b'b', IAC, DO, 24, b'c', IAC, 241, b'd']);
        assert_eq!(got.data, b"abcd");
        assert_eq!(got.answer, [IAC, DONT, 1, IAC, WONT, 24]);
        assert!(got.news.is_empty());
    }

    #[test]
    fn answers_to_our_own_requests_are_not_answered_again() {
        let mut client = TelnetClient::new();
        let start = client.start();
        assert_eq!(start, [IAC, WILL, 44, IAC, WILL, 0, IAC, DO, 0, IAC, DO, 3]);
        let got = client.receive(&[IAC, DO, 44, IAC, DO, 0, IAC, WILL, 0, IAC, WILL, 3]);
        assert!(got.answer.is_empty(), "{:?}", got.answer);
        assert_eq!(got.news, [ServerNews::ComPortAccepted]);
        assert!(client.com_port_accepted());
        // A repeated DO is no change: no answer, no loop.
        assert!(client.receive(&[IAC, DO, 0]).answer.is_empty());
    }

    #[test]
    fn a_refused_com_port_option_is_news() {
        let mut client = TelnetClient::new();
        client.start();
        let got = client.receive(&[IAC, DONT, 44]);
        assert_eq!(got.news, [ServerNews::ComPortRefused]);
        assert!(got.answer.is_empty());
        assert!(!client.com_port_accepted());
    }

    #[test]
    fn split_negotiation_and_subnegotiation_are_stripped() {
        let stream: Vec<u8> = [
            &b"x"[..],
            &[IAC, WILL, 3],
            &[IAC, SB, 44, 101, 0, 0, 0x25, 0x80, IAC, SE],
            b"y",
            &[IAC, SB, 44, 102, 8, IAC, SE],
            &[IAC, SB, 44, 106, 0x60, IAC, SE], // NOTIFY-LINESTATE: ignored
            b"z",
        ]
        .concat();
        // Every split point, so each state is crossed by a read boundary.
        for cut in 0..=stream.len() {
            let (a, b) = stream.split_at(cut);
            let mut client = TelnetClient::new();
            client.start();
            let first = client.receive(a);
            let second = client.receive(b);
            let data: Vec<u8> = [first.data, second.data].concat();
            let news: Vec<ServerNews> = [first.news, second.news].concat();
            assert_eq!(data, b"xyz", "cut at {cut}");
            assert_eq!(
                news,
                [ServerNews::Baud(9600), ServerNews::DataSize(8)],
                "cut at {cut}"
            );
        }
    }

    #[test]
    fn a_doubled_iac_inside_a_subnegotiation_is_a_value_byte() {
        let mut client = TelnetClient::new();
        let got = client.receive(&[IAC, SB, 44, 101, 0, 0, IAC, IAC, 0, IAC, SE, 7]);
        assert_eq!(got.news, [ServerNews::Baud(0x0000_FF00)]);
        assert_eq!(got.data, [7]);
    }

    #[test]
    fn an_overlong_subnegotiation_is_dropped_whole() {
        let mut client = TelnetClient::new();
        let mut stream = vec![IAC, SB, 44, 101];
        stream.extend(std::iter::repeat_n(1, 1000));
        stream.extend([IAC, SE, 9]);
        let got = client.receive(&stream);
        assert!(got.news.is_empty());
        assert_eq!(got.data, [9]);
    }

    /// RFC 2217, "SET-BAUDRATE ... IAC SB COM-PORT-OPTION SET-BAUDRATE
    /// <value(4)> IAC SE", value in network byte order; SET-DATASIZE 8,
    /// SET-PARITY 1 (NONE), 2 (ODD), 3 (EVEN); SET-STOPSIZE 1, 2, 3 (1.5).
    #[test]
    fn com_port_commands_are_the_rfc_bytes() {
        assert_eq!(
            set_baudrate(9600),
            [255, 250, 44, 1, 0, 0, 0x25, 0x80, 255, 240]
        );
        assert_eq!(
            set_baudrate(115_200),
            [255, 250, 44, 1, 0, 1, 0xC2, 0x00, 255, 240]
        );
        // A value byte 255 is doubled inside the subnegotiation too.
        assert_eq!(
            set_baudrate(0xFF),
            [255, 250, 44, 1, 0, 0, 0, 255, 255, 255, 240]
        );
        assert_eq!(set_datasize(8), [255, 250, 44, 2, 8, 255, 240]);
        assert_eq!(set_parity(ComParity::None), [255, 250, 44, 3, 1, 255, 240]);
        assert_eq!(set_parity(ComParity::Odd), [255, 250, 44, 3, 2, 255, 240]);
        assert_eq!(set_parity(ComParity::Even), [255, 250, 44, 3, 3, 255, 240]);
        assert_eq!(
            set_stopsize(ComStopBits::One),
            [255, 250, 44, 4, 1, 255, 240]
        );
        assert_eq!(
            set_stopsize(ComStopBits::Two),
            [255, 250, 44, 4, 2, 255, 240]
        );
        assert_eq!(
            set_stopsize(ComStopBits::OneAndHalf),
            [255, 250, 44, 4, 3, 255, 240]
        );
    }

    #[test]
    fn server_answers_are_the_client_codes_plus_100() {
        let mut client = TelnetClient::new();
        let got = client.receive(
            &[
                &[IAC, SB, 44, 101, 0, 1, 0xC2, 0x00, IAC, SE][..],
                &[IAC, SB, 44, 102, 7, IAC, SE],
                &[IAC, SB, 44, 103, 3, IAC, SE],
                &[IAC, SB, 44, 104, 2, IAC, SE],
                // A client code echoed back is no answer.
                &[IAC, SB, 44, 1, 0, 0, 0, 1, IAC, SE],
            ]
            .concat(),
        );
        assert_eq!(
            got.news,
            [
                ServerNews::Baud(115_200),
                ServerNews::DataSize(7),
                ServerNews::Parity(3),
                ServerNews::StopSize(2)
            ]
        );
        assert!(got.data.is_empty());
    }
}
