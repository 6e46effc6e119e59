//! The TCP link against a stand-in bridge on 127.0.0.1.

use std::time::Duration;

use axterm::link::{Link, LinkInput, LinkSpec};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};

/// Only guards against a hung test; a healthy exchange takes microseconds.
const GIVE_UP_AFTER: Duration = Duration::from_secs(10);

/// A listening bridge, a link connected to it, and the bridge's side.
async fn connected() -> (Link, TcpStream, String) {
    let listener = TcpListener::bind("127.0.0.1:0").await.expect("bind");
    let address = listener.local_addr().expect("address").to_string();
    let spec = LinkSpec::Tcp {
        address: address.clone(),
        baud: None,
    };
    let (link, accepted) = tokio::join!(spec.open(), listener.accept());
    let link = link.expect("connects");
    let (bridge, _) = accepted.expect("accepts");
    (link, bridge, address)
}

async fn next_input(link: &mut Link) -> Option<LinkInput> {
    tokio::time::timeout(GIVE_UP_AFTER, link.incoming.recv())
        .await
        .expect("the link reports within the guard time")
}

#[tokio::test]
async fn bytes_pass_both_ways() {
    let (mut link, mut bridge, address) = connected().await;
    assert_eq!(link.name, format!("tcp {address}"));
    assert_eq!(link.byte_time, None);

    bridge.write_all(b"from the module").await.expect("write");
    let mut got = Vec::new();
    while got.len() < 15 {
        match next_input(&mut link).await {
            Some(LinkInput::Bytes(bytes)) => got.extend(bytes),
            other => panic!("expected bytes, got {other:?}"),
        }
    }
    assert_eq!(got, b"from the module");

    link.outgoing.send(b"to the").expect("send");
    link.outgoing.send(b" module").expect("send");
    let mut buf = [0u8; 13];
    bridge.read_exact(&mut buf).await.expect("read");
    assert_eq!(&buf, b"to the module");
}

#[tokio::test]
async fn the_bridge_closing_is_a_loss() {
    let (mut link, bridge, _) = connected().await;
    drop(bridge);
    assert_eq!(
        next_input(&mut link).await,
        Some(LinkInput::Lost("the bridge closed the connection".into()))
    );
    assert!(link.incoming.try_recv().is_err(), "one loss notice only");
}

#[tokio::test]
async fn the_bridge_resetting_is_a_loss() {
    let (mut link, bridge, _) = connected().await;
    // A bridge that crashes or is restarted resets the connection.
    let bridge = bridge.into_std().expect("std stream");
    let socket = socket_with_zero_linger(bridge);
    drop(socket);
    assert_eq!(
        next_input(&mut link).await,
        Some(LinkInput::Lost("the bridge reset the connection".into()))
    );
}

/// SO_LINGER with a zero timeout makes close() send RST instead of FIN.
fn socket_with_zero_linger(stream: std::net::TcpStream) -> std::net::TcpStream {
    use std::os::fd::AsRawFd;
    let linger = libc::linger {
        l_onoff: 1,
        l_linger: 0,
    };
    // SAFETY: setsockopt on a socket we own, with a correctly sized struct.
    let done = unsafe {
        libc::setsockopt(
            stream.as_raw_fd(),
            libc::SOL_SOCKET,
            libc::SO_LINGER,
            std::ptr::from_ref(&linger).cast(),
            std::mem::size_of::<libc::linger>() as libc::socklen_t,
        )
    };
    assert_eq!(done, 0, "setsockopt(SO_LINGER)");
    stream
}

#[tokio::test]
async fn dropping_the_link_closes_the_connection() {
    let (link, mut bridge, _) = connected().await;
    drop(link);
    let mut buf = [0u8; 1];
    let read = tokio::time::timeout(GIVE_UP_AFTER, bridge.read(&mut buf))
        .await
        .expect("the bridge sees the end within the guard time");
    assert_eq!(read.expect("a clean close"), 0);
}

#[tokio::test]
async fn a_refused_connection_names_the_address() {
    // A port that was just free: nothing listens there now.
    let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("bind");
    let address = listener.local_addr().expect("address").to_string();
    drop(listener);
    let error = LinkSpec::Tcp {
        address: address.clone(),
        baud: None,
    }
    .open()
    .await
    .expect_err("refused");
    assert_eq!(
        error.to_string(),
        format!("cannot open tcp {address}: Connection refused")
    );
}

#[tokio::test]
async fn a_bad_address_names_the_address() {
    let error = LinkSpec::Tcp {
        address: "no port here".into(),
        baud: None,
    }
    .open()
    .await
    .expect_err("not an address");
    assert!(
        error
            .to_string()
            .starts_with("cannot open tcp no port here: "),
        "{error}"
    );
}
