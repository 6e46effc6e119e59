//! A serial-over-TCP bridge (ser2net, a MultiFlex ETH port) as a [`Link`]:
//! raw bytes, or Telnet with RFC 2217's COM-PORT-OPTION (`rfc2217://`),
//! which sets the remote port's baud rate and framing before the device
//! task sends anything. The Telnet byte handling is the pure state machine
//! of [`super::rfc2217`]; this file is its socket glue.

use std::io;
use std::time::Duration;

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use tokio::net::tcp::{OwnedReadHalf, OwnedWriteHalf};
use tokio::sync::mpsc;

use super::rfc2217::{self, ServerNews, TelnetClient};
use super::{Inbox, LINE_FRAMING, Link, LinkError, LinkWriter, io_reason};

/// How long connecting (name lookup included) may take: a bridge on the
/// line PC's network answers in milliseconds or not at all.
pub const CONNECT_TIMEOUT: Duration = Duration::from_secs(5);

/// How long an RFC 2217 server may take to answer our COM-PORT-OPTION
/// request, and then to confirm the port settings: it opens the serial
/// port in between, still milliseconds.
pub const NEGOTIATE_TIMEOUT: Duration = Duration::from_secs(5);

/// Open a bridge at `address`; with `rfc2217_baud`, speak RFC 2217 and set
/// its port to that rate and [`LINE_FRAMING`] first.
pub(super) async fn open(
    address: &str,
    rfc2217_baud: Option<u32>,
    name: String,
) -> Result<Link, LinkError> {
    let fail = |reason: String| LinkError::new(name.clone(), reason);
    let stream = match tokio::time::timeout(CONNECT_TIMEOUT, TcpStream::connect(address)).await {
        Ok(Ok(stream)) => stream,
        Ok(Err(e)) => return Err(fail(io_reason(&e))),
        Err(_) => {
            return Err(fail(format!(
                "no answer within {} s",
                CONNECT_TIMEOUT.as_secs()
            )));
        }
    };
    // Frames are a few bytes each; waiting to fill a segment only adds latency.
    stream
        .set_nodelay(true)
        .map_err(|e| fail(format!("cannot set TCP_NODELAY: {}", io_reason(&e))))?;
    let (mut read_half, mut write_half) = stream.into_split();
    let (inbox, incoming) = Inbox::new();

    // Device bytes that came with the server's negotiation, and the Telnet
    // state the reader carries on with.
    let (mut telnet, early) = match rfc2217_baud {
        Some(baud) => {
            let (telnet, early) = negotiate(&mut read_half, &mut write_half, baud)
                .await
                .map_err(fail)?;
            (Some(telnet), early)
        }
        None => (None, Vec::new()),
    };
    inbox.bytes(&early);

    // Writes go through a task so that `send` never blocks, whatever the
    // socket's buffer holds; order is kept by the channel. The reader puts
    // its Telnet answers on the same channel, as they are.
    let (outgoing, mut to_write) = mpsc::unbounded_channel::<Vec<u8>>();

    let reader_inbox = inbox.clone();
    let answers = outgoing.clone();
    tokio::spawn(async move {
        let inbox = reader_inbox;
        let mut buf = [0u8; 4096];
        loop {
            tokio::select! {
                _ = inbox.closed() => return,
                read = read_half.read(&mut buf) => match read {
                    Ok(0) => return inbox.lost("the bridge closed the connection"),
                    Ok(n) => {
                        let bytes = buf.get(..n).unwrap_or_default();
                        let delivered = match telnet.as_mut() {
                            None => inbox.bytes(bytes),
                            Some(telnet) => {
                                let received = telnet.receive(bytes);
                                if !received.answer.is_empty() {
                                    let _ = answers.send(received.answer);
                                }
                                inbox.bytes(&received.data)
                            }
                        };
                        if !delivered {
                            return;
                        }
                    }
                    Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                    Err(e) => return inbox.lost(loss(&e)),
                },
            }
        }
    });
    let writer_inbox = inbox.clone();
    tokio::spawn(async move {
        while let Some(bytes) = to_write.recv().await {
            if let Err(e) = write_half.write_all(&bytes).await {
                return writer_inbox.lost(loss(&e));
            }
        }
        // The link was dropped: say goodbye to the bridge.
        let _ = write_half.shutdown().await;
    });

    Ok(Link {
        name,
        incoming,
        outgoing: Box::new(TcpWriter {
            outgoing,
            inbox,
            telnet: rfc2217_baud.is_some(),
        }),
        byte_time: None,
    })
}

