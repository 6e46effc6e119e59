//! Why a serial port would not open, said so that a technician can fix it:
//! who owns the device and who may use it (as `ls -l` shows it), which
//! program holds a busy port, which ports there are when the one named is
//! not there.
//!
//! The explanations are pure functions of facts gathered beforehand
//! ([`NodeFacts`], [`Accounts`], [`Caller`], [`Holder`], the port list), so
//! that they are tested with any facts; the gathering (`stat`, `/etc/group`,
//! `/proc/*/fd`) is the small I/O part, [`explain`].

use std::fs;
use std::path::Path;

use super::ports::ListedPort;

/// What kind of failure an opening was.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PortTrouble {
    /// EACCES or EPERM: the device's owner, group and mode keep us out.
    PermissionDenied,
    /// EBUSY (the port is set exclusive, TIOCEXCL) or its exclusive
    /// `flock` is taken: another program has it open.
    Busy,
    /// ENOENT: nothing at that path.
    Missing,
    /// Anything else, said in the system's words.
    Other,
}

impl PortTrouble {
    /// The kind of serialport's error. serialport keeps no errno: EACCES
    /// and ENOENT arrive as their io kinds, EBUSY and a taken `flock` as
    /// `NoDevice` (its open uses that kind for nothing else), EPERM only as
    /// the system's words.
    pub fn of(e: &serialport::Error) -> PortTrouble {
        use std::io::ErrorKind as Io;
        match e.kind() {
            serialport::ErrorKind::Io(Io::PermissionDenied) => PortTrouble::PermissionDenied,
            serialport::ErrorKind::Io(Io::NotFound) => PortTrouble::Missing,
            serialport::ErrorKind::NoDevice => PortTrouble::Busy,
            _ if e.description == "Operation not permitted" => PortTrouble::PermissionDenied,
            _ if e.description == "Device or resource busy" => PortTrouble::Busy,
            _ => PortTrouble::Other,
        }
    }
}

/// A device node's owner, group and mode, as `stat` gives them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NodeFacts {
    /// `st_mode`: file type and permission bits.
    pub mode: u32,
    pub uid: u32,
    pub gid: u32,
}

/// Who is asking: this process's user and every group it runs with.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Caller {
    pub uid: u32,
    /// The effective group and the supplementary ones, as the process has
    /// them now (a group added since the login is not among them).
    pub gids: Vec<u32>,
}

/// User and group names from `/etc/passwd` and `/etc/group`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Accounts {
    users: Vec<User>,
    groups: Vec<Group>,
}

#[derive(Debug, Clone, PartialEq, Eq)]
struct User {
    name: String,
    uid: u32,
    /// The primary group.
    gid: u32,
}

#[derive(Debug, Clone, PartialEq, Eq)]
struct Group {
    name: String,
    gid: u32,
    members: Vec<String>,
}

impl Accounts {
    /// From the text of `/etc/passwd` (`name:x:uid:gid:…`) and `/etc/group`
    /// (`name:x:gid:member,member`); lines that do not read so are skipped.
    pub fn parse(passwd: &str, group: &str) -> Accounts {
        let users = passwd
            .lines()
            .filter_map(|line| {
                let mut fields = line.split(':');
                let name = fields.next()?;
                let uid = fields.nth(1)?.parse().ok()?;
                let gid = fields.next()?.parse().ok()?;
                Some(User {
                    name: name.to_string(),
                    uid,
                    gid,
                })
            })
            .collect();
        let groups = group
            .lines()
            .filter_map(|line| {
                let mut fields = line.split(':');
                let name = fields.next()?;
                let gid = fields.nth(1)?.parse().ok()?;
                let members = fields
                    .next()
                    .unwrap_or_default()
                    .split(',')
                    .map(str::trim)
                    .filter(|m| !m.is_empty())
                    .map(str::to_string)
                    .collect();
                Some(Group {
                    name: name.to_string(),
                    gid,
                    members,
                })
            })
            .collect();
        Accounts { users, groups }
    }

