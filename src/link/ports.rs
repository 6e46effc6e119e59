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

use std::fmt;
use std::fs;
use std::io;
use std::path::Path;

/// One serial port.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PortInfo {
    /// What to give `--port`: `/dev/ttyUSB0`, `COM3`.
    pub path: String,
    pub kind: PortKind,
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
    fn no_sysfs_means_no_ports() {
        assert!(scan_sysfs(Path::new("/nonexistent/class/tty"), Path::new("/dev")).is_empty());
    }
}
