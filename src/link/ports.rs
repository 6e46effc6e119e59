//! The serial ports of this machine, with what the system knows of each
//! adapter, for `axterm ports`.
//!
//! On Linux we read sysfs ourselves rather than take serialport's
//! `available_ports` (without libudev): that one panics when
//! `/sys/class/tty` is missing (some containers), lists every legacy
//! `ttyS` slot on kernels that put them on the `serial-base` bus whether a
//! UART is there or not, drops a USB port whose ids it cannot read, and
//! does not give the USB interface's name (which tells the ports of a
//! dual adapter apart). Pseudo-terminals never appear: they have no entry
//! under `/sys/class/tty` with a device behind it.
//!
//! Each port is listed with its stable names from `/dev/serial/by-id`
//! (udev's symbolic links, named after the adapter's vendor, product and
//! serial number: they stay the same whatever order adapters are plugged
//! in), and `--port` takes such a name, as a full path or the file name
//! alone ([`resolve_port`]).

use std::fmt;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// Where udev puts the stable names of serial devices (Linux).
pub const BY_ID_DIR: &str = "/dev/serial/by-id";

/// One serial port.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PortInfo {
    /// What to give `--port`: `/dev/ttyUSB0`, `COM3`.
    pub path: String,
    pub kind: PortKind,
}

/// A port as `axterm ports` lists it: with its stable names.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ListedPort {
    pub port: PortInfo,
    /// Its by-id names (`/dev/serial/by-id/usb-FTDI_…-if00-port0`), any
    /// of which `--port` takes.
    pub by_id: Vec<String>,
}

/// The port's line, and each stable name on a line of its own below it,
/// indented (the first line stays what scripts read).
impl fmt::Display for ListedPort {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.port)?;
        for name in &self.by_id {
            write!(f, "\n    {name}")?;
        }
        Ok(())
    }
}

/// What is behind a port.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PortKind {
    /// A USB adapter or a controller's own USB port.
    Usb(UsbIdentity),
    /// A UART on a PCI card.
    Pci,
    /// A Bluetooth serial link.
    Bluetooth,
    /// An on-board UART, or one the system says nothing about.
    Other,
}

/// A USB device's identity as it reports it.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct UsbIdentity {
    pub vid: u16,
    pub pid: u16,
    pub manufacturer: Option<String>,
    pub product: Option<String>,
    pub serial_number: Option<String>,
    /// The name of the USB interface behind this port, where it has one.
    pub interface: Option<String>,
}

/// `/dev/ttyACM0  usb 2a3c:0100  Trinamic  StepRocker  serial 0042`.
impl fmt::Display for PortInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.path)?;
        match &self.kind {
            PortKind::Usb(usb) => {
                write!(f, "  usb {:04x}:{:04x}", usb.vid, usb.pid)?;
                for part in [&usb.manufacturer, &usb.product].into_iter().flatten() {
                    write!(f, "  {part}")?;
                }
                if let Some(serial) = &usb.serial_number {
                    write!(f, "  serial {serial}")?;
                }
                if let Some(interface) = &usb.interface {
                    write!(f, "  ({interface})")?;
                }
                Ok(())
            }
            PortKind::Pci => write!(f, "  pci"),
            PortKind::Bluetooth => write!(f, "  bluetooth"),
            PortKind::Other => Ok(()),
        }
    }
}

/// The symbolic links in `dir` (a by-id directory), each with the path
/// it resolves to, sorted by name. Anything unreadable (no such
/// directory, a dangling link) is skipped.
pub fn by_id_links(dir: &Path) -> Vec<(PathBuf, PathBuf)> {
    let Ok(entries) = fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut links: Vec<(PathBuf, PathBuf)> = entries
        .flatten()
        .filter(|e| e.file_type().is_ok_and(|t| t.is_symlink()))
        .filter_map(|e| {
            let link = e.path();
            let target = link.canonicalize().ok()?;
            Some((link, target))
        })
        .collect();
    links.sort();
    links
}

/// Each port with the by-id names in `dir` that lead to it.
pub fn with_by_id_names(ports: Vec<PortInfo>, dir: &Path) -> Vec<ListedPort> {
    let links = by_id_links(dir);
    ports
        .into_iter()
        .map(|port| {
            let node = Path::new(&port.path).canonicalize().ok();
            let by_id = links
                .iter()
                .filter(|(_, target)| Some(target) == node.as_ref())
                .map(|(link, _)| link.to_string_lossy().into_owned())
                .collect();
            ListedPort { port, by_id }
        })
        .collect()
}