    /// This system's accounts; empty where the files cannot be read (names
    /// then show as numbers).
    pub fn read() -> Accounts {
        let read = |path| fs::read_to_string(path).unwrap_or_default();
        Accounts::parse(&read("/etc/passwd"), &read("/etc/group"))
    }

    /// A user's name, or the number when it has none here.
    pub fn user_name(&self, uid: u32) -> String {
        self.users
            .iter()
            .find(|u| u.uid == uid)
            .map_or_else(|| uid.to_string(), |u| u.name.clone())
    }

    /// A group's name, or the number when it has none here.
    pub fn group_name(&self, gid: u32) -> String {
        self.groups
            .iter()
            .find(|g| g.gid == gid)
            .map_or_else(|| gid.to_string(), |g| g.name.clone())
    }

    /// Whether the accounts files put user `uid` in group `gid` (as its
    /// primary group or as a member).
    fn lists_in_group(&self, uid: u32, gid: u32) -> bool {
        let Some(user) = self.users.iter().find(|u| u.uid == uid) else {
            return false;
        };
        user.gid == gid
            || self
                .groups
                .iter()
                .any(|g| g.gid == gid && g.members.contains(&user.name))
    }
}

/// `crw-rw----`, as `ls -l` writes a mode.
pub fn mode_string(mode: u32) -> String {
    let kind = match mode & 0o170_000 {
        0o020_000 => 'c',
        0o060_000 => 'b',
        0o040_000 => 'd',
        0o120_000 => 'l',
        0o010_000 => 'p',
        0o140_000 => 's',
        _ => '-',
    };
    let mut text = String::from(kind);
    // (permission bits, set-id or sticky bit, the letter that shows it)
    let triplets = [
        (mode >> 6, mode & 0o4000 != 0, 's'),
        (mode >> 3, mode & 0o2000 != 0, 's'),
        (mode, mode & 0o1000 != 0, 't'),
    ];
    for (bits, special, letter) in triplets {
        text.push(if bits & 4 != 0 { 'r' } else { '-' });
        text.push(if bits & 2 != 0 { 'w' } else { '-' });
        text.push(match (bits & 1 != 0, special) {
            (true, true) => letter,
            (false, true) => letter.to_ascii_uppercase(),
            (true, false) => 'x',
            (false, false) => '-',
        });
    }
    text
}

/// The group serial adapters are given on Debian, Ubuntu and Fedora.
const USUAL_SERIAL_GROUP: &str = "dialout";

/// Why `path` refused us, and what to do: its owner, group and mode as
/// `ls -l` shows them, whether `caller` is in the group that may use it,
/// and the fix. `node` is `None` when the device could not be looked at.
pub fn permission_advice(
    path: &str,
    node: Option<&NodeFacts>,
    accounts: &Accounts,
    caller: &Caller,
) -> Vec<String> {
    let Some(node) = node else {
        return vec![
            format!("{path} cannot even be looked at (its owner and mode are hidden from you)"),
            format!(
                "fix: usually `sudo usermod -aG {USUAL_SERIAL_GROUP} $USER`, then log out and in again"
            ),
        ];
    };
    let owner = accounts.user_name(node.uid);
    let group = accounts.group_name(node.gid);
    let me = accounts.user_name(caller.uid);
    let mut advice = vec![format!(
        "{} {owner} {group} {path}   (`ls -l {path}`)",
        mode_string(node.mode)
    )];
    let group_may = node.mode & 0o060 == 0o060;
    if node.gid == 0 || !group_may {
        // Joining the group would not help (it is root's, or it may not
        // read and write): the device itself must be given a group.
        advice.push(format!(
            "only {owner} may use it: its group {group} may not read and write it"
        ));
        advice.push(format!(
            "fix: a udev rule giving it group {USUAL_SERIAL_GROUP} and mode 0660 \
             (e.g. SUBSYSTEM==\"tty\", GROUP=\"{USUAL_SERIAL_GROUP}\", MODE=\"0660\"), \
             or run as {owner}"
        ));
    } else if caller.gids.contains(&node.gid) {
        // In the group and still refused: something other than the mode
        // (an ACL, a security module) decides.
        advice.push(format!(
            "you ({me}) are in group {group}, which may read and write it: \
             something else refuses (an ACL, AppArmor or SELinux?)"
        ));
    } else if accounts.lists_in_group(caller.uid, node.gid) {
        advice.push(format!(
            "you ({me}) were added to group {group}, but this login began before that"
        ));
        advice.push(format!(
            "fix: log out and in again (or start a shell with `newgrp {group}`)"
        ));
    } else {
        advice.push(format!(
            "you ({me}) are not in group {group}, which may read and write it"
        ));
        advice.push(format!(
            "fix: `sudo usermod -aG {group} $USER`, then log out and in again"
        ));
    }
    advice
}