/// RFC 2217's opening: ask for COM-PORT-OPTION, wait for the server's DO
/// (or its refusal), set the port's baud rate and framing and wait until
/// the server has confirmed each. Returns the Telnet state and any device
/// bytes that arrived meanwhile.
async fn negotiate(
    read_half: &mut OwnedReadHalf,
    write_half: &mut OwnedWriteHalf,
    baud: u32,
) -> Result<(TelnetClient, Vec<u8>), String> {
    let mut telnet = TelnetClient::new();
    let mut early = Vec::new();
    let written = |e: io::Error| format!("cannot write to the server: {}", io_reason(&e));
    write_half
        .write_all(&telnet.start())
        .await
        .map_err(written)?;

    let framing = LINE_FRAMING;
    let mut asked = false;
    let (mut baud_set, mut size_set, mut parity_set, mut stop_set) = (false, false, false, false);
    let mut buf = [0u8; 1024];
    let deadline = tokio::time::Instant::now() + NEGOTIATE_TIMEOUT;
    while !(baud_set && size_set && parity_set && stop_set) {
        let read = tokio::time::timeout_at(deadline, read_half.read(&mut buf)).await;
        let n = match read {
            Err(_) if !asked => {
                return Err(format!(
                    "the server did not answer COM-PORT-OPTION within {} s \
                     (is it a raw TCP port? then drop rfc2217://)",
                    NEGOTIATE_TIMEOUT.as_secs()
                ));
            }
            Err(_) => {
                return Err(format!(
                    "the server did not confirm the port settings within {} s",
                    NEGOTIATE_TIMEOUT.as_secs()
                ));
            }
            Ok(Ok(0)) => {
                return Err("the server closed the connection during the RFC 2217 opening".into());
            }
            Ok(Ok(n)) => n,
            Ok(Err(e)) if e.kind() == io::ErrorKind::Interrupted => continue,
            Ok(Err(e)) => return Err(loss(&e)),
        };
        let received = telnet.receive(buf.get(..n).unwrap_or_default());
        early.extend(received.data);
        if !received.answer.is_empty() {
            write_half
                .write_all(&received.answer)
                .await
                .map_err(written)?;
        }
        for news in received.news {
            match news {
                ServerNews::ComPortRefused => {
                    return Err("the server refused COM-PORT-OPTION (RFC 2217)".into());
                }
                ServerNews::ComPortAccepted if !asked => {
                    asked = true;
                    let settings = [
                        rfc2217::set_baudrate(baud),
                        rfc2217::set_datasize(framing.data_bits),
                        rfc2217::set_parity(framing.parity),
                        rfc2217::set_stopsize(framing.stop_bits),
                    ]
                    .concat();
                    write_half.write_all(&settings).await.map_err(written)?;
                }
                ServerNews::ComPortAccepted => {}
                // Answers before we asked are the server's own notices.
                _ if !asked => {}
                ServerNews::Baud(got) if got == baud => baud_set = true,
                ServerNews::Baud(got) => {
                    return Err(format!(
                        "the server set its port to {got} Bd, not the {baud} Bd asked for"
                    ));
                }
                ServerNews::DataSize(got) if got == framing.data_bits => size_set = true,
                ServerNews::DataSize(got) => {
                    return Err(format!(
                        "the server set its port to {got} data bits, not the {} asked for",
                        framing.data_bits
                    ));
                }
                ServerNews::Parity(got) if got == framing.parity as u8 => parity_set = true,
                ServerNews::Parity(got) => {
                    return Err(format!(
                        "the server set its port to parity {got} (RFC 2217 numbering), \
                         not the {:?} asked for",
                        framing.parity
                    ));
                }
                ServerNews::StopSize(got) if got == framing.stop_bits as u8 => stop_set = true,
                ServerNews::StopSize(got) => {
                    return Err(format!(
                        "the server set its port to stop size {got} (RFC 2217 numbering), \
                         not the {:?} asked for",
                        framing.stop_bits
                    ));
                }
            }
        }
    }
    Ok((telnet, early))
}

fn loss(e: &io::Error) -> String {
    match e.kind() {
        io::ErrorKind::ConnectionReset => "the bridge reset the connection".into(),
        io::ErrorKind::BrokenPipe | io::ErrorKind::ConnectionAborted => {
            "the connection to the bridge was broken".into()
        }
        _ => io_reason(e),
    }
}

struct TcpWriter {
    outgoing: mpsc::UnboundedSender<Vec<u8>>,
    inbox: Inbox,
    /// Telnet: data bytes 255 (IAC) are doubled.
    telnet: bool,
}

impl LinkWriter for TcpWriter {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        if self.inbox.is_lost() {
            return Err(io::Error::new(
                io::ErrorKind::BrokenPipe,
                "the connection to the bridge is lost",
            ));
        }
        let bytes = if self.telnet {
            rfc2217::escape(bytes)
        } else {
            bytes.to_vec()
        };
        self.outgoing.send(bytes).map_err(|_| {
            io::Error::new(
                io::ErrorKind::BrokenPipe,
                "the connection to the bridge is lost",
            )
        })
    }
}
