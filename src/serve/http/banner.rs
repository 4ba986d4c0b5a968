//! How the server shows itself at start: the address a client on the network reaches it by, its
//! URL (with the token), and that URL as a QR code in the terminal, for a headset that has no
//! keyboard worth typing on.

use std::net::{IpAddr, Ipv4Addr, UdpSocket};

/// The host to show in the URL: the listening address, or for an unspecified one (`0.0.0.0`)
/// this machine's address on the network (the source address of its default route; no packet
/// is sent), or `localhost` if it has none.
pub fn shown_host(host: IpAddr) -> String {
    let ip = if host.is_unspecified() { lan_address().unwrap_or(IpAddr::V4(Ipv4Addr::LOCALHOST)) } else { host };
    match ip {
        IpAddr::V6(v6) => format!("[{v6}]"),
        IpAddr::V4(v4) => v4.to_string(),
    }
}

/// `host:port`.
pub fn host_port(host: &str, port: u16) -> String {
    format!("{host}:{port}")
}

/// The URL a client opens: `http(s)://host:port/`, with `?token=` when there is one.
pub fn url(tls: bool, host: &str, port: u16, token: Option<&str>) -> String {
    let scheme = if tls { "https" } else { "http" };
    match token {
        Some(t) => format!("{scheme}://{}/?token={t}", host_port(host, port)),
        None => format!("{scheme}://{}/", host_port(host, port)),
    }
}

/// This machine's address on its default route, if it has one.
pub fn lan_address() -> Option<IpAddr> {
    let socket = UdpSocket::bind((Ipv4Addr::UNSPECIFIED, 0)).ok()?;
    // A documentation address (TEST-NET-1): connecting a UDP socket only picks the route.
    socket.connect((Ipv4Addr::new(192, 0, 2, 1), 9)).ok()?;
    let ip = socket.local_addr().ok()?.ip();
    (!ip.is_unspecified()).then_some(ip)
}

/// A text as a QR code drawn with block characters, two rows of modules per line, dark on a
/// light quiet zone (as a phone's or headset's camera reads it on a dark or light terminal).
pub fn qr(text: &str) -> String {
    match qrcode::QrCode::new(text.as_bytes()) {
        Ok(code) => code
            .render::<qrcode::render::unicode::Dense1x2>()
            .dark_color(qrcode::render::unicode::Dense1x2::Light)
            .light_color(qrcode::render::unicode::Dense1x2::Dark)
            .quiet_zone(true)
            .build(),
        Err(e) => format!("(no QR code: {e})"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_qr_code_is_a_square_of_block_characters() {
        let q = qr("http://192.168.1.5:8080/?token=0123456789abcdef0123456789abcdef");
        let lines: Vec<&str> = q.lines().collect();
        assert!(lines.len() > 10, "{q}");
        let width = lines[0].chars().count();
        assert!(lines.iter().all(|l| l.chars().count() == width));
        // Two rows of modules per line: about twice as wide as tall.
        assert!((width as f64 / lines.len() as f64 - 2.0).abs() < 0.3, "{width} x {}", lines.len());
        assert!(q.chars().all(|c| " ▀▄█\n".contains(c)));
    }

    #[test]
    fn an_unspecified_address_is_shown_as_a_reachable_one() {
        assert_eq!(shown_host("127.0.0.1".parse().unwrap()), "127.0.0.1");
        assert_eq!(shown_host("::1".parse().unwrap()), "[::1]");
        let shown = shown_host("0.0.0.0".parse().unwrap());
        assert!(shown.parse::<IpAddr>().is_ok_and(|ip| !ip.is_unspecified()), "{shown}");
    }
}
