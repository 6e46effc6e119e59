//! A raw serial-over-TCP bridge (ser2net, a MultiFlex ETH port) as a [`Link`].

use std::io;
use std::time::Duration;

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use tokio::sync::mpsc;

use super::{Inbox, Link, LinkError, LinkWriter, io_reason};

/// How long connecting (name lookup included) may take: a bridge on the
/// line PC's network answers in milliseconds or not at all.
pub const CONNECT_TIMEOUT: Duration = Duration::from_secs(5);

pub(super) async fn open(address: &str, name: String) -> Result<Link, LinkError> {
    let fail = |reason: String| LinkError {
        link: name.clone(),
        reason,
    };
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

    let reader_inbox = inbox.clone();
    tokio::spawn(async move {
        let inbox = reader_inbox;
        let mut buf = [0u8; 4096];
        loop {
            tokio::select! {
                _ = inbox.closed() => return,
                read = read_half.read(&mut buf) => match read {
                    Ok(0) => return inbox.lost("the bridge closed the connection"),
                    Ok(n) => {
                        if !inbox.bytes(buf.get(..n).unwrap_or_default()) {
                            return;
                        }
                    }
                    Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                    Err(e) => return inbox.lost(loss(&e)),
                },
            }
        }
    });

    // Writes go through a task so that `send` never blocks, whatever the
    // socket's buffer holds; order is kept by the channel.
    let (outgoing, mut to_write) = mpsc::unbounded_channel::<Vec<u8>>();
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
        outgoing: Box::new(TcpWriter { outgoing, inbox }),
        byte_time: None,
    })
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
}

impl LinkWriter for TcpWriter {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        if self.inbox.is_lost() {
            return Err(io::Error::new(
                io::ErrorKind::BrokenPipe,
                "the connection to the bridge is lost",
            ));
        }
        self.outgoing.send(bytes.to_vec()).map_err(|_| {
            io::Error::new(
                io::ErrorKind::BrokenPipe,
                "the connection to the bridge is lost",
            )
        })
    }
}