/// A process that has a device open.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Holder {
    pub pid: u32,
    /// Its command name (`/proc/PID/comm`), where it could be read.
    pub command: Option<String>,
}

/// Who holds a busy `path`: each holder by pid and command, or how to find
/// out when the system would not tell.
pub fn busy_advice(path: &str, holders: &[Holder]) -> Vec<String> {
    if holders.is_empty() {
        return vec![format!(
            "which program has it is hidden from you: `sudo fuser -v {path}` tells; \
             close that program (a terminal program, ModemManager, another axterm)"
        )];
    }
    let mut advice: Vec<String> = holders
        .iter()
        .map(|h| match &h.command {
            Some(command) => format!("held by {command} (pid {})", h.pid),
            None => format!("held by pid {}", h.pid),
        })
        .collect();
    advice.push("close it there, then try again".to_string());
    advice
}

/// What there is when `path` is not: the serial ports found.
pub fn missing_advice(path: &str, ports: &[ListedPort]) -> Vec<String> {
    if ports.is_empty() {
        return vec![format!(
            "no serial port is here at all: is the adapter plugged in and powered? \
             (`axterm ports` lists them; `dmesg` tells whether one was seen)"
        )];
    }
    let mut advice = vec![format!(
        "{path} is not among the serial ports here (`axterm ports`):"
    )];
    for port in ports {
        advice.extend(port.to_string().lines().map(|line| format!("  {line}")));
    }
    advice
}

/// The processes in `proc_root` (`/proc`) with `device` open, by pid, each
/// once. Processes whose descriptors cannot be read (another user's, when
/// we are not root) are skipped: the list may then be short.
pub fn holders(device: &Path, proc_root: &Path) -> Vec<Holder> {
    let Ok(device) = device.canonicalize() else {
        return Vec::new();
    };
    let Ok(entries) = fs::read_dir(proc_root) else {
        return Vec::new();
    };
    let mut found: Vec<Holder> = entries
        .flatten()
        .filter_map(|entry| {
            let pid: u32 = entry.file_name().to_str()?.parse().ok()?;
            let fds = fs::read_dir(entry.path().join("fd")).ok()?;
            let holds = fds
                .flatten()
                .any(|fd| fs::read_link(fd.path()).is_ok_and(|target| target == device));
            holds.then(|| Holder {
                pid,
                command: fs::read_to_string(entry.path().join("comm"))
                    .ok()
                    .map(|c| c.trim().to_string())
                    .filter(|c| !c.is_empty()),
            })
        })
        .collect();
    found.sort_by_key(|h| h.pid);
    found
}

/// Whether a port is opened for the first time or again after the link
/// was lost.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Opening {
    First,
    /// A reopening after a loss: a port not there has vanished, whatever
    /// the hang-up managed to see ([`vanished`]).
    Again,
}

/// Why a reopening found nothing at `path`.
pub fn vanished(path: &str) -> String {
    format!("the port vanished: {path} is not there (unplugged?)")
}