/// Every serial port found ([`available_ports`]) with its names in
/// [`BY_ID_DIR`].
pub fn listed_ports() -> io::Result<Vec<ListedPort>> {
    Ok(with_by_id_names(available_ports()?, Path::new(BY_ID_DIR)))
}

/// What `--port GIVEN` opens: `given` itself when something is there (a
/// device, or a by-id link given as a full path), else the by-id link of
/// that file name in `dir` (`--port usb-FTDI_FT232R_USB_UART_A50285BI-if00-port0`);
/// else `given` as it is, for the open to say what is wrong.
pub fn resolve_port(given: &str, dir: &Path) -> String {
    let as_given = Path::new(given);
    if fs::symlink_metadata(as_given).is_ok() || given.contains(['/', '\\']) || given.is_empty() {
        return given.to_string();
    }
    let by_id = dir.join(given);
    if fs::symlink_metadata(&by_id).is_ok() {
        return by_id.to_string_lossy().into_owned();
    }
    given.to_string()
}

/// Every serial port found, sorted by path.
pub fn available_ports() -> io::Result<Vec<PortInfo>> {
    #[cfg(target_os = "linux")]
    {
        Ok(scan_sysfs(Path::new("/sys/class/tty"), Path::new("/dev")))
    }
    #[cfg(not(target_os = "linux"))]
    {
        let ports = serialport::available_ports().map_err(io::Error::other)?;
        let mut ports: Vec<PortInfo> = ports
            .into_iter()
            .map(|port| PortInfo {
                path: port.port_name,
                kind: match port.port_type {
                    serialport::SerialPortType::UsbPort(usb) => PortKind::Usb(UsbIdentity {
                        vid: usb.vid,
                        pid: usb.pid,
                        manufacturer: usb.manufacturer,
                        product: usb.product,
                        serial_number: usb.serial_number,
                        interface: None,
                    }),
                    serialport::SerialPortType::PciPort => PortKind::Pci,
                    serialport::SerialPortType::BluetoothPort => PortKind::Bluetooth,
                    serialport::SerialPortType::Unknown => PortKind::Other,
                },
            })
            .collect();
        ports.sort_by(|a, b| a.path.cmp(&b.path));
        Ok(ports)
    }
}

/// The ports under a sysfs tty class directory whose device nodes exist
/// under `dev`. Anything unreadable is skipped, never fatal.
pub fn scan_sysfs(class_tty: &Path, dev: &Path) -> Vec<PortInfo> {
    let Ok(entries) = fs::read_dir(class_tty) else {
        return Vec::new();
    };
    let mut ports = Vec::new();
    for entry in entries.flatten() {
        let name = entry.file_name();
        let node = dev.join(&name);
        if !node.exists() {
            continue;
        }
        let class_entry = entry.path();
        let kind = if name.to_string_lossy().starts_with("rfcomm") {
            PortKind::Bluetooth
        } else {
            // Virtual consoles, ptmx and the like have no device behind them.
            let Ok(device) = class_entry.join("device").canonicalize() else {
                continue;
            };
            // A serial-core port whose UART type is 0 (PORT_UNKNOWN) is an
            // empty legacy slot: no UART answered there.
            if read_trimmed(&class_entry, "type").as_deref() == Some("0") {
                continue;
            }
            port_kind(&device)
        };
        ports.push(PortInfo {
            path: node.to_string_lossy().into_owned(),
            kind,
        });
    }
    ports.sort_by(|a, b| a.path.cmp(&b.path));
    ports
}

/// What sits behind a tty's device directory. A USB serial port's device
/// is the USB interface (cdc-acm) or a port below it (usb-serial drivers
/// such as ftdi_sio), so the USB device with the ids is at most two levels up.
fn port_kind(device: &Path) -> PortKind {
    let mut interface = None;
    for dir in device.ancestors().take(3) {
        if interface.is_none() && dir.join("bInterfaceNumber").exists() {
            interface = read_trimmed(dir, "interface");
        }
        let ids = (read_hex(dir, "idVendor"), read_hex(dir, "idProduct"));
        if let (Some(vid), Some(pid)) = ids {
            return PortKind::Usb(UsbIdentity {
                vid,
                pid,
                manufacturer: read_trimmed(dir, "manufacturer"),
                product: read_trimmed(dir, "product"),
                serial_number: read_trimmed(dir, "serial"),
                interface,
            });
        }
    }
    let subsystem = device.join("subsystem").canonicalize().ok();
    match subsystem.as_deref().and_then(Path::file_name) {
        Some(name) if name == "pci" => PortKind::Pci,
        _ => PortKind::Other,
    }
}