/// The reason (one line) and the advice (lines to show under it) for a
/// failed opening of `path`. Looks at the system: the device's metadata,
/// the accounts, `/proc`, the port list.
pub fn explain(path: &str, e: &serialport::Error, opening: Opening) -> (String, Vec<String>) {
    match PortTrouble::of(e) {
        // The port list is for someone choosing a port; the reconnect
        // line that shows this has room for one line only.
        PortTrouble::Missing if opening == Opening::Again => (vanished(path), Vec::new()),
        PortTrouble::PermissionDenied => {
            // A by-id name is a symbolic link: `ls -l` of it shows the
            // link's own mode, so the device it leads to is the one named.
            let device = fs::canonicalize(path)
                .map_or_else(|_| path.to_string(), |p| p.to_string_lossy().into_owned());
            (
                "permission denied".to_string(),
                permission_advice(
                    &device,
                    node_facts(&device).as_ref(),
                    &Accounts::read(),
                    &caller(),
                ),
            )
        }
        PortTrouble::Busy => (
            "the port is in use by another program".to_string(),
            busy_advice(path, &holders(Path::new(path), Path::new("/proc"))),
        ),
        PortTrouble::Missing => (
            "no such port (not plugged in? a wrong name?)".to_string(),
            missing_advice(path, &super::ports::listed_ports().unwrap_or_default()),
        ),
        PortTrouble::Other => (e.to_string(), Vec::new()),
    }
}

#[cfg(unix)]
fn node_facts(path: &str) -> Option<NodeFacts> {
    use std::os::unix::fs::MetadataExt;
    let meta = fs::metadata(path).ok()?;
    Some(NodeFacts {
        mode: meta.mode(),
        uid: meta.uid(),
        gid: meta.gid(),
    })
}

#[cfg(not(unix))]
fn node_facts(_path: &str) -> Option<NodeFacts> {
    None
}

/// This process's user and groups.
#[cfg(unix)]
fn caller() -> Caller {
    // SAFETY: geteuid and getegid only return this process's ids.
    let (uid, gid) = unsafe { (libc::geteuid(), libc::getegid()) };
    let mut gids = vec![gid];
    // SAFETY: with a size of 0 getgroups only counts the groups.
    let count = unsafe { libc::getgroups(0, std::ptr::null_mut()) };
    if let Ok(len) = usize::try_from(count) {
        let mut groups: Vec<libc::gid_t> = vec![0; len];
        // SAFETY: `groups` has room for `count` entries, as we say.
        let got = unsafe { libc::getgroups(count, groups.as_mut_ptr()) };
        if let Ok(got) = usize::try_from(got) {
            gids.extend(groups.iter().take(got));
        }
    }
    Caller { uid, gids }
}

#[cfg(not(unix))]
fn caller() -> Caller {
    Caller {
        uid: 0,
        gids: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const PASSWD: &str = "root:x:0:0:root:/root:/bin/bash\n\
                          alice:x:1000:1000:Alice:/home/alice:/bin/bash\n\
                          bob:x:1001:1001::/home/bob:/bin/sh\n\
                          broken line\n";
    const GROUP: &str = "root:x:0:\n\
                         dialout:x:20:bob\n\
                         alice:x:1000:\n\
                         uucp:x:14: alice , bob\n";

    fn accounts() -> Accounts {
        Accounts::parse(PASSWD, GROUP)
    }

    /// /dev/ttyUSB0 as udev makes it on Debian: crw-rw---- root dialout.
    fn usb0() -> NodeFacts {
        NodeFacts {
            mode: 0o020_660,
            uid: 0,
            gid: 20,
        }
    }

    fn alice() -> Caller {
        Caller {
            uid: 1000,
            gids: vec![1000],
        }
    }

    #[test]
    fn modes_read_as_ls_writes_them() {
        assert_eq!(mode_string(0o020_660), "crw-rw----");
        assert_eq!(mode_string(0o020_600), "crw-------");
        assert_eq!(mode_string(0o100_755), "-rwxr-xr-x");
        assert_eq!(mode_string(0o104_755), "-rwsr-xr-x");
        assert_eq!(mode_string(0o041_777), "drwxrwxrwt");
        assert_eq!(mode_string(0o102_644), "-rw-r-Sr--");
    }

    #[test]
    fn names_come_from_the_accounts_and_numbers_stand_in() {
        let accounts = accounts();
        assert_eq!(accounts.user_name(1000), "alice");
        assert_eq!(accounts.group_name(20), "dialout");
        assert_eq!(accounts.user_name(4242), "4242");
        assert_eq!(accounts.group_name(4242), "4242");
        assert_eq!(Accounts::default().group_name(20), "20");
    }

    #[test]
    fn a_user_outside_the_group_is_told_to_join_it() {
        let advice = permission_advice("/dev/ttyUSB0", Some(&usb0()), &accounts(), &alice());
        assert_eq!(
            advice,
            [
                "crw-rw---- root dialout /dev/ttyUSB0   (`ls -l /dev/ttyUSB0`)",
                "you (alice) are not in group dialout, which may read and write it",
                "fix: `sudo usermod -aG dialout $USER`, then log out and in again",
            ]
        );
    }

    #[test]
    fn the_group_named_is_the_devices_own() {
        // Arch and older SUSE give serial ports to uucp.
        let node = NodeFacts { gid: 14, ..usb0() };
        let advice = permission_advice("/dev/ttyACM0", Some(&node), &accounts(), &bob());
        assert_eq!(
            advice[0],
            "crw-rw---- root uucp /dev/ttyACM0   (`ls -l /dev/ttyACM0`)"
        );
        // Listed in /etc/group (with spaces around the name) but not in
        // this process's groups: the login predates it.
        assert!(advice[1].contains("added to group uucp, but this login began before"));
        assert!(advice[2].contains("log out and in again"), "{advice:?}");
        assert!(advice[2].contains("newgrp uucp"), "{advice:?}");
    }

    fn bob() -> Caller {
        Caller {
            uid: 1001,
            gids: vec![1001],
        }
    }

    #[test]
    fn a_member_whose_login_predates_it_is_told_to_log_in_again() {
        let advice = permission_advice("/dev/ttyUSB0", Some(&usb0()), &accounts(), &bob());
        assert_eq!(
            advice[1..],
            [
                "you (bob) were added to group dialout, but this login began before that",
                "fix: log out and in again (or start a shell with `newgrp dialout`)",
            ]
        );
    }

    #[test]
    fn a_member_with_the_group_still_refused_is_pointed_elsewhere() {
        let caller = Caller {
            uid: 1001,
            gids: vec![1001, 20],
        };
        let advice = permission_advice("/dev/ttyUSB0", Some(&usb0()), &accounts(), &caller);
        assert!(
            advice[1].contains("you (bob) are in group dialout"),
            "{advice:?}"
        );
        assert!(advice[1].contains("ACL"), "{advice:?}");
        assert_eq!(advice.len(), 2, "no usermod advice: {advice:?}");
    }

    #[test]
    fn a_device_only_root_may_use_needs_a_udev_rule_not_a_group() {
        let node = NodeFacts {
            mode: 0o020_600,
            uid: 0,
            gid: 0,
        };
        let advice = permission_advice("/dev/ttyS0", Some(&node), &accounts(), &alice());
        assert_eq!(
            advice[0],
            "crw------- root root /dev/ttyS0   (`ls -l /dev/ttyS0`)"
        );
        assert!(advice[1].starts_with("only root may use it"), "{advice:?}");
        assert!(advice[2].contains("udev rule"), "{advice:?}");
        assert!(!advice.iter().any(|l| l.contains("usermod")), "{advice:?}");
    }

    #[test]
    fn owners_and_groups_without_names_show_as_numbers() {
        let node = NodeFacts {
            mode: 0o020_660,
            uid: 4242,
            gid: 4343,
        };
        let caller = Caller {
            uid: 5000,
            gids: vec![5000],
        };
        let advice = permission_advice("/dev/ttyUSB3", Some(&node), &Accounts::default(), &caller);
        assert_eq!(
            advice,
            [
                "crw-rw---- 4242 4343 /dev/ttyUSB3   (`ls -l /dev/ttyUSB3`)",
                "you (5000) are not in group 4343, which may read and write it",
                "fix: `sudo usermod -aG 4343 $USER`, then log out and in again",
            ]
        );
    }

    #[test]
    fn a_device_that_cannot_be_looked_at_still_gets_the_usual_fix() {
        let advice = permission_advice("/dev/ttyUSB0", None, &accounts(), &alice());
        assert!(advice[0].contains("cannot even be looked at"), "{advice:?}");
        assert!(advice[1].contains("usermod -aG dialout"), "{advice:?}");
    }

    #[test]
    fn errors_are_sorted_by_what_they_mean() {
        use serialport::{Error, ErrorKind};
        use std::io::ErrorKind as Io;
        let of = |kind, text: &str| PortTrouble::of(&Error::new(kind, text));
        assert_eq!(
            of(ErrorKind::Io(Io::PermissionDenied), "Permission denied"),
            PortTrouble::PermissionDenied
        );
        // EPERM has no io kind of its own in serialport: only its words.
        assert_eq!(
            of(ErrorKind::Unknown, "Operation not permitted"),
            PortTrouble::PermissionDenied
        );
        // EBUSY from TIOCEXCL, and a taken flock.
        assert_eq!(
            of(ErrorKind::NoDevice, "Device or resource busy"),
            PortTrouble::Busy
        );
        assert_eq!(
            of(
                ErrorKind::NoDevice,
                "Unable to acquire exclusive lock on serial port"
            ),
            PortTrouble::Busy
        );
        assert_eq!(
            of(ErrorKind::Io(Io::NotFound), "No such file or directory"),
            PortTrouble::Missing
        );
        assert_eq!(
            of(ErrorKind::Unknown, "Input/output error"),
            PortTrouble::Other
        );
    }

    /// A by-id name is explained by the device it leads to.
    #[cfg(unix)]
    #[test]
    fn a_refused_link_name_shows_the_device_behind_it() {
        use std::os::unix::fs::{PermissionsExt, symlink};
        let dir = tempfile::tempdir().expect("temp dir");
        let device = dir.path().join("ttyUSB0");
        fs::write(&device, "").expect("device stand-in");
        fs::set_permissions(&device, fs::Permissions::from_mode(0o660)).expect("chmod");
        let device = device.canonicalize().expect("real path");
        let link = dir
            .path()
            .join("usb-FTDI_FT232R_USB_UART_A50285BI-if00-port0");
        symlink(&device, &link).expect("by-id link");
        let e = serialport::Error::new(
            serialport::ErrorKind::Io(std::io::ErrorKind::PermissionDenied),
            "Permission denied",
        );
        let (reason, advice) = explain(&link.to_string_lossy(), &e, Opening::First);
        assert_eq!(reason, "permission denied");
        let shown = device.to_string_lossy();
        assert!(
            advice[0].starts_with("-rw-rw---- ")
                && advice[0].ends_with(&format!(" {shown}   (`ls -l {shown}`)")),
            "{advice:?}"
        );
    }

    #[test]
    fn a_port_missing_at_a_reopening_has_vanished() {
        let e = serialport::Error::new(
            serialport::ErrorKind::Io(std::io::ErrorKind::NotFound),
            "No such file or directory",
        );
        assert_eq!(
            explain("/nonexistent/ttyUSB0", &e, Opening::Again),
            (
                "the port vanished: /nonexistent/ttyUSB0 is not there (unplugged?)".to_string(),
                Vec::new()
            )
        );
        let (reason, advice) = explain("/nonexistent/ttyUSB0", &e, Opening::First);
        assert_eq!(reason, "no such port (not plugged in? a wrong name?)");
        assert_eq!(advice.len().min(1), 1, "the ports there are (or none)");
    }

    #[test]
    fn a_busy_port_names_its_holders_or_how_to_find_them() {
        let holders = [
            Holder {
                pid: 812,
                command: Some("minicom".into()),
            },
            Holder {
                pid: 913,
                command: None,
            },
        ];
        assert_eq!(
            busy_advice("/dev/ttyUSB0", &holders),
            [
                "held by minicom (pid 812)",
                "held by pid 913",
                "close it there, then try again",
            ]
        );
        let unknown = busy_advice("/dev/ttyUSB0", &[]);
        assert!(
            unknown[0].contains("sudo fuser -v /dev/ttyUSB0"),
            "{unknown:?}"
        );
    }

    #[test]
    fn a_missing_port_lists_the_ports_there_are() {
        use super::super::ports::{PortInfo, PortKind};
        let ports = [ListedPort {
            port: PortInfo {
                path: "/dev/ttyACM0".into(),
                kind: PortKind::Other,
            },
            by_id: vec!["/dev/serial/by-id/usb-Trinamic_StepRocker-if00".into()],
        }];
        assert_eq!(
            missing_advice("/dev/ttyUSB0", &ports),
            [
                "/dev/ttyUSB0 is not among the serial ports here (`axterm ports`):",
                "  /dev/ttyACM0",
                "      /dev/serial/by-id/usb-Trinamic_StepRocker-if00",
            ]
        );
        let none = missing_advice("/dev/ttyUSB0", &[]);
        assert!(
            none[0].starts_with("no serial port is here at all"),
            "{none:?}"
        );
    }

    /// The test holds a pseudo-terminal open; the scan of the real /proc
    /// finds this process among its holders, by the slave's path.
    #[cfg(target_os = "linux")]
    #[test]
    fn the_proc_scan_finds_who_holds_a_device() {
        use serialport::SerialPort;
        let (_master, slave) = serialport::TTYPort::pair().expect("a pseudo-terminal");
        let path = slave.name().expect("the slave has a path");
        let me = std::process::id();
        let found = holders(Path::new(&path), Path::new("/proc"));
        let mine = found.iter().find(|h| h.pid == me);
        let comm = fs::read_to_string("/proc/self/comm").expect("own comm");
        assert_eq!(
            mine.map(|h| h.command.clone()),
            Some(Some(comm.trim().to_string())),
            "{found:?}"
        );
        drop(slave);
        let after = holders(Path::new(&path), Path::new("/proc"));
        assert!(!after.iter().any(|h| h.pid == me), "{after:?}");
    }

    /// A /proc whose entries cannot all be read: the others still count.
    #[cfg(unix)]
    #[test]
    fn unreadable_proc_entries_are_skipped() {
        use std::os::unix::fs::symlink;
        let dir = tempfile::tempdir().expect("temp dir");
        fs::write(dir.path().join("ttyUSB0"), "").expect("device stand-in");
        // /proc's links name the device by its real path.
        let device = dir
            .path()
            .join("ttyUSB0")
            .canonicalize()
            .expect("real path");
        let proc_root = dir.path().join("proc");
        for (pid, comm) in [("77", "picocom"), ("78", "bash")] {
            fs::create_dir_all(proc_root.join(pid).join("fd")).expect("mkdir");
            fs::write(proc_root.join(pid).join("comm"), format!("{comm}\n")).expect("comm");
        }
        symlink(&device, proc_root.join("77/fd/3")).expect("symlink");
        symlink(&device, proc_root.join("77/fd/4")).expect("symlink");
        symlink(dir.path().join("elsewhere"), proc_root.join("78/fd/3")).expect("symlink");
        // A process without a readable fd directory, and a non-process.
        fs::create_dir_all(proc_root.join("79")).expect("mkdir");
        fs::create_dir_all(proc_root.join("self").join("fd")).expect("mkdir");
        assert_eq!(
            holders(&device, &proc_root),
            [Holder {
                pid: 77,
                command: Some("picocom".into()),
            }]
        );
    }
}