fn read_trimmed(dir: &Path, file: &str) -> Option<String> {
    let text = fs::read_to_string(dir.join(file)).ok()?;
    let text = text.trim();
    (!text.is_empty()).then(|| text.to_string())
}

fn read_hex(dir: &Path, file: &str) -> Option<u16> {
    u16::from_str_radix(&read_trimmed(dir, file)?, 16).ok()
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use std::os::unix::fs::symlink;
    use std::path::PathBuf;

    struct FakeSys {
        _dir: tempfile::TempDir,
        root: PathBuf,
    }

    impl FakeSys {
        fn new() -> FakeSys {
            let dir = tempfile::tempdir().expect("temp dir");
            let root = dir.path().to_path_buf();
            for sub in ["class/tty", "dev", "bus/pci", "bus/pnp"] {
                fs::create_dir_all(root.join(sub)).expect("mkdir");
            }
            FakeSys { _dir: dir, root }
        }

        fn file(&self, path: &str, text: &str) {
            let path = self.root.join(path);
            fs::create_dir_all(path.parent().expect("has a parent")).expect("mkdir");
            fs::write(path, text).expect("write");
        }

        /// A tty called `name`, with a device node, and its device
        /// directory at `device` (None: a virtual tty without one).
        fn tty(&self, name: &str, device: Option<&str>) {
            let entry = self.root.join("class/tty").join(name);
            fs::create_dir_all(&entry).expect("mkdir");
            self.file(&format!("dev/{name}"), "");
            if let Some(device) = device {
                let target = self.root.join(device);
                fs::create_dir_all(&target).expect("mkdir");
                symlink(&target, entry.join("device")).expect("symlink");
            }
        }

        fn subsystem(&self, device: &str, bus: &str) {
            symlink(
                self.root.join("bus").join(bus),
                self.root.join(device).join("subsystem"),
            )
            .expect("symlink");
        }

        fn scan(&self) -> Vec<String> {
            scan_sysfs(&self.root.join("class/tty"), &self.root.join("dev"))
                .iter()
                .map(|p| {
                    p.to_string()
                        .replace(&self.root.join("dev").to_string_lossy().into_owned(), "")
                })
                .collect()
        }
    }

    #[test]
    fn usb_adapters_real_uarts_and_bluetooth_are_listed() {
        let sys = FakeSys::new();
        // An FTDI cable: the tty's device is a usb-serial port below the interface.
        sys.tty("ttyUSB0", Some("devices/usb1/1-1/1-1:1.0/ttyUSB0"));
        sys.file("devices/usb1/1-1/idVendor", "0403\n");
        sys.file("devices/usb1/1-1/idProduct", "6001\n");
        sys.file("devices/usb1/1-1/manufacturer", "FTDI\n");
        sys.file("devices/usb1/1-1/product", "FT232R USB UART\n");
        sys.file("devices/usb1/1-1/serial", "A50285BI\n");
        sys.file("devices/usb1/1-1/1-1:1.0/bInterfaceNumber", "00\n");
        // A module's own USB port (cdc-acm): the device is the interface.
        sys.tty("ttyACM0", Some("devices/usb1/1-2/1-2:1.0"));
        sys.file("devices/usb1/1-2/idVendor", "2a3c\n");
        sys.file("devices/usb1/1-2/idProduct", "0100\n");
        sys.file("devices/usb1/1-2/product", "StepRocker\n");
        sys.file("devices/usb1/1-2/1-2:1.0/bInterfaceNumber", "00\n");
        sys.file(
            "devices/usb1/1-2/1-2:1.0/interface",
            "CDC Abstract Control Model\n",
        );
        // An on-board UART that answered, and an empty legacy slot.
        sys.tty("ttyS0", Some("devices/pnp0/00:01"));
        sys.subsystem("devices/pnp0/00:01", "pnp");
        sys.file("class/tty/ttyS0/type", "4\n");
        sys.tty("ttyS1", Some("devices/platform/serial8250"));
        sys.file("class/tty/ttyS1/type", "0\n");
        // A PCI card.
        sys.tty("ttyS4", Some("devices/pci0000:00/0000:00:1f.0"));
        sys.subsystem("devices/pci0000:00/0000:00:1f.0", "pci");
        sys.tty("rfcomm0", None);
        // Virtual ttys, and a port whose device node is gone.
        sys.tty("tty0", None);
        sys.tty("ptmx", None);
        sys.tty("ttyUSB1", Some("devices/usb1/1-3/1-3:1.0/ttyUSB1"));
        fs::remove_file(sys.root.join("dev/ttyUSB1")).expect("rm");

        assert_eq!(
            sys.scan(),
            [
                "/rfcomm0  bluetooth",
                "/ttyACM0  usb 2a3c:0100  StepRocker  (CDC Abstract Control Model)",
                "/ttyS0",
                "/ttyS4  pci",
                "/ttyUSB0  usb 0403:6001  FTDI  FT232R USB UART  serial A50285BI",
            ]
        );
    }

    #[test]
    fn ports_are_listed_with_their_by_id_names_and_taken_by_them() {
        let sys = FakeSys::new();
        sys.tty("ttyUSB0", Some("devices/usb1/1-1/1-1:1.0/ttyUSB0"));
        sys.tty("ttyUSB1", Some("devices/usb1/1-3/1-3:1.0/ttyUSB1"));
        sys.tty("ttyACM0", Some("devices/usb1/1-2/1-2:1.0"));
        // udev's links, relative as udev writes them; one adapter has
        // two (by serial and by interface), one port none, one is dangling.
        let by_id = sys.root.join("dev/serial/by-id");
        fs::create_dir_all(&by_id).expect("mkdir");
        let ftdi = "usb-FTDI_FT232R_USB_UART_A50285BI-if00-port0";
        symlink("../../ttyUSB0", by_id.join(ftdi)).expect("symlink");
        symlink("../../ttyUSB0", by_id.join("usb-FTDI-alias")).expect("symlink");
        symlink("../../ttyACM0", by_id.join("usb-Trinamic_StepRocker-if00")).expect("symlink");
        symlink("../../ttyUSB9", by_id.join("usb-gone-if00")).expect("symlink");
        fs::write(by_id.join("not-a-link"), "").expect("write");

        let ports = with_by_id_names(
            scan_sysfs(&sys.root.join("class/tty"), &sys.root.join("dev")),
            &by_id,
        );
        let names = |path: &str| -> Vec<String> {
            let port = ports
                .iter()
                .find(|p| p.port.path.ends_with(path))
                .expect("listed");
            port.by_id
                .iter()
                .map(|n| n.rsplit('/').next().unwrap_or_default().to_string())
                .collect()
        };
        assert_eq!(names("/ttyUSB0"), ["usb-FTDI-alias", ftdi], "by name");
        assert_eq!(names("/ttyACM0"), ["usb-Trinamic_StepRocker-if00"]);
        assert!(names("/ttyUSB1").is_empty());
        // Each name on a line of its own under the port.
        let acm = ports
            .iter()
            .find(|p| p.port.path.ends_with("/ttyACM0"))
            .expect("listed")
            .to_string();
        let lines: Vec<&str> = acm.lines().collect();
        assert_eq!(lines.len(), 2, "{acm}");
        assert!(
            lines[1].starts_with("    ")
                && lines[1].ends_with("/dev/serial/by-id/usb-Trinamic_StepRocker-if00"),
            "{acm}"
        );

        // --port: the file name alone, the full path, a device path, and a
        // name that is nowhere (left for the open to refuse).
        let full = by_id.join(ftdi).to_string_lossy().into_owned();
        assert_eq!(resolve_port(ftdi, &by_id), full);
        assert_eq!(resolve_port(&full, &by_id), full);
        let device = sys.root.join("dev/ttyUSB1").to_string_lossy().into_owned();
        assert_eq!(resolve_port(&device, &by_id), device);
        assert_eq!(resolve_port("usb-nothing-if00", &by_id), "usb-nothing-if00");
        assert_eq!(resolve_port("COM3", &by_id), "COM3");
        assert_eq!(
            Path::new(&resolve_port(ftdi, &by_id)).canonicalize().ok(),
            sys.root.join("dev/ttyUSB0").canonicalize().ok()
        );
    }

    #[test]
    fn no_sysfs_means_no_ports() {
        assert!(scan_sysfs(Path::new("/nonexistent/class/tty"), Path::new("/dev")).is_empty());
    }
}
